#pragma once
// Plain data crossing into and out of the tracker. Sensor frame throughout:
// y along the laser line, z the range along the optical axis (mm); the work
// lies at +z, so "out of the work, towards the sensor" is roughly -z.
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include <Eigen/Core>

namespace vts::tracker {

using Vec2 = Eigen::Vector2d;  // (y, z), sensor frame, mm

// The joint a template describes (docs/JOINTS.md). The grooves (v-groove,
// single bevel, U, J) are read by one groove model with the fill (beads laid
// in it) as well.
enum class JointType { Fillet, Corner, Lap, Butt, VGroove, Bevel, UGroove, JGroove };

inline constexpr JointType kAllJointTypes[] = {JointType::Fillet, JointType::Corner,  JointType::Lap,
                                              JointType::Butt,   JointType::VGroove, JointType::Bevel,
                                              JointType::UGroove, JointType::JGroove};

// "fillet", "corner", "lap", "butt", "vgroove", "bevel", "ugroove", "jgroove".
std::string_view to_string(JointType type);
std::optional<JointType> joint_type_from_string(std::string_view name);

// One profile as the sensor delivers it, in scan order (column 0 first).
// The spans match vts::Profile's vectors but nothing here depends on them.
// A point is used only if valid[i] != 0 (an empty `valid` means all valid),
// both coordinates are finite and it lies in front of the ray origin
// (z > TrackerParams::ray_origin_yz.z); anything else counts as invalid.
struct ProfileView {
  std::span<const float> y_mm;
  std::span<const float> z_mm;
  std::span<const std::uint8_t> valid;
};

}  // namespace vts::tracker
