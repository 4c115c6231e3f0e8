// The tracker parameter file reader (trackio/params_yaml.h): values land in
// the fields docs/CLI.md names, errors name the file, line and key path.
#include <catch2/catch.hpp>

#include <string>

#include "trackio/params_yaml.h"

namespace {

using vts::trackio::ParamsError;
using vts::trackio::ParamsFile;
namespace tk = vts::tracker;

std::string error_of(const std::string& yaml) {
  ParamsFile f;
  try {
    vts::trackio::read_params(yaml, "p.yaml", f);
  } catch (const ParamsError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("trackio params: every key of docs/CLI.md's example file lands in its field", "[trackio]") {
  const std::string yaml = R"(joint: lap
surface_tol_mm: 0.05
max_joint_width_mm: 25
square_edges: false
hidden_face_deg: 2.5
segmentation:
  roi_first: 3
  roi_last: 500
  ray_origin_yz: [1.5, -2]
  outliers: {enabled: false, max_cluster_points: 5, threshold_mm: 0.25, support_points: 2, support_tol_mm: 0.15}
  segments:
    split_threshold_mm: 0.35
    split_interval: 3
    min_segment_points: 7
    max_merge_gap_points: 9
    max_merge_angle_deg: 14
    max_merge_offset_mm: 0.25
    break_min_mm: 0.4
    break_ratio: 5
    fit_tol_mm: 0.03
fillet: {angle_deg: [40, 140], gap_mm: [0, 3.5], web: second, curved_plates: false, curve_window_mm: 12, curve_t: 4,
         min_curve_radius: 6, curve_rms_sigma: 1.25}
confidence: {track_interval_mm: 0.5}
corner: {angle_deg: [61, 171], gap_mm: [0, 2]}
lap: {step_mm: [1, 20], gap_mm: [0, 2.5], angle_deg: [50, 130], max_plate_angle_deg: 10, upper_thickness_mm: 3}
butt: {gap_mm: [0, 4], mismatch_mm: [0, 2], max_plate_angle_deg: 12}
vgroove: {angle_deg: [30, 110], gap_mm: [0, 4], mismatch_mm: [0, 2], depth_mm: [1, 50], min_bevel_points: 6}
)";
  ParamsFile f;
  vts::trackio::read_params(yaml, "p.yaml", f);
  const tk::TrackerParams& p = f.params;
  CHECK(f.joint == tk::JointType::Lap);
  CHECK(p.surface_tol_mm == 0.05);
  CHECK(p.max_joint_width_mm == 25);
  CHECK_FALSE(p.square_edges);
  CHECK(p.hidden_face_deg == 2.5);
  CHECK(p.segmentation.roi_first == 3);
  CHECK(p.segmentation.roi_last == 500);
  CHECK(p.segmentation.ray_origin_yz == tk::Vec2(1.5, -2));
  CHECK_FALSE(p.segmentation.outliers.enabled);
  CHECK(p.segmentation.outliers.max_cluster_points == 5);
  CHECK(p.segmentation.outliers.threshold_mm == 0.25);
  CHECK(p.segmentation.outliers.support_points == 2);
  CHECK(p.segmentation.outliers.support_tol_mm == 0.15);
  const tk::SegmentParams& s = p.segmentation.segments;
  CHECK(s.split_threshold_mm == 0.35);
  CHECK(s.split_interval == 3);
  CHECK(s.min_segment_points == 7);
  CHECK(s.max_merge_gap_points == 9);
  CHECK(s.max_merge_angle_deg == 14);
  CHECK(s.max_merge_offset_mm == 0.25);
  CHECK(s.break_min_mm == 0.4);
  CHECK(s.break_ratio == 5);
  CHECK(s.fit_tol_mm == 0.03);
  CHECK(p.fillet.angle_deg.min == 40);
  CHECK(p.fillet.angle_deg.max == 140);
  CHECK(p.fillet.gap_mm.max == 3.5);
  CHECK(p.fillet.web == tk::WebSide::Second);
  CHECK_FALSE(p.fillet.curved_plates);
  CHECK(p.fillet.curve_window_mm == 12);
  CHECK(p.fillet.curve_t == 4);
  CHECK(p.fillet.min_curve_radius == 6);
  CHECK(p.fillet.curve_rms_sigma == 1.25);
  CHECK(p.confidence.track_interval_mm == 0.5);
  CHECK(p.corner.angle_deg.min == 61);
  CHECK(p.corner.gap_mm.max == 2);
  CHECK(p.lap.step_mm.min == 1);
  CHECK(p.lap.gap_mm.max == 2.5);
  CHECK(p.lap.angle_deg.max == 130);
  CHECK(p.lap.max_plate_angle_deg == 10);
  CHECK(p.lap.upper_thickness_mm == 3);
  CHECK(p.butt.gap_mm.max == 4);
  CHECK(p.butt.mismatch_mm.max == 2);
  CHECK(p.butt.max_plate_angle_deg == 12);
  CHECK(p.vgroove.angle_deg.min == 30);
  CHECK(p.vgroove.gap_mm.max == 4);
  CHECK(p.vgroove.mismatch_mm.max == 2);
  CHECK(p.vgroove.depth_mm.min == 1);
  CHECK(p.vgroove.min_bevel_points == 6);
}

TEST_CASE("trackio params: keys not in the file keep their values", "[trackio]") {
  ParamsFile f;
  f.params.surface_tol_mm = 0.07;
  vts::trackio::read_params("segmentation: {segments: {split_interval: 4}}\n", "p.yaml", f);
  CHECK(f.params.surface_tol_mm == 0.07);
  CHECK(f.params.segmentation.segments.split_interval == 4);
  CHECK(f.params.segmentation.segments.min_segment_points == tk::SegmentParams{}.min_segment_points);
  CHECK_FALSE(f.joint);
  vts::trackio::read_params("", "empty.yaml", f);
  CHECK(f.params.segmentation.segments.split_interval == 4);
}

TEST_CASE("trackio params: errors name the file, the line and the key path", "[trackio]") {
  CHECK(error_of("a: 1\n") ==
        "p.yaml:1: a: unknown key (expected one of: joint, surface_tol_mm, max_joint_width_mm, square_edges, "
        "hidden_face_deg, segmentation, fillet, corner, lap, butt, vgroove, groove, noise, confidence)");
  CHECK(error_of("segmentation:\n  segments:\n    split_interval: two\n") ==
        "p.yaml:3: segmentation.segments.split_interval: expected an integer, got 'two'");
  CHECK(error_of("corner: {angle_deg: [170, 60]}\n") == "p.yaml:1: corner.angle_deg: min 170 is greater than max 60");
  CHECK(error_of("surface_tol_mm: 0\n") == "p.yaml:1: surface_tol_mm: '0' is out of range: expected > 0");
  CHECK(error_of("hidden_face_deg: -1\n") ==
        "p.yaml:1: hidden_face_deg: '-1' is out of range: expected from 0 to 45");
  CHECK(error_of("vgroove: {min_bevel_points: 1}\n") ==
        "p.yaml:1: vgroove.min_bevel_points: '1' is out of range: expected from 2 to 4096");
  CHECK(error_of("lap:\n  step_mm: [1, 2]\n  step_mm: [1, 3]\n") == "p.yaml:3: lap.step_mm: duplicate key");
  CHECK(error_of("fillet: 3\n") == "p.yaml:1: fillet: expected a map, got '3'");
  CHECK(error_of("fillet: {web: left}\n") == "p.yaml:1: fillet.web: 'left' is not auto, first or second");
  CHECK(error_of("joint: tee\n") ==
        "p.yaml:1: joint: 'tee' is not a joint; expected fillet, corner, lap, butt, vgroove, bevel, ugroove or jgroove");
  CHECK(error_of("- 1\n") == "p.yaml:1: expected a map of parameters (docs/CLI.md)");
  CHECK(error_of("square_edges: yes\n") == "p.yaml:1: square_edges: expected true or false, got 'yes'");
  CHECK(error_of("segmentation: {ray_origin_yz: 3}\n") ==
        "p.yaml:1: segmentation.ray_origin_yz: expected [y, z] in mm, got '3'");
  CHECK(error_of("segmentation: {outliers: {colour: red}}\n") ==
        "p.yaml:1: segmentation.outliers.colour: unknown key (expected one of: enabled, max_cluster_points, "
        "threshold_mm, support_points, support_tol_mm)");
  CHECK(error_of("a: [1\n").rfind("p.yaml:", 0) == 0);
}

TEST_CASE("trackio params: the field table", "[trackio]") {
  for (const auto& f : vts::trackio::param_fields()) CHECK(vts::trackio::find_param(f.path) == &f);
  CHECK(vts::trackio::find_param("segments") == nullptr);
  CHECK(vts::trackio::unit_of("lap.step_mm") == "mm");
  CHECK(vts::trackio::unit_of("segmentation.segments.max_merge_angle_deg") == "degrees");
  CHECK(vts::trackio::unit_of("vgroove.min_bevel_points").empty());
  ParamsFile missing;
  CHECK_THROWS_WITH(vts::trackio::read_params_file("/nonexistent/p.yaml", missing),
                    "/nonexistent/p.yaml: cannot open file");
}
