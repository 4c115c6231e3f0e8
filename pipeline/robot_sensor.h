#pragma once
// A robot between the master and the sensor (issue 19, docs/SIM.md): the
// master's tool pose of each cycle is the robot's servo target; the robot
// moves (a perfect one exactly, an arm with its servo lag, correction
// latency and absolute-accuracy errors); the sensor scans from where the
// TCP really is and stamps its data with where the controller says it is,
// as a real sensor's data are stamped. The master talks to this as to any
// sensor interface and cannot tell.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot/perfect_robot.h"
#include "sensor/sim_cell.h"
#include "sensor/virtual_sensor.h"
#include "tracker/sensor_interface.h"

namespace vts {

// Places a sensor head for the robot's present pose. actual_from_reported:
// what the head scans from relative to the pose the robot reports, the real
// TCP, which an arm's report misses by its absolute error, and the part's
// motion (the moved part is scanned as the part unmoved from the sensor
// moved back); empty when both are exact (a perfect robot, a part that
// stays). moving_part: the box's lift against the plate (set only when the
// cell has one). `distortion` may be null (the part stays); it is updated
// with the real TCP.
void place_head(VirtualProfileStream& head, const robot::Robot& robot, bool exact_robot, SeamDistortion* distortion);

class RobotSensor final : public tracker::SensorInterface {
 public:
  // `unit` may be null (a program without a sensor: the laser never comes
  // on); `head` is the virtual sensor inside unit's stream (null on a
  // replay). The robot (robot::make_robot) is made at the first advance(),
  // with its TCP at the first commanded pose.
  RobotSensor(tracker::SensorInterface* unit, VirtualProfileStream* head, std::string robot,
              std::uint64_t robot_seed);

  bool laser_on() override;
  void laser_off() override;
  void search_start() override;
  void start_tracking() override;
  void look_for_end() override;
  void idle() override;
  // Servo target `commanded`; the robot and then the sensor advance to t
  // (through every break of the robot's motion). A robot fault ends the
  // stream (Event::StreamEnded, error() "the robot stopped: ...").
  std::vector<tracker::Event> advance(double t, const tracker::Pose3& commanded) override;
  std::optional<tracker::JointData> latest_joint(double now_s) const override;
  tracker::SensorState state() const override;
  std::optional<Eigen::Vector3d> start_point() const override;
  std::optional<Eigen::Vector3d> end_point() const override;
  const tracker::SequenceCounters& counters() const override;
  std::string error() const override;

  // Thermal distortion (sensor/sim_cell.h), updated with where the TCP
  // really is; the sensor scans the part as it lies. Null: the part stays.
  SeamDistortion* distortion = nullptr;

  // The TCP where it really was at the end of each advance() (world).
  const std::vector<tracker::Pose3>& actual() const { return actual_; }
  // An arm's joints at the end of each advance() (empty for a perfect robot).
  const std::vector<robot::Joints>& joints() const { return joints_; }
  // Null before the first advance().
  const robot::Robot* robot() const { return robot_.get(); }
  const std::string& fault() const { return fault_; }

 private:
  tracker::SensorInterface* unit_;
  VirtualProfileStream* head_;
  std::string name_;
  std::uint64_t seed_;
  std::unique_ptr<robot::Robot> robot_;
  std::vector<tracker::Pose3> actual_;
  std::vector<robot::Joints> joints_;
  std::string fault_;
  tracker::SequenceCounters none_;
};

}  // namespace vts
