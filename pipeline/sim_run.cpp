#include "pipeline/sim_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "pipeline/robot_sensor.h"
#include "robot/arm_robot.h"
#include "sensor/recorded_sensor.h"
#include "sensor/reference_source.h"
#include "sensor/virtual_sensor.h"

namespace vts {
namespace {

namespace fs = std::filesystem;
namespace tk = vts::tracker;

double rotation_angle_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / std::numbers::pi;
}

// Every per-column vector of a Profile, in a fixed order.
template <class P, class F>
void for_each_column(P& p, F&& f) {
  f(p.y_mm), f(p.z_mm), f(p.range_mm), f(p.valid), f(p.cos_incidence), f(p.camera_visible), f(p.intensity),
      f(p.true_y_mm), f(p.true_z_mm), f(p.true_valid);
}
template <class T>
void put(std::ostream& out, const T& v) { out.write(reinterpret_cast<const char*>(&v), sizeof v); }
template <class T>
void get(std::istream& in, T& v) { in.read(reinterpret_cast<char*>(&v), sizeof v); }

}  // namespace

SimRig make_sim_rig(const SimSpec& spec, const std::function<void(const Profile&)>& record) {
  SimRig rig;
  SimRun& run = rig.run;
  run.cell = build_sim_cell(spec.cell);
  run.scanner = spec.scanner;
  run.scanner.tool_from_laser = run.cell.tool_from_laser;
  if (const std::string why = validate(run.scanner); !why.empty()) throw std::invalid_argument("scanner: " + why);

  std::unique_ptr<tk::ProfileStream> stream;
  if (!spec.replay.empty()) {
    auto rec = RecordedProfileStream::open(spec.replay);  // throws ExrError naming the file
    // The control unit keeps its configuration; the head's rate is the recording's.
    run.scanner.rate_hz = rec->recording().info.scanner.rate_hz;
    stream = std::move(rec);
    run.source_name = "replay";
  } else {
    if (!run.cell.moving_part.triangles.empty()) {
      // The box lifting off the plate: an Embree instance that moves.
      if (spec.source != SourceKind::Reference)
        throw std::invalid_argument("distortion_lift_deg_per_100mm: the " + std::string(to_string(spec.source)) +
                                    " source scans a rigid part; the lifting wall needs source: reference");
      rig.source = make_reference_source(run.scanner, run.cell.fixed_part, 0, &run.cell.moving_part);
    } else {
      rig.source = make_source(spec.source, run.scanner, run.cell.mesh);
    }
    auto vs = std::make_unique<VirtualProfileStream>(*rig.source, spec.seed);
    if (record) vs->record = record;
    rig.head = vs.get();
    stream = std::move(vs);
    run.source_name = std::string(to_string(spec.source));
  }
  rig.sensor = std::make_unique<tk::SensorUnit>(std::move(stream), sim_tracker_params(run.scanner, spec.cell.standoff_mm));
  rig.master = sim_master_params(run.cell, spec.speed_mm_s, run.scanner.rate_hz);
  if (spec.robot != "perfect") {
    rig.master.move_speed_mm_s = kArmMoveSpeedMmS;
    rig.master.settle_s = kArmSettleS;
  }
  rig.master.weave = spec.weave;
  if (spec.search_margin_mm) rig.master.search_margin_mm = *spec.search_margin_mm;
  run.robot = spec.robot;
  return rig;
}

CellRig make_cell_rig(const Cell& cell, SourceKind source, std::uint64_t seed) {
  CellRig rig;
  rig.cell = cell;
  rig.workpiece = -1;
  for (std::size_t k = 0; k < cell.workpieces.size() && rig.workpiece < 0; ++k)
    if (cell.workpieces[k].has_joint() && tracker_joint(cell.workpieces[k].type)) rig.workpiece = static_cast<int>(k);
  if (rig.workpiece < 0) throw std::invalid_argument("cell " + cell.name + ": no workpiece has a joint the tracker knows");
  const Workpiece& w = cell.workpieces[static_cast<std::size_t>(rig.workpiece)];
  // The path's standoff: its first laser origin's distance from the seam line.
  const Vec3 o = cell.path.pose_at(0).translation() - w.seam_origin();
  const Vec3 d = w.seam_direction();
  rig.standoff_mm = (o - o.dot(d) * d).norm();
  rig.scanner = cell.scanner;
  rig.scanner.tool_from_laser = Pose::Identity();
  rig.scanner.tool_from_laser.translation() = Vec3(kCellLookaheadMm, 0.0, -rig.standoff_mm);
  if (const std::string why = validate(rig.scanner); !why.empty()) throw std::invalid_argument("scanner: " + why);
  rig.source = make_source(source, rig.scanner, cell.mesh());
  rig.source_name = std::string(to_string(source));
  tk::TrackerParams params = sim_tracker_params(rig.scanner, rig.standoff_mm);
  params.joint = *tracker_joint(w.type);
  if (params.joint == tk::JointType::Lap && !w.is_mesh()) params.lap.upper_thickness_mm = w.params.thickness_mm;
  rig.sensor = std::make_unique<tk::SensorUnit>(std::make_unique<VirtualProfileStream>(*rig.source, seed), params);
  return rig;
}

