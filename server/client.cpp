#include "server/client.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace vts::client {
namespace tk = vts::tracker;

Client::Client(const std::string& host, int port, const std::string& role, const std::string& name) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* res = nullptr;
  const std::string where = host + ":" + std::to_string(port);
  if (const int e = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res); e != 0)
    throw std::runtime_error("vts::client: cannot resolve " + where + ": " + ::gai_strerror(e));
  std::string why = "no address";
  for (addrinfo* a = res; a; a = a->ai_next) {
    fd_ = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd_ < 0) continue;
    if (::connect(fd_, a->ai_addr, a->ai_addrlen) == 0) break;
    why = std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
  }
  ::freeaddrinfo(res);
  if (fd_ < 0) throw std::runtime_error("vts::client: cannot connect to " + where + ": " + why);
  Json h;
  h["protocol"] = server::kProtocolVersion;
  h["role"] = role;
  h["client"] = name;
  try {
    hello_ = request("hello", h);
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

Client::~Client() {
  if (fd_ >= 0) ::close(fd_);
}

void Client::send_line(const std::string& line) {
  std::size_t off = 0;
  while (off < line.size()) {
    const ssize_t n = ::send(fd_, line.data() + off, line.size() - off, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("vts::client: connection lost: ") + std::strerror(errno));
    }
    off += static_cast<std::size_t>(n);
  }
}

bool Client::read_line(std::string& line, int timeout_ms) {
  while (true) {
    if (const std::size_t nl = in_.find('\n'); nl != std::string::npos) {
      line.assign(in_, 0, nl);
      in_.erase(0, nl + 1);
      return true;
    }
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, timeout_ms);
    if (r == 0) return false;
    if (r < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("vts::client: poll: ") + std::strerror(errno));
    }
    char buf[65536];
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n == 0) throw std::runtime_error("vts::client: the server closed the connection");
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      throw std::runtime_error(std::string("vts::client: connection lost: ") + std::strerror(errno));
    }
    in_.append(buf, static_cast<std::size_t>(n));
  }
}

Json Client::request(const std::string& cmd, Json fields) {
  const std::int64_t id = next_id_++;
  fields["cmd"] = cmd;
  fields["id"] = id;
  send_line(server::to_line(fields));
  std::string line;
  while (true) {
    read_line(line, -1);
    Json j = Json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object())
      throw std::runtime_error("vts::client: the server sent a line that is not a JSON object");
    if (j.contains("event")) {
      events_.push_back(std::move(j));
      continue;
    }
    if (j.value("id", Json()) != Json(id) && !j["id"].is_null()) continue;  // not ours (cannot happen in order)
    if (!j.value("ok", false))
      throw Error(j.value("error", std::string("failed")), j.value("message", std::string()));
    return j;
  }
}

std::optional<Json> Client::next_event(std::chrono::milliseconds timeout) {
  std::string line;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (events_.empty()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (!read_line(line, static_cast<int>(std::max<std::int64_t>(0, left.count())))) return std::nullopt;
    Json j = Json::parse(line, nullptr, false);
    if (j.is_object() && j.contains("event")) events_.push_back(std::move(j));
  }
  Json e = std::move(events_.front());
  events_.pop_front();
  return e;
}

tk::Pose3 pose_from_json(const Json& j) {
  Json wrap;
  wrap["p"] = j;
  return server::pose_field(wrap, "p");
}

Eigen::Vector3d vec3_from_json(const Json& j) {
  Json wrap;
  wrap["v"] = j;
  return server::vec3_field(wrap, "v");
}

namespace {

tk::Event event_from(const std::string& name) {
  for (tk::Event e : {tk::Event::StartFound, tk::Event::StartBehind, tk::Event::EndFound, tk::Event::SeamLost,
                      tk::Event::StreamEnded})
    if (tk::to_string(e) == name) return e;
  throw std::runtime_error("vts::client: unknown sensor event '" + name + "'");
}

tk::SensorState state_from(const std::string& name) {
  using S = tk::SensorState;
  for (S s : {S::Idle, S::LaserOn, S::Searching, S::StartFound, S::Tracking, S::LookingForEnd, S::EndFound, S::SeamLost})
    if (tk::to_string(s) == name) return s;
  throw std::runtime_error("vts::client: unknown sensor state '" + name + "'");
}

}  // namespace

