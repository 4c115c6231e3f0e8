#pragma once
// The served cell (docs/PROTOCOL.md): the paper's box cell with its virtual
// sensor behind the sensor interface (pipeline/sim_run.h's SimRig: the same
// set-up `vts sim` runs), a robot (server/robot.h) and the clock, answering
// the protocol's requests. No sockets here: server/server.h carries the
// lines; tests and other front-ends call handle() directly.
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "pipeline/sim_run.h"
#include "sensor/virtual_sensor.h"
#include "server/protocol.h"
#include "robot/perfect_robot.h"

namespace vts::server {

struct HostOptions {
  SimSpec sim;            // the box cell, sensor, source, seed, speed (as `vts sim`)
  // Instead of the box: a cell of `vts cells` or a scene file, with its
  // scanner (pipeline/sim_run.h make_cell_rig); sim.source and sim.seed
  // still choose the source and the error model's draws.
  std::optional<Cell> cell;
  bool realtime = false;  // wall-clock time (the server loop calls advance_to); else lockstep
  // The robot: "perfect" (the TCP where commanded, at once) or an arm preset
  // (robot/arm.h: "irb2400", "kr16") with its servo, latency and, with
  // robot_seed > 0, the absolute-accuracy errors of that seed (docs/ROBOT.md).
  std::string robot = "perfect";
  std::uint64_t robot_seed = 0;
};

// What the host keeps of one connection.
struct Peer {
  int id = 0;
  bool hello = false;
  bool controller = false;
  bool events = false, profiles = false, joints = false;  // subscriptions
  std::string name;
};

// What a push is about, for the subscriptions.
enum class Topic { Event, Profile, Joint };

class CellHost {
 public:
  static constexpr std::size_t kJointsHeld = 1000;
  static constexpr double kMaxStepS = 60.0;

  // Builds the cell and the sensor; throws as make_sim_rig.
  explicit CellHost(const HostOptions& options);
  ~CellHost();
  CellHost(const CellHost&) = delete;
  CellHost& operator=(const CellHost&) = delete;

  // One request line from `peer`: the answer to send (exactly one). Never
  // throws for anything the line contains.
  Json handle_line(std::string_view line, Peer& peer);
  Json handle(const Request& request, Peer& peer);
  // The peer is gone: control is released.
  void disconnected(Peer& peer);

  // Real time: run the robot and the sensor up to t (the server's clock).
  void advance_to(double t);
  bool realtime() const { return options_.realtime; }
  double time_s() const { return robot_->time_s(); }
  double rate_hz() const;
  // Pushes, called during handle() and advance_to(): the server forwards
  // each to the peers subscribed to its topic.
  std::function<void(const Json& message, Topic topic)> publish;

 private:
  Json dispatch(const Request& r, Peer& peer);
  Json step(double to_s);  // the events raised, as a JSON array
  Json joint_json(const tracker::JointData& j) const;
  Json job_json() const;
  Json truth_json() const;
  Json state_json() const;
  void require_control(const Request& r, const Peer& peer) const;
  void subscribe(const Peer& peer, int add);  // the peer's subscriptions counted in or out
  void raise(const Json& event);  // into the current step's answer and to the subscribers
  Json robot_command(const Request& r);  // robot.servo, .move, .stop, .correct

  tracker::SensorUnit& sensor() const;
  std::string cell_name() const;
  Json profile_json(const tracker::SensorProfile& p, const tracker::TrackResult& r) const;

  HostOptions options_;
  std::optional<SimRig> box_;    // the box cell (its thermal distortion in distortion_), or
  std::optional<SeamDistortion> distortion_;
  std::optional<CellRig> cell_;  // another cell
  // The virtual sensor head behind the unit, told where an arm really is
  // (VirtualProfileStream::actual_from_reported); null on a replay.
  VirtualProfileStream* head_ = nullptr;
  bool arm_ = false;  // the robot is an arm: it may not be where it reports
  std::unique_ptr<robot::Robot> robot_;
  bool controller_taken_ = false;
  std::deque<tracker::JointData> joints_;  // the last kJointsHeld joint data, oldest first
  std::int64_t joints_dropped_index_ = -1;  // the newest profile index dropped from joints_
  Json step_events_;                    // events raised in the current advance
  int subscribers_[3] = {0, 0, 0};      // peers subscribed, per Topic
};

}  // namespace vts::server
