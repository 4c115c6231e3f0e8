#pragma once
// The robots a cell can be welded with, by name (docs/ROBOT.md): "perfect"
// (the TCP where it is commanded, at once) or an arm preset ("irb2400",
// "kr16") standing where it reaches the cell. `vts sim` and `vts serve`
// build theirs here.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "robot/perfect_robot.h"

namespace vts::robot {

// The torch on the flange: the TCP this far along the flange's z.
inline constexpr double kTorchMm = 400.0;
// An arm's base from the TCP's start across its travel direction, and below
// it, facing it: the cell in the middle of the arm's reach.
inline constexpr double kBaseAcrossMm = 1100.0;
inline constexpr double kBaseBelowMm = 300.0;

// "perfect", then the arm presets.
std::vector<std::string> robot_names();
bool is_robot_name(const std::string& name);

// The robot `name` with its TCP at `home`; an arm as built from
// accuracy_seed (0: exactly its nominal model). Throws std::invalid_argument
// for an unknown name ("robot = 'x': expected perfect, irb2400 or kr16") or a
// home the arm cannot reach within its limits (the reason).
std::unique_ptr<Robot> make_robot(const std::string& name, std::uint64_t accuracy_seed, const Pose3& home);

}  // namespace vts::robot
