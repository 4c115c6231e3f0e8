// Raster emulator against the Embree reference and against analytic geometry.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include <Eigen/Eigenvalues>

#include "render/raster_source.h"
#include "sensor/cell.h"
#include "sensor/presets.h"
#include "sensor/reference_source.h"

using namespace vts;

namespace {

constexpr double kRangeTolMm = 0.001;
constexpr double kJumpMm = 1.0;  // a range step this large between neighbours is a depth discontinuity

// Pair (k, k+1) of the profile is a depth discontinuity: the hit state changes,
// or the range jumps.
std::vector<bool> discontinuities(const Profile& p) {
  std::vector<bool> d(p.size() > 0 ? p.size() - 1 : 0, false);
  for (int k = 0; k + 1 < p.size(); ++k)
    d[k] = p.valid[k] != p.valid[k + 1] ||
           (p.valid[k] && std::abs(p.range_mm[k] - p.range_mm[k + 1]) > kJumpMm);
  return d;
}

struct Agreement {
  int both_valid = 0;
  double max_diff_mm = 0.0;
  int disagreements = 0;     // hit/miss (or different surface) columns
  int unexplained = 0;       // disagreements not next to a free discontinuity
};

// Every disagreeing column must sit next to a depth discontinuity of the
// reference, and each discontinuity explains at most one column.
Agreement compare(const Profile& raster, const Profile& ref) {
  Agreement a;
  auto disc = discontinuities(ref);
  const auto disc_raster = discontinuities(raster);
  for (std::size_t k = 0; k < disc.size(); ++k) disc[k] = disc[k] || disc_raster[k];
  std::vector<bool> used(disc.size(), false);
  for (int i = 0; i < ref.size(); ++i) {
    bool agree = raster.valid[i] == ref.valid[i];
    if (agree && ref.valid[i]) {
      const double d = std::abs(double(raster.range_mm[i]) - ref.range_mm[i]);
      if (d <= kRangeTolMm) {
        ++a.both_valid;
        a.max_diff_mm = std::max(a.max_diff_mm, d);
      } else {
        agree = false;  // a different surface: allowed only at a discontinuity
      }
    }
    if (agree) continue;
    ++a.disagreements;
    bool explained = false;
    for (int k : {i - 1, i}) {
      if (k >= 0 && k < static_cast<int>(disc.size()) && disc[k] && !used[k]) {
        used[k] = explained = true;
        break;
      }
    }
    if (!explained) ++a.unexplained;
  }
  return a;
}

std::unique_ptr<ProfileSource> raster_for(const Cell& c, bool merge_planar) {
  return make_raster_source(c.scanner, c.mesh(), {.merge_planar = merge_planar});
}
std::unique_ptr<ProfileSource> reference_for(const Cell& c) { return make_reference_source(c.scanner, c.mesh()); }

// merge_planar: the raster source re-triangulates flat regions first
// (sensor/planar_merge.h; the default), or draws every triangle as given.
void check_poses(const Cell& cell, const std::vector<Pose>& poses, bool merge_planar,
                 int* total_columns = nullptr) {
  auto raster = raster_for(cell, merge_planar);
  auto reference = reference_for(cell);
  Profile a, b;
  double max_diff = 0.0;
  int disagreements = 0, valid = 0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    raster->scan(poses[k], a);
    reference->scan(poses[k], b);
    const Agreement g = compare(a, b);
    INFO(cell.name << (merge_planar ? "" : " (unmerged)") << " pose " << k << ": " << g.both_valid << " columns agree, max diff " << g.max_diff_mm
                   << " mm, " << g.disagreements << " disagreements");
    CHECK(g.max_diff_mm <= kRangeTolMm);
    CHECK(g.unexplained == 0);
    if (total_columns) *total_columns += g.both_valid;
    max_diff = std::max(max_diff, g.max_diff_mm);
    disagreements += g.disagreements;
    valid += g.both_valid;
  }
  WARN(cell.name << (merge_planar ? "" : " (unmerged)") << ": " << poses.size() << " poses, " << valid << " columns agree (max |diff| " << max_diff
                 << " mm), " << disagreements << " disagreeing columns, all next to a discontinuity");
}

}  // namespace

TEST_CASE("raster and reference agree on every built-in cell along its path", "[gl][crosscheck]") {
  for (const auto& name : builtin_cell_names(CellSet::Small)) {
    const Cell cell = *builtin_cell(name);
    std::vector<Pose> poses;
    for (int i = 0; i < 20; ++i) poses.push_back(cell.path.pose_at(i * 5));
    for (const bool merge : {true, false}) {
      int agreeing = 0;
      check_poses(cell, poses, merge, &agreeing);
      INFO(name);
      CHECK(agreeing > 20 * cell.scanner.points / 2);  // the cells are mostly in view
    }
  }
}

