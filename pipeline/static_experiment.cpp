#include "pipeline/static_experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "pipeline/sinks.h"
#include "sensor/cell.h"

namespace vts {
namespace {

namespace tk = vts::tracker;
constexpr double kDeg = std::numbers::pi / 180.0;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Where the ray from the sensor origin through direction d meets the line
// through p along u; +inf when it does not (parallel, or behind the origin).
double ray_line(const Vec2& d, const Vec2& p, const Vec2& u) {
  const double den = cross(d, u);
  if (std::abs(den) < 1e-12) return INFINITY;
  const double s = cross(p, u) / den;
  return s > 0.0 ? s : INFINITY;
}


// B0: the flange point of the end column that sees the flange; B4 the web
// point of the other end column (the first surface each ray meets); B1 the
// root; with a gap, B3 the web edge (web_toe) and B2 where the ray grazing it
// meets the flange (the last flange point seen under the web); without, both
// are the root. Column rays as in sensor/rays.h: (0, t_i, 1) with
// t_i = tan(fan/2) (2 (i + 0.5) / N - 1).
StaticTruth truth_at(const Workpiece& w, const ScannerDesc& desc, const Pose& pose) {
  const Pose sensor_from_joint = pose.inverse() * w.world_from_joint;
  auto to_s = [&](const Vec2& yz) { return w.in_sensor_frame(pose, yz); };
  auto dir_s = [&](const Vec2& u) {
    const Vec3 d = sensor_from_joint.linear() * Vec3(0.0, u.x(), u.y());
    return Vec2(d.y(), d.z()).normalized();
  };
  const double a = w.truth.angle_deg * kDeg;
  const Vec2 root = to_s(w.truth.root_yz);
  const Vec2 uf = dir_s(Vec2(1.0, 0.0)), uw = dir_s(Vec2(std::cos(a), std::sin(a)));
  StaticTruth t;
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

std::string csv_table(const std::vector<StaticRow>& rows) {
  std::ostringstream o;
  o << "setup,distance_mm,gap_true_mm,profiles,accepted";
  for (int k = 0; k < kStaticBreaks; ++k)
    o << ",B" << k << "_y,B" << k << "_z,B" << k << "_y_true,B" << k << "_z_true,B" << k << "_dy,B" << k << "_dz";
  o << ",gap_mm,gap_dev_mm,gap_paper_mm,angle_deg,angle_dev_deg\n";
  auto v = [](double x) { return fmt(x, 4); };
  for (const StaticRow& r : rows) {
    o << "static-" << r.label << "," << fmt(r.distance_mm, 1) << "," << fmt(r.truth.gap_mm, 1) << "," << r.profiles
      << "," << r.ok;
    for (int k = 0; k < kStaticBreaks; ++k)
      o << "," << v(r.bp[k].x()) << "," << v(r.bp[k].y()) << "," << v(r.bp_true[k].x()) << ","
        << v(r.bp_true[k].y()) << "," << v(r.bp[k].x() - r.bp_true[k].x()) << "," << v(r.bp[k].y() - r.bp_true[k].y());
    o << "," << v(r.gap) << "," << v(r.gap - r.truth.gap_mm) << "," << v(r.gap_paper) << "," << v(r.angle) << ","
      << v(r.angle - r.truth.angle_deg) << "\n";
  }
  return o.str();
}

std::string md_table(const std::vector<StaticRow>& rows, const std::string& conditions) {
  std::ostringstream o;
  o << "Conditions: " << conditions << ". Physical sensor frame (docs/STATIC.md), mm; medians over the "
       "accepted profiles.\n\n";
  o << "Measured break points (y, z), gap and angle:\n\n";
  o << "| setup | distance | accepted |";
  for (int k = 0; k < kStaticBreaks; ++k) o << " B" << k << " y | B" << k << " z |";
  o << " gap | angle |\n|---|---|---|";
  for (int k = 0; k < 2 * kStaticBreaks + 2; ++k) o << "---|";
  o << "\n";
  for (const StaticRow& r : rows) {
    o << "| " << r.label << " | " << fmt(r.distance_mm, 0) << " | " << r.ok << "/" << r.profiles << " |";
    for (int k = 0; k < kStaticBreaks; ++k) o << " " << fmt(r.bp[k].x(), 2) << " | " << fmt(r.bp[k].y(), 2) << " |";
    o << " " << fmt(r.gap, 2) << " | " << fmt(r.angle, 2) << " |\n";
  }
  o << "\nDeviation from the analytic truth (measured - true):\n\n";
  o << "| setup |";
  for (int k = 0; k < kStaticBreaks; ++k) o << " B" << k << " y | B" << k << " z |";
  o << " gap | angle |\n|---|";
  for (int k = 0; k < 2 * kStaticBreaks + 2; ++k) o << "---|";
  o << "\n";
  for (const StaticRow& r : rows) {
    o << "| " << r.label << " |";
    for (int k = 0; k < kStaticBreaks; ++k)
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
plot::Canvas static_figure_of(const StaticRow& r, const std::string& conditions) {
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
    for (int k = 0; k < kStaticBreaks; ++k) {
      const Vec2 t = physical(r.drawn_truth.bp[k], r.distance_mm);
      if (t.x() < v.x0 || t.x() > v.x1 || t.y() < v.yy0 || t.y() > v.yy1) continue;
      chart.marker(t.x(), t.y(), truth_c, "", 7.0);
      chart.marker(t.x(), t.y(), {255, 255, 255}, "", 5.0);
    }
    // Labels are offset so coinciding break points (no gap: B1 = B2 = B3) stay readable.
    std::string merged[kStaticBreaks];
    for (int k = 0; k < kStaticBreaks; ++k) {
      if (!res.break_points[k]) continue;
      int first = k;
      for (int j = 0; j < k; ++j)
        if (res.break_points[j] && (*res.break_points[j] - *res.break_points[k]).norm() < 1e-6) {
          first = j;
          break;
        }
      merged[first] += (merged[first].empty() ? "B" : "=B") + std::to_string(k);
    }
    for (int k = 0; k < kStaticBreaks; ++k) {
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

}  // namespace

StaticResult run_static_experiment(const StaticSpec& spec) {
  const int n = spec.profiles;
  StaticResult result;
  result.conditions = std::string(spec.source == SourceKind::Raster ? "raster emulator" : "Embree reference") + ", " +
                      (spec.ideal ? "ideal profiles (--ideal)" : "error model on, seed " + std::to_string(spec.seed)) +
                      ", " + std::to_string(n) + (n == 1 ? " profile" : " profiles");
  for (const StaticSetup& setup : kStaticSetups) {
    ScanSpec scan;
    scan.cell = *builtin_cell(std::string("static-") + setup.label);
    scan.cell.scanner.ideal = spec.ideal;
    scan.cell.path.profiles = n;
    scan.source = spec.source;
    scan.seed = spec.seed;
    const Workpiece& w = scan.cell.workpieces.front();
    tk::TrackerParams params;
    params.joint = tk::JointType::Fillet;
    tk::Tracker tracker(params);
    StaticRow row;
    row.label = setup.label;
    row.distance_mm = setup.distance_mm;
    row.profiles = n;
    std::vector<double> vals[2 * kStaticBreaks + 3];
    std::vector<double> truth_vals[2 * kStaticBreaks];
    tk::TrackResult res;
    CallbackSink sink([&](const ScanBatch& batch) {
      for (const Profile& measured : batch.profiles) {
        const std::int64_t i = measured.index;
        tracker.track(tk::ProfileView{measured.y_mm, measured.z_mm, measured.valid}, res);
        const StaticTruth truth = truth_at(w, scan.cell.scanner, scan.cell.path.pose_at(i));
        if (i == 0) {
          row.truth = truth;
          row.drawn = measured;
          row.drawn_result = res;
          row.drawn_truth = truth;
        }
        if (res.status != tk::TrackStatus::Ok) {
          if (row.first_reason.empty())
            row.first_reason =
                "profile " + std::to_string(i) + ": " + std::string(tk::to_string(res.status)) + ": " + res.reason;
          continue;
        }
        ++row.ok;
        for (int k = 0; k < kStaticBreaks; ++k) {
          const Vec2 m = res.break_points[k] ? physical(*res.break_points[k], setup.distance_mm) : Vec2(NAN, NAN);
          const Vec2 t = physical(truth.bp[k], setup.distance_mm);
          vals[2 * k].push_back(m.x());
          vals[2 * k + 1].push_back(m.y());
          truth_vals[2 * k].push_back(t.x());
          truth_vals[2 * k + 1].push_back(t.y());
        }
        vals[2 * kStaticBreaks].push_back(res.gap_mm);
        vals[2 * kStaticBreaks + 1].push_back(res.gap_paper_mm);
        vals[2 * kStaticBreaks + 2].push_back(res.angle_deg);
      }
    });
    run_scan_job(scan, sink);
    for (int k = 0; k < kStaticBreaks; ++k) {
      row.bp[k] = Vec2(median(vals[2 * k]), median(vals[2 * k + 1]));
      row.bp_true[k] = row.ok ? Vec2(median(truth_vals[2 * k]), median(truth_vals[2 * k + 1]))
                              : physical(row.truth.bp[k], setup.distance_mm);
    }
    row.gap = median(vals[2 * kStaticBreaks]);
    row.gap_paper = median(vals[2 * kStaticBreaks + 1]);
    row.angle = median(vals[2 * kStaticBreaks + 2]);
    result.rows.push_back(std::move(row));
  }
  return result;
}

std::string static_table_csv(const StaticResult& result) { return csv_table(result.rows); }

std::string static_table_markdown(const StaticResult& result) { return md_table(result.rows, result.conditions); }

plot::Canvas static_figure(const StaticRow& row, const std::string& conditions) {
  return static_figure_of(row, conditions);
}

}  // namespace vts
