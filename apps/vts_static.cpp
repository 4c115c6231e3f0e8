#include "apps/vts_static.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/plot.h"
#include "apps/scan.h"
#include "render/raster_source.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/reference_source.h"
#include "tracker/tracker.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;
namespace tk = vts::tracker;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::uint64_t kDefaultSeed = 1;
constexpr int kBreaks = 5;  // the fillet's B0..B4

struct StaticOptions {
  std::string out_dir = "static";
  std::string profiles = "10";
  std::string seed;
  std::string source = "raster";
  bool ideal = false;
};

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Where the ray from the sensor origin through direction d meets the line
// through p along u; +inf when it does not (parallel, or behind the origin).
double ray_line(const Vec2& d, const Vec2& p, const Vec2& u) {
  const double den = cross(d, u);
  if (std::abs(den) < 1e-12) return INFINITY;
  const double s = cross(p, u) / den;
  return s > 0.0 ? s : INFINITY;
}

// The analytic truth of one setup at one sensor pose, sensor frame (y, z) mm.
struct Truth {
  std::array<Vec2, kBreaks> bp;
  double gap_mm = 0.0;
  double angle_deg = 0.0;
};

// B0: the flange point of the end column that sees the flange; B4 the web
// point of the other end column (the first surface each ray meets); B1 the
// root; with a gap, B3 the web edge (web_toe) and B2 where the ray grazing it
// meets the flange (the last flange point seen under the web); without, both
// are the root. Column rays as in sensor/rays.h: (0, t_i, 1) with
// t_i = tan(fan/2) (2 (i + 0.5) / N - 1).
Truth truth_at(const Workpiece& w, const ScannerDesc& desc, const Pose& pose) {
  const Pose sensor_from_joint = pose.inverse() * w.world_from_joint;
  const double x0 = (w.world_from_joint.inverse() * pose).translation().x();  // the laser plane cuts the seam here
  auto to_s = [&](const Vec2& yz) {
    const Vec3 s = sensor_from_joint * Vec3(x0, yz.x(), yz.y());
    return Vec2(s.y(), s.z());
  };
  auto dir_s = [&](const Vec2& u) {
    const Vec3 d = sensor_from_joint.linear() * Vec3(0.0, u.x(), u.y());
    return Vec2(d.y(), d.z()).normalized();
  };
  const double a = w.truth.angle_deg * kDeg;
  const Vec2 root = to_s(w.truth.root_yz);
  const Vec2 uf = dir_s(Vec2(1.0, 0.0)), uw = dir_s(Vec2(std::cos(a), std::sin(a)));
  Truth t;
  t.gap_mm = w.truth.gap_mm;
  t.angle_deg = w.truth.angle_deg;
  const double half = std::tan(0.5 * desc.fan_deg * kDeg);
  for (int col : {0, desc.points - 1}) {
    const Vec2 d(half * (2.0 * (col + 0.5) / desc.points - 1.0), 1.0);
    const double sf = ray_line(d, root, uf), sw = ray_line(d, root, uw);
    if (sf < sw) t.bp[0] = sf * d;
    else t.bp[4] = sw * d;
  }
  t.bp[1] = root;
  if (w.truth.gap_mm > 0.0) {
    Vec2 toe = Vec2::Zero();
    for (const auto& [name, p] : w.truth.features)
      if (name == "web_toe") toe = to_s(p);
    t.bp[3] = toe;
    t.bp[2] = ray_line(toe, root, uf) * toe;
  } else {
    t.bp[2] = t.bp[3] = root;
  }
  return t;
}

// The paper's "physical" sensor frame (Figure 5; docs/STATIC.md): origin on
// the optical axis at the setup's distance (the nominal joint root), z
// pointing back towards the sensor, y along the laser line as in the sensor
// frame (the sensor frame turned 180 degrees about y, so still right-handed).
Vec2 physical(const Vec2& s, double distance_mm) { return Vec2(s.x(), distance_mm - s.y()); }

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One setup's result: medians over the accepted profiles, physical frame.
struct Row {
  char label = 'A';
  double distance_mm = 0.0;
  int profiles = 0, ok = 0;
  std::array<Vec2, kBreaks> bp, bp_true;
  double gap = NAN, gap_paper = NAN, angle = NAN;
  Truth truth;
  std::string first_reason;  // of the first profile not accepted
  // Drawn in the PNG: the first profile and its result (sensor frame).
  Profile drawn;
  tk::TrackResult drawn_result;
  Truth drawn_truth;
};

