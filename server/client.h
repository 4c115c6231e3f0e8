#pragma once
// vts::client (docs/PROTOCOL.md): a blocking C++ client of `vts serve`.
// request() sends one request and returns its answer; events that arrive
// before the answer are kept for next_event(). RemoteSensor is the sensor
// interface (tracker/sensor_interface.h) over a connection: the C++ master
// (tracker/master.h) runs against a served cell through it unchanged.
#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>

#include "server/protocol.h"
#include "tracker/sensor_interface.h"

namespace vts::client {

using Json = server::Json;

// An answer with "ok": false: its code and message (docs/PROTOCOL.md, "Errors").
struct Error : std::runtime_error {
  Error(std::string code, const std::string& message) : std::runtime_error(code + ": " + message), code(std::move(code)) {}
  std::string code;
};

class Client {
 public:
  // Connects and says hello; throws std::runtime_error when the connection
  // fails, Error when the server refuses the hello.
  Client(const std::string& host, int port, const std::string& role = "control",
         const std::string& name = "vts::client");
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Sends {"cmd": cmd, ...fields} with a fresh id and returns the answer;
  // throws Error for an error answer, std::runtime_error when the
  // connection is lost.
  Json request(const std::string& cmd, Json fields = Json::object());
  // The next pushed event, waiting up to `timeout`; empty if none came.
  std::optional<Json> next_event(std::chrono::milliseconds timeout = std::chrono::milliseconds(0));
  const Json& hello() const { return hello_; }

 private:
  bool read_line(std::string& line, int timeout_ms);  // false on timeout
  void send_line(const std::string& line);

  int fd_ = -1;
  std::int64_t next_id_ = 1;
  std::string in_;
  std::deque<Json> events_;
  Json hello_;
};

// The sensor interface over a served cell in lockstep: advance() servos the
// robot to the tool pose and steps time (the answer carries the alerts);
// every other call is one request.
class RemoteSensor final : public tracker::SensorInterface {
 public:
  explicit RemoteSensor(Client& client) : c_(client) {}
  bool laser_on() override;
  void laser_off() override;
  void search_start() override;
  void start_tracking() override;
  void look_for_end() override;
  void idle() override;
  std::vector<tracker::Event> advance(double time_s, const tracker::Pose3& world_from_tool) override;
  std::optional<tracker::JointData> latest_joint(double now_s) const override;
  tracker::SensorState state() const override;
  std::optional<Eigen::Vector3d> start_point() const override;
  std::optional<Eigen::Vector3d> end_point() const override;
  const tracker::SequenceCounters& counters() const override;
  std::string error() const override { return error_; }
  // The TCP after the last advance() as the simulator knows it (the step's
  // world_from_tool_actual): behind and off the commanded pose with an arm.
  const tracker::Pose3& last_actual() const { return actual_; }

 private:
  Client& c_;
  tracker::Pose3 actual_ = tracker::Pose3::Identity();
  mutable tracker::SequenceCounters counters_;
  std::string error_;
};

// Reads the protocol's JSON forms back.
tracker::Pose3 pose_from_json(const Json& j);
Eigen::Vector3d vec3_from_json(const Json& j);

}  // namespace vts::client