SimRun run_sim(const SimSpec& spec, const std::function<void(const Profile&)>& record) {
  SimRig rig = make_sim_rig(spec, record);
  SimRun& run = rig.run;
  {
    RobotSensor loop(rig.sensor.get(), rig.head, spec.robot, spec.robot_seed);
    SeamDistortion distortion(run.cell);
    if (spec.cell.distorted()) loop.distortion = &distortion;
    run.result = tk::Master(rig.master).run(loop, run.cell.nominal_world_from_workpiece, run.cell.plan);
    run.actual_tcp = loop.actual();
    run.robot_fault = loop.fault();
    if (const auto* arm = dynamic_cast<const robot::ArmRobot*>(loop.robot())) {
      run.arm = SimRun::ArmTrace{arm->as_built(), arm->setup().world_from_base, arm->setup().flange_from_tool,
                                 loop.joints()};
    }
  }
  run.metrics = evaluate(run.cell, run.result, &run.actual_tcp);
  run.profiles = rig.sensor->counters().profiles;
  if (spec.open_loop) {
    // The same program and robot without the sensor.
    tk::MasterParams blind = rig.master;
    blind.open_loop = true;
    RobotSensor loop(nullptr, nullptr, spec.robot, spec.robot_seed);
    run.open_loop = tk::Master(blind).run(loop, run.cell.nominal_world_from_workpiece, run.cell.plan);
    run.open_loop_tcp = loop.actual();
    run.open_loop_fault = loop.fault();
    run.open_loop_metrics = evaluate(run.cell, run.open_loop, &run.open_loop_tcp);
    for (auto& m : run.open_loop_metrics)
      if (m.failure.empty() && !run.open_loop_fault.empty()) m.failure = run.open_loop_fault;
  }
  return std::move(run);
}

bool SimRun::completed() const {
  bool ok = true;
  for (const auto& m : metrics) ok = ok && m.welded && m.end_found && m.failure.empty();
  return ok && robot_fault.empty();
}

double SimRun::sim_time_s() const { return result.samples.empty() ? 0.0 : result.samples.back().time_s; }

double SimRun::offset_mm() const {
  return (cell.actual_world_from_workpiece.translation() - cell.nominal_world_from_workpiece.translation()).norm();
}

double SimRun::rotation_deg() const {
  return rotation_angle_deg(cell.nominal_world_from_workpiece, cell.actual_world_from_workpiece);
}

std::string sim_timeseries_csv(const SimRun& run) {
  const SimCell& cell = run.cell;
  std::ostringstream f;
  {
    f << "time_s,seam,phase,sensor_state,tcp_x_mm,tcp_y_mm,tcp_z_mm,q_w,q_x,q_y,q_z,s_mm,"
         "true_x_mm,true_y_mm,true_z_mm,lateral_error_mm,vertical_error_mm,cmd_x_mm,cmd_y_mm,cmd_z_mm,weave_mm\n";
    char buf[512];
    const auto& samples = run.result.samples;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const auto& s = samples[i];
      const Pose tcp = sample_tcp(run.result, &run.actual_tcp, i);
      const Vec3 p = tcp.translation();
      const Eigen::Quaterniond q = rotation_quat(tcp);
      std::snprintf(buf, sizeof buf, "%.4f,%d,%s,%s,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.6f,%.4f", s.time_s,
                    s.seam + 1, std::string(tk::to_string(s.phase)).c_str(),
                    std::string(tk::to_string(s.sensor)).c_str(), p.x(), p.y(), p.z(), q.w(), q.x(), q.y(),
                    q.z(), s.s_mm);
      f << buf;
      if (s.phase == tk::Phase::Weld && s.seam >= 0 && s.seam < static_cast<int>(cell.truth.size())) {
        const PointError e = seam_error(cell.truth[s.seam], weld_centre(run.result, &run.actual_tcp, i));
        std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.4f,%.5f,%.5f", e.true_point.x(), e.true_point.y(),
                      e.true_point.z(), e.lateral_mm, e.vertical_mm);
        f << buf;
      } else {
        f << ",,,,,";
      }
      const Vec3 c = s.world_from_tool.translation();
      const double weave = s.weave_mm.dot(s.world_from_tool.linear().col(1));
      std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.4f,%.4f\n", c.x(), c.y(), c.z(), weave);
      f << buf;
    }
  }
  return f.str();
}

