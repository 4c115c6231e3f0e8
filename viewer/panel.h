#pragma once
// vts-view's Dear ImGui panels: the profile panel on the right (after the
// paper's Figure 7: points, fitted segments, break points B0..B7, track
// point, process values, accept/reject, and the cell / joint template /
// source / sensor controls), a status overlay and the key help overlay.
#include "viewer/app.h"

namespace vts::viewer {

// The panel's background, opaque (ImGui WindowBg). The screenshot test looks
// for it: RGB (23, 26, 31).
inline constexpr float kPanelBg[4] = {0.09f, 0.10f, 0.12f, 1.0f};

// Width of the profile panel for a window `window_width` pixels wide; the 3D
// view gets the rest, on the left.
int panel_width(int window_width);

// Applies the viewer's ImGui style (after ImGui::CreateContext).
void apply_style();

struct FrameStats {
  double fps = 0.0;
  double frame_ms = 0.0;
};

// Builds this frame's panels (between ImGui::NewFrame and ImGui::Render).
void draw_panels(App& app, int window_width, int window_height, const FrameStats& stats);

}  // namespace vts::viewer
