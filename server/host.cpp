#include "server/host.h"

#include <cmath>
#include <stdexcept>

#include "common/version.h"
#include "pipeline/profile_truth.h"
#include "pipeline/robot_sensor.h"
#include "robot/robots.h"
#include "sensor/sim_cell.h"

namespace vts::server {
namespace {

namespace tk = vts::tracker;

Json maybe(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json vec2(const tk::Vec2& v) { return Json::array({v.x(), v.y()}); }

Json event_json(tk::Event e, double time_s) {
  Json j;
  j["event"] = std::string(tk::to_string(e));
  j["time_s"] = time_s;
  return j;
}

Json unknown_command(const Request& r) {
  return error_answer(r.id, "unknown_command", "unknown command \"" + r.cmd + "\" (docs/PROTOCOL.md)");
}

struct Failed : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct NotController : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct WrongMode : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace

CellHost::CellHost(const HostOptions& options) : options_(options), step_events_(Json::array()) {
  Pose3 home = Pose3::Identity();
  if (options.cell) {
    cell_.emplace(make_cell_rig(*options.cell, options.sim.source, options.sim.seed));
    // The torch where the sensor sees the cell path's first profile.
    home = cell_->cell.path.pose_at(0) * cell_->scanner.tool_from_laser.inverse();
  } else {
    box_.emplace(make_sim_rig(options.sim));
    if (options.sim.cell.distorted()) distortion_.emplace(box_->run.cell);
    // Where the master's first move will take it from: the nominal
    // workpiece origin, 200 mm up, torch down.
    home.translation() = box_->run.cell.nominal_world_from_workpiece * Eigen::Vector3d(0.0, 0.0, 200.0);
    home.linear() = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  }
  robot_ = robot::make_robot(options.robot, options.robot_seed, home);
  arm_ = options.robot != "perfect";
  head_ = dynamic_cast<VirtualProfileStream*>(&sensor().stream());
  sensor().on_profile = [this](const tk::SensorProfile& p, const tk::TrackResult& r, const tk::JointData* j,
                               std::optional<tk::Event> e) {
    if (j) {
      joints_.push_back(*j);
      while (joints_.size() > kJointsHeld) {
        joints_dropped_index_ = joints_.front().profile_index;
        joints_.pop_front();
      }
      if (publish && subscribers_[static_cast<int>(Topic::Joint)] > 0) {
        Json m;
        m["event"] = "joint";
        m["joint"] = joint_json(*j);
        publish(m, Topic::Joint);
      }
    }
    if (e) {
      Json ev = event_json(*e, p.time_s);
      if (*e == tk::Event::StartFound && sensor().start_point()) ev["point"] = to_json(*sensor().start_point());
      if (*e == tk::Event::EndFound && sensor().end_point()) ev["point"] = to_json(*sensor().end_point());
      raise(ev);
    }
    if (publish && subscribers_[static_cast<int>(Topic::Profile)] > 0) {
      Json m;
      m["event"] = "profile";
      m["profile"] = profile_json(p, r);
      publish(m, Topic::Profile);
    }
  };
}

void CellHost::raise(const Json& event) {
  step_events_.push_back(event);
  if (publish) publish(event, Topic::Event);
}

CellHost::~CellHost() = default;

Json CellHost::profile_json(const tk::SensorProfile& p, const tk::TrackResult& r) const {
  Json prof;
  prof["index"] = p.index;
  prof["time_s"] = p.time_s;
  prof["world_from_sensor"] = to_json(p.world_from_sensor);
  Json y = Json::array(), z = Json::array(), v = Json::array();
  for (std::size_t i = 0; i < p.y_mm.size(); ++i) {
    const bool ok = i < p.valid.size() && p.valid[i];
    y.push_back(ok ? static_cast<double>(p.y_mm[i]) : 0.0);
    z.push_back(ok ? static_cast<double>(p.z_mm[i]) : 0.0);
    v.push_back(ok ? 1 : 0);
  }
  prof["y_mm"] = std::move(y);
  prof["z_mm"] = std::move(z);
  prof["valid"] = std::move(v);
  prof["status"] = std::string(tk::to_string(r.status));
  prof["reason"] = r.reason;
  prof["confidence"] = r.confidence;
  if (cell_) {
    // The joint's truth in this profile (pipeline/profile_truth.h), as a dataset labels it.
    const Workpiece& w = cell_->cell.workpieces[static_cast<std::size_t>(cell_->workpiece)];
    prof["truth"] = profile_truth_json(profile_truth(w, cell_->scanner, p.world_from_sensor));
  }
  return prof;
}


Json CellHost::joint_json(const tk::JointData& j) const {
  Json o;
  o["profile_index"] = j.profile_index;
  o["time_s"] = j.time_s;
  o["world_from_sensor"] = to_json(j.world_from_sensor);
  Json bps = Json::array();
  for (const auto& b : j.break_points) bps.push_back(b ? vec2(*b) : Json(nullptr));
  o["break_points_sensor"] = bps;
  o["track_point_sensor"] = vec2(j.track_point_sensor);
  o["track_point_world"] = to_json(j.track_point_world);
  o["gap_mm"] = maybe(j.gap_mm);
  o["angle_deg"] = maybe(j.angle_deg);
  o["confidence"] = j.confidence;
  return o;
}

Json CellHost::step(double to_s) {
  step_events_ = Json::array();
  auto run_to = [&](double t) {
    const bool faulted = !robot_->fault().empty();
    const bool done = robot_->advance(t);
    if (!faulted && !robot_->fault().empty()) {
      Json j;
      j["event"] = "robot-fault";
      j["time_s"] = t;
      j["message"] = robot_->fault();
      raise(j);
    }
    // The sensor's data are stamped with the pose the controller reports;
    // it scans where the arm really is.
    const Pose3 reported = robot_->reported_tcp();
    if (head_) place_head(*head_, *robot_, !arm_, distortion_ ? &*distortion_ : nullptr);
    const std::vector<tk::Event> ev = sensor().advance(t, reported);
    for (tk::Event e : ev) {
      if (e != tk::Event::StreamEnded) continue;  // the others came through on_profile
      Json j = event_json(e, t);
      j["message"] = sensor().error();
      raise(j);
    }
    if (done) {
      Json j;
      j["event"] = "move-done";
      j["time_s"] = t;
      raise(j);
    }
  };
  for (double b : robot_->breaks_before(to_s)) run_to(b);
  run_to(to_s);
  Json out = std::move(step_events_);
  step_events_ = Json::array();
  return out;
}

void CellHost::advance_to(double t) {
  if (t > robot_->time_s()) step(t);
}

void CellHost::subscribe(const Peer& peer, int add) {
  subscribers_[static_cast<int>(Topic::Event)] += peer.events ? add : 0;
  subscribers_[static_cast<int>(Topic::Profile)] += peer.profiles ? add : 0;
  subscribers_[static_cast<int>(Topic::Joint)] += peer.joints ? add : 0;
}

void CellHost::disconnected(Peer& peer) {
  if (peer.controller) controller_taken_ = false;
  peer.controller = false;
  subscribe(peer, -1);
  peer.events = peer.profiles = peer.joints = false;
}

void CellHost::require_control(const Request& r, const Peer& peer) const {
  if (!peer.controller)
    throw NotController(r.cmd + " needs the controlling client; this one observes (hello with \"role\": \"control\")");
}

Json CellHost::handle_line(std::string_view line, Peer& peer) {
  auto parsed = parse_request(line);
  if (auto* err = std::get_if<Json>(&parsed)) return std::move(*err);
  return handle(std::get<Request>(parsed), peer);
}

Json CellHost::handle(const Request& r, Peer& peer) {
  try {
    return dispatch(r, peer);
  } catch (const BadArgument& e) {
    return error_answer(r.id, "bad_argument", r.cmd + ": " + e.what());
  } catch (const NotController& e) {
    return error_answer(r.id, "not_controller", e.what());
  } catch (const WrongMode& e) {
    return error_answer(r.id, "wrong_mode", e.what());
  } catch (const Failed& e) {
    return error_answer(r.id, "failed", e.what());
  } catch (const std::exception& e) {
    return error_answer(r.id, "failed", r.cmd + ": " + e.what());
  }
}

Json CellHost::state_json() const {
  const tk::SensorInterface& s = sensor();
  Json o;
  o["state"] = std::string(tk::to_string(s.state()));
  o["start_point"] = s.start_point() ? to_json(*s.start_point()) : Json(nullptr);
  o["end_point"] = s.end_point() ? to_json(*s.end_point()) : Json(nullptr);
  const tk::SequenceCounters& c = s.counters();
  Json k;
  k["profiles"] = c.profiles;
  k["with_joint"] = c.joint_profiles;
  k["without_joint"] = c.invalid_profiles;
  k["longest_gap_mm"] = c.longest_gap_mm;
  o["counters"] = k;
  return o;
}

tk::SensorUnit& CellHost::sensor() const { return box_ ? *box_->sensor : *cell_->sensor; }

double CellHost::rate_hz() const { return box_ ? box_->run.scanner.rate_hz : cell_->scanner.rate_hz; }

std::string CellHost::cell_name() const { return box_ ? std::string("box") : cell_->cell.name; }

Json CellHost::job_json() const {
  const ScannerDesc& scanner = box_ ? box_->run.scanner : cell_->scanner;
  Json sensor_j;
  sensor_j["name"] = scanner.name;
  sensor_j["material"] = scanner.material;
  sensor_j["error_model"] = !scanner.ideal;
  sensor_j["rate_hz"] = scanner.rate_hz;
  sensor_j["points"] = scanner.points;
  sensor_j["tool_from_sensor"] = to_json(sensor().stream().tool_from_sensor());
  Json o;
  o["cell"] = cell_name();
  if (cell_) {
    // A cell of `vts cells` or a scene: its tracked joint's seam, where it
    // is (no displacement), and the torch pose at the path's first profile.
    const Workpiece& w = cell_->cell.workpieces[static_cast<std::size_t>(cell_->workpiece)];
    o["joint"] = std::string(tk::to_string(*tracker_joint(w.type)));
    Json seams = Json::array();
    if (!w.is_mesh()) {
      Json seam;
      seam["start"] = to_json(w.seam_origin());
      seam["end"] = to_json(Eigen::Vector3d(w.seam_origin() + w.params.length_mm * w.seam_direction()));
      seams.push_back(seam);
    }
    o["seams"] = seams;
    o["world_from_tool_start"] = to_json(Pose3(cell_->cell.path.pose_at(0) * cell_->scanner.tool_from_laser.inverse()));
    o["path_step_mm"] = cell_->cell.path.step_mm;
    o["path_profiles"] = cell_->cell.path.profiles;
    o["standoff_mm"] = cell_->standoff_mm;
    o["sensor"] = sensor_j;
    o["source"] = cell_->source_name;
    o["seed"] = options_.sim.seed;
    return o;
  }
  const SimRun& run = box_->run;
  const SimSpec& spec = options_.sim;
  Json seams = Json::array();
  for (const tk::SeamPlan& p : run.cell.plan) {
    Json s;
    s["start_mm"] = to_json(p.start_mm);
    s["end_mm"] = to_json(p.end_mm);
    s["plate_normal"] = to_json(p.plate_normal);
    s["wall_normal"] = to_json(p.wall_normal);
    if (!p.path.empty()) {
      // A curved seam (the saddle): the root with its normals; the weld
      // runs from weld_from_mm along it (tracker/master.h SeamPlan).
      Json path = Json::array();
      for (const tk::PathPoint& q : p.path)
        path.push_back({{"point", to_json(q.point)},
                        {"plate_normal", to_json(q.plate_normal)},
                        {"wall_normal", to_json(q.wall_normal)}});
      s["path"] = path;
      s["weld_from_mm"] = p.weld_from_mm;
    }
    seams.push_back(s);
  }
  const tk::MasterParams& m = box_->master;
  Json mp;
  mp["speed_mm_s"] = m.speed_mm_s;
  mp["control_rate_hz"] = m.control_rate_hz;
  mp["lookahead_mm"] = m.lookahead_mm;
  mp["search_margin_mm"] = m.search_margin_mm;
  mp["search_margin_recalibrated_mm"] = m.search_margin_recalibrated_mm;
  mp["search_extra_mm"] = m.search_extra_mm;
  mp["max_search_retries"] = m.max_search_retries;
  mp["end_margin_mm"] = m.end_margin_mm;
  mp["fit_window_mm"] = m.fit_window_mm;
  mp["gate_mm"] = m.gate_mm;
  mp["gate_after"] = m.gate_after;
  mp["direction_span_mm"] = m.direction_span_mm;
  mp["refit_after_rejections"] = m.refit_after_rejections;
  mp["recalibrate"] = m.recalibrate;
  mp["move_speed_mm_s"] = m.move_speed_mm_s;
  mp["settle_s"] = m.settle_s;
  mp["plan_tolerance_mm"] = m.plan_tolerance_mm;
  mp["weave"] = {{"amplitude_mm", m.weave.amplitude_mm}, {"frequency_hz", m.weave.frequency_hz},
                 {"dwell_s", m.weave.dwell_s}};
  o["seams"] = seams;
  o["world_from_workpiece"] = to_json(run.cell.nominal_world_from_workpiece);
  o["master"] = mp;
  o["sensor"] = sensor_j;
  o["source"] = run.source_name;
  o["seed"] = spec.seed;
  o["speed_mm_s"] = spec.speed_mm_s;
  return o;
}

Json CellHost::truth_json() const {
  Json o;
  Json seams = Json::array();
  if (cell_) {
    // Where it is planned: a served cell is not displaced. Each profile
    // carries its own truth ("truth" in sensor.profile and the pushes).
    const Json job = job_json();
    o["seams"] = job["seams"];
    o["joint"] = job["joint"];
    return o;
  }
  const SimRun& run = box_->run;
  for (const SimSeamTruth& t : run.cell.truth) {
    Json s;
    s["start"] = to_json(t.start);
    s["end"] = to_json(t.end);
    s["plate_normal"] = to_json(t.plate_normal);
    s["wall_normal"] = to_json(t.wall_normal);
    s["lateral"] = to_json(t.lateral());
    if (!t.path.empty()) {
      Json path = Json::array();
      for (const Vec3& q : t.path) path.push_back(to_json(q));
      s["path"] = path;
      if (t.path_lateral.size() == t.path.size() && t.path_plate_normal.size() == t.path.size()) {
        Json lat = Json::array(), nrm = Json::array();
        for (std::size_t i = 0; i < t.path.size(); ++i) {
          lat.push_back(to_json(t.path_lateral[i]));
          nrm.push_back(to_json(t.path_plate_normal[i]));
        }
        s["path_lateral"] = lat;
        s["path_plate_normal"] = nrm;
      }
    }
    seams.push_back(s);
  }
  o["seams"] = seams;
  o["world_from_workpiece"] = to_json(run.cell.actual_world_from_workpiece);
  o["workpiece_offset_mm"] = run.offset_mm();
  o["workpiece_rotation_deg"] = run.rotation_deg();
  return o;
}

Json CellHost::dispatch(const Request& r, Peer& peer) {
  const std::string& c = r.cmd;
  const Json& b = r.body;
  Json a = ok_answer(r.id);
  if (c == "hello") {
    const std::int64_t v = integer_field(b, "protocol", 0, 1000000, kProtocolVersion);
    if (v != kProtocolVersion) {
      Json e = error_answer(r.id, "version",
                            "this server speaks protocol " + std::to_string(kProtocolVersion) + ", not " +
                                std::to_string(v));
      e["server_protocol"] = kProtocolVersion;
      return e;
    }
    const std::string role = string_field(b, "role", "observe");
    if (role != "control" && role != "observe")
      throw BadArgument("role = \"" + role + "\": expected \"control\" or \"observe\"");
    if (role == "control" && !peer.controller) {
      if (controller_taken_) return error_answer(r.id, "busy", "another client controls the cell; observe instead");
      controller_taken_ = true;
      peer.controller = true;
    } else if (role == "observe" && peer.controller) {
      controller_taken_ = false;
      peer.controller = false;
    }
    peer.hello = true;
    peer.name = string_field(b, "client", peer.name);
    a["protocol"] = kProtocolVersion;
    a["server"] = "vts " + std::string(version());
    a["role"] = peer.controller ? "control" : "observe";
    a["mode"] = realtime() ? "realtime" : "lockstep";
    a["cell"] = cell_name();
    a["time_s"] = time_s();
    return a;
  }
  if (!peer.hello) return error_answer(r.id, "no_hello", "send hello first (docs/PROTOCOL.md, \"Session\")");

  if (c == "time") {
    a["time_s"] = time_s();
    a["mode"] = realtime() ? "realtime" : "lockstep";
  } else if (c == "step") {
    require_control(r, peer);
    if (realtime()) throw WrongMode("step: time runs by the wall clock (vts serve --realtime)");
    const bool has_to = b.contains("to_s"), has_dt = b.contains("dt_s");
    if (has_to == has_dt) throw BadArgument("to_s/dt_s: give exactly one");
    const double now = time_s();
    const double to = has_to ? number_field(b, "to_s", -1e300, 1e300) : now + number_field(b, "dt_s", 0.0, kMaxStepS);
    if (!(to > now)) throw BadArgument("to_s = " + Json(to).dump() + ": not after the current time " + Json(now).dump());
    if (to - now > kMaxStepS) throw BadArgument("to_s = " + Json(to).dump() + ": more than 60 s ahead");
    a["events"] = step(to);
    a["time_s"] = time_s();
    a["world_from_tool"] = to_json(robot_->reported_tcp());
    a["world_from_tool_actual"] = to_json(robot_->tcp());
  } else if (c == "sensor.laser_on") {
    require_control(r, peer);
    joints_.clear();  // as the unit's latest joint: nothing from before this laser-on
    a["confirmed"] = sensor().laser_on();
    if (!a["confirmed"].get<bool>()) a["message"] = sensor().error();
  } else if (c == "sensor.laser_off") {
    require_control(r, peer);
    sensor().laser_off();
  } else if (c == "sensor.search_start") {
    require_control(r, peer);
    joints_.clear();
    sensor().search_start();
  } else if (c == "sensor.start_tracking") {
    require_control(r, peer);
    sensor().start_tracking();
  } else if (c == "sensor.look_for_end") {
    require_control(r, peer);
    sensor().look_for_end();
  } else if (c == "sensor.idle") {
    require_control(r, peer);
    sensor().idle();
  } else if (c == "sensor.state") {
    a.update(state_json());
  } else if (c == "sensor.joint") {
    const auto j = sensor().latest_joint(time_s());
    if (j) {
      Json jj = joint_json(*j);
      jj["age_s"] = j->age_s;
      a["joint"] = jj;
    } else {
      a["joint"] = nullptr;
    }
  } else if (c == "sensor.joints") {
    const std::int64_t after = integer_field(b, "after_index", -1, INT64_MAX, -1);
    Json list = Json::array();
    for (const tk::JointData& j : joints_)
      if (j.profile_index > after) list.push_back(joint_json(j));
    a["joints"] = list;
    a["dropped"] = joints_dropped_index_ > after ? 1 : 0;
  } else if (c == "sensor.profile") {
    // The last profile: published form rebuilt from the unit.
    if (sensor().last_profile().y_mm.empty())
      a["profile"] = nullptr;
    else
      a["profile"] = profile_json(sensor().last_profile(), sensor().last_result());
  } else if (c == "robot.pose") {
    a["time_s"] = time_s();
    a["world_from_tool"] = to_json(robot_->reported_tcp());
    a["world_from_tool_actual"] = to_json(robot_->tcp());
    a["moving"] = robot_->moving();
    a["queued"] = robot_->queued();
    a["correction_mm"] = to_json(robot_->correction_mm());
    a["robot"] = options_.robot;
    if (const auto q = robot_->joints()) {
      Json jd = Json::array();
      for (int i = 0; i < 6; ++i) jd.push_back((*q)[i] * 180.0 / M_PI);
      a["joints_deg"] = jd;
    }
    a["fault"] = robot_->fault().empty() ? Json(nullptr) : Json(robot_->fault());
  } else if (c.rfind("robot.", 0) == 0) {
    require_control(r, peer);
    if (!robot_->fault().empty()) throw Failed(c + ": the robot stopped on a fault: " + robot_->fault());
    return robot_command(r);
  } else if (c == "sim.job") {
    a.update(job_json());
  } else if (c == "sim.truth") {
    a.update(truth_json());
  } else if (c == "subscribe") {
    const bool events = bool_field(b, "events", true), profiles = bool_field(b, "profiles", false),
               joints = bool_field(b, "joints", false);
    subscribe(peer, -1);
    peer.events = events;
    peer.profiles = profiles;
    peer.joints = joints;
    subscribe(peer, +1);
  } else {
    return unknown_command(r);
  }
  return a;
}

Json CellHost::robot_command(const Request& r) {
  const std::string& c = r.cmd;
  const Json& b = r.body;
  if (c == "robot.servo") {
    robot_->servo(pose_field(b, "world_from_tool"));
  } else if (c == "robot.move") {
    const Pose3 target = pose_field(b, "world_from_tool");
    const double speed = number_field(b, "speed_mm_s", 0.1, 2000.0);
    if (!robot_->move(target, speed, bool_field(b, "queue", false)))
      throw Failed("robot.move: " + std::to_string(robot::PerfectRobot::kMaxQueued) + " moves are queued already");
  } else if (c == "robot.stop") {
    robot_->stop();
  } else if (c == "robot.correct") {
    const Eigen::Vector3d off = vec3_field(b, "offset_mm");
    if (off.norm() > 100.0) throw BadArgument("offset_mm = " + to_json(off).dump() + ": longer than 100 mm");
    robot_->set_correction(off);
  } else {
    return unknown_command(r);
  }
  return ok_answer(r.id);
}

}  // namespace vts::server
