// The tracker on measured profiles: the built-in joints scanned with the Embree
// reference, passed through the sensor error model (sensor/error_model.h, the
// default mspot sensor on matte steel, fixed seeds), at standoffs 50..250 mm
// and the sensor tilted -20..+20 degrees about the seam, against each
// workpiece's analytic JointTruth (issue 4, point 4: "with the error model the
// same tests hold with tolerances derived from the sensor's resolution").
//
// Tolerances. At range z the sensor's resolution is
//   sigma(z) = sqrt(depth_noise(z)^2 + depth_step(z)^2 / 12),
// the standard deviation of one point along its ray: speckle noise plus the
// sub-pixel quantization (a uniform error of one step has variance step^2/12);
// and the ray spacing across the ray is lateral_spacing(z). The ideal test's
// tolerances (tests/sensor/tracker_accuracy_test.cpp) grow by:
// - a value from fitted lines that meet (a root, an angle): 3 sigma for a
//   position (one point's 3-sigma error bounds an intersection fitted through
//   many), and 6 sigma / L rad for an angle, L the shorter plate's seen length
//   (a line's slope error is at most its end points' error over its length;
//   for a lap, whose angle is measured on the upper plate's edge face, L is
//   the plate's thickness, for a v-groove, whose angle is the bevels', the
//   shorter bevel face);
// - a value where a plate edge decides: the ideal tolerance is one ray spacing
//   along the surface; noise and a dropout next to the edge can move the last
//   point seen by one more spacing, so two spacings + 3 sigma.
// The tracker is told the sensor's resolution the way a user would set it:
// surface_tol_mm = max(0.02, 3 sigma) at the standoff (docs/JOINTS.md).
//
// Seeds. Each cell is scanned with the error model's seeds kSeeds (1, 2, 3).
// To look for failures over more seeds, set VTS_NOISY_SEEDS to a list of seeds
// and ranges, e.g. VTS_NOISY_SEEDS=1-40 or VTS_NOISY_SEEDS=4,24 or "1-3,13";
// the cells then use those seeds instead (an empty or malformed value fails).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "joint_views.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/reference_source.h"
#include "sensor/workpiece.h"
#include "tracker/tracker.h"

using namespace vts;
namespace tk = vts::tracker;

