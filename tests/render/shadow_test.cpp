// Camera shadow: the raster's shadow pass and the reference's shadow rays
// against geometry worked out here, and against each other.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "render/raster_source.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/presets.h"
#include "sensor/reference_source.h"

using namespace vts;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Does the segment a -> b (world) pass through the plate, a convex polygon in
// the joint's y-z plane extruded along x, grown outward by `grow_mm` (negative:
// shrunk)? Cyrus-Beck clipping against the plate's half-spaces.
bool segment_hits_plate(const Workpiece& w, const Plate& plate, const Vec3& a_world,
                        const Vec3& b_world, double grow_mm) {
  const Pose joint_from_world = w.world_from_joint.inverse();
  const Vec3 a = joint_from_world * a_world, b = joint_from_world * b_world;
  double s0 = 0.0, s1 = 1.0;
  // Half-space n . p <= d + grow, n unit.
  auto clip = [&](const Vec3& n, double d) {
    const double fa = n.dot(a) - d - grow_mm, fb = n.dot(b) - d - grow_mm;
    if (fa > 0.0 && fb > 0.0) return false;
    if (fa <= 0.0 && fb <= 0.0) return true;
    const double s = fa / (fa - fb);
    if (fa > 0.0) s0 = std::max(s0, s);
    else s1 = std::min(s1, s);
    return s0 < s1;
  };
  if (!clip(Vec3(-1, 0, 0), -plate.x0_mm) || !clip(Vec3(1, 0, 0), plate.x1_mm)) return false;
  const auto& poly = plate.section_yz;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec2 p = poly[k], q = poly[(k + 1) % poly.size()];
    // Counter-clockwise polygon: the outward normal of edge p -> q is (dz, -dy).
    const Vec2 e = (q - p).normalized();
    const Vec3 n(0.0, e.y(), -e.x());
    if (!clip(n, n.y() * p.x() + n.z() * p.y())) return false;
  }
  return s0 < s1;
}

enum class Expect { Visible, Shadowed, Unsure };

// What the camera should see of the lit point of every valid column, from the
// plates themselves: shadowed if the sight line (from 0.2 mm off the point to
// the camera centre) crosses a plate shrunk by 0.02 mm, visible if it misses
// every plate grown by 0.02 mm, else too close to an edge to call.
std::vector<Expect> expected_shadow(const ScannerDesc& desc, const Workpiece& w, const Pose& pose,
                                    const Profile& p) {
  const Vec3 camera = pose * camera_model(desc).centre_mm;
  std::vector<Expect> out(p.size(), Expect::Unsure);
  for (int i = 0; i < p.size(); ++i) {
    if (!p.valid[i]) continue;
    const Vec3 point = pose * Vec3(0.0, p.y_mm[i], p.z_mm[i]);
    const Vec3 start = point + 0.2 * (camera - point).normalized();
    bool sure_hit = false, may_hit = false;
    for (const Plate& plate : w.plates) {
      sure_hit = sure_hit || segment_hits_plate(w, plate, start, camera, -0.02);
      may_hit = may_hit || segment_hits_plate(w, plate, start, camera, 0.02);
    }
    out[i] = sure_hit ? Expect::Shadowed : may_hit ? Expect::Unsure : Expect::Visible;
  }
  return out;
}

// Sensor looking straight down (-z of the joint) at height h over joint point
// (x, y), its travel axis (camera side) at yaw_deg from the joint's -y.
Pose looking_down(const Workpiece& w, double x, double y, double h, double yaw_deg) {
  const double a = yaw_deg * kDeg;
  Pose joint_from_sensor = Pose::Identity();
  joint_from_sensor.linear().col(0) = Vec3(std::sin(a), -std::cos(a), 0.0);
  joint_from_sensor.linear().col(2) = Vec3(0.0, 0.0, -1.0);
  joint_from_sensor.linear().col(1) =
      joint_from_sensor.linear().col(2).cross(joint_from_sensor.linear().col(0));
  joint_from_sensor.translation() = Vec3(x, y, h);
  return w.world_from_joint * joint_from_sensor;
}

