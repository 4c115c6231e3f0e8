#include "viewer/panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cfloat>
#include <cstdint>
#include <cstdio>
#include <string>

#include "plot/plot.h"
#include "sensor/pose.h"
#include "sensor/presets.h"

namespace vts::viewer {
namespace {

constexpr ImU32 kPlotBg = IM_COL32(14, 16, 20, 255);
constexpr ImU32 kPlotFrame = IM_COL32(90, 96, 108, 255);
constexpr ImU32 kPlotGrid = IM_COL32(40, 44, 52, 255);
constexpr ImU32 kPlotText = IM_COL32(170, 176, 188, 255);
constexpr ImU32 kPointColor = IM_COL32(120, 200, 255, 255);
constexpr ImU32 kOutlierColor = IM_COL32(230, 90, 230, 255);
constexpr ImU32 kSegmentColor = IM_COL32(255, 214, 60, 255);
constexpr ImU32 kBreakColor = IM_COL32(255, 140, 20, 255);
constexpr ImU32 kTrackColor = IM_COL32(70, 235, 110, 255);
constexpr ImU32 kCameraTrueColor = IM_COL32(60, 220, 255, 200);
const ImVec4 kOkText{0.45f, 0.95f, 0.55f, 1.0f};
const ImVec4 kRejectText{1.0f, 0.55f, 0.45f, 1.0f};
const ImVec4 kDimText{0.62f, 0.65f, 0.70f, 1.0f};

bool measured(double v) { return std::isfinite(v); }

// Maps sensor (y, z) in mm to panel pixels: y to the right, z downwards,
// one scale for both axes.
struct PlotMap {
  ImVec2 origin;  // pixel of (y0, z0)
  double y0 = 0.0, z0 = 0.0, scale = 1.0;
  ImVec2 operator()(double y, double z) const {
    return ImVec2(origin.x + static_cast<float>((y - y0) * scale),
                  origin.y + static_cast<float>((z - z0) * scale));
  }
};

void plot_profile(const App& app, ImVec2 size) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  ImGui::Dummy(size);
  dl->AddRectFilled(p0, p1, kPlotBg);

  const Profile* profile = app.last_profile();
  const tracker::TrackResult* track = app.last_track();
  const ScannerDesc& desc = app.cell().scanner;

  // Data range: the valid points (or, before the first scan, the fan at the
  // depth of field's near part), padded; equal aspect.
  double ylo = 1e30, yhi = -1e30, zlo = 1e30, zhi = -1e30;
  int valid = 0;
  if (profile) {
    for (int i = 0; i < profile->size(); ++i) {
      if (!profile->valid[i]) continue;
      ++valid;
      ylo = std::min<double>(ylo, profile->y_mm[i]);
      yhi = std::max<double>(yhi, profile->y_mm[i]);
      zlo = std::min<double>(zlo, profile->z_mm[i]);
      zhi = std::max<double>(zhi, profile->z_mm[i]);
    }
  }
  if (valid < 2) {
    const double z = 100.0, half = z * std::tan(0.5 * desc.fan_deg * 3.14159265358979 / 180.0);
    ylo = -half, yhi = half, zlo = 0.6 * z, zhi = 1.4 * z;
  }
  const float left = 46.0f, right = 12.0f, top = 22.0f, bottom = 30.0f;
  const double w = std::max(1.0f, size.x - left - right), h = std::max(1.0f, size.y - top - bottom);
  double dy = std::max(yhi - ylo, 1.0), dz = std::max(zhi - zlo, 1.0);
  const double scale = 0.9 * std::min(w / dy, h / dz);
  const double yc = 0.5 * (ylo + yhi), zc = 0.5 * (zlo + zhi);
  dy = w / scale;
  dz = h / scale;
  PlotMap map{ImVec2(p0.x + left, p0.y + top), yc - 0.5 * dy, zc - 0.5 * dz, scale};

