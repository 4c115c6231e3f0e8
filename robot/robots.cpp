#include "robot/robots.h"

#include <stdexcept>

#include "robot/arm_robot.h"

namespace vts::robot {

std::vector<std::string> robot_names() {
  std::vector<std::string> names{"perfect"};
  for (const std::string& n : arm_preset_names()) names.push_back(n);
  return names;
}

bool is_robot_name(const std::string& name) { return name == "perfect" || arm_preset(name).has_value(); }

std::unique_ptr<Robot> make_robot(const std::string& name, std::uint64_t accuracy_seed, const Pose3& home) {
  if (name == "perfect") return std::make_unique<PerfectRobot>(home);
  const auto model = arm_preset(name);
  if (!model) {
    std::string expected;
    for (const std::string& n : robot_names()) expected += (expected.empty() ? "" : ", ") + n;
    throw std::invalid_argument("robot = '" + name + "': expected one of " + expected);
  }
  ArmSetup s;
  s.nominal = *model;
  s.accuracy_seed = accuracy_seed;
  s.flange_from_tool.translation() = Eigen::Vector3d(0.0, 0.0, kTorchMm);
  Eigen::Vector3d x = home.linear().col(0);
  x.z() = 0.0;
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(x);
  const Eigen::Vector3d base = home.translation() - kBaseAcrossMm * across - Eigen::Vector3d(0.0, 0.0, kBaseBelowMm);
  s.world_from_base.linear() << across, Eigen::Vector3d::UnitZ().cross(across), Eigen::Vector3d::UnitZ();
  s.world_from_base.translation() = base;
  return std::make_unique<ArmRobot>(s, home);
}

}  // namespace vts::robot