// Every valid column's visibility against the plates; returns how many
// columns are surely shadowed.
int check_against_geometry(ProfileSource& source, const Workpiece& w, const Pose& pose) {
  Profile p;
  source.scan(pose, p);
  const auto expect = expected_shadow(source.scanner(), w, pose, p);
  int shadowed = 0, visible = 0;
  for (int i = 0; i < p.size(); ++i) {
    if (expect[i] == Expect::Unsure) continue;
    INFO(source.kind() << " column " << i << " of " << p.size());
    CHECK(p.camera_visible[i] == (expect[i] == Expect::Visible ? 1 : 0));
    (expect[i] == Expect::Shadowed ? shadowed : visible)++;
  }
  CHECK(visible > 0);
  return shadowed;
}

}  // namespace

TEST_CASE("camera shadow: lap seen along the seam, camera over the upper plate", "[gl][shadow]") {
  // The laser line runs along the seam over the lower plate, y_l from the
  // step; the camera sits b across the seam over the upper plate, at height
  // h - c_z. A sight line from a lit point to the camera crosses the step's
  // plane y = 0 at height y_l (h - c_z) / b, so the whole line is hidden iff
  // that is below the step top g + t: y_l < (g + t) b / (h - c_z).
  const Workpiece w = build_workpiece(JointType::Lap, default_params(JointType::Lap));
  const double step = w.params.gap_mm + w.params.thickness_mm;
  for (const char* preset : {"mspot", "lps-1280-mid"}) {
    const ScannerDesc desc = *sensor_preset(preset);
    const CameraModel cam = camera_model(desc);
    const double h = desc.name == "mspot" ? 100.0 : 180.0;
    const double threshold = step * desc.baseline_mm / (h - cam.centre_mm.z());
    auto raster = make_raster_source(desc, w.mesh());
    auto reference = make_reference_source(desc, w.mesh());
    for (const double factor : {0.5, 0.9, 1.1, 2.0}) {
      const Pose pose = looking_down(w, 100.0, factor * threshold, h, 0.0);
      for (ProfileSource* source : {raster.get(), reference.get()}) {
        Profile p;
        source->scan(pose, p);
        int lit = 0, seen = 0;
        for (int i = 0; i < p.size(); ++i) {
          if (!p.valid[i]) continue;
          ++lit;
          seen += p.camera_visible[i];
        }
        INFO(preset << " " << source->kind() << ": laser " << factor << " x the threshold "
                    << threshold << " mm from the step");
        REQUIRE(lit > p.size() / 4);
        CHECK(seen == (factor < 1.0 ? 0 : lit));
      }
    }
  }
}

TEST_CASE("camera shadow: lap seen across the step, camera on the far side", "[gl][shadow]") {
  // The laser line crosses the step at 45 degrees; the camera is on the upper
  // plate's side, so lit points of the lower plate near the step's foot are
  // hidden behind the step. Expected per column from the plates' geometry.
  const Workpiece w = build_workpiece(JointType::Lap, default_params(JointType::Lap));
  for (const char* preset : {"mspot", "lps-1280-mid"}) {
    const ScannerDesc desc = *sensor_preset(preset);
    const double h = desc.name == "mspot" ? 100.0 : 180.0;
    auto raster = make_raster_source(desc, w.mesh());
    auto reference = make_reference_source(desc, w.mesh());
    for (const double yaw : {-45.0, 30.0, 45.0, 60.0}) {
      const Pose pose = looking_down(w, 100.0, 0.0, h, yaw);
      INFO(preset << ", yaw " << yaw);
      const int raster_shadowed = check_against_geometry(*raster, w, pose);
      const int reference_shadowed = check_against_geometry(*reference, w, pose);
      // mspot's 24 mm baseline casts a narrower shadow than lps-1280-mid's 60 mm.
      const int at_least = desc.name == "mspot" ? 3 : 10;
      CHECK(raster_shadowed >= at_least);
      CHECK(reference_shadowed >= at_least);
    }
    // Camera on the lower plate's side: nothing hides the lit points.
    const Pose pose = looking_down(w, 100.0, 0.0, h, 180.0);
    CHECK(check_against_geometry(*raster, w, pose) == 0);
    CHECK(check_against_geometry(*reference, w, pose) == 0);
  }
}

