#pragma once
// The stripe peaks of a camera image (stripe/peaks.h) as a profile, through
// the scanner's camera (sensor/camera_image.h: camera_geometry, triangulate,
// with its Scheimpflug tilt when it has one), and as CSV
// (docs/PEAKS.md "CSV").
//
// Image frame: pixel row r covers [r - 0.5, r + 0.5] (stripe/peaks.h), so the
// principal point, at the centre of an H x W image, is row (H - 1) / 2 and
// column (W - 1) / 2. A peak at row r of column c has
//   u = r + row_offset - (H - 1) / 2,   v = c - (W - 1) / 2
// (H, W: the scanner's image_height_px, image_width_px; row_offset: the
// sensor row of the image's row 0, for a region of interest), and
//   z = K / (F tan(theta) - u),   y = v z cos(theta) / F
// without tilt, the inverse of u = F tan(theta) - K / z, v = F y / (z cos(theta)).
#include <iosfwd>

#include "sensor/profile.h"
#include "sensor/scanner.h"
#include "stripe/peaks.h"

namespace vts {

// One point per image column into `out` (resized to the image's width): the
// column's chosen peak triangulated, valid where the column has one and the
// row maps to a depth > 0 (y, z, range = hypot(y, z); intensity = peak_dn /
// full scale of `bits`), invalid (zeros) elsewhere. Throws
// std::invalid_argument when the image is not as wide as the scanner's
// camera or row_offset + image_height > the camera's rows.
void peaks_to_profile(const ScannerDesc& desc, const stripe::PeakResult& peaks, int image_height, int bits,
                      int row_offset, Profile& out);

// Writes the peaks as CSV, one line per image column (docs/PEAKS.md "CSV"):
// header `column,row,width_px,peak_dn,strength,saturated,peaks,others`; the
// chosen peak's fields (empty when the column has none chosen), the number
// of peaks, and the other peaks as `row:width_px:peak_dn:strength:saturated`
// joined by `;`. Rows 4 decimals, widths 3, peak_dn whole DN, strength 1.
void write_peaks_csv(std::ostream& out, const stripe::PeakResult& peaks);

}  // namespace vts
