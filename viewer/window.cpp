#include "viewer/window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "viewer/app.h"
#include "viewer/keys.h"
#include "viewer/panel.h"
#include "viewer/renderer.h"
#include "viewer/sim_view.h"
#include "tracker/master.h"

namespace vts::viewer {
namespace {

namespace fs = std::filesystem;

constexpr int kExitOk = 0;
constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

// Scripted runs (--screenshot, --frames, --keys) advance the simulation by
// this much per frame, so a key script gives the same pictures on any machine.
constexpr double kScriptedFrameS = 1.0 / 30.0;
// Interactive frames longer than this (a stall) advance the simulation by
// this much only.
constexpr double kMaxFrameS = 0.1;

constexpr Rgba kBackground{0.16f, 0.17f, 0.20f, 1.0f};


// Held keys and presses since the last frame, from GLFW's callbacks.
struct Input {
  std::vector<Key> presses;
  double scroll = 0.0;
  bool scripted = false;
};

std::optional<Key> press_key_of(int glfw_key) {
  switch (glfw_key) {
    case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD: return Key::Faster;
    case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT: return Key::Slower;
    case GLFW_KEY_H: return Key::Help;
    case GLFW_KEY_SPACE: return Key::Pause;
    case GLFW_KEY_P: return Key::Record;
    case GLFW_KEY_M: return Key::AutoTravel;
    case GLFW_KEY_V: return Key::FollowCamera;
    case GLFW_KEY_BACKSPACE: return Key::ResetTorch;
    case GLFW_KEY_HOME: return Key::ResetView;
    case GLFW_KEY_B: return Key::LayBead;
    case GLFW_KEY_I: return Key::CameraImage;
    case GLFW_KEY_ESCAPE: return Key::Quit;
    default: return std::nullopt;
  }
}

struct HeldKey {
  int glfw;
  Key key;
};
constexpr HeldKey kHeldKeys[] = {
    {GLFW_KEY_W, Key::Forward},   {GLFW_KEY_S, Key::Back},      {GLFW_KEY_A, Key::Left},
    {GLFW_KEY_D, Key::Right},     {GLFW_KEY_R, Key::Up},        {GLFW_KEY_F, Key::Down},
    {GLFW_KEY_Q, Key::RollLeft},  {GLFW_KEY_E, Key::RollRight}, {GLFW_KEY_Z, Key::YawLeft},
    {GLFW_KEY_C, Key::YawRight},  {GLFW_KEY_T, Key::PitchUp},   {GLFW_KEY_G, Key::PitchDown},
};

void on_key(GLFWwindow* window, int key, int, int action, int) {
  auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
  if (!input || input->scripted || action != GLFW_PRESS) return;
  if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard) return;
  if (auto k = press_key_of(key)) input->presses.push_back(*k);
}

void on_scroll(GLFWwindow* window, double, double dy) {
  auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
  if (!input || input->scripted) return;
  if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
  input->scroll += dy;
}

void add_motion(Key k, MotionInput& m) {
  switch (k) {
    case Key::Forward: m.translate.x() += 1; break;
    case Key::Back: m.translate.x() -= 1; break;
    case Key::Right: m.translate.y() += 1; break;
    case Key::Left: m.translate.y() -= 1; break;
    case Key::Down: m.translate.z() += 1; break;
    case Key::Up: m.translate.z() -= 1; break;
    case Key::RollRight: m.rotate.x() += 1; break;
    case Key::RollLeft: m.rotate.x() -= 1; break;
    case Key::PitchUp: m.rotate.y() += 1; break;
    case Key::PitchDown: m.rotate.y() -= 1; break;
    case Key::YawRight: m.rotate.z() += 1; break;
    case Key::YawLeft: m.rotate.z() -= 1; break;
    default: break;
  }
}

std::string write_png(const fs::path& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  std::error_code ec;
  if (!path.parent_path().empty()) fs::create_directories(path.parent_path(), ec);
  const fs::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  if (!stbi_write_png(tmp.c_str(), width, height, 3, rgb.data(), width * 3)) {
    fs::remove(tmp, ec);
    return "cannot write " + tmp.string();
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return "cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message();
  }
  return {};
}

}  // namespace