namespace {

struct ShadowAgreement {
  int both_lit = 0, shadowed = 0, disagreements = 0, unexplained = 0;
};

// Columns lit in both profiles at the same point must agree on visibility,
// except next to a shadow edge: a disagreeing column must have a neighbour
// whose visibility or validity differs from its own in one of the profiles.
ShadowAgreement compare_shadows(const Profile& a, const Profile& b) {
  ShadowAgreement g;
  const int n = a.size();
  auto state = [](const Profile& p, int i) { return p.valid[i] ? 1 + p.camera_visible[i] : 0; };
  for (int i = 0; i < n; ++i) {
    if (!a.valid[i] || !b.valid[i] || std::abs(a.range_mm[i] - b.range_mm[i]) > 0.001f) continue;
    ++g.both_lit;
    g.shadowed += b.camera_visible[i] ? 0 : 1;
    if (a.camera_visible[i] == b.camera_visible[i]) continue;
    ++g.disagreements;
    bool edge = false;
    for (int k : {i - 1, i + 1})
      if (k >= 0 && k < n)
        edge = edge || state(a, k) != state(a, i) || state(b, k) != state(b, i);
    if (!edge) ++g.unexplained;
  }
  return g;
}

}  // namespace

TEST_CASE("camera shadow: raster and reference agree on lap and v-groove at many poses",
          "[gl][shadow][crosscheck]") {
  std::mt19937_64 rng(977);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int poses = 0, shadowed = 0, both_lit = 0, disagreements = 0;
  for (const char* preset : {"mspot", "lps-1280-mid"}) {
    for (const char* joint : {"lap", "vgroove"}) {
      const Cell cell = *builtin_cell(joint);
      const Workpiece& w = cell.workpieces.front();
      const ScannerDesc desc = *sensor_preset(preset);
      const double near = desc.min_range_mm, far = std::min(desc.max_range_mm, 300.0);
      // With the planar merge (the default) and without (every triangle as
      // given, as on a mesh with no flat regions).
      auto merged = make_raster_source(desc, cell.mesh());
      auto unmerged = make_raster_source(desc, cell.mesh(), {.merge_planar = false});
      auto reference = make_reference_source(desc, cell.mesh());
      Profile a, b;
      for (int k = 0; k < 60; ++k) {
        // Look at a point near the seam, tilted up to ~25 degrees, yawed anywhere
        // so the camera lands on either side of the seam.
        const Vec3 target = w.world_from_joint * Vec3(100.0 + 50.0 * u(rng), 6.0 * u(rng), 0.0);
        const Vec3 view = (default_view_direction(w) + 0.45 * Vec3(u(rng), u(rng), 0.0)).normalized();
        const double standoff = near + (far - near) * (0.15 + 0.35 * (1.0 + u(rng)));
        Pose pose = sensor_pose_looking_at(target, view, standoff, w.seam_direction());
        pose.linear() = pose.linear() * Eigen::AngleAxisd(std::numbers::pi * u(rng),
                                                          Vec3::UnitZ()).toRotationMatrix();
        reference->scan(pose, b);
        for (auto* raster : {merged.get(), unmerged.get()}) {
          raster->scan(pose, a);
          const ShadowAgreement g = compare_shadows(a, b);
          INFO(preset << " " << joint << (raster == merged.get() ? "" : " (unmerged)") << " pose " << k
                      << ": " << g.both_lit << " lit, " << g.shadowed << " shadowed, " << g.disagreements
                      << " disagreements");
          CHECK(g.unexplained == 0);
          ++poses;
          shadowed += g.shadowed;
          both_lit += g.both_lit;
          disagreements += g.disagreements;
        }
      }
    }
  }
  WARN(poses << " poses: " << both_lit << " columns lit in both, " << shadowed
             << " in camera shadow, " << disagreements << " disagreements (all at shadow edges)");
  CHECK(shadowed > 1000);  // the poses do show shadows
  CHECK(disagreements * 100 <= shadowed);
}