namespace {

using namespace vts::test;

double sigma_mm(const ScannerDesc& d, double z) {
  const double noise = depth_noise_mm(d, z), step = depth_step_mm(d, z);
  return std::sqrt(noise * noise + step * step / 12.0);
}

struct Scan : JointView {
  Profile ideal, measured;
};

Scan scan(const Workpiece& w, double standoff_mm, double tilt_deg, std::uint64_t seed, std::int64_t index) {
  Scan s;
  s.w = &w;
  s.desc.min_range_mm = 20.0;  // see the whole cross-section at 50 mm
  s.pose = root_view(w, standoff_mm, tilt_deg);
  auto source = make_reference_source(s.desc, w.mesh());
  source->scan(s.pose, s.ideal);
  s.ideal.index = index;
  ScanState state;
  state.seed = seed;
  apply_error_model(s.desc, s.ideal, state, s.measured);
  return s;
}

struct Tol {
  double track, gap, angle, other;
  bool angle_always = true;
};

Tol tolerances(const Scan& s, double standoff) {
  const Workpiece& w = *s.w;
  const JointParams& p = w.params;
  const double sig = sigma_mm(s.desc, standoff);
  // The shorter plate's seen length: half the field of view at the standoff.
  const double seen = standoff * std::tan(0.5 * s.desc.fan_deg * kDeg);
  Tol t{kTrackTolMm + 3 * sig, kGapTolMm + 3 * sig, kAngleTolDeg + 6 * sig / seen / kDeg, kGapTolMm + 3 * sig};
  auto edge = [&](double ds) { return 2 * ds + 3 * sig; };
  const auto [d1, d2] = edge_spacings(s);
  switch (w.type) {
    case JointType::Fillet:
      if (p.gap_mm > 0.0) t.gap = std::max(t.gap, edge(d1));
      break;
    case JointType::Corner:
    case JointType::Butt:
      if (w.type == JointType::Butt || p.gap_mm > 0.0) {
        t.track = std::max(t.track, 0.5 * (edge(d1) + edge(d2)));
        t.gap = std::max(t.gap, edge(d1) + edge(d2));
      }
      break;
    case JointType::Lap:
      t.track = std::max(t.track, edge(d1));
      if (p.gap_mm > 0.0) t.gap = std::max(t.gap, std::min(edge(d2), 10.0));
      t.angle_always = false;
      // The angle is the lower plate's against the upper plate's edge face,
      // and the face is at most the upper plate's thickness long: the rule
      // above (6 sigma / L) with L = thickness_mm.
      t.angle = std::max(t.angle, kAngleTolDeg + 6 * sig / p.thickness_mm / kDeg);
      break;
    case JointType::VGroove: {
      const Vec2 lr = feature(w, "left_root"), rr = feature(w, "right_root");
      // The angle is the one between the bevels, each at most its face long
      // (root to top): the rule above (6 sigma / L) with L the shorter bevel.
      const double bevel = std::min((feature(w, "left_top") - lr).norm(), (feature(w, "right_top") - rr).norm());
      t.angle = std::max(t.angle, kAngleTolDeg + 6 * sig / bevel / kDeg);
      if (p.gap_mm > 0.0 || p.mismatch_mm != 0.0) {
        t.track = std::max(t.track, std::max(edge(d1), edge(d2)));
        t.gap = std::max(t.gap, edge(d1) + edge(d2));
        t.other = std::max(t.other, std::max(edge(d1), edge(d2)));
      }
      break;
    }
    default: break;
  }
  return t;
}

// The tracker may say it is not sure of a few scans at the noise limit (a
// 1 mm gap at 250 mm with 0.15 mm noise shows one or two rays into it; a
// lap's top edge followed by a camera shadow at 250 mm, tilted: "uncertain"),
// at most 2 % of them (see check_scan); any reading it gives must be right.
void check_unsure(const Worst& worst) { CHECK(worst.unsure <= std::max(1, worst.scans / 50)); }

void check_scan(const Scan& s, double standoff, double tilt, std::uint64_t seed, Worst& worst) {
  const Workpiece& w = *s.w;
  tk::TrackerParams tp = params_for(w);
  tp.surface_tol_mm = std::max(0.02, 3.0 * sigma_mm(s.desc, standoff));
  tk::Tracker tracker(tp);
  const tk::TrackResult& r = tracker.track(view_of(s.measured));
  const Tol tol = tolerances(s, standoff);
  INFO(to_string(w.type) << " gap " << w.params.gap_mm << " at " << standoff << " mm, tilt " << tilt << " deg, seed "
                         << seed << ": " << to_string(r.status) << " " << r.reason << ", " << r.segments.size()
                         << " segments, " << r.valid_points << " valid points, " << r.outliers << " outliers");
  // CHECK and return rather than REQUIRE: a failed scan must not end the
  // test case and hide the scans after it (a VTS_NOISY_SEEDS sweep counts
  // them all).
  ++worst.scans;
  if (r.status == tk::TrackStatus::Rejected && (r.reason.rfind("weak", 0) == 0 || r.reason.rfind("ambiguous", 0) == 0 ||
                                                 r.reason.rfind("uncertain", 0) == 0)) {
    // A butt without mismatch shows its gap only by the rays that fall into
    // it; fewer than five is what one reflection cluster or dropout run
    // shows too, so "not sure" is a fair answer there (not counted). With
    // more, a dropout run of the error model elsewhere is still a rival as
    // gap-like as the joint itself (at 100 mm, runs 4-42 mm away weigh
    // 0.72-0.85 against the 1 mm gap at the calibrated confidence,
    // docs/JOINTS.md "Calibration"): "ambiguous" is fair there too.
    const double spacing = standoff * 2.0 * std::tan(0.5 * s.desc.fan_deg * kDeg) / s.desc.points;
    const bool gap_only = w.type == JointType::Butt && w.params.mismatch_mm == 0.0;
    // Where the rays themselves place the track point no better than the
    // false-read distance (tolerances(): two ray spacings along a bevel
    // seen at a grazing angle and 3 sigma, more than
    // ConfidenceParams::track_interval_mm), a reading whose fits locate it
    // to no better than that is fairly "uncertain" too (docs/JOINTS.md
    // "Localization"; the built-in v-groove, and the one with gap and
    // mismatch, at 200-250 mm and 20 degrees of tilt: 0.06-0.92 mm off,
    // stated 0.64-1.0 mm rms).
    const bool located = r.reason.rfind("uncertain: confidence", 0) == 0;
    const bool coarse = tol.track > tp.confidence.track_interval_mm;
    if (!(gap_only && (w.params.gap_mm < 5.0 * spacing || r.reason.rfind("ambiguous", 0) == 0)) && !(located && coarse))
      ++worst.unsure;
    return;
  }
  CHECK(r.status == tk::TrackStatus::Ok);
  if (r.status != tk::TrackStatus::Ok) return;
  const Vec2 root = s.to_sensor(w.truth.root_yz);
  const double track_err = (*r.track_point - root).norm();
  const double gap_err = std::abs(r.gap_mm - w.truth.gap_mm);
  INFO("track " << r.track_point->transpose() << " vs " << root.transpose() << " (err " << track_err << ", tol "
                << tol.track << "); gap " << r.gap_mm << " vs " << w.truth.gap_mm << " (tol " << tol.gap
                << "); angle " << r.angle_deg << " vs " << w.truth.angle_deg << " (tol " << tol.angle << ")");
  const std::string key = std::string(to_string(w.type));
  CHECK(track_err <= tol.track);
  worst.add(key + " track", track_err / tol.track);
  CHECK(gap_err <= tol.gap);
  worst.add(key + " gap", gap_err / tol.gap);
  if (tol.angle_always) CHECK(std::isfinite(r.angle_deg));
  if (std::isfinite(r.angle_deg)) {
    CHECK(std::abs(r.angle_deg - w.truth.angle_deg) <= tol.angle);
    worst.add(key + " angle", std::abs(r.angle_deg - w.truth.angle_deg) / tol.angle);
  }
  if (w.type == JointType::Butt || w.type == JointType::VGroove) {
    CHECK(std::abs(r.mismatch_mm - w.truth.mismatch_mm) <= tol.other);
    worst.add(key + " mismatch", std::abs(r.mismatch_mm - w.truth.mismatch_mm) / tol.other);
  }
  if (w.type == JointType::Lap) {
    CHECK(std::abs(r.step_mm - w.truth.step_mm) <= tol.other);
    worst.add(key + " step", std::abs(r.step_mm - w.truth.step_mm) / tol.other);
  }
  if (w.type == JointType::VGroove && std::isfinite(r.depth_mm)) {
    CHECK(std::abs(r.depth_mm - w.truth.depth_mm) <= tol.other);
    worst.add(key + " depth", std::abs(r.depth_mm - w.truth.depth_mm) / tol.other);
  }
}

constexpr double kStandoffs[] = {50.0, 100.0, 150.0, 200.0, 250.0};
constexpr double kTilts[] = {-20.0, 0.0, 20.0};
constexpr std::uint64_t kSeeds[] = {1, 2, 3};

// kSeeds, or the seeds VTS_NOISY_SEEDS lists ("1-40", "4,24", "1-3,13").
std::vector<std::uint64_t> parse_seeds(const std::string& text) {
  std::vector<std::uint64_t> seeds;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto dash = item.find('-');
    std::size_t used = 0;
    try {
      const std::uint64_t first = std::stoull(item.substr(0, dash), &used);
      if (used != item.substr(0, dash).size()) throw std::invalid_argument(item);
      std::uint64_t last = first;
      if (dash != std::string::npos) {
        const std::string rest = item.substr(dash + 1);
        last = std::stoull(rest, &used);
        if (used != rest.size()) throw std::invalid_argument(item);
      }
      for (std::uint64_t v = first; v <= last; ++v) seeds.push_back(v);
    } catch (const std::exception&) {
      FAIL("VTS_NOISY_SEEDS: cannot read '" << item << "' in '" << text << "' (e.g. 1-40 or 4,24)");
    }
  }
  if (seeds.empty()) FAIL("VTS_NOISY_SEEDS: no seeds in '" << text << "'");
  return seeds;
}