bool RemoteSensor::laser_on() {
  const Json a = c_.request("sensor.laser_on");
  error_ = a.value("message", std::string());
  return a.value("confirmed", false);
}
void RemoteSensor::laser_off() { c_.request("sensor.laser_off"); }
void RemoteSensor::search_start() { c_.request("sensor.search_start"); }
void RemoteSensor::start_tracking() { c_.request("sensor.start_tracking"); }
void RemoteSensor::look_for_end() { c_.request("sensor.look_for_end"); }
void RemoteSensor::idle() { c_.request("sensor.idle"); }

std::vector<tk::Event> RemoteSensor::advance(double time_s, const tk::Pose3& world_from_tool) {
  Json s;
  s["world_from_tool"] = server::to_json(world_from_tool);
  c_.request("robot.servo", s);
  Json t;
  t["to_s"] = time_s;
  const Json a = c_.request("step", t);
  actual_ = pose_from_json(a["world_from_tool_actual"]);
  std::vector<tk::Event> out;
  for (const Json& e : a["events"]) {
    const std::string name = e.value("event", std::string());
    if (name == "move-done") continue;
    out.push_back(event_from(name));
    if (name == "stream-ended") error_ = e.value("message", std::string());
  }
  return out;
}

std::optional<tk::JointData> RemoteSensor::latest_joint(double) const {
  const Json a = c_.request("sensor.joint");
  const Json& j = a["joint"];
  if (j.is_null()) return std::nullopt;
  tk::JointData d;
  d.profile_index = j["profile_index"].get<std::int64_t>();
  d.time_s = j["time_s"].get<double>();
  d.age_s = j["age_s"].get<double>();
  d.world_from_sensor = pose_from_json(j["world_from_sensor"]);
  const Json& bps = j["break_points_sensor"];
  for (std::size_t i = 0; i < d.break_points.size() && i < bps.size(); ++i)
    if (!bps[i].is_null()) d.break_points[i] = tk::Vec2(bps[i][0].get<double>(), bps[i][1].get<double>());
  d.track_point_sensor = tk::Vec2(j["track_point_sensor"][0].get<double>(), j["track_point_sensor"][1].get<double>());
  d.track_point_world = vec3_from_json(j["track_point_world"]);
  d.gap_mm = j["gap_mm"].is_null() ? tk::kNotMeasured : j["gap_mm"].get<double>();
  d.angle_deg = j["angle_deg"].is_null() ? tk::kNotMeasured : j["angle_deg"].get<double>();
  d.confidence = j["confidence"].get<double>();
  return d;
}

tk::SensorState RemoteSensor::state() const { return state_from(c_.request("sensor.state")["state"].get<std::string>()); }

std::optional<Eigen::Vector3d> RemoteSensor::start_point() const {
  const Json a = c_.request("sensor.state");
  if (a["start_point"].is_null()) return std::nullopt;
  return vec3_from_json(a["start_point"]);
}

std::optional<Eigen::Vector3d> RemoteSensor::end_point() const {
  const Json a = c_.request("sensor.state");
  if (a["end_point"].is_null()) return std::nullopt;
  return vec3_from_json(a["end_point"]);
}

const tk::SequenceCounters& RemoteSensor::counters() const {
  const Json k = c_.request("sensor.state")["counters"];
  counters_.profiles = k["profiles"].get<std::int64_t>();
  counters_.joint_profiles = k["with_joint"].get<std::int64_t>();
  counters_.invalid_profiles = k["without_joint"].get<std::int64_t>();
  counters_.longest_gap_mm = k["longest_gap_mm"].get<double>();
  return counters_;
}

}  // namespace vts::client