std::string fmt(double v, int decimals = 3) {
  if (!std::isfinite(v)) return "n/a";
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", decimals, std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v);
  return b;
}
std::string fmt_signed(double v, int decimals = 3) {
  if (!std::isfinite(v)) return "n/a";
  char b[48];
  std::snprintf(b, sizeof b, "%+.*f", decimals, std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v);
  return b;
}

std::string csv_table(const std::vector<Row>& rows) {
  std::ostringstream o;
  o << "setup,distance_mm,gap_true_mm,profiles,accepted";
  for (int k = 0; k < kBreaks; ++k)
    o << ",B" << k << "_y,B" << k << "_z,B" << k << "_y_true,B" << k << "_z_true,B" << k << "_dy,B" << k << "_dz";
  o << ",gap_mm,gap_dev_mm,gap_paper_mm,angle_deg,angle_dev_deg\n";
  auto v = [](double x) { return fmt(x, 4); };
  for (const Row& r : rows) {
    o << "static-" << r.label << "," << fmt(r.distance_mm, 1) << "," << fmt(r.truth.gap_mm, 1) << "," << r.profiles
      << "," << r.ok;
    for (int k = 0; k < kBreaks; ++k)
      o << "," << v(r.bp[k].x()) << "," << v(r.bp[k].y()) << "," << v(r.bp_true[k].x()) << ","
        << v(r.bp_true[k].y()) << "," << v(r.bp[k].x() - r.bp_true[k].x()) << "," << v(r.bp[k].y() - r.bp_true[k].y());
    o << "," << v(r.gap) << "," << v(r.gap - r.truth.gap_mm) << "," << v(r.gap_paper) << "," << v(r.angle) << ","
      << v(r.angle - r.truth.angle_deg) << "\n";
  }
  return o.str();
}

std::string md_table(const std::vector<Row>& rows, const std::string& conditions) {
  std::ostringstream o;
  o << "Conditions: " << conditions << ". Physical sensor frame (docs/STATIC.md), mm; medians over the "
       "accepted profiles.\n\n";
  o << "Measured break points (y, z), gap and angle:\n\n";
  o << "| setup | distance | accepted |";
  for (int k = 0; k < kBreaks; ++k) o << " B" << k << " y | B" << k << " z |";
  o << " gap | angle |\n|---|---|---|";
  for (int k = 0; k < 2 * kBreaks + 2; ++k) o << "---|";
  o << "\n";
  for (const Row& r : rows) {
    o << "| " << r.label << " | " << fmt(r.distance_mm, 0) << " | " << r.ok << "/" << r.profiles << " |";
    for (int k = 0; k < kBreaks; ++k) o << " " << fmt(r.bp[k].x(), 2) << " | " << fmt(r.bp[k].y(), 2) << " |";
    o << " " << fmt(r.gap, 2) << " | " << fmt(r.angle, 2) << " |\n";
  }
  o << "\nDeviation from the analytic truth (measured - true):\n\n";
  o << "| setup |";
  for (int k = 0; k < kBreaks; ++k) o << " B" << k << " y | B" << k << " z |";
  o << " gap | angle |\n|---|";
  for (int k = 0; k < 2 * kBreaks + 2; ++k) o << "---|";
  o << "\n";
  for (const Row& r : rows) {
    o << "| " << r.label << " |";
    for (int k = 0; k < kBreaks; ++k)
      o << " " << fmt_signed(r.bp[k].x() - r.bp_true[k].x()) << " | " << fmt_signed(r.bp[k].y() - r.bp_true[k].y())
        << " |";
    o << " " << fmt_signed(r.gap - r.truth.gap_mm) << " | " << fmt_signed(r.angle - r.truth.angle_deg) << " |\n";
  }
  return o.str();
}

// Clips segment a-b to the box [x0, x1] x [y0, y1] (Liang-Barsky); false if
// nothing is left.
bool clip(Vec2& a, Vec2& b, double x0, double x1, double y0, double y1) {
  double t0 = 0.0, t1 = 1.0;
  const Vec2 d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - x0, x1 - a.x(), a.y() - y0, y1 - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
  }
  if (t0 > t1) return false;
  const Vec2 a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

