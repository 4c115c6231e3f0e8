#include "apps/vts_sim.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/plot.h"
#include "apps/scan.h"
#include "render/raster_source.h"
#include "sensor/presets.h"
#include "sensor/profile_exr.h"
#include "sensor/recorded_sensor.h"
#include "sensor/reference_source.h"
#include "sensor/sim_cell.h"
#include "sensor/virtual_sensor.h"
#include "tracker/master.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;
namespace tk = vts::tracker;
using Json = nlohmann::ordered_json;

struct SimOptions {
  std::string speed, rate, seed, offset, rotation, source, sensor, material, out_dir, replay;
  bool ideal = false;
  bool json = false;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void bad(const std::string& option, const std::string& value, const std::string& why) {
  throw UsageError(option + " = '" + value + "': " + why);
}

double parse_number(const std::string& option, const std::string& text, double lo, double hi,
                    const char* unit) {
  char* end = nullptr;
  const double v = text.empty() || std::isspace(static_cast<unsigned char>(text.front()))
                       ? std::numeric_limits<double>::quiet_NaN()
                       : std::strtod(text.c_str(), &end);
  if (!std::isfinite(v) || end != text.c_str() + text.size())
    bad(option, text, std::string("expected a number in ") + unit);
  if (v < lo || v > hi) {
    std::ostringstream s;
    s << "out of range: expected " << lo << " to " << hi << " " << unit;
    bad(option, text, s.str());
  }
  return v;
}

std::uint64_t parse_seed(const std::string& text) {
  std::uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size())
    bad("--seed", text, "expected an unsigned 64-bit integer (0 .. 18446744073709551615)");
  return v;
}

// Everything checked before anything is created.
struct SimPlan {
  SimCellParams cell;
  ScannerDesc scanner;
  double speed_mm_s = 10.0;
  bool reference = false;
  fs::path out_dir;
  fs::path replay;
  std::uint64_t seed = 1;
};

SimPlan plan_sim(const SimOptions& o) {
  SimPlan plan;
  if (!o.speed.empty()) plan.speed_mm_s = parse_number("--speed", o.speed, 0.1, 500.0, "mm/s");
  plan.seed = o.seed.empty() ? 1 : parse_seed(o.seed);
  plan.cell.seed = plan.seed;
  if (!o.offset.empty()) plan.cell.offset_mm = parse_number("--offset", o.offset, 0.0, 20.0, "mm");
  if (!o.rotation.empty()) plan.cell.rotation_deg = parse_number("--rotation", o.rotation, 0.0, 10.0, "degrees");

  ScannerDesc& sc = plan.scanner;
  if (!o.sensor.empty()) {
    const auto preset = sensor_preset(o.sensor);
    if (!preset)
      bad("--sensor", o.sensor, "unknown sensor; valid names: " + join_names(sensor_preset_names()));
    set_sensor_fields(sc, *preset);
  }
  if (!o.material.empty() && !apply_material(sc, o.material))
    bad("--material", o.material, "unknown material; valid names: " + join_names(material_names()));
  sc.ideal = o.ideal;
  if (!o.rate.empty()) sc.rate_hz = parse_number("--rate", o.rate, 1.0, 10000.0, "Hz");
  const std::string source = o.source.empty() ? "raster" : o.source;
  if (source != "raster" && source != "reference")
    bad("--source", o.source, "expected 'raster' or 'reference'");
  plan.reference = source == "reference";
  plan.cell.standoff_mm = sim_standoff_mm(sc);
  if (const std::string why = validate(plan.cell); !why.empty()) throw UsageError("cell: " + why);

  const std::string dir = o.out_dir.empty() ? std::string("sim") : o.out_dir;
  std::error_code ec;
  plan.out_dir = fs::absolute(dir, ec).lexically_normal();
  if (ec) bad("--out-dir", dir, "cannot make an absolute path: " + ec.message());
  if (fs::exists(plan.out_dir, ec) && !fs::is_directory(plan.out_dir, ec))
    bad("--out-dir", dir, "exists and is not a directory");
  if (!o.replay.empty()) {
    plan.replay = o.replay;
    if (!fs::is_regular_file(plan.replay, ec)) bad("--replay", o.replay, "no such file");
  }
  return plan;
}

