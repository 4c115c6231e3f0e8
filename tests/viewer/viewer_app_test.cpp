// The viewer's App without a window: an OSMesa core context stands in for the
// window's, so cells, presets, the error model switch, recording and the
// scene handed to the renderer are exercised headless. Tagged [gl].
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "viewer/app.h"
#include "render/gl_context.h"
#include "viewer/renderer.h"
#include "sensor/cell.h"
#include "sensor/presets.h"
#include "sensor/profile_exr.h"

namespace {

using namespace vts::viewer;
using vts::SourceKind;

// Frames of 1/30 s with the scans waited for, as in a scripted run.
void run_frames(App& app, int frames, MotionInput motion = {}) {
  app.sync_scans = true;
  for (int i = 0; i < frames; ++i) app.update(motion, 1.0 / 30.0);
}

int laser_points(const SceneView& view) {
  int n = 0;
  for (const auto& p : view.points)
    n += p.color.r == kLaserLineColor.r && p.color.g == kLaserLineColor.g && p.color.b == kLaserLineColor.b;
  return n;
}

struct Fixture {
  vts::GlContext gl;
  Renderer renderer;
};

}  // namespace

TEST_CASE("viewer app: every built-in cell scans and lights a line", "[viewer][gl]") {
  Fixture f;
  AppOptions options;
  App app(options, f.renderer);
  for (const auto& name : vts::builtin_cell_names(vts::CellSet::Small)) {
    INFO("cell " << name);
    app.load_builtin(name);
    REQUIRE(app.scene_label() == name);
    run_frames(app, 4);
    REQUIRE(app.last_profile());
    REQUIRE(app.last_ideal());
    // Each cell's path starts looking at its joint: most columns hit.
    CHECK(app.last_ideal()->valid_count() > app.last_ideal()->size() / 2);
    SceneView view;
    app.build_scene(view, 800, 600);
    CHECK(view.meshes.size() == 6);
    CHECK(laser_points(view) == app.last_ideal()->valid_count());
    CHECK(view.translucent_triangles.size() % 3 == 0);
    CHECK_FALSE(view.translucent_triangles.empty());
  }
}

TEST_CASE("viewer app: a mesh workpiece scans and is tracked with its joint", "[viewer][gl]") {
  // The built-in fillet's triangles as a CAD part (no seam, no truth) that
  // names its joint, on the fillet's path.
  const vts::Cell fillet = *vts::builtin_cell("fillet");
  auto cell = std::make_shared<vts::Cell>(fillet);
  cell->workpieces = {vts::mesh_workpiece(std::make_shared<const vts::Mesh>(fillet.mesh()),
                                          vts::Pose::Identity(), vts::JointType::Fillet)};
  Fixture f;
  AppOptions options;
  options.given_cell = cell;
  options.given_label = "fillet-mesh";
  App app(options, f.renderer);
  run_frames(app, 3);
  REQUIRE(app.last_ideal());
  CHECK(app.last_ideal()->valid_count() > app.last_ideal()->size() / 2);
  REQUIRE(app.last_track());
  CHECK(app.last_track()->joint == vts::tracker::JointType::Fillet);
  CHECK(app.last_track()->status == vts::tracker::TrackStatus::Ok);
  SceneView view;
  app.build_scene(view, 800, 600);
  CHECK(laser_points(view) == app.last_ideal()->valid_count());
}

TEST_CASE("viewer app: the default cell is tracked and accepted", "[viewer][gl]") {
  Fixture f;
  App app(AppOptions{}, f.renderer);
  CHECK(app.scene_label() == "static-B");
  run_frames(app, 3);
  REQUIRE(app.last_track());
  CHECK(app.last_track()->joint == vts::tracker::JointType::Fillet);
  CHECK(app.last_track()->status == vts::tracker::TrackStatus::Ok);
  REQUIRE(app.last_track()->track_point);
  // Table 2 B: the root lies on the optical axis, 103 mm away.
  CHECK(app.last_track()->track_point->x() == Approx(0.0).margin(0.2));
  CHECK(app.last_track()->track_point->y() == Approx(103.0).margin(0.2));
}

TEST_CASE("viewer app: B lays a bead where the sensor said", "[viewer][gl]") {
  // vgroove-thick as the viewer scans it (raster source, the cell's error
  // model): the sensor's next-bead point is the model's centre within the
  // 0.5 mm the multi-pass sim finds with noise (docs/SIM.md), so the bead
  // lands there, and the fill rises by about one layer (4 mm: the cell's
  // truth before and after, docs/CELLS.md).
  Fixture f;
  AppOptions options;
  App app(options, f.renderer);
  app.load_builtin("vgroove-thick");
  // Before any profile: nothing to place the bead by.
  const int passes0 = app.cell().workpieces.front().params.passes;  // the cell's beads, centred
  const double depth0 = app.cell().workpieces.front().truth.depth_mm;
  app.lay_bead();
  CHECK(app.status().find("no bead laid") == 0);
  CHECK(app.cell().workpieces.front().params.passes == passes0);
  run_frames(app, 3);
  REQUIRE(app.last_track());
  REQUIRE(app.last_track()->status == vts::tracker::TrackStatus::Ok);
  app.lay_bead();
  INFO(app.status());
  const auto& w = app.cell().workpieces.front();
  REQUIRE(w.params.passes == passes0 + 1);
  REQUIRE(w.params.bead_offsets_mm.size() == static_cast<std::size_t>(passes0 + 1));
  for (int k = 0; k < passes0; ++k) CHECK(w.params.bead_offsets_mm[k] == 0.0);
  CHECK(w.params.bead_offsets_mm.back() != 0.0);  // where the sensor said, not the model's exact centre
  CHECK(std::abs(w.params.bead_offsets_mm.back()) < 0.5);
  CHECK(w.truth.depth_mm == Approx(depth0 - 4.0).margin(0.5));
  CHECK(app.status().find("where the sensor said") != std::string::npos);
}

