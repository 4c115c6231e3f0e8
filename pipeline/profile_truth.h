#pragma once
// A joint's analytic truth as one profile sees it: the workpiece's JointTruth
// (sensor/workpiece.h, docs/CELLS.md) carried into the sensor frame of the
// profile's pose by Workpiece::in_sensor_frame (where the laser plane cuts
// each feature's line along the seam), with the break points numbered and
// ordered as the tracker numbers its own (docs/JOINTS.md,
// tracker::break_point_name): the labels of `vts dataset` (docs/DATASETS.md),
// and what `vts score` compares a reading with.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sensor/pose.h"
#include "sensor/scanner.h"
#include "sensor/workpiece.h"
#include "tracker/tracker.h"
#include "trackio/result_json.h"

namespace vts {

// Sensor frame (y along the laser line, z the range), mm and degrees; NaN
// where a value does not apply to the joint.
struct ProfileTruth {
  tracker::JointType joint = tracker::JointType::Fillet;
  // The point to weld: JointTruth::root_yz, for the grooves track_yz (B3).
  Vec2 track_point = Vec2::Zero();
  // The break points the joint's geometry fixes, by the tracker's index:
  //   fillet B1 root, B2 the flange point seen under the web through the gap
  //     (the ray past the web edge), B3 the web edge (B2 = B3 = B1 without a gap);
  //   corner B1, B3 the plate edges in scan order, B2 the outer faces' apex;
  //   lap B1 the foot of the step, B2 the upper plate's bottom edge, B3 its top edge;
  //   butt B1, B3 the plate edges in scan order, B2 the gap centre (the root);
  //   grooves B1, B5 the top edges and B2, B4 the toes in scan order, B3 the
  //     track point.
  // The outer ends (B0, B4 or B6) are where the fan ends, not the joint: none.
  std::array<std::optional<Vec2>, tracker::kMaxBreakPoints> break_points;
  // JointTruth::features (web_toe, left_root, ...), each in the sensor frame.
  std::vector<std::pair<std::string, Vec2>> features;
  double gap_mm = tracker::kNotMeasured;
  double angle_deg = tracker::kNotMeasured;
  double mismatch_mm = tracker::kNotMeasured;   // butt, grooves: side b (joint y > 0) raised by this
  double step_mm = tracker::kNotMeasured;       // lap
  double depth_mm = tracker::kNotMeasured;      // grooves
  double area_mm2 = tracker::kNotMeasured;      // grooves
  double top_width_mm = tracker::kNotMeasured;  // grooves
  // Grooves: the walls against their plate tops, a = the first in scan
  // order (as the tracker reports them).
  double wall_angle_a_deg = tracker::kNotMeasured;
  double wall_angle_b_deg = tracker::kNotMeasured;
  std::optional<Vec2> fill_lowest;  // grooves
  // The track point lies inside the fan and the depth of field; whether a
  // plate hides it from the laser or the camera is not checked.
  bool in_window = false;
};

// Throws std::invalid_argument for a workpiece without a joint (a plate, a mesh).
ProfileTruth profile_truth(const Workpiece& w, const ScannerDesc& scanner, const Pose& world_from_sensor);

// As JSON, the labels of a `vts dataset` line (docs/DATASETS.md, "Per
// profile"): in_window, track_point {y, z}, break_points [{name, meaning, y,
// z}], gap_mm .. wall_angle_b_deg (null where they do not apply),
// fill_lowest, features {name: {y, z}}, in that order.
trackio::Json profile_truth_json(const ProfileTruth& t);

}  // namespace vts