// A million triangles: the large-mesh paths of the raster source (blocks of
// parallel laser planes culled together, collinear slice runs joined: with
// the planar merge off, as on a mesh with no flat regions) against Embree on
// the same mesh; and with the merge on (24 triangles left).
TEST_CASE("raster and reference agree on the 1M-triangle fillet-1m", "[gl][crosscheck]") {
  const Cell cell = *builtin_cell("fillet-1m");
  REQUIRE(cell.mesh().triangle_count() > 1'000'000);
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Pose> poses;
  for (int i = 0; i < 12; ++i) poses.push_back(cell.path.pose_at(i * 37));
  const Workpiece& w = cell.workpieces.front();
  for (int k = 0; k < 12; ++k) {
    const Vec3 target = w.world_from_joint * Vec3(300.0 + 250.0 * u(rng), 10.0 * u(rng), 10.0 * u(rng));
    const Vec3 view = (default_view_direction(w) + 0.4 * Vec3(u(rng), u(rng), u(rng))).normalized();
    poses.push_back(sensor_pose_looking_at(target, view, 150.0 + 100.0 * u(rng), w.seam_direction()));
  }
  for (const bool merge : {true, false}) {
    int agreeing = 0;
    check_poses(cell, poses, merge, &agreeing);
    CHECK(agreeing > 24 * cell.scanner.points / 2);
  }
  // The same poses as one batch (several workers, several passes' worth of
  // culling blocks) give the same profiles as one scan each.
  auto raster = make_raster_source(cell.scanner, cell.mesh(),
                                   {.threads = 2, .rows_per_pass = 5, .merge_planar = false});
  std::vector<Profile> batch(poses.size());
  raster->scan_batch(poses, batch);
  Profile one;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    raster->scan(poses[k], one);
    INFO("pose " << k);
    CHECK(one.valid == batch[k].valid);
    CHECK(one.range_mm == batch[k].range_mm);
    CHECK(one.camera_visible == batch[k].camera_visible);
  }
}

// fillet-1m's mesh turned and moved off the axes: its plates' corners,
// rounded to float again, no longer lie exactly in one plane, so the slice of
// a plate is a very slightly wavy line (each triangle cut exactly), and
// joining its collinear runs must not lose a piece of it (a lost piece let
// the plate behind show through: ranges off by up to 0.6 mm in a few columns).
TEST_CASE("raster and reference agree on fillet-1m turned off the axes with the merge off", "[gl][crosscheck]") {
  Cell cell = *builtin_cell("fillet-1m");
  const Pose turn(Eigen::Translation3d(13.7, -21.3, 5.1) *
                  Eigen::AngleAxisd(0.31, Vec3(0.2, 0.9, 0.4).normalized()));
  cell.workpieces = {mesh_workpiece(std::make_shared<const Mesh>(cell.mesh()), turn)};
  cell.path.start = turn * cell.path.start;
  cell.path.direction = turn.linear() * cell.path.direction;
  std::mt19937 rng(11);
  std::normal_distribution<double> jitter(0.0, 1.0);
  auto draw = [&] {
    const double x = jitter(rng), y = jitter(rng);
    return Vec3(x, y, jitter(rng));
  };
  // Path poses, then poses moved and turned at random about them (the join
  // that lost pieces did so at one of these 1,000).
  std::vector<Pose> poses;
  for (int i = 0; i < 20; ++i) poses.push_back(cell.path.pose_at(i * 10));
  for (int i = 0; i < 1000; ++i) {
    Pose p = cell.path.pose_at(i * 2 % 400);
    p.translation() += 3.0 * draw();
    const double angle = 0.1 * jitter(rng);
    p.linear() = p.linear() * Eigen::AngleAxisd(angle, draw().normalized()).toRotationMatrix();
    poses.push_back(p);
  }
  int agreeing = 0;
  check_poses(cell, poses, false, &agreeing);
  CHECK(agreeing > static_cast<int>(poses.size()) * cell.scanner.points / 2);
}

TEST_CASE("raster and reference agree at 240 seeded random sensor poses", "[gl][crosscheck]") {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int poses_checked = 0;
  for (const char* name : {"fillet", "corner", "lap", "butt", "vgroove", "plate"}) {
    Cell cell = *builtin_cell(name);
    const Workpiece& w = cell.workpieces.front();
    std::vector<Pose> poses;
    for (int k = 0; k < 40; ++k) {
      // Look at a point near the seam from a tilted direction, 40..450 mm away.
      const Vec3 target = w.world_from_joint * Vec3(100.0 + 60.0 * u(rng), 15.0 * u(rng), 5.0 * u(rng));
      const Vec3 view = (default_view_direction(w) + 0.45 * Vec3(u(rng), u(rng), u(rng))).normalized();
      const double standoff = 245.0 + 205.0 * u(rng);
      Pose p = sensor_pose_looking_at(target, view, standoff, w.seam_direction());
      // Roll about the optical axis up to 20 degrees.
      p.linear() = p.linear() * Eigen::AngleAxisd(0.35 * u(rng), Vec3::UnitZ()).toRotationMatrix();
      poses.push_back(p);
    }
    for (const bool merge : {true, false}) check_poses(cell, poses, merge);
    poses_checked += static_cast<int>(poses.size());
  }
  CHECK(poses_checked >= 200);
}

