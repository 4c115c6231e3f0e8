#include "sensor/stripe_profile.h"

#include "sensor/camera_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <stdexcept>
#include <string>

#include "sensor/error_model.h"

namespace vts {

void peaks_to_profile(const ScannerDesc& desc, const stripe::PeakResult& peaks, int image_height, int bits,
                      int row_offset, Profile& out) {
  const int width = peaks.width();
  if (width != desc.image_width_px)
    throw std::invalid_argument("the image is " + std::to_string(width) + " columns wide, the sensor's camera " +
                                std::to_string(desc.image_width_px));
  if (row_offset < 0 || row_offset + image_height > desc.image_height_px)
    throw std::invalid_argument("rows " + std::to_string(row_offset) + ".." +
                                std::to_string(row_offset + image_height - 1) +
                                " are outside the sensor camera's rows 0.." +
                                std::to_string(desc.image_height_px - 1));
  const CameraGeometry cam = camera_geometry(desc);
  const double full_scale = stripe::full_scale_dn(bits);
  out.resize(width);
  for (int c = 0; c < width; ++c) {
    const stripe::Peak* p = peaks.chosen_peak(c);
    if (!p) continue;
    Eigen::Vector2d yz;
    if (!triangulate(cam, c, p->row + row_offset, yz) || !(yz.y() > 0.0) || !std::isfinite(yz.y())) continue;
    const double y = yz.x(), z = yz.y();
    out.y_mm[c] = static_cast<float>(y);
    out.z_mm[c] = static_cast<float>(z);
    out.range_mm[c] = static_cast<float>(std::hypot(y, z));
    out.intensity[c] = static_cast<float>(std::min(1.0, p->peak_dn / full_scale));
    out.valid[c] = 1;
  }
}

void write_peaks_csv(std::ostream& out, const stripe::PeakResult& peaks) {
  out << "column,row,width_px,peak_dn,strength,saturated,peaks,others\n";
  char buf[128];
  for (int c = 0; c < peaks.width(); ++c) {
    const stripe::Peak* chosen = peaks.chosen_peak(c);
    if (chosen)
      std::snprintf(buf, sizeof buf, "%d,%.4f,%.3f,%.0f,%.1f,%d,%d,", c, chosen->row, chosen->width_px,
                    chosen->peak_dn, chosen->strength, chosen->saturated ? 1 : 0, peaks.count(c));
    else
      std::snprintf(buf, sizeof buf, "%d,,,,,,%d,", c, peaks.count(c));
    out << buf;
    bool first = true;
    for (int i = peaks.column_offset[c]; i < peaks.column_offset[c + 1]; ++i) {
      if (i == peaks.chosen[c]) continue;
      const stripe::Peak& p = peaks.peaks[i];
      std::snprintf(buf, sizeof buf, "%s%.4f:%.3f:%.0f:%.1f:%d", first ? "" : ";", p.row, p.width_px, p.peak_dn,
                    p.strength, p.saturated ? 1 : 0);
      out << buf;
      first = false;
    }
    out << '\n';
  }
}

}  // namespace vts