// Writes to a temporary name in the same directory, renamed by commit().
class TempFile {
 public:
  explicit TempFile(fs::path final) : final_(std::move(final)) {
    tmp_ = final_;
    tmp_ += ".tmp-" + std::to_string(::getpid());
  }
  ~TempFile() {
    std::error_code ec;
    if (!committed_) fs::remove(tmp_, ec);
  }
  const fs::path& tmp() const { return tmp_; }
  void commit() {
    fs::rename(tmp_, final_);
    committed_ = true;
  }

 private:
  fs::path final_, tmp_;
  bool committed_ = false;
};

// The measured profiles of the run, spooled to a scratch file as they are
// taken (the EXR writer needs the row count up front), then converted.
class Spool {
 public:
  explicit Spool(const fs::path& path) : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
    if (!out_) throw std::runtime_error("cannot create " + path.string());
  }
  ~Spool() {
    std::error_code ec;
    out_.close();
    fs::remove(path_, ec);
  }
  void add(const Profile& p) {
    put(p.index);
    put(p.time_s);
    const Eigen::Matrix4d m = p.world_from_sensor.matrix();
    out_.write(reinterpret_cast<const char*>(m.data()), sizeof(double) * 16);
    for_each_column(p, [&](const auto& v) {
      out_.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof v[0]));
    });
    ++count_;
    points_ = p.size();
  }
  int count() const { return count_; }
  void write_exr(const fs::path& exr, ProfileFileInfo info) {
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

 private:
  template <class T>
  void put(const T& v) { out_.write(reinterpret_cast<const char*>(&v), sizeof v); }
  template <class T>
  static void get(std::istream& in, T& v) { in.read(reinterpret_cast<char*>(&v), sizeof v); }
  // Every per-column vector of a Profile, in a fixed order.
  template <class P, class F>
  static void for_each_column(P& p, F&& f) {
    f(p.y_mm), f(p.z_mm), f(p.range_mm), f(p.valid), f(p.cos_incidence), f(p.camera_visible), f(p.intensity),
        f(p.true_y_mm), f(p.true_z_mm), f(p.true_valid);
  }
  fs::path path_;
  std::ofstream out_;
  int count_ = 0;
  int points_ = 0;
};

double rotation_angle_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / std::numbers::pi;
}

void write_csv(const fs::path& path, const SimCell& cell, const tk::MasterResult& result) {
  TempFile tmp(path);
  {
    std::ofstream f(tmp.tmp());
    if (!f) throw std::runtime_error("cannot create " + tmp.tmp().string());
    f << "time_s,seam,phase,sensor_state,tcp_x_mm,tcp_y_mm,tcp_z_mm,q_w,q_x,q_y,q_z,s_mm,"
         "true_x_mm,true_y_mm,true_z_mm,lateral_error_mm,vertical_error_mm\n";
    char buf[512];
    for (const auto& s : result.samples) {
      const Vec3 p = s.world_from_tool.translation();
      const Eigen::Quaterniond q = rotation_quat(s.world_from_tool);
      std::snprintf(buf, sizeof buf, "%.4f,%d,%s,%s,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.6f,%.4f", s.time_s,
                    s.seam + 1, std::string(tk::to_string(s.phase)).c_str(),
                    std::string(tk::to_string(s.sensor)).c_str(), p.x(), p.y(), p.z(), q.w(), q.x(), q.y(),
                    q.z(), s.s_mm);
      f << buf;
      if (s.phase == tk::Phase::Weld && s.seam >= 0 && s.seam < static_cast<int>(cell.truth.size())) {
        const PointError e = seam_error(cell.truth[s.seam], p);
        std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.4f,%.5f,%.5f\n", e.true_point.x(), e.true_point.y(),
                      e.true_point.z(), e.lateral_mm, e.vertical_mm);
        f << buf;
      } else {
        f << ",,,,,\n";
      }
    }
    if (!f.flush()) throw std::runtime_error("cannot write " + tmp.tmp().string());
  }
  tmp.commit();
}