  // Grid and tick labels.
  const ImVec2 a0(p0.x + left, p0.y + top), a1(p1.x - right, p1.y - bottom);
  dl->PushClipRect(p0, p1, true);
  char label[32];
  for (double y : plot::ticks(map.y0, map.y0 + dy, 6)) {
    const float x = map(y, map.z0).x;
    if (x < a0.x || x > a1.x) continue;
    dl->AddLine(ImVec2(x, a0.y), ImVec2(x, a1.y), kPlotGrid);
    std::snprintf(label, sizeof label, "%g", y);
    dl->AddText(ImVec2(x - ImGui::CalcTextSize(label).x * 0.5f, a1.y + 3.0f), kPlotText, label);
  }
  for (double z : plot::ticks(map.z0, map.z0 + dz, 6)) {
    const float y = map(map.y0, z).y;
    if (y < a0.y || y > a1.y) continue;
    dl->AddLine(ImVec2(a0.x, y), ImVec2(a1.x, y), kPlotGrid);
    std::snprintf(label, sizeof label, "%g", z);
    dl->AddText(ImVec2(a0.x - ImGui::CalcTextSize(label).x - 4.0f, y - 7.0f), kPlotText, label);
  }
  dl->AddRect(a0, a1, kPlotFrame);
  dl->AddText(ImVec2(a1.x - 60.0f, a1.y + 15.0f), kPlotText, "y (mm)");
  dl->AddText(ImVec2(p0.x + 4.0f, p0.y + 4.0f), kPlotText, "z (mm), down: range along the optical axis");

