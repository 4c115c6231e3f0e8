// vts serve's pieces (docs/PROTOCOL.md): the wire format, the served cell,
// and the server with real sockets on loopback. The master of the paper's
// experiment runs against the served cell through vts::client and must
// weld exactly as `vts sim` does in process (same seed, lockstep): the
// truth here is the in-process run, a separate path through the same
// libraries, and the comparison is exact.
#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/scenario.h"
#include "server/client.h"
#include "server/host.h"
#include "server/server.h"
#include "sensor/cell.h"
#include "tracker/master.h"

using namespace vts;
using namespace vts::server;
using Catch::Matchers::Contains;

namespace {

HostOptions box_options(std::uint64_t seed = 5) {
  HostOptions o;
  o.sim.seed = seed;
  o.sim.cell.seed = seed;
  o.sim.cell.standoff_mm = sim_standoff_mm(o.sim.scanner);
  return o;
}

// A server on a free loopback port, run on its own thread for the test's life.
struct Running {
  explicit Running(const HostOptions& ho, ServerOptions so = {}) : host(ho) {
    so.port = 0;
    server = std::make_unique<Server>(host, so);
    thread = std::thread([this] { server->run(); });
  }
  ~Running() {
    server->stop();
    thread.join();
  }
  CellHost host;
  std::unique_ptr<Server> server;
  std::thread thread;
};

// A raw socket for the tests that send what no client library would.
struct Raw {
  explicit Raw(int port) {
    fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
  }
  ~Raw() { ::close(fd); }
  void send(const std::string& s) const {
    std::size_t off = 0;
    while (off < s.size()) {
      const ssize_t n = ::send(fd, s.data() + off, s.size() - off, MSG_NOSIGNAL);
      if (n <= 0) return;  // the server may close on us: that is what some tests check
      off += static_cast<std::size_t>(n);
    }
  }
  // The next line, or "" when the server closed the connection.
  std::string line() {
    while (true) {
      if (const auto nl = in.find('\n'); nl != std::string::npos) {
        std::string l = in.substr(0, nl);
        in.erase(0, nl + 1);
        return l;
      }
      char buf[4096];
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) return "";
      in.append(buf, static_cast<std::size_t>(n));
    }
  }
  Json answer() {
    const std::string l = line();
    return l.empty() ? Json() : Json::parse(l);
  }
  int fd = -1;
  std::string in;
};

}  // namespace

TEST_CASE("LineBuffer splits a byte stream into lines, across reads and with CRLF", "[server]") {
  LineBuffer b(16);
  std::vector<std::string> got;
  auto on = [&](std::string_view l) { got.emplace_back(l); };
  REQUIRE(b.feed("ab", on));
  REQUIRE(b.feed("c\r\nd\n\nef", on));
  CHECK(got == std::vector<std::string>{"abc", "d", ""});
  CHECK(b.pending() == 2);
  REQUIRE(b.feed("\n", on));
  CHECK(got.back() == "ef");
  // 16 bytes without a newline fit; the 17th breaks the framing.
  CHECK(b.feed(std::string(16, 'x'), on));
  CHECK_FALSE(b.feed("y", on));
  CHECK(b.pending() == 0);
}

TEST_CASE("parse_request: a command object or the bad_json answer", "[server]") {
  auto req = parse_request(R"({"id": 3, "cmd": "time"})");
  REQUIRE(std::holds_alternative<Request>(req));
  CHECK(std::get<Request>(req).cmd == "time");
  CHECK(std::get<Request>(req).id == 3);
  for (const char* bad : {"", "nonsense", "[1,2]", "{\"cmd\": 3}", "{\"id\": [1], \"cmd\": \"time\"}", "\"cmd\"",
                          "{\"cmd\": \"time\"", "{\"cmd\": \"\xff\"}"}) {
    INFO(bad);
    auto r = parse_request(bad);
    REQUIRE(std::holds_alternative<Json>(r));
    CHECK(std::get<Json>(r)["error"] == "bad_json");
  }
  // The id is echoed even when the rest is wrong.
  CHECK(std::get<Json>(parse_request(R"({"id": "a", "cmd": 1})"))["id"] == "a");
}

