// Scans the built-in fillet with the installed raster emulator (ideal
// profile) and tracks it; exit 0 when the tracked root is within 0.1 mm of
// the cell's analytic root in the sensor frame.
#include <cmath>
#include <cstdio>

#include "render/raster_source.h"
#include "sensor/cell.h"
#include "tracker/tracker.h"

int main() {
  auto cell = vts::builtin_cell("fillet");
  if (!cell) return 1;
  cell->scanner.ideal = true;
  auto source = vts::make_raster_source(cell->scanner, cell->mesh());
  vts::Profile p;
  const vts::Pose pose = cell->path.pose_at(0);
  source->scan(pose, p);
  vts::tracker::Tracker tracker;
  const auto& r = tracker.track({p.y_mm, p.z_mm, p.valid});
  const vts::Workpiece& w = cell->workpieces.front();
  const vts::Vec2 truth = w.in_sensor_frame(pose, w.truth.root_yz);
  if (r.status != vts::tracker::TrackStatus::Ok || !r.track_point) {
    std::printf("not tracked (%d valid points)\n", p.valid_count());
    return 1;
  }
  const double err = (*r.track_point - truth).norm();
  std::printf("%d valid points; root (%.4f, %.4f), truth (%.4f, %.4f), error %.4f mm\n", p.valid_count(),
              r.track_point->x(), r.track_point->y(), truth.x(), truth.y(), err);
  return err < 0.1 ? 0 : 1;
}
