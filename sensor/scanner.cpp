#include "sensor/scanner.h"

#include <cmath>
#include <sstream>

namespace vts {
namespace {
std::string bad(const char* field, double value, const char* why) {
  std::ostringstream s;
  s << field << " = " << value << ": " << why;
  return s.str();
}
}  // namespace

std::string validate(const ScannerDesc& d) {
  if (!std::isfinite(d.fan_deg) || d.fan_deg <= 0.0 || d.fan_deg >= 170.0)
    return bad("fan_deg", d.fan_deg, "must be > 0 and < 170 degrees");
  if (d.points < kMinPoints || d.points > kMaxPoints)
    return bad("points", d.points, "must be between 16 and 4096");
  if (!std::isfinite(d.min_range_mm) || d.min_range_mm <= 0.0)
    return bad("min_range_mm", d.min_range_mm, "must be > 0");
  if (!std::isfinite(d.max_range_mm) || d.max_range_mm <= d.min_range_mm)
    return bad("max_range_mm", d.max_range_mm, "must be greater than min_range_mm");
  if (!std::isfinite(d.max_hit_mm) || d.max_hit_mm <= 0.0)
    return bad("max_hit_mm", d.max_hit_mm, "must be > 0");
  if (!std::isfinite(d.rate_hz) || d.rate_hz <= 0.0)
    return bad("rate_hz", d.rate_hz, "must be > 0");
  if (!d.tool_from_laser.matrix().allFinite())
    return "tool_from_laser: must be finite";
  return {};
}

}  // namespace vts