plot::Canvas sim_error_figure(const SimRun& run) {
  const SimCell& cell = run.cell;
  const tk::MasterResult& result = run.result;
  const std::vector<SeamMetrics>& metrics = run.metrics;
  const int n = static_cast<int>(cell.truth.size());
  plot::Canvas canvas(1100, 360 * n + 50);
  for (int k = 0; k < n; ++k) {
    std::vector<double> s, lat, ver;
    for (std::size_t i = 0; i < result.samples.size(); ++i) {
      const auto& smp = result.samples[i];
      if (smp.seam != k || smp.phase != tk::Phase::Weld) continue;
      const PointError e = seam_error(cell.truth[k], weld_centre(result, &run.actual_tcp, i));
      s.push_back(smp.s_mm);
      lat.push_back(e.lateral_mm);
      ver.push_back(e.vertical_mm);
    }
    // Scaled to the errors (the targets, 0.1 mm rms and 0.3 mm max, are
    // drawn when they fit).
    double lim = 0.01;
    for (double v : lat) lim = std::max(lim, 1.25 * std::abs(v));
    for (double v : ver) lim = std::max(lim, 1.25 * std::abs(v));
    const double len = std::max(10.0, s.empty() ? cell.truth[k].length() : s.back());
    const int top = 20 + 360 * k;
    plot::Chart chart(canvas, 90, top + 40, 1070, top + 300, 0.0, len, -lim, lim);
    chart.frame("seam " + std::to_string(k + 1) + ": TCP error from the true seam", "s [mm] along the weld",
                "error [mm]");
    const plot::Rgb grey{150, 150, 150}, blue{30, 90, 200}, orange{230, 120, 20};
    chart.polyline({0.0, len}, {0.0, 0.0}, grey);
    for (double target : {0.1, 0.3})
      if (target < lim) {
        chart.polyline({0.0, len}, {target, target}, grey);
        chart.polyline({0.0, len}, {-target, -target}, grey);
      }
    chart.polyline(s, lat, blue, 2);
    chart.polyline(s, ver, orange, 2);
    const SeamMetrics& m = metrics[k];
    char line[256];
    std::snprintf(line, sizeof line,
                  "rms lateral %.4f mm   rms vertical %.4f mm   max %.4f mm   start error %.3f mm   end error "
                  "%.3f mm   search %.1f mm",
                  m.rms_lateral_mm, m.rms_vertical_mm, m.max_error_mm, m.start_error_mm, m.end_error_mm,
                  m.search_mm);
    canvas.text(90, top + 334, line, {40, 40, 40});
    if (k < static_cast<int>(run.open_loop_metrics.size())) {
      // The program without the sensor, for scale (not drawn: millimetres).
      const SeamMetrics& o = run.open_loop_metrics[static_cast<std::size_t>(k)];
      std::snprintf(line, sizeof line, "open loop (no sensor): rms lateral %.3f mm   rms vertical %.3f mm   max %.3f mm",
                    o.rms_lateral_mm, o.rms_vertical_mm, o.max_error_mm);
      canvas.text(90, top + 362, line, {150, 40, 40});
    }
    canvas.text(90, top + 348,
                "blue: lateral (in the plate, towards the open side)   orange: vertical (along the plate normal)",
                {40, 40, 40});
  }
  return canvas;
}

