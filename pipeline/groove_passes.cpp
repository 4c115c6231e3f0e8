#include "pipeline/groove_passes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "tracker/tracker.h"

namespace vts {
namespace {

namespace tk = vts::tracker;

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fmt(double v, int decimals) {
  if (!std::isfinite(v)) return "n/a";
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", decimals, std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v);
  return b;
}

}  // namespace

std::string_view to_string(FillMode mode) { return mode == FillMode::Adaptive ? "adaptive" : "model"; }

std::string validate(const GroovePassSpec& spec) {
  if (spec.cell.workpieces.size() != 1) return "the cell must hold one groove workpiece";
  const Workpiece& w = spec.cell.workpieces.front();
  if (w.is_mesh() || !is_groove(w.type))
    return "cell '" + spec.cell.name + "': " + std::string(to_string(w.type)) +
           " is no groove (vgroove, bevel, ugroove or jgroove)";
  if (spec.profiles < 1 || spec.profiles > 100000) return "profiles = " + std::to_string(spec.profiles) + ": must be 1..100000";
  const int last = spec.last_pass < 0 ? w.params.passes : spec.last_pass;
  if (spec.first_pass < 0 || spec.first_pass > last)
    return "passes " + std::to_string(spec.first_pass) + ".." + std::to_string(last) + ": must be 0 <= first <= last";
  JointParams p = w.params;
  p.passes = last;
  if (const std::string e = vts::validate(w.type, p); !e.empty()) return e;
  if (!std::isfinite(spec.bias_mm) || std::abs(spec.bias_mm) > 20.0)
    return "bias = " + fmt(spec.bias_mm, 3) + " mm: must be -20..20";
  if (spec.bias_mm != 0.0 && spec.fill != FillMode::Adaptive)
    return "a bias on the reported next-bead point only moves beads with the adaptive fill";
  return {};
}

GroovePassRun run_groove_passes(const GroovePassSpec& spec) {
  if (const std::string e = validate(spec); !e.empty()) throw std::invalid_argument(e);
  const Workpiece& base = spec.cell.workpieces.front();
  const int last = spec.last_pass < 0 ? base.params.passes : spec.last_pass;
  GroovePassRun run;
  run.cell = spec.cell.name;
  run.conditions = std::string(spec.source == SourceKind::Raster ? "raster emulator" : "Embree reference") + ", " +
                   (spec.cell.scanner.ideal ? "ideal profiles" : "error model on, seed " + std::to_string(spec.seed)) +
                   ", " + spec.cell.scanner.name + ", " + std::to_string(spec.profiles) + " profiles per pass, " +
                   (spec.fill == FillMode::Adaptive ? "adaptive fill (each bead where the sensor said)"
                                                    : "beads where the cell's model centres them");
  if (spec.bias_mm != 0.0) run.conditions += ", next-bead point biased " + fmt(spec.bias_mm, 3) + " mm along the laser line";
  run.fill = spec.fill;
  // Where the beads were laid, from the middle of the fill under each
  // (JointParams::bead_offsets_mm); the ones before the first scan centred.
  std::vector<double> offsets(static_cast<std::size_t>(spec.first_pass), 0.0);
  tk::TrackerParams params;
  params.joint = *tracker_joint(base.type);
  for (int laid = spec.first_pass; laid <= last; ++laid) {
    ScanSpec scan;
    scan.cell = spec.cell;
    JointParams p = base.params;
    p.passes = laid;
    if (spec.fill == FillMode::Adaptive) p.bead_offsets_mm = offsets;
    scan.cell.workpieces.front() = build_workpiece(base.type, p, base.world_from_joint);
    scan.cell.path.profiles = spec.profiles;
    scan.source = spec.source;
    scan.seed = spec.seed + static_cast<std::uint64_t>(laid);
    const Workpiece& w = scan.cell.workpieces.front();
    const JointTruth& t = w.truth;
    // Beads laid: the v-groove's bottom is its fill (--fill); an empty one's
    // root is read by its own template.
    params.groove.vgroove_fill = laid > 0;
    GroovePass pass;
    pass.laid = laid;
    pass.profiles = spec.profiles;
    pass.depth_true = t.depth_mm, pass.area_true = t.area_mm2, pass.width_true = t.top_width_mm;
    // The tracker's walls are in scan order: which of the joint's is first?
    const bool a_first = w.in_sensor_frame(scan.cell.path.pose_at(0), t.top_a_yz).x() <=
                         w.in_sensor_frame(scan.cell.path.pose_at(0), t.top_b_yz).x();
    pass.wall_a_true = a_first ? t.wall_angle_a_deg : t.wall_angle_b_deg;
    pass.wall_b_true = a_first ? t.wall_angle_b_deg : t.wall_angle_a_deg;
    std::vector<double> depth, area, width, wa, wb, dy, dz, across;
    tk::Tracker tracker(params);
    tk::TrackResult r;
    CallbackSink sink([&](const ScanBatch& batch) {
      for (const Profile& prof : batch.profiles) {
        tracker.track(tk::ProfileView{prof.y_mm, prof.z_mm, prof.valid}, r);
        if (r.status != tk::TrackStatus::Ok || !r.track_point) {
          if (pass.first_reason.empty())
            pass.first_reason = "profile " + std::to_string(prof.index) + ": " + std::string(tk::to_string(r.status)) +
                                ": " + r.reason;
          continue;
        }
        ++pass.ok;
        depth.push_back(r.depth_mm), area.push_back(r.area_mm2), width.push_back(r.top_width_mm);
        wa.push_back(r.wall_angle_a_deg), wb.push_back(r.wall_angle_b_deg);
        const Vec2 b3 = w.in_sensor_frame(scan.cell.path.pose_at(prof.index), t.track_yz);
        dy.push_back(r.track_point->x() - b3.x()), dz.push_back(r.track_point->y() - b3.y());
        // The reported point (biased as the sensor's mount would) into the
        // part frame through the pose the profile was taken at.
        across.push_back(
            w.in_joint_frame(scan.cell.path.pose_at(prof.index), Vec2(r.track_point->x() + spec.bias_mm, r.track_point->y()))
                .x());
      }
    });
    run_scan_job(scan, sink);
    pass.depth = median(depth), pass.area = median(area), pass.width = median(width);
    pass.wall_a = median(wa), pass.wall_b = median(wb);
    pass.next_dy = median(dy), pass.next_dz = median(dz);
    pass.model_y = t.track_yz.x();
    pass.toe_a = t.toe_a_yz, pass.toe_b = t.toe_b_yz, pass.top_a = t.top_a_yz, pass.top_b = t.top_b_yz;
    pass.reported_y = median(across);
    if (laid < last) {
      if (spec.fill == FillMode::Model) {
        pass.laid_y = pass.model_y;
        pass.bead_laid = true;
      } else if (pass.ok == 0) {
        run.stopped = "after " + std::to_string(laid) + " beads no profile was accepted (" + pass.first_reason +
                      "): bead " + std::to_string(laid + 1) +
                      " cannot be placed; the run stops there (a cell would stop and ask the operator)";
      } else {
        JointParams next = with_bead_laid(p, pass.reported_y - pass.model_y);  // p: this scan's beads
        if (const std::string e = vts::validate(base.type, next); !e.empty()) {
          run.stopped = "bead " + std::to_string(laid + 1) + " where the sensor said (" + fmt(pass.reported_y, 3) +
                        " mm across, " + fmt(pass.reported_y - pass.model_y, 3) +
                        " mm off the middle) cannot be laid: " + e + "; the run stops there";
        } else {
          pass.laid_y = pass.reported_y;
          pass.bead_laid = true;
          offsets = std::move(next.bead_offsets_mm);
        }
      }
    }
    run.passes.push_back(pass);
    if (!run.stopped.empty()) break;
  }
  return run;
}

namespace {

// One pass's measured and true values as the tables' columns from
// "accepted" on.
std::string pass_cells(const GroovePass& p) {
  std::ostringstream o;
  o << p.ok << "/" << p.profiles << " | " << fmt(p.depth, 3) << " | " << fmt(p.depth_true, 3) << " | "
    << fmt(p.area, 1) << " | " << fmt(p.area_true, 1) << " | " << fmt(p.width, 3) << " | " << fmt(p.width_true, 3)
    << " | " << fmt(p.wall_a, 2) << ", " << fmt(p.wall_b, 2) << " | " << fmt(p.wall_a_true, 2) << ", "
    << fmt(p.wall_b_true, 2) << " | " << fmt(p.next_dy, 3) << " / " << fmt(p.next_dz, 3) << " |";
  return o.str();
}

constexpr const char* kPassColumns =
    "accepted | depth left (mm) | true | area left (mm2) | true | top width (mm) | true | walls (deg) | true";

}  // namespace

std::string groove_passes_markdown(const GroovePassRun& run) {
  std::ostringstream o;
  o << "Multi-pass: " << run.cell << ", " << run.conditions
    << ". Medians over the accepted profiles; true values from the cell's analytic truth.\n\n"
    << "| beads laid | " << kPassColumns
    << " | next bead: error across / in depth (mm) | next bead laid / model's centre, across (mm) |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const GroovePass& p : run.passes) {
    o << "| " << p.laid << " | " << pass_cells(p) << " ";
    if (p.bead_laid) {
      char off[32];
      std::snprintf(off, sizeof off, "%+.3f", std::abs(p.laid_y - p.model_y) < 5e-4 ? 0.0 : p.laid_y - p.model_y);
      o << fmt(p.laid_y, 3) << " / " << fmt(p.model_y, 3) << " (" << off << ")";
    } else {
      o << "none laid";
    }
    o << " |\n";
  }
  for (const GroovePass& p : run.passes)
    if (p.ok < p.profiles) o << "\nafter " << p.laid << " beads, " << p.first_reason;
  if (!run.stopped.empty()) o << "\n\nSTOPPED: " << run.stopped;
  return o.str();
}

