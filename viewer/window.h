#pragma once
// vts-view's window: GLFW, an OpenGL 3.3 core context, Dear ImGui panels
// around the App (viewer/app.h); runs until Esc, the window closes or a
// scripted run's last frame (README "Viewer").
#include <optional>
#include <string>
#include <vector>

#include "viewer/app.h"
#include "viewer/keys.h"

namespace vts::viewer {

struct WindowOptions {
  AppOptions app;
  int width = 1280, height = 720;  // window size, pixels
  std::string screenshot;          // after the last frame, write the window to this PNG and exit
  std::optional<int> frames;       // run this many frames and exit
  std::vector<KeyFrame> script;    // scripted keys, one entry per frame
  bool fps = false;                // print the frame rate at exit; real-time simulation
  SourceKind source = SourceKind::Raster;
  std::string sensor, material;    // presets; empty: the cell's
  bool ideal = false;              // start with the error model off
  bool camera_image = false;       // start in the camera-image mode
  bool sim = false;                // show the run of `vts sim` (docs/SIM.md)
  std::string scenario;            // with sim: this scenario's run (a name or a file)
};

// Opens the window and runs the viewer. Returns the exit code: 0, 1 for a
// runtime failure (no display, GLFW or OpenGL, the screenshot), 2 for a bad
// cell or scene. Needs an X display ($DISPLAY).
int run_window(WindowOptions options);

}  // namespace vts::viewer