// The paper's Figure 7: the profile, the fitted segments and the break points.
// Left the whole profile, right the root enlarged; physical frame, z up.
plot::Canvas draw_setup(const Row& r, const std::string& conditions) {
  plot::Canvas canvas(1400, 760);
  const Profile& p = r.drawn;
  const tk::TrackResult& res = r.drawn_result;
  std::vector<double> ys, zs;
  double y0 = INFINITY, y1 = -INFINITY, z0 = INFINITY, z1 = -INFINITY;
  for (int i = 0; i < p.size(); ++i) {
    if (!p.valid[i]) continue;
    const Vec2 q = physical(Vec2(p.y_mm[i], p.z_mm[i]), r.distance_mm);
    ys.push_back(q.x());
    zs.push_back(q.y());
    y0 = std::min(y0, q.x()), y1 = std::max(y1, q.x()), z0 = std::min(z0, q.y()), z1 = std::max(z1, q.y());
  }
  if (!std::isfinite(y0)) y0 = -10, y1 = 10, z0 = -10, z1 = 10;
  const plot::Rgb points_c{60, 110, 200}, seg_c{230, 170, 0}, bp_c{200, 30, 30}, truth_c{20, 150, 60},
      text_c{30, 30, 30};
  const Vec2 root = physical(r.drawn_truth.bp[1], r.distance_mm);
  const double zoom = r.truth.gap_mm > 0.0 ? 4.0 : 2.5;  // half-width of the enlarged view, mm
  struct View {
    int l, t, rr, b;
    double x0, x1, yy0, yy1;
    const char* title;
  };
  const double pad = 0.05 * std::max(y1 - y0, z1 - z0) + 1.0;
  const View views[2] = {
      {70, 110, 690, 680, y0 - pad, y1 + pad, z0 - pad, z1 + pad, "whole profile"},
      {770, 110, 1380, 680, root.x() - zoom, root.x() + zoom, root.y() - zoom, root.y() + zoom, "at the root"}};
  for (const View& v : views) {
    plot::Chart chart(canvas, v.l, v.t, v.rr, v.b, v.x0, v.x1, v.yy0, v.yy1, true, false);
    chart.frame(std::string("static-") + r.label + ": " + v.title, "y [mm] (physical frame)", "z [mm] (towards the sensor)");
    chart.points(ys, zs, points_c, v.title[0] == 'w' ? 1.5 : 2.5);
    // Segments: each fitted line between its end points' feet.
    for (const auto& s : res.segments) {
      if (s.points < 2) continue;
      const Vec2 a = s.line.project(Vec2(p.y_mm[s.first_col], p.z_mm[s.first_col]));
      const Vec2 b = s.line.project(Vec2(p.y_mm[s.last_col], p.z_mm[s.last_col]));
      Vec2 pa = physical(a, r.distance_mm), pb = physical(b, r.distance_mm);
      if (!clip(pa, pb, v.x0, v.x1, v.yy0, v.yy1)) continue;
      chart.polyline({pa.x(), pb.x()}, {pa.y(), pb.y()}, seg_c, 2);
    }
    for (int k = 0; k < kBreaks; ++k) {
      const Vec2 t = physical(r.drawn_truth.bp[k], r.distance_mm);
      if (t.x() < v.x0 || t.x() > v.x1 || t.y() < v.yy0 || t.y() > v.yy1) continue;
      chart.marker(t.x(), t.y(), truth_c, "", 7.0);
      chart.marker(t.x(), t.y(), {255, 255, 255}, "", 5.0);
    }
    // Labels are offset so coinciding break points (no gap: B1 = B2 = B3) stay readable.
    std::string merged[kBreaks];
    for (int k = 0; k < kBreaks; ++k) {
      if (!res.break_points[k]) continue;
      int first = k;
      for (int j = 0; j < k; ++j)
        if (res.break_points[j] && (*res.break_points[j] - *res.break_points[k]).norm() < 1e-6) {
          first = j;
          break;
        }
      merged[first] += (merged[first].empty() ? "B" : "=B") + std::to_string(k);
    }
    for (int k = 0; k < kBreaks; ++k) {
      if (merged[k].empty()) continue;
      const Vec2 q = physical(*res.break_points[k], r.distance_mm);
      if (q.x() < v.x0 || q.x() > v.x1 || q.y() < v.yy0 || q.y() > v.yy1) continue;
      chart.marker(q.x(), q.y(), bp_c, merged[k], 3.5);
    }
  }
  char line[400];
  std::snprintf(line, sizeof line, "static-%c: distance %.0f mm, gap %.0f mm (paper Table 2); %s", r.label,
                r.distance_mm, r.truth.gap_mm, conditions.c_str());
  canvas.text(70, 14, line, text_c, 1);
  std::snprintf(line, sizeof line, "profile %lld: %s%s%s, gap %s mm (true %.1f), angle %s deg (true %.0f)",
                static_cast<long long>(p.index), std::string(tk::to_string(res.status)).c_str(),
                res.reason.empty() ? "" : ": ", res.reason.c_str(), fmt(res.gap_mm).c_str(), r.truth.gap_mm,
                fmt(res.angle_deg, 2).c_str(), r.truth.angle_deg);
  canvas.text(70, 30, line, text_c, 1);
  canvas.text(70, 725,
              "blue: profile points   yellow: fitted segments   red: break points B0..B4 (tracker)   "
              "green rings: analytic truth",
              text_c, 2);
  return canvas;
}