  dl->PushClipRect(a0, a1, true);
  if (profile) {
    const tracker::Segmentation& seg = app.tracker().segmentation();
    for (int i = 0; i < profile->size(); ++i) {
      if (!profile->valid[i]) continue;
      const bool outlier = i < static_cast<int>(seg.column_state.size()) &&
                           seg.column_state[static_cast<std::size_t>(i)] == tracker::kColumnOutlier;
      dl->AddCircleFilled(map(profile->y_mm[i], profile->z_mm[i]), outlier ? 2.5f : 1.6f,
                          outlier ? kOutlierColor : kPointColor, 6);
    }
  }
  if (profile && track) {
    // Fitted segments, between the feet of their end columns on their lines.
    for (const auto& s : track->segments) {
      if (s.points < 2) continue;
      const auto foot = [&](int col) {
        const tracker::Vec2 q(profile->y_mm[col], profile->z_mm[col]);
        return s.line.project(q);
      };
      const tracker::Vec2 a = foot(s.first_col), b = foot(s.last_col);
      dl->AddLine(map(a.x(), a.y()), map(b.x(), b.y()), kSegmentColor, 2.0f);
    }
    // Labels of break points that (nearly) coincide are stacked upwards.
    ImVec2 placed[tracker::kMaxBreakPoints];
    int placed_count = 0;
    for (int k = 0; k < tracker::kMaxBreakPoints; ++k) {
      const auto& bp = track->break_points[static_cast<std::size_t>(k)];
      if (!bp) continue;
      const ImVec2 c = map(bp->x(), bp->y());
      dl->AddCircle(c, 5.0f, kBreakColor, 16, 2.0f);
      int stack = 0;
      for (int j = 0; j < placed_count; ++j)
        if (std::abs(placed[j].x - c.x) < 14.0f && std::abs(placed[j].y - c.y) < 14.0f) ++stack;
      placed[placed_count++] = c;
      std::snprintf(label, sizeof label, "B%d", k);
      dl->AddText(ImVec2(c.x + 7.0f, c.y - 16.0f - 13.0f * static_cast<float>(stack)), kBreakColor, label);
    }
    if (track->track_point) {
      const ImVec2 c = map(track->track_point->x(), track->track_point->y());
      dl->AddLine(ImVec2(c.x - 8, c.y), ImVec2(c.x + 8, c.y), kTrackColor, 2.0f);
      dl->AddLine(ImVec2(c.x, c.y - 8), ImVec2(c.x, c.y + 8), kTrackColor, 2.0f);
      dl->AddText(ImVec2(c.x + 6, c.y + 4), kTrackColor, "TP");
    }
  }
  dl->PopClipRect();
  dl->PopClipRect();
}

// A name and value pair in a two-pair-per-row table; NaN (not measured) is skipped.
void value_cell(const char* name, double v, const char* unit) {
  if (!measured(v)) return;
  ImGui::TableNextColumn();
  ImGui::TextColored(kDimText, "%s", name);
  ImGui::TableNextColumn();
  ImGui::Text("%.3f %s", v, unit);
}

void track_readout(const App& app) {
  const tracker::TrackResult* t = app.last_track();
  const Profile* p = app.last_profile();
  if (!t || !p) {
    ImGui::TextColored(kDimText, "no profile yet (the sensor scans while the simulation runs)");
    return;
  }
  ImGui::Text("%s template:", std::string(tracker::to_string(t->joint)).c_str());
  ImGui::SameLine();
  if (t->status == tracker::TrackStatus::Ok)
    ImGui::TextColored(kOkText, "ACCEPTED");
  else
    ImGui::TextColored(kRejectText, "%s", t->status == tracker::TrackStatus::Rejected ? "REJECTED" : "NO DATA");
  ImGui::SameLine();
  ImGui::TextColored(kDimText, "  profile #%lld at %.2f s", static_cast<long long>(p->index), p->time_s);
  ImGui::TextColored(kDimText, "%d/%d points valid, %d outliers, %zu segments", p->valid_count(), p->size(),
                     t->outliers, t->segments.size());
  if (!t->reason.empty()) ImGui::TextColored(kRejectText, "reason: %s", t->reason.c_str());

  if (ImGui::BeginTable("values", 4, ImGuiTableFlags_SizingStretchProp)) {
    if (t->track_point) {
      ImGui::TableNextColumn();
      ImGui::TextColored(kDimText, "track point");
      ImGui::TableNextColumn();
      ImGui::Text("%.3f, %.3f mm", t->track_point->x(), t->track_point->y());
    }
    value_cell("gap", t->gap_mm, "mm");
    value_cell("angle", t->angle_deg, "deg");
    value_cell("gap (paper)", t->gap_paper_mm, "mm");
    value_cell("mismatch", t->mismatch_mm, "mm");
    value_cell("step", t->step_mm, "mm");
    value_cell("depth", t->depth_mm, "mm");
    value_cell("area", t->area_mm2, "mm2");
    value_cell("wall a", t->wall_angle_a_deg, "deg");
    value_cell("wall b", t->wall_angle_b_deg, "deg");
    value_cell("top width", t->top_width_mm, "mm");
    ImGui::EndTable();
  }
  if (ImGui::BeginTable("breaks", 4, ImGuiTableFlags_SizingFixedFit)) {
    for (int k = 0; k < tracker::kMaxBreakPoints; ++k) {
      const auto& bp = t->break_points[static_cast<std::size_t>(k)];
      if (!bp) continue;
      ImGui::TableNextColumn();
      ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.08f, 1.0f), "B%d", k);
      ImGui::TableNextColumn();
      ImGui::Text("y %8.3f", bp->x());
      ImGui::TableNextColumn();
      ImGui::Text("z %8.3f", bp->y());
      ImGui::TableNextColumn();
      ImGui::TextColored(kDimText, "%s", std::string(tracker::break_point_name(t->joint, k)).c_str());
    }
    ImGui::EndTable();
  }
}

template <typename Names, typename Describe, typename Pick>
void name_combo(const char* id, const std::string& prefix, const std::string& current, const Names& names,
                Describe describe, Pick pick) {
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (ImGui::BeginCombo(id, (prefix + current).c_str())) {
    for (const auto& name : names) {
      if (ImGui::Selectable(name.c_str(), name == current)) pick(name);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", describe(name).c_str());
    }
    ImGui::EndCombo();
  }
}

