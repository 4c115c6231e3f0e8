#pragma once
// vts-view's state and logic, apart from the window and the panels: the cell,
// the torch the keys drive, the sensor scanning at its rate of simulated time
// (a scan session, source and error model, on the sensor thread), the tracker on
// the latest profile, recording to EXR, and the 3D scene handed to the
// renderer as plain data. Needs a current OpenGL 3.3 core context (meshes
// are uploaded on load), nothing of the window.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "viewer/camera.h"
#include "viewer/keys.h"
#include "viewer/scan_worker.h"
#include "viewer/torch.h"
#include "viewer/renderer.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/profile.h"
#include "tracker/tracker.h"

namespace vts::viewer {

// Colour of the lit laser line in the 3D view: pure red, drawn unlit and
// unblended, and used nowhere else (the screenshot test looks for it).
inline constexpr Rgba kLaserLineColor{1.0f, 0.0f, 0.0f, 1.0f};

struct AppOptions {
  std::string cell = "static-B";  // built-in cell, unless scene is set
  std::filesystem::path scene;    // scene file (docs/SCENE_FORMAT.md)
  std::filesystem::path record;   // first recording's file; empty: a timestamped name
  std::uint64_t seed = 0;         // seed of the error model's random draws
  // A cell given directly instead of cell/scene (vts-view --sim), and its label.
  std::shared_ptr<const Cell> given_cell;
  std::string given_label;
};

class App {
 public:
  // Loads the cell; throws std::runtime_error (bad scene file, unknown cell)
  // with a message naming the option and value. `renderer` must outlive the App.
  App(const AppOptions& options, Renderer& renderer);
  ~App();

  // One frame: takes the scans finished since the last frame (error model,
  // tracker, recording), then moves the torch for dt_s of simulated time
  // with the held keys and submits the scans falling due to the sensor
  // thread. With sync_scans it waits for them, so the frame shows them
  // (reproducible pictures); otherwise they show a frame or more later. If
  // the sensor thread falls behind by more than half a second of scans, the
  // simulated clock waits for it.
  void update(const MotionInput& held, double dt_s);
  bool sync_scans = false;
  // When set, the torch follows this instead of the keys: its pose at a
  // simulated time (vts-view --sim), or empty to stay. Cleared when another
  // built-in cell is loaded.
  std::function<std::optional<Pose>(double time_s)> drive_torch;
  // Extra solids drawn with the cell (vts-view --sim: the robot arm's
  // links), uploaded now and with every reload, and their world poses at a
  // simulated time (one per attachment; empty: not drawn).
  struct Attachment {
    Mesh mesh;
    Rgba color;
  };
  void set_attachments(std::vector<Attachment> attachments,
                       std::function<std::vector<Pose>(double time_s)> poses);
  // Seam lines beyond the workpieces' straight ones (a curved seam's truth), world.
  std::vector<std::vector<Vec3>> seam_paths;
  // A non-motion key press (see key_table()).
  void press(Key key);
  bool quit_requested() const { return quit_; }

  // The 3D scene for a viewport of width x height pixels.
  void build_scene(SceneView& view, int width, int height);
  // Pixel (viewport top-left origin) of the TCP and of the nozzle's middle in
  // the last built scene.
  Vec2 tcp_pixel() const { return tcp_px_; }
  Vec2 nozzle_pixel() const { return nozzle_px_; }

  // Mouse gestures on the 3D view.
  OrbitCamera& camera() { return camera_; }
  void reset_camera();

  // Switches done from the panel.
  void load_builtin(const std::string& name);
  void set_source(SourceKind kind);
  void set_joint_template(tracker::JointType joint);
  // Sensor fields from a preset (sensor/presets.h); the mount and the
  // surface stay. Unknown names only set the status line.
  void set_sensor_preset(const std::string& name);
  void set_material(const std::string& name);
  // Error model on: profiles as the sensor measures them; off: ideal.
  void set_error_model(bool on);
  bool error_model() const { return !cell_.scanner.ideal; }
  // Camera-image mode (docs/SENSOR_MODEL.md, "The camera image"): profiles
  // read from the rendered stripe image; turns the error model on.
  void set_camera_image(bool on);
  bool camera_image() const { return cell_.scanner.camera_image && !cell_.scanner.ideal; }
  void toggle_recording();
  void reset_torch();
  // A groove cell: one more bead laid (the workpiece rebuilt, the sensor
  // and the drawing on the new one), as `vts sim --cell` does between passes.
  void lay_bead();