TEST_CASE("pose_field reads a rotation matrix exactly and refuses a non-rotation", "[server]") {
  Pose3 p = Pose3::Identity();
  p.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(600.125, -1e-7, 3.0 / 7.0);
  Json body;
  body["pose"] = Json::parse(to_line(to_json(p)));  // through text and back
  const Pose3 q = pose_field(body, "pose");
  CHECK(q.matrix() == p.matrix());  // exact: shortest round-trip text
  body["pose"]["R"][0][0] = 1.01;
  CHECK_THROWS_WITH(pose_field(body, "pose"), Contains("pose = ") && Contains("not a rotation"));
  body["pose"] = Json::parse(R"({"t": [0, 0], "R": [[1,0,0],[0,1,0],[0,0,1]]})");
  CHECK_THROWS_WITH(pose_field(body, "pose"), Contains("expected [x, y, z]"));
  body["pose"] = Json::parse(R"({"t": [0, 0, 0], "R": [[-1,0,0],[0,1,0],[0,0,1]]})");
  CHECK_THROWS_WITH(pose_field(body, "pose"), Contains("determinant"));
}

TEST_CASE("CellHost: hello first, one controller, observers read only", "[server][gl]") {
  CellHost host(box_options());
  Peer a, b;
  a.id = 1;
  b.id = 2;
  CHECK(host.handle_line(R"({"cmd": "time"})", a)["error"] == "no_hello");
  const Json v = host.handle_line(R"({"cmd": "hello", "protocol": 2})", a);
  CHECK(v["error"] == "version");
  CHECK(v["server_protocol"] == 1);
  CHECK(host.handle_line(R"({"cmd": "hello", "role": "control"})", a)["role"] == "control");
  CHECK(host.handle_line(R"({"id": 9, "cmd": "hello", "role": "control"})", b)["error"] == "busy");
  CHECK(host.handle_line(R"({"cmd": "hello", "role": "observe"})", b)["ok"] == true);
  CHECK(host.handle_line(R"({"cmd": "sensor.laser_on"})", b)["error"] == "not_controller");
  CHECK(host.handle_line(R"({"cmd": "step", "dt_s": 1})", b)["error"] == "not_controller");
  CHECK(host.handle_line(R"({"cmd": "sensor.state"})", b)["state"] == "idle");
  CHECK(host.handle_line(R"({"cmd": "fly"})", a)["error"] == "unknown_command");
  const Json e = host.handle_line(R"({"cmd": "step", "dt_s": -1})", a);
  CHECK(e["error"] == "bad_argument");
  CHECK_THAT(e["message"].get<std::string>(), Contains("dt_s = -1"));
  CHECK(host.handle_line(R"({"cmd": "step", "dt_s": 0.5})", a)["time_s"] == 0.5);
  CHECK(host.handle_line(R"({"cmd": "step", "to_s": 0.5})", a)["error"] == "bad_argument");
  // The controller leaves: control is free again.
  host.disconnected(a);
  CHECK(host.handle_line(R"({"cmd": "hello", "role": "control"})", b)["role"] == "control");
}

TEST_CASE("CellHost: a linear move takes distance / speed, and the sensor sees the path", "[server][gl]") {
  CellHost host(box_options());
  Peer a;
  host.handle_line(R"({"cmd": "hello", "role": "control"})", a);
  const Json p0 = host.handle_line(R"({"cmd": "robot.pose"})", a)["world_from_tool"];
  Json to = p0;
  to["t"][0] = p0["t"][0].get<double>() + 30.0;
  Json m;
  m["cmd"] = "robot.move";
  m["world_from_tool"] = to;
  m["speed_mm_s"] = 10.0;
  CHECK(host.handle_line(m.dump(), a)["ok"] == true);
  const Json s1 = host.handle_line(R"({"cmd": "step", "to_s": 1.5})", a);
  CHECK(s1["events"].empty());
  const Json mid = host.handle_line(R"({"cmd": "robot.pose"})", a);
  CHECK(mid["moving"] == true);
  CHECK(mid["world_from_tool"]["t"][0].get<double>() == Approx(p0["t"][0].get<double>() + 15.0).margin(1e-9));
  const Json s2 = host.handle_line(R"({"cmd": "step", "to_s": 4})", a);
  REQUIRE(s2["events"].size() == 1);
  CHECK(s2["events"][0]["event"] == "move-done");
  CHECK(s2["events"][0]["time_s"].get<double>() == Approx(3.0));  // the segment's end, not the step's
  CHECK(host.handle_line(R"({"cmd": "robot.pose"})", a)["world_from_tool"]["t"] == to["t"]);
}