const std::vector<std::uint64_t>& seeds() {
  static const std::vector<std::uint64_t> list = [] {
    const char* env = std::getenv("VTS_NOISY_SEEDS");
    if (env == nullptr) return std::vector<std::uint64_t>(std::begin(kSeeds), std::end(kSeeds));
    return parse_seeds(env);
  }();
  return list;
}

}  // namespace

// Every standoff, tilt and seed on workpiece w; index_factor spreads the
// profiles' indices (and so their draws) per seed.
static void sweep(const Workpiece& w, std::int64_t index_factor, const std::string& label) {
  Worst worst;
  for (double standoff : kStandoffs)
    for (double tilt : kTilts)
      for (std::uint64_t seed : seeds()) {
        const Scan s = scan(w, standoff, tilt, seed, static_cast<std::int64_t>(seed) * index_factor);
        check_scan(s, standoff, tilt, seed, worst);
      }
  WARN(label << " worst error / tolerance: " << worst.str());
  check_unsure(worst);
}

static void check_builtin(const char* name) {
  const Cell cell = *builtin_cell(name);
  sweep(cell.workpieces.front(), 17, name);
}

static void check_variant(JointType type, double gap, double mismatch) {
  JointParams p = default_params(type);
  p.gap_mm = gap;
  p.mismatch_mm = mismatch;
  std::ostringstream label;
  label << to_string(type) << " gap " << gap;
  sweep(build_workpiece(type, p), 31, label.str());
}

