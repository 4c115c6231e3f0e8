#include "pipeline/robot_sensor.h"

#include <stdexcept>

#include "robot/robots.h"

namespace vts {

namespace tk = vts::tracker;

RobotSensor::RobotSensor(tk::SensorInterface* unit, VirtualProfileStream* head, std::string robot,
                         std::uint64_t robot_seed)
    : unit_(unit), head_(head), name_(std::move(robot)), seed_(robot_seed) {}

bool RobotSensor::laser_on() { return unit_ && fault_.empty() && unit_->laser_on(); }
void RobotSensor::laser_off() {
  if (unit_) unit_->laser_off();
}
void RobotSensor::search_start() {
  if (unit_) unit_->search_start();
}
void RobotSensor::start_tracking() {
  if (unit_) unit_->start_tracking();
}
void RobotSensor::look_for_end() {
  if (unit_) unit_->look_for_end();
}
void RobotSensor::idle() {
  if (unit_) unit_->idle();
}

std::vector<tk::Event> RobotSensor::advance(double t, const tk::Pose3& commanded) {
  std::vector<tk::Event> events;
  if (!robot_ && fault_.empty()) {
    try {
      robot_ = robot::make_robot(name_, seed_, commanded);
    } catch (const std::invalid_argument& e) {
      fault_ = std::string("the robot cannot start at the first pose: ") + e.what();
    }
  }
  if (!robot_) {
    actual_.push_back(commanded);
    events.push_back(tk::Event::StreamEnded);
    return events;
  }
  const bool was_faulted = !fault_.empty();
  robot_->servo(commanded);
  auto run_to = [&](double s) {
    robot_->advance(s);
    if (fault_.empty() && !robot_->fault().empty()) fault_ = "the robot stopped: " + robot_->fault();
    if (!unit_) return;
    const tk::Pose3 reported = robot_->reported_tcp();
    // The sensor scans from where the arm really is (a perfect robot is
    // where it reports itself, exactly); a moved part is scanned as the
    // part unmoved from the sensor moved back.
    if (head_ && part_motion)
      head_->actual_from_reported = Pose(part_motion(robot_->tcp()).inverse() * robot_->tcp() * reported.inverse());
    else if (head_ && name_ != "perfect")
      head_->actual_from_reported = Pose(robot_->tcp() * reported.inverse());
    for (tk::Event e : unit_->advance(s, reported)) events.push_back(e);
  };
  for (double b : robot_->breaks_before(t)) run_to(b);
  run_to(t);
  if (!was_faulted && !fault_.empty()) events.push_back(tk::Event::StreamEnded);
  actual_.push_back(robot_->tcp());
  if (const auto q = robot_->joints()) joints_.push_back(*q);
  return events;
}

std::optional<tk::JointData> RobotSensor::latest_joint(double now_s) const {
  return unit_ ? unit_->latest_joint(now_s) : std::nullopt;
}
tk::SensorState RobotSensor::state() const { return unit_ ? unit_->state() : tk::SensorState::Idle; }
std::optional<Eigen::Vector3d> RobotSensor::start_point() const { return unit_ ? unit_->start_point() : std::nullopt; }
std::optional<Eigen::Vector3d> RobotSensor::end_point() const { return unit_ ? unit_->end_point() : std::nullopt; }
const tk::SequenceCounters& RobotSensor::counters() const { return unit_ ? unit_->counters() : none_; }
std::string RobotSensor::error() const {
  if (!fault_.empty()) return fault_;
  return unit_ ? unit_->error() : std::string();
}

}  // namespace vts