std::string write_plot(const fs::path& path, const SimCell& cell, const tk::MasterResult& result,
                       const std::vector<SeamMetrics>& metrics) {
  const int n = static_cast<int>(cell.truth.size());
  plot::Canvas canvas(1100, 360 * n + 40);
  for (int k = 0; k < n; ++k) {
    std::vector<double> s, lat, ver;
    for (const auto& smp : result.samples) {
      if (smp.seam != k || smp.phase != tk::Phase::Weld) continue;
      const PointError e = seam_error(cell.truth[k], smp.world_from_tool.translation());
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
    canvas.text(90, top + 348,
                "blue: lateral (in the plate, towards the open side)   orange: vertical (along the plate normal)",
                {40, 40, 40});
  }
  return canvas.save_png(path);
}

Json metrics_json(const SeamMetrics& m, int index) {
  Json j;
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
  j["points"] = m.points;
  j["rejected_points"] = m.rejected_points;
  j["refits"] = m.refits;
  return j;
}

int run_sim(const SimOptions& o) {
  const SimPlan plan = plan_sim(o);  // throws UsageError; nothing created yet
  const auto wall0 = std::chrono::steady_clock::now();
  const SimCell cell = build_sim_cell(plan.cell);
  ScannerDesc scanner = plan.scanner;
  scanner.tool_from_laser = cell.tool_from_laser;
  if (const std::string why = validate(scanner); !why.empty()) throw UsageError("scanner: " + why);

  std::unique_ptr<ProfileSource> source;
  std::unique_ptr<tk::ProfileStream> stream;
  VirtualProfileStream* virtual_stream = nullptr;
  std::string source_name;
  if (!plan.replay.empty()) {
    auto rec = RecordedProfileStream::open(plan.replay);  // throws ExrError naming the file
    // The control unit keeps its configuration; the head's rate is the recording's.
    scanner.rate_hz = rec->recording().info.scanner.rate_hz;
    stream = std::move(rec);
    source_name = "replay";
  } else {
    if (plan.reference) {
      source = make_reference_source(scanner, cell.mesh);
    } else {
      try {
        source = make_raster_source(scanner, cell.mesh);
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string("cannot create the raster source (OSMesa): ") + e.what());
      }
    }
    auto vs = std::make_unique<VirtualProfileStream>(*source, plan.seed);
    virtual_stream = vs.get();
    stream = std::move(vs);
    source_name = plan.reference ? "reference" : "raster";
  }

  fs::create_directories(plan.out_dir);
  std::unique_ptr<Spool> spool;
  if (virtual_stream) {
    spool = std::make_unique<Spool>(plan.out_dir / (".profiles.spool-" + std::to_string(::getpid())));
    virtual_stream->record = [&](const Profile& p) { spool->add(p); };
  }

  tk::SensorUnit sensor(std::move(stream), sim_tracker_params(scanner, plan.cell.standoff_mm));
  tk::Master master(sim_master_params(cell, plan.speed_mm_s, scanner.rate_hz));
  const tk::MasterResult result = master.run(sensor, cell.nominal_world_from_workpiece, cell.plan);
  const std::vector<SeamMetrics> metrics = evaluate(cell, result);

  // Outputs, each under a temporary name first.
  const fs::path csv = plan.out_dir / "timeseries.csv", exr = plan.out_dir / "profiles.exr",
                 png = plan.out_dir / "tracking_error.png";
  write_csv(csv, cell, result);
  if (spool) {
    ProfileFileInfo info;
    info.scanner = scanner;
    info.scene_name = "sim-box";
    info.error_model = !scanner.ideal;
    info.seed = plan.seed;
    if (spool->count() > 0) spool->write_exr(exr, info);
  }
  if (const std::string err = write_plot(png, cell, result, metrics); !err.empty())
    throw std::runtime_error(err);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double sim_s = result.samples.empty() ? 0.0 : result.samples.back().time_s;
  const Vec3 shift = cell.actual_world_from_workpiece.translation() - cell.nominal_world_from_workpiece.translation();
  const double rot = rotation_angle_deg(cell.nominal_world_from_workpiece, cell.actual_world_from_workpiece);
  const std::int64_t profiles = sensor.counters().profiles;

  bool ok = true;
  for (const auto& m : metrics) ok = ok && m.welded && m.end_found && m.failure.empty();
  if (o.json) {
    Json j;
    j["source"] = source_name;
    j["sensor"] = scanner.name;
    j["material"] = scanner.material;
    j["error_model"] = !scanner.ideal;
    j["seed"] = plan.seed;
    j["speed_mm_s"] = plan.speed_mm_s;
    j["rate_hz"] = scanner.rate_hz;
    j["workpiece_offset_mm"] = shift.norm();
    j["workpiece_rotation_deg"] = rot;
    j["profiles"] = profiles;
    j["sim_time_s"] = sim_s;
    j["wall_time_s"] = wall_s;
    j["completed"] = ok;
    Json seams = Json::array();
    for (std::size_t k = 0; k < metrics.size(); ++k) seams.push_back(metrics_json(metrics[k], static_cast<int>(k)));
    j["seams"] = seams;
    j["out_dir"] = plan.out_dir.string();
    std::cout << j.dump() << "\n";
  } else {
    std::printf("vts sim: box cell, workpiece displaced %.2f mm and turned %.2f deg from nominal (seed %llu)\n",
                shift.norm(), rot, static_cast<unsigned long long>(plan.seed));
    std::printf("sensor %s, %s, error model %s, %s source, %.0f Hz, %.1f mm/s\n", scanner.name.c_str(),
                scanner.material.c_str(), scanner.ideal ? "off" : "on", source_name.c_str(), scanner.rate_hz,
                plan.speed_mm_s);
    for (std::size_t k = 0; k < metrics.size(); ++k) {
      const SeamMetrics& m = metrics[k];
      std::printf(
          "seam %zu: search %.1f mm, start error %.3f mm, rms lateral %.3f mm, rms vertical %.3f mm, max %.3f mm, "
          "end error %.3f mm, welded %.1f mm; sensor track points rms %.4f mm%s%s%s\n",
          k + 1, m.search_mm, m.start_error_mm, m.rms_lateral_mm, m.rms_vertical_mm, m.max_error_mm,
          m.end_error_mm, m.welded_mm, m.sensor_rms_mm, m.lost ? ", SEAM LOST" : "", m.failure.empty() ? "" : ", failed: ",
          m.failure.c_str());
    }
    std::printf("%lld profiles, %.1f s simulated in %.2f s; wrote %s/{timeseries.csv,%stracking_error.png}\n",
                static_cast<long long>(profiles), sim_s, wall_s, plan.out_dir.c_str(),
                spool ? "profiles.exr," : "");
  }
  std::fflush(stdout);
  return ok ? cli::kExitOk : cli::kExitRuntime;
}

}  // namespace