TEST_CASE("tracker with the error model: built-in joints at standoffs 50-250 mm and tilts -20..+20 deg",
          "[tracker][accuracy][noisy]") {
  check_builtin("fillet");
}

TEST_CASE("tracker with the error model: built-in corner", "[tracker][accuracy][noisy]") { check_builtin("corner"); }

TEST_CASE("tracker with the error model: built-in lap", "[tracker][accuracy][noisy]") {
  check_builtin("lap");
}
TEST_CASE("tracker with the error model: built-in butt", "[tracker][accuracy][noisy]") {
  check_builtin("butt");
}
// The v-groove at 250 mm sees bevels only ~11 mm long (their angle tolerance
// follows from that length, as the header says); a far bevel thinned by
// dropouts to 3 points is still read (VGrooveParams::min_short_bevel_points).
TEST_CASE("tracker with the error model: built-in v-groove", "[tracker][accuracy][noisy]") {
  check_builtin("vgroove");
}
TEST_CASE("tracker with the error model: fillet with a 2 mm gap", "[tracker][accuracy][noisy]") {
  check_variant(JointType::Fillet, 2.0, 0.0);
}
TEST_CASE("tracker with the error model: corner with a 1 mm gap", "[tracker][accuracy][noisy]") {
  check_variant(JointType::Corner, 1.0, 0.0);
}
TEST_CASE("tracker with the error model: lap with a 1 mm gap", "[tracker][accuracy][noisy]") {
  check_variant(JointType::Lap, 1.0, 0.0);
}
TEST_CASE("tracker with the error model: butt with gap and mismatch", "[tracker][accuracy][noisy]") {
  check_variant(JointType::Butt, 1.5, 1.0);
}
TEST_CASE("tracker with the error model: v-groove with gap and mismatch", "[tracker][accuracy][noisy]") {
  check_variant(JointType::VGroove, 1.5, 0.5);
}

TEST_CASE("tracker with the error model: the paper's static setups A-F", "[tracker][accuracy][noisy][static]") {
  Worst worst;
  for (const auto& setup : kStaticSetups) {
    const Cell cell = *builtin_cell(std::string("static-") + setup.label);
    const Workpiece& w = cell.workpieces.front();
    for (double tilt : kTilts)
      for (std::uint64_t seed : seeds()) {
        const Scan s = scan(w, setup.distance_mm, tilt, seed, static_cast<std::int64_t>(seed));
        check_scan(s, setup.distance_mm, tilt, seed, worst);
      }
  }
  WARN("static A-F worst error / tolerance: " << worst.str());
  check_unsure(worst);
}