TEST_CASE("viewer app: the torch moves and the sensor scans at its rate", "[viewer][gl]") {
  Fixture f;
  App app(AppOptions{}, f.renderer);
  const vts::Vec3 start = app.world_from_torch().translation();
  MotionInput forward;
  forward.translate = vts::Vec3(1, 0, 0);
  run_frames(app, 30, forward);  // one second at 25 mm/s
  const vts::Vec3 moved = app.world_from_torch().translation() - start;
  CHECK(moved.isApprox(vts::Vec3(25.0, 0, 0), 1e-9));
  CHECK(app.scans() >= 20);
  CHECK(app.scans() <= 21);
  CHECK(app.last_profile()->time_s == Approx((app.scans() - 1) / 20.0));
}

TEST_CASE("viewer app: sensor presets and the error model switch", "[viewer][gl]") {
  Fixture f;
  App app(AppOptions{}, f.renderer);
  for (const auto& name : vts::sensor_preset_names()) {
    INFO("preset " << name);
    app.set_sensor_preset(name);
    CHECK(app.cell().scanner.name == name);
    run_frames(app, 3);
    REQUIRE(app.last_profile());
    CHECK(app.last_profile()->size() == vts::sensor_preset(name)->points);
  }
  app.set_error_model(false);
  CHECK_FALSE(app.error_model());
  run_frames(app, 3);
  REQUIRE(app.last_profile());
  // Ideal: the measured profile is the geometric one.
  const vts::Profile& m = *app.last_profile();
  const vts::Profile& g = *app.last_ideal();
  REQUIRE(m.size() == g.size());
  for (int i = 0; i < m.size(); ++i) {
    CHECK(m.valid[i] == g.valid[i]);
    CHECK(m.z_mm[i] == g.z_mm[i]);
  }
}

TEST_CASE("viewer app: P records the scanned profiles to a vts EXR", "[viewer][gl]") {
  Fixture f;
  const auto dir = std::filesystem::temp_directory_path() / "vts_viewer_app_test";
  std::filesystem::remove_all(dir);
  AppOptions options;
  options.record = dir / "rec.exr";
  App app(options, f.renderer);
  app.press(Key::Record);
  CHECK(app.recording());
  run_frames(app, 30);
  const auto recorded = app.recorded_profiles();
  CHECK(recorded >= 20);
  app.press(Key::Record);
  CHECK_FALSE(app.recording());
  const vts::ProfileRecording rec = vts::read_profile_exr(dir / "rec.exr");
  CHECK(rec.profiles.size() == recorded);
  CHECK(rec.info.scene_name == "static-B");
  CHECK(rec.profiles.front().time_s == Approx(0.0));
  CHECK(rec.profiles.back().time_s == Approx((recorded - 1) / 20.0));
  // The mount the viewer chose travels with the file.
  CHECK(rec.info.scanner.tool_from_laser.translation().x() == Approx(kLookAheadMm));
  std::filesystem::remove_all(dir);
}

TEST_CASE("viewer app: I shows the camera image the profile was read from, labelled", "[viewer][gl]") {
  Fixture f;
  App app(AppOptions{}, f.renderer);
  app.load_builtin("vgroove");
  CHECK_FALSE(app.camera_image());
  run_frames(app, 2);
  CHECK(app.last_image() == nullptr);
  app.press(Key::CameraImage);
  REQUIRE(app.camera_image());
  CHECK(app.error_model());
  run_frames(app, 3);
  const vts::CameraImage* im = app.last_image();
  REQUIRE(im);
  CHECK(im->width == app.cell().scanner.image_width_px);
  // The image belongs to the profile shown: its chosen peaks were made into
  // the profile's points, and the labels say where the true stripe is.
  int labelled = 0, chose_true = 0;
  for (int c = 0; c < im->width; ++c) {
    if (im->true_peak[static_cast<std::size_t>(c)] < 0) continue;
    ++labelled;
    chose_true += im->chosen_peak[static_cast<std::size_t>(c)] == im->true_peak[static_cast<std::size_t>(c)];
  }
  CHECK(labelled > im->width / 2);
  CHECK(chose_true >= labelled * 9 / 10);
  CHECK(app.image_texture() != 0u);
  const std::uint64_t serial = app.image_serial();
  run_frames(app, 2);
  CHECK(app.image_serial() != serial);  // a new image with each scan
  app.press(Key::CameraImage);
  CHECK_FALSE(app.camera_image());
  run_frames(app, 2);
  CHECK(app.last_image() == nullptr);
}