CLI::App* add_sim_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<SimOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sim",
      "The paper's dynamic experiment, headless: a master welds two fillet seams of a box displaced from its\n"
      "nominal pose, guided by the virtual sensor (start search, tracking, end of seam, re-calibration).\n"
      "Writes timeseries.csv, profiles.exr and tracking_error.png to --out-dir (docs/SIM.md).");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("--speed", o->speed, "Weld (and search) speed, mm/s, 0.1..500 (default 10)")->type_name("MM_PER_S");
  cmd->add_option("--rate", o->rate, "Sensor profile rate, Hz, 1..10000 (default: the sensor's, 20 for mspot)")
      ->type_name("HZ");
  cmd->add_option("--seed", o->seed, "Seed of the workpiece displacement and the error model (default 1)")
      ->type_name("S");
  cmd->add_option("--offset", o->offset, "Largest workpiece translation from nominal, mm, 0..20 (default 10)")
      ->type_name("MM");
  cmd->add_option("--rotation", o->rotation, "Largest workpiece rotation from nominal, degrees, 0..10 (default 5)")
      ->type_name("DEG");
  cmd->add_option("--source", o->source, "Profile source: raster (OSMesa emulator, default) or reference (Embree)")
      ->type_name("raster|reference");
  cmd->add_option("--sensor", o->sensor, "Sensor preset (see `vts sensors`), default mspot")->type_name("NAME");
  cmd->add_option("--material", o->material, "Surface material preset, default matte-steel")->type_name("NAME");
  cmd->add_flag("--ideal", o->ideal, "Error model off: ideal geometric profiles");
  cmd->add_option("--out-dir", o->out_dir, "Directory for the outputs (created if missing), default sim/")
      ->type_name("DIR");
  cmd->add_option("--replay", o->replay,
                  "Run the master on a recorded sensor instead: the profiles.exr of an earlier run. The master must "
                  "move as it did then (same --speed); errors are measured against the cell of --seed, --offset and "
                  "--rotation, so give the recorded run's (no profiles.exr is written)")
      ->type_name("FILE.exr");
  cmd->add_flag("--json", o->json, "Print the summary as one JSON object");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_sim(*o);
    } catch (const UsageError& e) {
      std::cerr << "vts sim: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const ExrError& e) {
      std::cerr << "vts sim: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "vts sim: error: " << e.what() << "\n";
      exit_code = cli::kExitRuntime;
    }
  });
  return cmd;
}

}  // namespace vts::apps