int run_window(WindowOptions o) {
  const std::vector<KeyFrame>& script = o.script;
  const int width = o.width, height = o.height;
  const bool scripted = !o.screenshot.empty() || o.frames || !script.empty();
  const long total_frames = o.frames ? *o.frames : static_cast<long>(script.size()) + 3;

  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) {
    std::cerr << "vts-view: no X display ($DISPLAY is not set). Without a screen, run it under Xvfb:\n"
                 "  xvfb-run -a -s '-screen 0 1280x1024x24' vts-view "
              << (o.screenshot.empty() ? "" : "--screenshot " + o.screenshot + " ") << "...\n";
    return kExitRuntime;
  }

  glfwSetErrorCallback([](int code, const char* what) {
    std::cerr << "vts-view: GLFW error " << code << ": " << what << "\n";
  });
  if (!glfwInit()) {
    std::cerr << "vts-view: cannot initialise GLFW on display " << display << "\n";
    return kExitRuntime;
  }
  struct GlfwTerminate {
    ~GlfwTerminate() { glfwTerminate(); }
  } glfw_terminate;

  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, "vts-view", nullptr, nullptr);
  if (!window) {
    std::cerr << "vts-view: cannot open a " << width << "x" << height
              << " OpenGL 3.3 core window (under Xvfb give it a 24-bit screen: "
                 "xvfb-run -a -s '-screen 0 1280x1024x24')\n";
    return kExitRuntime;
  }
  struct WindowDestroy {
    GLFWwindow* w;
    ~WindowDestroy() { glfwDestroyWindow(w); }
  } window_destroy{window};
  glfwMakeContextCurrent(window);
  glfwSwapInterval(scripted || o.fps ? 0 : 1);

  Input input;
  input.scripted = scripted;
  glfwSetWindowUserPointer(window, &input);
  // Installed before ImGui's, which chains to them.
  glfwSetKeyCallback(window, on_key);
  glfwSetScrollCallback(window, on_scroll);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  struct ImGuiDestroy {
    ~ImGuiDestroy() { ImGui::DestroyContext(); }
  } imgui_destroy;
  ImGui::GetIO().IniFilename = nullptr;  // nothing written to the working directory
  apply_style();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  struct BackendShutdown {
    ~BackendShutdown() {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
    }
  } backend_shutdown;

  Renderer renderer;
  std::unique_ptr<App> app;
  SimView sim_view;
  try {
    if (o.sim) {
      sim_view = run_sim_for_view(o.app.seed, o.sensor, o.material, o.ideal, o.scenario);
      o.app.given_cell = sim_view.cell;
      o.app.given_label = sim_view.label;
    }
    app = std::make_unique<App>(o.app, renderer);
  } catch (const std::runtime_error& e) {
    std::cerr << "vts-view: " << e.what() << "\n";
    return kExitUsage;
  }
  app->set_source(o.source);
  if (!o.sensor.empty()) app->set_sensor_preset(o.sensor);
  if (!o.material.empty()) app->set_material(o.material);
  if (o.ideal) app->set_error_model(false);
  if (o.camera_image) app->set_camera_image(true);
  // Scripted runs wait for each frame's scans, so their pictures do not
  // depend on the machine's speed; --fps measures the interactive behaviour.
  app->sync_scans = scripted && !o.fps;
  if (o.sim) {
    app->drive_torch = [&sim_view](double t) -> std::optional<vts::Pose> {
      if (sim_view.samples.empty()) return std::nullopt;
      const std::size_t k = sample_at(sim_view, t);
      // Where the TCP really was (an arm's, not the master's command).
      return k < sim_view.tcp.size() ? sim_view.tcp[k] : sim_view.samples[k].world_from_tool;
    };
    app->seam_paths = sim_view.seam_paths;
    if (!sim_view.arm_links.empty()) {
      app->set_attachments(sim_view.arm_links, [&sim_view](double t) {
        const std::size_t k = sample_at(sim_view, t);
        return k < sim_view.arm_poses.size() ? sim_view.arm_poses[k] : std::vector<vts::Pose>{};
      });
      // Far enough to see the arm and the cell: from the side of the line
      // from the base to the work, above.
      if (!sim_view.arm_poses.empty() && !sim_view.tcp.empty()) {
        const vts::Vec3 base = sim_view.arm_poses.front().front().translation();
        const vts::Vec3 work = sim_view.tcp.front().translation();
        vts::Vec3 across = vts::Vec3::UnitZ().cross(work - base);
        across.z() = 0.0;
        app->camera() = camera_looking_at(0.5 * (base + work) + vts::Vec3(0.0, 0.0, 500.0),
                                          across.normalized() + 0.5 * vts::Vec3::UnitZ(), 4200.0);
      }
    }
    app->set_status(sim_view.summary);
  }

  using Clock = std::chrono::steady_clock;
  auto last = Clock::now();
  Clock::time_point timing_start = last;
  long frames_done = 0;
  constexpr long kWarmupFrames = 10;
  FrameStats stats;
  double smoothed_s = 0.0;
  int drag_button = -1;
  double drag_x = 0.0, drag_y = 0.0;
  int exit_code = kExitOk;
  std::string last_status;

  for (long frame = 0; !glfwWindowShouldClose(window) && !app->quit_requested(); ++frame) {
    if (scripted && frame >= total_frames) break;
    glfwPollEvents();
    const auto now = Clock::now();
    const double real_dt = std::chrono::duration<double>(now - last).count();
    last = now;
    if (frame > 0) smoothed_s = smoothed_s == 0.0 ? real_dt : 0.9 * smoothed_s + 0.1 * real_dt;
    stats.frame_ms = 1000.0 * smoothed_s;
    stats.fps = smoothed_s > 0.0 ? 1.0 / smoothed_s : 0.0;
    if (frame == kWarmupFrames) timing_start = now;

    int win_w = 0, win_h = 0, fb_w = 0, fb_h = 0;
    glfwGetWindowSize(window, &win_w, &win_h);
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    const int view_win_w = win_w - panel_width(win_w);
    const double fb_per_win = win_w > 0 ? static_cast<double>(fb_w) / win_w : 1.0;

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImGuiIO& io = ImGui::GetIO();

    MotionInput motion;
    std::vector<Key> presses;
    if (scripted) {
      if (frame < static_cast<long>(script.size()))
        for (Key k : script[static_cast<std::size_t>(frame)]) {
          if (key_info(k).held)
            add_motion(k, motion);
          else
            presses.push_back(k);
        }
    } else {
      presses.swap(input.presses);
      if (!io.WantCaptureKeyboard)
        for (const HeldKey& h : kHeldKeys)
          if (glfwGetKey(window, h.glfw) == GLFW_PRESS) add_motion(h.key, motion);

      // Mouse on the 3D view: left-drag orbit, right/middle-drag pan, wheel zoom.
      double mx = 0.0, my = 0.0;
      glfwGetCursorPos(window, &mx, &my);
      if (drag_button < 0 && !io.WantCaptureMouse && mx < view_win_w) {
        for (int b : {GLFW_MOUSE_BUTTON_LEFT, GLFW_MOUSE_BUTTON_RIGHT, GLFW_MOUSE_BUTTON_MIDDLE})
          if (glfwGetMouseButton(window, b) == GLFW_PRESS) {
            drag_button = b;
            drag_x = mx;
            drag_y = my;
            break;
          }
      }
      if (drag_button >= 0) {
        if (glfwGetMouseButton(window, drag_button) != GLFW_PRESS) {
          drag_button = -1;
        } else {
          if (drag_button == GLFW_MOUSE_BUTTON_LEFT)
            app->camera().orbit(mx - drag_x, my - drag_y);
          else
            app->camera().pan(mx - drag_x, my - drag_y, win_h);
          drag_x = mx;
          drag_y = my;
        }
      }
      if (input.scroll != 0.0) {
        app->camera().zoom(input.scroll);
        input.scroll = 0.0;
      }
    }
    for (Key k : presses) app->press(k);
    // Recordings written (or not) go to the terminal as well.
    if (app->status() != last_status) {
      last_status = app->status();
      if (last_status.rfind("wrote ", 0) == 0 || last_status.rfind("recording", 0) == 0)
        std::printf("vts-view: %s\n", last_status.c_str());
    }
    if (o.sim && !sim_view.samples.empty() && !app->recording()) {
      const auto& smp = sim_view.samples[sample_at(sim_view, app->sim_time_s())];
      const std::string where = smp.seam < 0 ? std::string("done")
                                             : "seam " + std::to_string(smp.seam + 1) + ", " +
                                                   std::string(vts::tracker::to_string(smp.phase)) + ", sensor " +
                                                   std::string(vts::tracker::to_string(smp.sensor));
      app->set_status(where + " | " + sim_view.summary);
    }
    const double dt = scripted && !o.fps ? kScriptedFrameS : std::min(real_dt, kMaxFrameS);
    app->update(motion, frame == 0 ? kScriptedFrameS : dt);

    draw_panels(*app, win_w, win_h, stats);
    ImGui::Render();

    renderer.clear(fb_w, fb_h, kBackground);
    SceneView view;
    app->build_scene(view, static_cast<int>(view_win_w * fb_per_win), fb_h);
    renderer.draw(view);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

    if (!o.screenshot.empty() && frame == total_frames - 1) {
      const auto rgb = renderer.read_pixels_rgb(fb_w, fb_h);
      if (const std::string err = write_png(o.screenshot, fb_w, fb_h, rgb); !err.empty()) {
        std::cerr << "vts-view: --screenshot: " << err << "\n";
        exit_code = kExitRuntime;
      } else {
        const vts::Vec2 tcp = app->tcp_pixel(), nozzle = app->nozzle_pixel();
        std::printf("vts-view: wrote %s (%dx%d); 3D view x < %d; TCP at pixel %.0f %.0f; nozzle at pixel %.0f %.0f\n",
                    o.screenshot.c_str(), fb_w, fb_h, static_cast<int>(view_win_w * fb_per_win), tcp.x(),
                    tcp.y(), nozzle.x(), nozzle.y());
      }
    }
    glfwSwapBuffers(window);
    ++frames_done;
  }

  if (o.fps) {
    const double s = std::chrono::duration<double>(Clock::now() - timing_start).count();
    const long timed_frames = frames_done - kWarmupFrames;
    if (timed_frames > 0 && s > 0.0)
      std::printf("vts-view: %ld frames at %dx%d in %.2f s: %.1f frames/s (%.2f ms per frame); "
                  "%lld scans in %.2f s simulated (%s, last %.2f ms per scan)\n",
                  timed_frames, width, height, s, timed_frames / s, 1000.0 * s / timed_frames,
                  static_cast<long long>(app->scans()), app->sim_time_s(),
                  app->source_kind() == SourceKind::Raster ? "raster" : "reference", app->last_scan_ms());
    else
      std::printf("vts-view: too few frames to time (need more than %ld)\n", kWarmupFrames);
  }
  if (app->recording()) {
    app->toggle_recording();  // a recording still running at exit is written
    std::printf("vts-view: %s\n", app->status().c_str());
  }
  app.reset();  // frees OSMesa contexts while the window exists
  std::fflush(stdout);
  return exit_code;
}

}  // namespace vts::viewer