// The camera-image panel (the camera-image mode): the latest image, cropped
// to the rows around the light, with the true stripe (where the ideal lit
// point of each column images) and the peaks the detector chose.
void camera_image_panel(App& app, ImVec2 size) {
  const CameraImage* im = app.last_image();
  const unsigned texture = app.image_texture();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (!im || !texture || im->width <= 0 || im->rows <= 0) {
    ImGui::TextColored(kDimText, "camera image: waiting for the first image");
    return;
  }
  // Rows with light in them, padded.
  float lo = 1e30f, hi = -1e30f;
  int chose_true = 0, labelled = 0;
  for (int c = 0; c < im->width; ++c) {
    for (const std::vector<float>* rows : {&im->true_row, &im->chosen_row, &im->mirror_row, &im->bounce_row})
      if (c < static_cast<int>(rows->size()) && std::isfinite((*rows)[static_cast<std::size_t>(c)])) {
        lo = std::min(lo, (*rows)[static_cast<std::size_t>(c)]);
        hi = std::max(hi, (*rows)[static_cast<std::size_t>(c)]);
      }
    if (c < static_cast<int>(im->true_peak.size()) && im->true_peak[static_cast<std::size_t>(c)] >= 0) {
      ++labelled;
      chose_true += im->chosen_peak[static_cast<std::size_t>(c)] == im->true_peak[static_cast<std::size_t>(c)];
    }
  }
  const float first = static_cast<float>(im->first_row), last = first + static_cast<float>(im->rows);
  if (!(lo <= hi)) lo = first, hi = last;
  lo = std::max(first, std::floor(lo) - 16.0f);
  hi = std::min(last, std::ceil(hi) + 17.0f);
  if (hi - lo < 48.0f) {
    const float mid = 0.5f * (lo + hi);
    lo = std::max(first, mid - 24.0f);
    hi = std::min(last, lo + 48.0f);
  }
  ImGui::TextColored(kDimText, "camera image, rows %.0f-%.0f: true stripe cyan, chosen peaks green, true in %d/%d columns",
                     lo, hi - 1.0f, chose_true, labelled);
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  ImGui::Dummy(size);
  const float v0 = (lo - first) / static_cast<float>(im->rows), v1 = (hi - first) / static_cast<float>(im->rows);
  dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(texture)), p0, p1, ImVec2(0.0f, v0),
               ImVec2(1.0f, v1));
  dl->AddRect(p0, p1, kPlotFrame);
  const float sx = size.x / static_cast<float>(im->width), sy = size.y / (hi - lo);
  const auto at = [&](int c, float row) {  // pixel centre (c, row)
    return ImVec2(p0.x + (static_cast<float>(c) + 0.5f) * sx, p0.y + (row - lo + 0.5f) * sy);
  };
  dl->PushClipRect(p0, p1, true);
  for (int c = 0; c + 1 < static_cast<int>(im->true_row.size()); ++c) {
    const float a = im->true_row[static_cast<std::size_t>(c)], b = im->true_row[static_cast<std::size_t>(c + 1)];
    if (std::isfinite(a) && std::isfinite(b) && std::abs(a - b) < 4.0f) dl->AddLine(at(c, a), at(c + 1, b), kCameraTrueColor);
  }
  const int step = std::max(1, static_cast<int>(4.0f / std::max(sx, 1e-3f)));  // a peak every 4 px
  for (int c = 0; c < static_cast<int>(im->chosen_row.size()); c += step) {
    const float r = im->chosen_row[static_cast<std::size_t>(c)];
    if (std::isfinite(r)) dl->AddRectFilled(ImVec2(at(c, r).x - 1.0f, at(c, r).y - 1.0f), ImVec2(at(c, r).x + 1.0f, at(c, r).y + 1.0f), kTrackColor);
  }
  dl->PopClipRect();
}