void write_text(const fs::path& path, const std::string& text) {
  fs::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + path.string());
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot rename onto " + path.string() + ": " + ec.message());
  }
}

int run_static(const StaticOptions& o) {
  int n = 0;
  {
    const auto r = std::from_chars(o.profiles.data(), o.profiles.data() + o.profiles.size(), n);
    if (r.ec != std::errc() || r.ptr != o.profiles.data() + o.profiles.size() || n < 1 || n > 100000)
      throw InputError("--profiles = '" + o.profiles + "': expected an integer from 1 to 100000");
  }
  std::uint64_t seed = kDefaultSeed;
  if (!o.seed.empty()) {
    const auto r = std::from_chars(o.seed.data(), o.seed.data() + o.seed.size(), seed);
    if (r.ec != std::errc() || r.ptr != o.seed.data() + o.seed.size())
      throw InputError("--seed = '" + o.seed + "': expected an unsigned 64-bit integer (0 .. 18446744073709551615)");
  }
  if (o.source != "raster" && o.source != "reference")
    throw InputError("--source = '" + o.source + "': expected 'raster' or 'reference'");
  const fs::path dir = fs::absolute(o.out_dir).lexically_normal();
  {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
      throw InputError("--out-dir = '" + o.out_dir + "': exists and is not a directory");
  }
  const std::string conditions =
      std::string(o.source == "raster" ? "raster emulator" : "Embree reference") + ", " +
      (o.ideal ? "ideal profiles (--ideal)" : "error model on, seed " + std::to_string(seed)) + ", " +
      std::to_string(n) + (n == 1 ? " profile" : " profiles");

  // Scan and track everything first: a failure leaves no files behind.
  std::vector<Row> rows;
  for (const StaticSetup& setup : kStaticSetups) {
    const std::string name = std::string("static-") + setup.label;
    Cell cell = *builtin_cell(name);
    cell.scanner.ideal = o.ideal;
    const Workpiece& w = cell.workpieces.front();
    std::unique_ptr<ProfileSource> source;
    if (o.source == "raster") {
      try {
        source = make_raster_source(cell.scanner, cell.mesh());
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string("cannot create the raster source (OSMesa): ") + e.what());
      }
    } else {
      source = make_reference_source(cell.scanner, cell.mesh());
    }
    tk::TrackerParams params;
    params.joint = tk::JointType::Fillet;
    tk::Tracker tracker(params);
    ScanState state;
    state.seed = seed;
    Row row;
    row.label = setup.label;
    row.distance_mm = setup.distance_mm;
    row.profiles = n;
    std::vector<double> vals[2 * kBreaks + 3];
    std::vector<double> truth_vals[2 * kBreaks];
    Profile ideal, measured;
    tk::TrackResult res;
    for (int i = 0; i < n; ++i) {
      const Pose pose = cell.path.pose_at(i);
      source->scan(pose, ideal);
      ideal.world_from_sensor = pose;
      ideal.index = i;
      ideal.time_s = i / cell.scanner.rate_hz;
      apply_error_model(cell.scanner, ideal, state, measured);
      tracker.track(tk::ProfileView{measured.y_mm, measured.z_mm, measured.valid}, res);
      const Truth truth = truth_at(w, cell.scanner, pose);
      if (i == 0) {
        row.truth = truth;
        row.drawn = measured;
        row.drawn_result = res;
        row.drawn_truth = truth;
      }
      if (res.status != tk::TrackStatus::Ok) {
        if (row.first_reason.empty())
          row.first_reason = "profile " + std::to_string(i) + ": " + std::string(tk::to_string(res.status)) + ": " +
                             res.reason;
        continue;
      }
      ++row.ok;
      for (int k = 0; k < kBreaks; ++k) {
        const Vec2 m = res.break_points[k] ? physical(*res.break_points[k], setup.distance_mm) : Vec2(NAN, NAN);
        const Vec2 t = physical(truth.bp[k], setup.distance_mm);
        vals[2 * k].push_back(m.x());
        vals[2 * k + 1].push_back(m.y());
        truth_vals[2 * k].push_back(t.x());
        truth_vals[2 * k + 1].push_back(t.y());
      }
      vals[2 * kBreaks].push_back(res.gap_mm);
      vals[2 * kBreaks + 1].push_back(res.gap_paper_mm);
      vals[2 * kBreaks + 2].push_back(res.angle_deg);
    }
    for (int k = 0; k < kBreaks; ++k) {
      row.bp[k] = Vec2(median(vals[2 * k]), median(vals[2 * k + 1]));
      row.bp_true[k] = row.ok ? Vec2(median(truth_vals[2 * k]), median(truth_vals[2 * k + 1]))
                              : physical(row.truth.bp[k], setup.distance_mm);
    }
    row.gap = median(vals[2 * kBreaks]);
    row.gap_paper = median(vals[2 * kBreaks + 1]);
    row.angle = median(vals[2 * kBreaks + 2]);
    rows.push_back(std::move(row));
  }

  const std::string csv = csv_table(rows);
  const std::string md = "# The paper's static experiment (Table 3)\n\n" + md_table(rows, conditions);
  std::vector<plot::Canvas> pictures;
  for (const Row& r : rows) pictures.push_back(draw_setup(r, conditions));

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
  write_text(dir / "table3.csv", csv);
  write_text(dir / "table3.md", md);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const fs::path png = dir / (std::string("static-") + rows[i].label + ".png");
    if (const std::string err = pictures[i].save_png(png); !err.empty()) throw std::runtime_error(err);
  }
  std::cout << md_table(rows, conditions);
  for (const Row& r : rows)
    if (r.ok < r.profiles) std::cout << "static-" << r.label << ": " << r.first_reason << "\n";
  std::cout << "\nwrote table3.csv, table3.md and static-A.png .. static-F.png to " << dir.string() << "\n";
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_static_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<StaticOptions>();
  CLI::App* cmd = app.add_subcommand(
      "static",
      "The paper's static experiment: scan setups static-A .. static-F, track them with the fillet template "
      "and write Table 3 (CSV, Markdown) and one PNG per setup (Figure 7) to --out-dir");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("--out-dir", o->out_dir, "Output directory, created if missing (default: static)")
      ->type_name("DIR");
  cmd->add_option("--profiles", o->profiles,
                  "Profiles scanned per setup, 0.5 mm apart along the seam (default 10); the table reports "
                  "medians over the accepted ones")
      ->type_name("N");
  cmd->add_option("--seed", o->seed, "Seed of the sensor error model (default 1)")->type_name("S");
  cmd->add_flag("--ideal", o->ideal, "Error model off: track the ideal geometric profiles");
  cmd->add_option("--source", o->source,
                  "Profile source: raster (OSMesa emulator, default) or reference (Embree ray caster)")
      ->type_name("raster|reference");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_static(*o);
    } catch (const InputError& e) {
      std::cerr << "vts static: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    }
  });
  return cmd;
}

}  // namespace vts::apps