TEST_CASE("cross-check holds at N = 16 and 256 and 4096", "[gl][crosscheck]") {
  for (int n : {16, 256, 4096}) {
    Cell cell = *builtin_cell("vgroove");
    cell.scanner.points = n;
    check_poses(cell, {cell.path.pose_at(0), cell.path.pose_at(50)}, true);
  }
}

namespace {

// Total least-squares line through 2D points: returns (point, unit direction).
std::pair<Vec2, Vec2> fit_line(const std::vector<Vec2>& pts) {
  Vec2 mean = Vec2::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  return {mean, es.eigenvectors().col(1)};
}

Vec2 intersect(const std::pair<Vec2, Vec2>& l1, const std::pair<Vec2, Vec2>& l2) {
  Eigen::Matrix2d m;
  m.col(0) = l1.second;
  m.col(1) = -l2.second;
  const Vec2 s = m.colPivHouseholderQr().solve(l2.first - l1.first);
  return l1.first + s(0) * l1.second;
}

}  // namespace

TEST_CASE("static setups A-F: points on the analytic plates and fitted lines meeting at the root",
          "[gl][crosscheck][static]") {
  for (const auto& s : kStaticSetups) {
    const Cell cell = *builtin_cell(std::string("static-") + s.label);
    const Workpiece& w = cell.workpieces.front();
    const auto planes = w.face_planes();
    // The flange's top face (z = 0) and the web's open-side face (through the root, normal +y).
    const Vec3 flange_n = Vec3::UnitZ(), web_n = Vec3::UnitY();
    std::unique_ptr<ProfileSource> sources[] = {raster_for(cell, true), reference_for(cell)};
    for (auto& source : sources) {
      Profile p;
      const Pose pose = cell.path.pose_at(0);
      source->scan(pose, p);
      std::vector<Vec2> flange, web;
      for (int i = 0; i < p.size(); ++i) {
        if (!p.valid[i]) continue;
        const Vec3 world = pose * Vec3(0.0, p.y_mm[i], p.z_mm[i]);
        double nearest = 1e9;
        for (const auto& [n, d] : planes) nearest = std::min(nearest, std::abs(n.dot(world) - d));
        INFO("static-" << s.label << " " << source->kind() << " column " << i);
        CHECK(nearest <= 0.001);
        const Vec2 yz(p.y_mm[i], p.z_mm[i]);
        if (std::abs(world.dot(flange_n)) <= 0.001) flange.push_back(yz);
        else if (std::abs(world.dot(web_n)) <= 0.001) web.push_back(yz);
      }
      REQUIRE(flange.size() > 50);
      REQUIRE(web.size() > 50);
      const Vec2 root_sensor = intersect(fit_line(flange), fit_line(web));
      // The analytic root in the laser plane: on the seam at the laser's x.
      const Vec3 root_world(pose.translation().x(), 0.0, 0.0);
      const Vec3 measured = pose * Vec3(0.0, root_sensor.x(), root_sensor.y());
      INFO("static-" << s.label << " " << source->kind() << " root error " << (measured - root_world).norm());
      CHECK((measured - root_world).norm() <= 0.01);
      // And it lies on the optical axis at the Table 2 distance.
      CHECK(root_sensor.x() == Approx(0.0).margin(0.01));
      CHECK(root_sensor.y() == Approx(s.distance_mm).margin(0.01));
    }
  }
}

// The groove cells (thick plates, arcs as polylines, beads) seen by the two
// profile sensors and the default one at 90-400 mm from the root: raster and
// reference agree column by column.
TEST_CASE("raster and reference agree on the groove cells at 90-400 mm", "[gl][crosscheck][groove]") {
  struct View {
    const char* preset;
    double standoff_mm;
  };
  const View views[] = {{"lps-2048-short", 90.0}, {"lps-1280-mid", 100.0}, {"lps-1280-mid", 150.0},
                        {"lps-1280-mid", 300.0}, {"mspot", 400.0}};
  for (const char* name : {"vgroove-thick", "bevel", "bevel-thick", "ugroove", "ugroove-fill", "jgroove"}) {
    for (const View& v : views) {
      Cell cell = *builtin_cell(name);
      cell.scanner = *sensor_preset(v.preset);
      cell.path = default_path(cell.workpieces.front(), v.standoff_mm);
      cell.name = std::string(name) + " / " + v.preset + " at " + std::to_string(static_cast<int>(v.standoff_mm));
      std::vector<Pose> poses;
      for (int i = 0; i < 5; ++i) poses.push_back(cell.path.pose_at(i * 20));
      check_poses(cell, poses, true);
    }
  }
}