void controls(App& app) {
  const ScannerDesc& desc = app.cell().scanner;
  if (!ImGui::BeginTable("controls", 2, ImGuiTableFlags_SizingStretchSame)) return;

  ImGui::TableNextColumn();
  name_combo("##cell", "cell: ", app.scene_label(), builtin_cell_names(),
             [](const std::string& n) { return builtin_cell_description(n); },
             [&](const std::string& n) { app.load_builtin(n); });
  ImGui::TableNextColumn();
  const tracker::JointType joint = app.tracker().params().joint;
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (ImGui::BeginCombo("##joint", ("joint template: " + std::string(tracker::to_string(joint))).c_str())) {
    for (tracker::JointType j : tracker::kAllJointTypes)
      if (ImGui::Selectable(std::string(tracker::to_string(j)).c_str(), j == joint)) app.set_joint_template(j);
    ImGui::EndCombo();
  }

  // Sensor preset (sensor/presets.h), surface material, error model
  // (sensor/error_model.h).
  ImGui::TableNextColumn();
  name_combo("##preset", "sensor: ", desc.name, sensor_preset_names(),
             [](const std::string& n) { return sensor_preset_description(n); },
             [&](const std::string& n) { app.set_sensor_preset(n); });
  ImGui::TableNextColumn();
  name_combo("##material", "material: ", desc.material, material_names(),
             [](const std::string& n) { return material_description(n); },
             [&](const std::string& n) { app.set_material(n); });

  ImGui::TableNextColumn();
  bool on = app.error_model();
  if (ImGui::Checkbox("error model", &on)) app.set_error_model(on);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("on: profiles as the sensor measures them (noise, quantization, camera shadow, "
                      "outliers, dropouts); off: the ideal geometric profile");
  ImGui::TableNextColumn();
  bool image = app.camera_image();
  if (ImGui::Checkbox("camera image (I)", &image)) app.set_camera_image(image);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("profiles read from the rendered stripe image, peaks per image column "
                      "(sheet, reflections, speckle, sensor noise); the image is shown under the 3D view");
  ImGui::TableNextColumn();
  int source = app.source_kind() == SourceKind::Raster ? 0 : 1;
  if (ImGui::RadioButton("raster", &source, 0)) app.set_source(SourceKind::Raster);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the OSMesa raster emulator (render/)");
  ImGui::SameLine();
  if (ImGui::RadioButton("reference", &source, 1)) app.set_source(SourceKind::Reference);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the Embree ray-cast reference (sensor/)");

  ImGui::TableNextColumn();
  float speed = static_cast<float>(app.speed_mm_s);
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (ImGui::SliderFloat("##speed", &speed, 0.5f, 1000.0f, "speed %.1f mm/s", ImGuiSliderFlags_Logarithmic))
    app.speed_mm_s = speed;
  ImGui::TableNextColumn();
  float turn = static_cast<float>(app.turn_deg_s);
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (ImGui::SliderFloat("##turn", &turn, 0.5f, 360.0f, "turn %.1f deg/s", ImGuiSliderFlags_Logarithmic))
    app.turn_deg_s = turn;

  ImGui::TableNextColumn();
  ImGui::Checkbox("pause (Space)", &app.paused);
  ImGui::TableNextColumn();
  ImGui::Checkbox("auto travel (M)", &app.auto_travel);
  ImGui::TableNextColumn();
  ImGui::Checkbox("camera follows (V)", &app.follow_camera);
  ImGui::TableNextColumn();
  ImGui::Checkbox("world axes", &app.world_axes);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the keys move and turn the torch along world x, y, z");
  ImGui::EndTable();

  if (ImGui::Button(app.recording() ? "stop recording (P)" : "record EXR (P)")) app.toggle_recording();
  ImGui::SameLine();
  if (ImGui::Button("reset torch")) app.reset_torch();
  ImGui::SameLine();
  if (ImGui::Button("reset view")) app.reset_camera();
  ImGui::SameLine();
  ImGui::Checkbox("help (H)", &app.show_help);
  ImGui::TextColored(kDimText, "%d points, %.0f deg fan, %.0f Hz, depth of field %.0f..%.0f mm", desc.points,
                     desc.fan_deg, desc.rate_hz, desc.min_range_mm, desc.max_range_mm);
}

}  // namespace

int panel_width(int window_width) { return std::clamp(window_width * 2 / 5, 200, 470); }

void apply_style() {
  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0.0f;
  style.WindowBorderSize = 0.0f;
  style.Colors[ImGuiCol_WindowBg] = ImVec4(kPanelBg[0], kPanelBg[1], kPanelBg[2], kPanelBg[3]);
}