  // Read by the panels.
  const Cell& cell() const { return cell_; }
  const std::string& scene_label() const { return scene_label_; }
  const std::string& mount_note() const { return mount_note_; }
  const Pose& world_from_torch() const { return world_from_torch_; }
  Pose world_from_laser() const { return world_from_torch_ * cell_.scanner.tool_from_laser; }
  // The latest profile as measured (error model applied) and as the ideal
  // geometry gave it (the lit line).
  const Profile* last_profile() const { return have_profile_ ? &last_ : nullptr; }
  const Profile* last_ideal() const { return have_profile_ ? &last_ideal_ : nullptr; }
  // The latest camera image in the camera-image mode (labelled: true stripe,
  // chosen peaks), and a number that changes with each new one.
  const CameraImage* last_image() const { return last_image_ ? &*last_image_ : nullptr; }
  std::uint64_t image_serial() const { return image_serial_; }
  // That image as an OpenGL texture (uploaded when it changed; needs the
  // context current), 0 if there is none.
  unsigned image_texture();
  std::uint64_t seed() const { return options_.seed; }
  const tracker::TrackResult* last_track() const { return have_profile_ ? &track_ : nullptr; }
  const tracker::Tracker& tracker() const { return tracker_; }
  SourceKind source_kind() const { return source_kind_; }
  double sim_time_s() const { return clock_.time_s; }
  std::int64_t scans() const { return clock_.next_scan; }
  double last_scan_ms() const { return worker_.last_scan_ms(); }
  bool sensor_behind() const { return sensor_behind_; }
  bool recording() const { return recorder_.has_value(); }
  std::size_t recorded_profiles() const { return recorder_ ? recorder_->profiles.size() : 0; }
  const std::string& status() const { return status_; }
  void set_status(std::string s) { status_ = std::move(s); }

  // Settings the panel edits directly.
  double speed_mm_s = 25.0;
  double turn_deg_s = 20.0;
  bool paused = false;
  bool auto_travel = false;
  bool follow_camera = false;
  bool world_axes = false;  // translate/rotate along world axes instead of the tool's
  bool show_help = false;

 private:
  struct Recorder {
    std::filesystem::path path;
    double start_time_s = 0.0;
    std::vector<Profile> profiles;
    std::size_t bytes = 0;  // estimated memory of `profiles`
  };

  void load(Cell cell, std::string label);
  void upload_meshes();
  void scanner_changed();
  void configure_worker();
  void take_scans();
  void finish_recording();
  std::filesystem::path next_record_path();

  AppOptions options_;
  Renderer& renderer_;

  Cell cell_;
  std::string scene_label_;
  std::string mount_note_;
  double standoff_mm_ = 100.0;
  Pose start_torch_ = Pose::Identity();
  Pose world_from_torch_ = Pose::Identity();
  ScanClock clock_;

  SourceKind source_kind_ = SourceKind::Raster;
  ScanWorker worker_;
  std::vector<ScanWorker::Request> requests_;
  Profile last_;        // measured (error model applied)
  Profile last_ideal_;  // as the source gave it
  bool have_profile_ = false;
  std::optional<CameraImage> last_image_;
  std::uint64_t image_serial_ = 0;
  std::uint64_t uploaded_serial_ = 0;
  unsigned image_texture_ = 0;
  bool sensor_behind_ = false;

  tracker::Tracker tracker_;
  tracker::TrackResult track_;

  std::optional<Recorder> recorder_;
  int recordings_ = 0;
  std::string status_;
  bool quit_ = false;

  std::vector<Eigen::Vector3f> column_dirs_;  // sensor frame, per column
  Eigen::Vector3f bbox_lo_ = Eigen::Vector3f::Zero(), bbox_hi_ = Eigen::Vector3f::Zero();
  bool has_bbox_ = false;

  OrbitCamera camera_;
  struct Meshes {
    int workpieces = -1, nozzle = -1, body = -1, bracket = -1, housing = -1, camera = -1;
  } mesh_;
  std::vector<Attachment> attachments_;
  std::vector<int> attachment_ids_;
  std::function<std::vector<Pose>(double)> attachment_poses_;
  Vec2 tcp_px_ = Vec2::Zero(), nozzle_px_ = Vec2::Zero();
};

}  // namespace vts::viewer