trackio::Json seam_metrics_json(const SeamMetrics& m, int index) {
  trackio::Json j;
  j["seam"] = index + 1;
  j["rms_lateral_mm"] = m.rms_lateral_mm;
  j["rms_vertical_mm"] = m.rms_vertical_mm;
  j["max_error_mm"] = m.max_error_mm;
  j["start_error_mm"] = m.start_error_mm;
  j["end_error_mm"] = m.end_error_mm;
  j["start_along_mm"] = m.start_along_mm;
  j["end_along_mm"] = m.end_along_mm;
  j["search_mm"] = m.search_mm;
  j["welded_mm"] = m.welded_mm;
  j["start_found"] = m.start_found;
  j["end_found"] = m.end_found;
  j["lost"] = m.lost;
  j["failure"] = m.failure;
  j["sensor_rms_mm"] = m.sensor_rms_mm;
  j["sensor_max_gap_mm"] = m.sensor_max_gap_mm;
  j["points"] = m.points;
  j["rejected_points"] = m.rejected_points;
  j["refits"] = m.refits;
  return j;
}

trackio::Json sim_summary_json(const SimSpec& spec, const SimRun& run, double wall_time_s, double sim_wall_time_s) {
  trackio::Json j;
  const ScannerDesc& scanner = run.scanner;
  j["source"] = run.source_name;
  j["sensor"] = scanner.name;
  j["material"] = scanner.material;
  j["error_model"] = !scanner.ideal;
  j["seed"] = spec.seed;
  j["speed_mm_s"] = spec.speed_mm_s;
  j["rate_hz"] = scanner.rate_hz;
  j["workpiece_offset_mm"] = run.offset_mm();
  j["workpiece_rotation_deg"] = run.rotation_deg();
  j["robot"] = run.robot;
  j["robot_seed"] = spec.robot_seed;
  j["robot_fault"] = run.robot_fault;
  if (spec.weave.amplitude_mm > 0.0)
    j["weave"] = {{"amplitude_mm", spec.weave.amplitude_mm}, {"frequency_hz", spec.weave.frequency_hz},
                  {"dwell_s", spec.weave.dwell_s}};
  j["profiles"] = run.profiles;
  j["sim_time_s"] = run.sim_time_s();
  j["wall_time_s"] = wall_time_s;
  j["sim_wall_time_s"] = sim_wall_time_s;
  j["completed"] = run.completed();
  trackio::Json seams = trackio::Json::array();
  for (std::size_t k = 0; k < run.metrics.size(); ++k) {
    trackio::Json m = seam_metrics_json(run.metrics[k], static_cast<int>(k));
    if (k < run.open_loop_metrics.size()) {
      const SeamMetrics& o = run.open_loop_metrics[k];
      m["open_loop"] = {{"rms_lateral_mm", o.rms_lateral_mm}, {"rms_vertical_mm", o.rms_vertical_mm},
                        {"max_error_mm", o.max_error_mm},     {"start_error_mm", o.start_error_mm},
                        {"end_error_mm", o.end_error_mm},     {"failure", o.failure}};
    }
    seams.push_back(m);
  }
  j["seams"] = seams;
  return j;
}

ProfileSpool::ProfileSpool(const fs::path& path) : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw std::runtime_error("cannot create " + path.string());
}

ProfileSpool::~ProfileSpool() {
  std::error_code ec;
  out_.close();
  fs::remove(path_, ec);
}

void ProfileSpool::add(const Profile& p) {
  put(out_, p.index);
  put(out_, p.time_s);
  const Eigen::Matrix4d m = p.world_from_sensor.matrix();
  out_.write(reinterpret_cast<const char*>(m.data()), sizeof(double) * 16);
  for_each_column(p, [&](const auto& v) {
    out_.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof v[0]));
  });
  ++count_;
  points_ = p.size();
}

void ProfileSpool::write_exr(const fs::path& exr, ProfileFileInfo info) {
  out_.close();
  info.profiles = count_;
  ProfileExrWriter writer(exr, info);
  std::ifstream in(path_, std::ios::binary);
  Profile p;
  p.resize(points_);
  for (int i = 0; i < count_; ++i) {
    get(in, p.index);
    get(in, p.time_s);
    Eigen::Matrix4d m;
    in.read(reinterpret_cast<char*>(m.data()), sizeof(double) * 16);
    p.world_from_sensor.matrix() = m;
    for_each_column(p, [&](auto& v) {
      in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof v[0]));
    });
    if (!in) throw std::runtime_error("cannot read back the profile spool " + path_.string());
    writer.write(p);
  }
  writer.finish();
}

}  // namespace vts
