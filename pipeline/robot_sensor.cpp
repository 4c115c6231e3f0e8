#include "pipeline/robot_sensor.h"

#include <stdexcept>

#include "robot/robots.h"

namespace vts {

namespace tk = vts::tracker;

void place_head(VirtualProfileStream& head, const robot::Robot& robot, bool exact_robot, SeamDistortion* distortion) {
  const Pose tcp = robot.tcp();
  if (distortion) distortion->update(tcp.translation());
  head.moving_part.reset();
  if (distortion && !distortion->cell().moving_part.triangles.empty()) head.moving_part = distortion->wall_motion();
  if (exact_robot && !distortion) {
    head.actual_from_reported.reset();  // a perfect robot is where it says, exactly
    return;
  }
  const Pose actual_from_reported = tcp * robot.reported_tcp().inverse();
  head.actual_from_reported =
      distortion ? Pose(distortion->part_motion().inverse() * actual_from_reported) : actual_from_reported;
}

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
    if (head_) place_head(*head_, *robot_, name_ == "perfect", distortion);
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