TEST_CASE("The C++ master through vts::client welds exactly as vts sim does in process", "[server][gl]") {
  const HostOptions ho = box_options(5);
  const SimRun local = run_sim(ho.sim);
  REQUIRE(local.completed());

  Running srv(ho);
  client::Client c("127.0.0.1", srv.server->port(), "control", "test-master");
  CHECK(c.hello()["mode"] == "lockstep");
  client::RemoteSensor sensor(c);
  const Json job = c.request("sim.job");
  const SimRig rig = make_sim_rig(ho.sim);  // the master's parameters and plan, as the host has them
  CHECK(job["master"]["search_margin_mm"].get<double>() == rig.master.search_margin_mm);
  tracker::Master master(rig.master);
  const tracker::MasterResult r =
      master.run(sensor, client::pose_from_json(job["world_from_workpiece"]), rig.run.cell.plan);
  const std::vector<SeamMetrics> m = evaluate(rig.run.cell, r);
  REQUIRE(m.size() == local.metrics.size());
  for (std::size_t k = 0; k < m.size(); ++k) {
    INFO("seam " << k + 1);
    CHECK(m[k].failure == local.metrics[k].failure);
    CHECK(m[k].end_found);
    CHECK(m[k].rms_lateral_mm == local.metrics[k].rms_lateral_mm);
    CHECK(m[k].rms_vertical_mm == local.metrics[k].rms_vertical_mm);
    CHECK(m[k].max_error_mm == local.metrics[k].max_error_mm);
    CHECK(m[k].start_error_mm == local.metrics[k].start_error_mm);
    CHECK(m[k].end_error_mm == local.metrics[k].end_error_mm);
    CHECK(m[k].search_mm == local.metrics[k].search_mm);
    CHECK(m[k].welded_mm == local.metrics[k].welded_mm);
    CHECK(m[k].sensor_rms_mm == local.metrics[k].sensor_rms_mm);
    CHECK(m[k].points == local.metrics[k].points);
  }
  CHECK(r.samples.size() == local.result.samples.size());
  CHECK(sensor.counters().profiles == local.profiles);
}

