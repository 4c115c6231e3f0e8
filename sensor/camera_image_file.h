#pragma once
// Writes a camera image (sensor/camera_image.h) with its labels, as a
// labelled example for stripe extraction: DIR/image_NNNNNN.png (8-bit
// greyscale for 8-bit images, else 16-bit holding the DN values as they are,
// with an sBIT chunk giving the depth; the region of interest's rows only)
// and DIR/image_NNNNNN.csv, one line per image column:
//   column, true_row, bounce_row, mirror_row, true_peak, chosen_peak, chosen_row, peaks
// rows in full-image coordinates (a region of interest's first row is
// `first_row`, written in the CSV's header comment), NaN written as empty;
// true_peak/chosen_peak index the column's peaks from the lowest row (-1:
// none), `peaks` is how many the detector found. docs/SENSOR_MODEL.md, "The
// camera image", describes both. Each file is written whole or not at all.
#include <filesystem>

#include "sensor/camera_image.h"

namespace vts {

// The two files' paths for profile `index` under dir.
std::filesystem::path camera_image_path(const std::filesystem::path& dir, std::int64_t index);
std::filesystem::path camera_labels_path(const std::filesystem::path& dir, std::int64_t index);

// Throws std::runtime_error naming the file when it cannot be written.
void write_camera_image(const std::filesystem::path& dir, const CameraImage& image);

}  // namespace vts