void draw_panels(App& app, int window_width, int window_height, const FrameStats& stats) {
  const float pw = static_cast<float>(panel_width(window_width));
  const float view_w = static_cast<float>(window_width) - pw;

  ImGui::SetNextWindowPos(ImVec2(view_w, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(pw, static_cast<float>(window_height)));
  ImGui::Begin("Profile", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoSavedSettings);
  ImGui::TextColored(kDimText, "profile, sensor frame: y along the laser line, z the range");
  const float plot_h = std::clamp(static_cast<float>(window_height) * 0.38f, 160.0f, 360.0f);
  plot_profile(app, ImVec2(ImGui::GetContentRegionAvail().x, plot_h));
  ImGui::Separator();
  track_readout(app);
  ImGui::Separator();
  controls(app);
  ImGui::Separator();
  ImGui::TextWrapped("%s", app.status().c_str());
  ImGui::End();

  if (app.camera_image()) {
    // Under the 3D view, beside the profile panel.
    const float h = std::clamp(static_cast<float>(window_height) * 0.3f, 140.0f, 320.0f);
    ImGui::SetNextWindowPos(ImVec2(0.0f, static_cast<float>(window_height) - h));
    ImGui::SetNextWindowSize(ImVec2(view_w, h));
    ImGui::Begin("Camera image", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoTitleBar);
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    camera_image_panel(app, ImVec2(avail.x, std::max(40.0f, avail.y - ImGui::GetTextLineHeightWithSpacing())));
    ImGui::End();
  }

  // Status overlay, top-left of the 3D view.
  ImGui::SetNextWindowPos(ImVec2(8.0f, 8.0f));
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("Status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
  const Pose& t = app.world_from_torch();
  Vec3 rpy = rpy_deg_of(t);
  for (int i = 0; i < 3; ++i)
    if (std::abs(rpy[i]) < 5e-3) rpy[i] = 0.0;  // no "-0.00"
  Vec3 tcp = t.translation();
  for (int i = 0; i < 3; ++i)
    if (std::abs(tcp[i]) < 5e-3) tcp[i] = 0.0;
  ImGui::Text("%s   %s", app.scene_label().c_str(), app.paused ? "PAUSED" : "");
  ImGui::Text("TCP  %8.2f %8.2f %8.2f mm   rpy %7.2f %7.2f %7.2f deg (world)", tcp.x(), tcp.y(), tcp.z(),
              rpy.x(), rpy.y(), rpy.z());
  ImGui::Text("speed %.1f mm/s, %.1f deg/s%s   sim %.2f s, %lld scans (%s, %.2f ms each)",
              app.speed_mm_s, app.turn_deg_s, app.auto_travel ? " (auto travel)" : "", app.sim_time_s(),
              static_cast<long long>(app.scans()),
              app.source_kind() == SourceKind::Raster ? "raster" : "reference", app.last_scan_ms());
  ImGui::Text("%.1f frames/s (%.1f ms)   H: help", stats.fps, stats.frame_ms);
  if (app.recording())
    ImGui::TextColored(kRejectText, "REC %zu profiles", app.recorded_profiles());
  if (app.sensor_behind())
    ImGui::TextColored(kRejectText, "the sensor thread is behind: simulated time waits for it");
  ImGui::TextColored(kDimText, "%s", app.mount_note().c_str());
  ImGui::End();

  if (app.show_help) {
    ImGui::SetNextWindowPos(ImVec2(8.0f, static_cast<float>(window_height) - 8.0f), ImGuiCond_Always,
                            ImVec2(0.0f, 1.0f));
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("Keys", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoCollapse);
    const auto keys = key_table();
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i].action.empty()) continue;
      std::string label(keys[i].label);
      if (i + 1 < keys.size() && keys[i + 1].action.empty()) label += " / " + std::string(keys[i + 1].label);
      ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.4f, 1.0f), "%-9s", label.c_str());
      ImGui::SameLine();
      ImGui::Text("%s", std::string(keys[i].action).c_str());
    }
    ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.4f, 1.0f), "%-9s", "mouse");
    ImGui::SameLine();
    ImGui::Text("left-drag orbit, right/middle-drag pan, wheel zoom");
    ImGui::End();
  }
}

}  // namespace vts::viewer