TEST_CASE("Server: garbage, oversized and half lines, silent and slow clients, and the others are served", "[server][gl]") {
  ServerOptions so;
  so.max_queue_bytes = 1 << 20;
  Running srv(box_options(), so);
  const int port = srv.server->port();
  {  // a controller that commands a 20 s step and leaves before the answers
    Raw r(port);
    r.send("{\"cmd\":\"hello\",\"role\":\"control\"}\n{\"cmd\":\"sensor.laser_on\"}\n"
           "{\"cmd\":\"step\",\"dt_s\":20}\n");
  }
  // Control is free once the server has seen the disconnect.
  std::unique_ptr<client::Client> owner;
  for (int i = 0; i < 200 && !owner; ++i) {
    try {
      owner = std::make_unique<client::Client>("127.0.0.1", port, "control");
    } catch (const client::Error& e) {
      REQUIRE(e.code == "busy");
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  REQUIRE(owner);
  client::Client& ctl = *owner;
  CHECK(ctl.request("time")["time_s"] == 20.0);  // the step completed, its answer went nowhere

  {  // garbage: an error answer, the connection stays
    Raw r(port);
    r.send("\x01\x02 not json\n{\"cmd\":\"hello\"}\n");
    CHECK(r.answer()["error"] == "bad_json");
    CHECK(r.answer()["ok"] == true);
  }
  {  // a line over 64 KiB: too_long, then the server closes
    Raw r(port);
    r.send(std::string(70000, 'a'));
    CHECK(r.answer()["error"] == "too_long");
    CHECK(r.line().empty());
  }
  {  // half a message, then gone
    Raw r(port);
    r.send("{\"cmd\":\"hel");
  }
  // A client that subscribes to profiles and never reads: dropped once its
  // queue passes the limit (1 MB here, about 80 profiles), not kept growing.
  Raw silent(port);
  silent.send("{\"cmd\":\"hello\"}\n{\"cmd\":\"subscribe\",\"profiles\":true}\n");
  ctl.request("sensor.laser_on");
  for (int i = 0; i < 40 && srv.server->stats().dropped_slow == 0; ++i) {
    Json s;
    s["dt_s"] = 5.0;  // 100 profiles a step
    ctl.request("step", s);
  }
  CHECK(srv.server->stats().dropped_slow == 1);
  CHECK(srv.server->stats().max_queue <= so.max_queue_bytes);
  CHECK(srv.server->stats().too_long == 1);
  // The controller is still served.
  CHECK(ctl.request("time")["time_s"].get<double>() > 0.0);
}

TEST_CASE("Server: observers receive every profile and event the controller causes", "[server][gl]") {
  Running srv(box_options());
  const int port = srv.server->port();
  client::Client ctl("127.0.0.1", port, "control");
  std::vector<std::unique_ptr<client::Client>> obs;
  for (int i = 0; i < 5; ++i) {
    obs.push_back(std::make_unique<client::Client>("127.0.0.1", port, "observe"));
    Json s;
    s["profiles"] = true;
    obs.back()->request("subscribe", s);
  }
  ctl.request("sensor.laser_on");
  Json s;
  s["to_s"] = 2.0;
  ctl.request("step", s);  // profiles 1..40 at 20 Hz (k / 20 in (0, 2])
  for (auto& o : obs) {
    std::vector<std::int64_t> idx;
    while (auto e = o->next_event(std::chrono::seconds(10)))
      if ((*e)["event"] == "profile") {
        idx.push_back((*e)["profile"]["index"].get<std::int64_t>());
        if (idx.size() == 40) break;
      }
    REQUIRE(idx.size() == 40);
    for (std::size_t i = 0; i < idx.size(); ++i) CHECK(idx[i] == static_cast<std::int64_t>(i));
  }
}

TEST_CASE("CellHost serves a built-in cell: every profile carries its joint's truth, and the tracker reads it", "[server][gl]") {
  for (const char* name : {"butt", "vgroove", "fillet"}) {
    INFO(name);
    HostOptions o;
    o.cell = builtin_cell(name);
    REQUIRE(o.cell);
    CellHost host(o);
    Peer a;
    host.handle_line(R"({"cmd": "hello", "role": "control"})", a);
    const Json job = host.handle_line(R"({"cmd": "sim.job"})", a);
    CHECK(job["cell"] == name);
    CHECK(job["joint"] == name);
    // The torch starts where the sensor sees the cell path's first profile:
    // kCellLookaheadMm ahead along the seam of the TCP.
    const Eigen::Vector3d seam_start = client::vec3_from_json(job["seams"][0]["start"]);
    const Pose3 tool = client::pose_from_json(job["world_from_tool_start"]);
    const Pose3 laser = tool * client::pose_from_json(job["sensor"]["tool_from_sensor"]);
    CHECK((laser.translation() - tool.translation()).dot(Eigen::Vector3d(client::vec3_from_json(job["seams"][0]["end"]) - seam_start).normalized()) ==
          Approx(kCellLookaheadMm));
    host.handle_line(R"({"cmd": "sensor.laser_on"})", a);
    host.handle_line(R"({"cmd": "sensor.search_start"})", a);
    host.handle_line(R"({"cmd": "step", "dt_s": 1.0})", a);
    const Json p = host.handle_line(R"({"cmd": "sensor.profile"})", a)["profile"];
    REQUIRE(p["truth"]["in_window"] == true);
    const Json j = host.handle_line(R"({"cmd": "sensor.joint"})", a)["joint"];
    REQUIRE(!j.is_null());
    CHECK(j["profile_index"] == p["index"]);
    // The truth (analytic, pipeline/profile_truth.h) against the reading, in the sensor frame.
    const double dy = j["track_point_sensor"][0].get<double>() - p["truth"]["track_point"]["y"].get<double>();
    const double dz = j["track_point_sensor"][1].get<double>() - p["truth"]["track_point"]["z"].get<double>();
    CHECK(std::hypot(dy, dz) < 0.3);
  }
  HostOptions plate;
  plate.cell = builtin_cell("plate");
  CHECK_THROWS_WITH(CellHost(plate), Contains("no workpiece has a joint"));
}

TEST_CASE("An arm with absolute-accuracy errors: the sensor's world points are off, the guided torch is not", "[server][gl]") {
  // KUKA KR 16 whose flange lands 0.5-0.7 mm from where its controller
  // believes (robot/arm.h perturbed, seed 3): the sensor's data are stamped
  // with the believed pose, so its joint points are off by that much in
  // world coordinates; the torch, guided by them, follows the seam within
  // servo lag. Truth: the box's analytic seams.
  HostOptions ho = box_options(5);
  ho.robot = "kr16";
  ho.robot_seed = 3;
  Running srv(ho);
  client::Client c("127.0.0.1", srv.server->port(), "control");
  client::RemoteSensor sensor(c);
  const Json job = c.request("sim.job");
  const SimRig rig = make_sim_rig(ho.sim);
  std::vector<std::pair<int, Eigen::Vector3d>> weld;  // seam, actual TCP
  tracker::Master master(rig.master);
  const tracker::MasterResult r = master.run(sensor, client::pose_from_json(job["world_from_workpiece"]), rig.run.cell.plan,
                                             [&](const tracker::MasterSample& s) {
                                               if (s.phase == tracker::Phase::Weld)
                                                 weld.emplace_back(s.seam, sensor.last_actual().translation());
                                             });
  REQUIRE(r.seams.size() == 2);
  for (int k = 0; k < 2; ++k) {
    INFO("seam " << k + 1);
    CHECK(r.seams[static_cast<std::size_t>(k)].end_found);
    const SimSeamTruth& truth = rig.run.cell.truth[static_cast<std::size_t>(k)];
    double torch = 0.0, points = 0.0;
    int n = 0;
    for (const auto& [seam, tcp] : weld)
      if (seam == k) {
        const PointError e = seam_error(truth, tcp);
        torch += e.lateral_mm * e.lateral_mm + e.vertical_mm * e.vertical_mm;
        ++n;
      }
    for (const Eigen::Vector3d& p : r.seams[static_cast<std::size_t>(k)].track_points) {
      const PointError e = seam_error(truth, p);
      points += e.lateral_mm * e.lateral_mm + e.vertical_mm * e.vertical_mm;
    }
    REQUIRE(n > 100);
    CHECK(std::sqrt(torch / n) < 0.2);
    CHECK(std::sqrt(points / r.seams[static_cast<std::size_t>(k)].track_points.size()) > 0.3);
  }
}

TEST_CASE("An arm stops on a pose it cannot reach, says why, and refuses motion after", "[server][gl]") {
  HostOptions ho = box_options(5);
  ho.robot = "irb2400";
  CellHost host(ho);
  Peer a;
  host.handle_line(R"({"cmd": "hello", "role": "control"})", a);
  Json far = host.handle_line(R"({"cmd": "robot.pose"})", a)["world_from_tool"];
  CHECK(host.handle_line(R"({"cmd": "robot.pose"})", a)["joints_deg"].size() == 6);
  far["t"][2] = far["t"][2].get<double>() + 2000.0;  // 2 m straight up: out of reach
  Json m;
  m["cmd"] = "robot.move";
  m["world_from_tool"] = far;
  m["speed_mm_s"] = 500.0;
  CHECK(host.handle_line(m.dump(), a)["ok"] == true);
  const Json s = host.handle_line(R"({"cmd": "step", "dt_s": 5})", a);
  bool fault = false;
  for (const Json& e : s["events"]) fault = fault || e["event"] == "robot-fault";
  CHECK(fault);
  const Json pose = host.handle_line(R"({"cmd": "robot.pose"})", a);
  CHECK_THAT(pose["fault"].get<std::string>(), Contains("out of reach") || Contains("singular") || Contains("axis"));
  const Json refused = host.handle_line(m.dump(), a);
  CHECK(refused["error"] == "failed");
  CHECK_THAT(refused["message"].get<std::string>(), Contains("stopped on a fault"));
}

TEST_CASE("vts serve hosts a vts sim scenario: its arm, curved seam and program, welded from outside", "[server]") {
  // s-curve: the KR 16, seam 1 an S; the master's parameters (move speed,
  // settling) come with sim.job. The arm starts elsewhere than in vts sim
  // (above the workpiece, not at the first search pose), so the runs are
  // close, not identical.
  const Scenario sc = builtin_scenario("s-curve");
  HostOptions ho;
  ho.sim = sc.spec;
  ho.robot = sc.spec.robot;
  ho.robot_seed = sc.spec.robot_seed;
  const SimRun local = run_sim(sc.spec);
  REQUIRE(local.completed());

  Running srv(ho);
  client::Client c("127.0.0.1", srv.server->port(), "control", "test-master");
  c.hello();
  client::RemoteSensor sensor(c);
  const Json job = c.request("sim.job");
  CHECK(job["master"]["move_speed_mm_s"].get<double>() == kArmMoveSpeedMmS);
  const SimRig rig = make_sim_rig(sc.spec);
  // The real TCP of each cycle, as the simulator knew it.
  std::vector<Pose> actual;
  const tracker::MasterResult r =
      tracker::Master(rig.master).run(sensor, client::pose_from_json(job["world_from_workpiece"]), rig.run.cell.plan,
                                      [&](const tracker::MasterSample&) { actual.push_back(sensor.last_actual()); });
  const Json truth = c.request("sim.truth");
  CHECK(truth["seams"][0]["path"].size() == rig.run.cell.truth[0].path.size());
  CHECK_FALSE(truth["seams"][1].contains("path"));
  const std::vector<SeamMetrics> m = evaluate(rig.run.cell, r, &actual);
  REQUIRE(m.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    INFO("seam " << k + 1 << ": " << m[k].failure);
    CHECK(m[k].failure.empty());
    CHECK(m[k].end_found);
    CHECK(m[k].rms_lateral_mm < kScenarioRmsMm);
    CHECK(m[k].max_error_mm < kScenarioMaxMm);
    CHECK(std::abs(m[k].rms_lateral_mm - local.metrics[k].rms_lateral_mm) < 0.05);
  }
}