std::string groove_cells_markdown(const std::vector<GroovePassRun>& runs) {
  std::ostringstream o;
  o << "| cell | beads | " << kPassColumns << " | B3 error across / in depth (mm) |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const GroovePassRun& run : runs)
    if (!run.passes.empty())
      o << "| " << run.cell << " | " << run.passes.back().laid << " | " << pass_cells(run.passes.back()) << "\n";
  for (const GroovePassRun& run : runs)
    for (const GroovePass& p : run.passes)
      if (p.ok < p.profiles) o << "\n" << run.cell << ": " << p.first_reason;
  return o.str();
}

trackio::Json groove_passes_json(const GroovePassRun& run) {
  auto num = [](double v) { return std::isfinite(v) ? trackio::Json(std::round(v * 1e6) / 1e6) : trackio::Json(); };
  trackio::Json passes = trackio::Json::array();
  for (const GroovePass& p : run.passes)
    passes.push_back(trackio::Json{{"laid", p.laid},
                                   {"profiles", p.profiles},
                                   {"accepted", p.ok},
                                   {"depth_mm", num(p.depth)},
                                   {"depth_true_mm", num(p.depth_true)},
                                   {"area_mm2", num(p.area)},
                                   {"area_true_mm2", num(p.area_true)},
                                   {"top_width_mm", num(p.width)},
                                   {"top_width_true_mm", num(p.width_true)},
                                   {"wall_angle_a_deg", num(p.wall_a)},
                                   {"wall_angle_a_true_deg", num(p.wall_a_true)},
                                   {"wall_angle_b_deg", num(p.wall_b)},
                                   {"wall_angle_b_true_deg", num(p.wall_b_true)},
                                   {"next_bead_error_y_mm", num(p.next_dy)},
                                   {"next_bead_error_z_mm", num(p.next_dz)},
                                   {"first_reason", p.first_reason},
                                   {"next_bead_model_y_mm", num(p.model_y)},
                                   {"next_bead_reported_y_mm", num(p.reported_y)},
                                   {"next_bead_laid", p.bead_laid},
                                   {"next_bead_laid_y_mm", num(p.laid_y)},
                                   {"next_bead_offset_mm", num(p.laid_y - p.model_y)},
                                   {"toe_a_yz_true", {num(p.toe_a.x()), num(p.toe_a.y())}},
                                   {"toe_b_yz_true", {num(p.toe_b.x()), num(p.toe_b.y())}},
                                   {"top_a_yz_true", {num(p.top_a.x()), num(p.top_a.y())}},
                                   {"top_b_yz_true", {num(p.top_b.x()), num(p.top_b.y())}}});
  return trackio::Json{{"cell", run.cell},       {"conditions", run.conditions}, {"fill", std::string(to_string(run.fill))},
                       {"passes", std::move(passes)}, {"stopped", run.stopped}};
}

}  // namespace vts
