// Tracks a hand-made 90-degree fillet (two lines at +-45 degrees meeting at
// (1.5, 120) mm) with the installed tracker; exit 0 when the root is found
// within 0.05 mm and the stripe detector finds a 3-row peak centred on row 10.
#include <cmath>
#include <cstdio>
#include <vector>

#include "stripe/peaks.h"
#include "tracker/tracker.h"

int main() {
  const std::uint16_t column[20] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 2000, 4000, 2000};
  vts::stripe::PeakResult peaks;
  vts::stripe::detect_peaks({column, 1, 20, 1, 12}, {}, peaks);
  if (!peaks.chosen_peak(0) || std::abs(peaks.chosen_peak(0)->row - 10.0f) > 1e-4f) {
    std::printf("stripe peak not found at row 10\n");
    return 1;
  }
  const int n = 400;
  std::vector<float> y(n), z(n);
  std::vector<std::uint8_t> valid(n, 1);
  for (int i = 0; i < n; ++i) {
    y[i] = static_cast<float>(1.5 - 25.0 + 50.0 * i / (n - 1));
    z[i] = static_cast<float>(120.0 - std::abs(y[i] - 1.5));
  }
  vts::tracker::Tracker tracker;
  const auto& r = tracker.track({y, z, valid});
  if (r.status != vts::tracker::TrackStatus::Ok || !r.track_point) {
    std::printf("not tracked\n");
    return 1;
  }
  const double err = std::hypot(r.track_point->x() - 1.5, r.track_point->y() - 120.0);
  std::printf("root (%.4f, %.4f), error %.4f mm, angle %.3f deg\n", r.track_point->x(), r.track_point->y(), err,
              r.angle_deg);
  return err < 0.05 && std::abs(r.angle_deg - 90.0) < 0.2 ? 0 : 1;
}
