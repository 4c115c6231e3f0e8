#include "viewer/app.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <stdexcept>
#include <utility>

#include "viewer/geometry.h"
#include "sensor/error_model.h"
#include "sensor/presets.h"
#include "sensor/profile_exr.h"
#include "sensor/rays.h"
#include "sensor/scene_file.h"

namespace vts::viewer {
namespace {

namespace fs = std::filesystem;

// More scans than this in one frame and the simulation runs slower than real
// time instead (a 10 kHz sensor at 30 frames per second would need 333).
constexpr int kMaxScansPerFrame = 400;

// Recordings are held in memory until P stops them (the EXR writer needs the
// row count first); past this they stop and are written by themselves.
constexpr std::size_t kMaxRecordingBytes = std::size_t{1} << 30;

std::size_t profile_bytes(const Profile& p) {
  const std::size_t n = static_cast<std::size_t>(p.size());
  return sizeof(Profile) + n * (9 * sizeof(float) + 3 * sizeof(std::uint8_t));
}

constexpr Rgba kSteel{0.60f, 0.64f, 0.70f, 1.0f};
constexpr Rgba kCopper{0.86f, 0.52f, 0.28f, 1.0f};
constexpr Rgba kTorchBody{0.20f, 0.22f, 0.25f, 1.0f};
constexpr Rgba kBracket{0.42f, 0.44f, 0.48f, 1.0f};
constexpr Rgba kHousing{0.16f, 0.30f, 0.52f, 1.0f};
constexpr Rgba kCameraBody{0.08f, 0.08f, 0.10f, 1.0f};
constexpr Rgba kGrid{0.30f, 0.33f, 0.38f, 1.0f};
constexpr Rgba kSeam{1.0f, 0.84f, 0.25f, 1.0f};
constexpr Rgba kCameraRays{0.30f, 0.85f, 1.0f, 1.0f};
constexpr Rgba kFan{1.0f, 0.25f, 0.20f, 0.22f};

Eigen::Vector3f f3(const Vec3& v) { return v.cast<float>(); }

Eigen::Matrix4f matrix_of(const Pose& p) { return p.matrix().cast<float>(); }

std::string file_safe(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  return out.empty() ? std::string("scene") : out;
}

tracker::JointType template_for(const Cell& cell) {
  if (cell.workpieces.empty()) return tracker::JointType::Fillet;
  return tracker_joint(cell.workpieces.front().type).value_or(tracker::JointType::Fillet);
}

// Camera pose in the laser frame, from the error model's camera geometry
// (sensor/error_model.h): centre on the baseline, z its optical axis.
Pose laser_from_camera(const ScannerDesc& desc) {
  const CameraModel cam = camera_model(desc);
  Pose p = Pose::Identity();
  p.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), cam.axis.normalized()).toRotationMatrix();
  p.translation() = cam.centre_mm;
  return p;
}

}  // namespace

App::App(const AppOptions& options, Renderer& renderer) : options_(options), renderer_(renderer) {
  if (options.given_cell) {
    load(*options.given_cell, options.given_label);
  } else if (!options.scene.empty()) {
    Cell cell;
    try {
      cell = load_scene(options.scene);
    } catch (const SceneError& e) {
      throw std::runtime_error(std::string("--scene: ") + e.what());
    }
    load(std::move(cell), options.scene.string());
  } else {
    auto cell = builtin_cell(options.cell);
    if (!cell) {
      std::string names;
      for (const auto& n : builtin_cell_names()) names += (names.empty() ? "" : ", ") + n;
      throw std::runtime_error("--cell = '" + options.cell + "': unknown cell; valid names: " + names);
    }
    load(std::move(*cell), options.cell);
  }
}

App::~App() { finish_recording(); }

void App::load(Cell cell, std::string label) {
  finish_recording();
  cell_ = std::move(cell);
  scene_label_ = std::move(label);

  standoff_mm_ = standoff_at_start(cell_);
  if (cell_.scanner.tool_from_laser.isApprox(Pose::Identity())) {
    cell_.scanner.tool_from_laser = default_tool_from_laser(standoff_mm_);
    char note[160];
    std::snprintf(note, sizeof note,
                  "viewer mount: laser %.0f mm ahead of the TCP, %.1f mm standoff (the path start's)",
                  kLookAheadMm, standoff_mm_);
    mount_note_ = note;
  } else {
    mount_note_ = "mount: the scene's scanner.tool_from_laser";
  }
  start_torch_ = cell_.path.start * cell_.scanner.tool_from_laser.inverse();
  world_from_torch_ = start_torch_;
  clock_ = ScanClock{cell_.scanner.rate_hz};
  have_profile_ = false;

  tracker::TrackerParams params = tracker_.params();
  params.joint = template_for(cell_);
  // Beads laid in a v-groove: its bottom is the fill (vts track --fill).
  params.groove.vgroove_fill = !cell_.workpieces.empty() && cell_.workpieces.front().params.passes > 0;
  tracker_.set_params(params);

  column_dirs_ = column_directions(cell_.scanner);
  const Mesh mesh = cell_.mesh();
  has_bbox_ = !mesh.vertices.empty();
  bbox_lo_ = Eigen::Vector3f::Constant(1e9f);
  bbox_hi_ = -bbox_lo_;
  for (const auto& p : mesh.vertices) {
    bbox_lo_ = bbox_lo_.cwiseMin(p);
    bbox_hi_ = bbox_hi_.cwiseMax(p);
  }

  configure_worker();
  upload_meshes();
  reset_camera();
  status_ = "loaded " + scene_label_ + " (" + std::to_string(mesh.triangle_count()) + " triangles)";
}

void App::lay_bead() {
  if (cell_.workpieces.size() != 1 || cell_.workpieces.front().is_mesh() ||
      !is_groove(cell_.workpieces.front().type)) {
    status_ = "B lays a bead in a groove cell (vgroove, bevel, ugroove, jgroove); this is none";
    return;
  }
  Workpiece& w = cell_.workpieces.front();
  // The adaptive fill (docs/SIM.md "Multi-pass"): the bead goes where the
  // sensor reads the next bead's place in the latest profile, taken into
  // the part frame through the pose it was scanned at; with no accepted
  // reading there is nothing to place it by.
  if (!have_profile_ || track_.status != tracker::TrackStatus::Ok || !track_.track_point) {
    status_ = "no bead laid: the latest profile gives no accepted reading of the groove (" +
              (have_profile_ ? track_.reason : std::string("no profile yet")) +
              "); the bead goes where the sensor says";
    return;
  }
  const double offset = w.in_joint_frame(last_.world_from_sensor, *track_.track_point).x() - w.truth.track_yz.x();
  const JointParams p = with_bead_laid(w.params, offset);
  if (const std::string why = validate(w.type, p); !why.empty()) {
    status_ = "no bead laid where the sensor said (" + std::to_string(offset) + " mm off the middle): " + why;
    return;
  }
  w = build_workpiece(w.type, p, w.world_from_joint);
  tracker::TrackerParams params = tracker_.params();
  params.groove.vgroove_fill = true;
  tracker_.set_params(params);
  have_profile_ = false;
  configure_worker();
  upload_meshes();
  char note[160];
  std::snprintf(note, sizeof note, "bead %d laid where the sensor said, %+.2f mm off the middle: %.3g mm deep and "
                "%.4g mm2 left to fill (true)",
                p.passes, offset, w.truth.depth_mm, w.truth.area_mm2);
  status_ = note;
}

void App::load_builtin(const std::string& name) {
  auto cell = builtin_cell(name);
  if (!cell) {
    status_ = "unknown cell " + name;
    return;
  }
  drive_torch = nullptr;
  load(std::move(*cell), name);
}

void App::upload_meshes() {
  renderer_.clear_meshes();
  mesh_.workpieces = renderer_.add_mesh(cell_.mesh(), false);
  mesh_.nozzle = renderer_.add_mesh(torch_nozzle_mesh(), true);
  mesh_.body = renderer_.add_mesh(torch_body_mesh(), true);
  mesh_.housing =
      renderer_.add_mesh(sensor_housing_mesh(camera_model(cell_.scanner).centre_mm.cast<float>()), false);
  mesh_.camera = renderer_.add_mesh(camera_body_mesh(), true);
  // Bracket from the torch body to the back of the housing, tool frame.
  const Pose& tool_from_laser = cell_.scanner.tool_from_laser;
  const Vec3 housing_back = tool_from_laser * Vec3(-10.0, 0.0, -40.0);
  const Vec3 on_torch(0.0, 0.0, std::min(-90.0, housing_back.z()));
  mesh_.bracket = renderer_.add_mesh(beam(f3(on_torch), f3(housing_back), 12.0f), false);
  attachment_ids_.clear();
  for (const Attachment& a : attachments_) attachment_ids_.push_back(renderer_.add_mesh(a.mesh, false));
}

void App::set_attachments(std::vector<Attachment> attachments, std::function<std::vector<Pose>(double)> poses) {
  attachments_ = std::move(attachments);
  attachment_poses_ = std::move(poses);
  upload_meshes();
}

// From ahead of the sensor, to the side the torch leans to and above: the fan
// is seen nearly face-on, the torch behind it.
void App::reset_camera() {
  const Eigen::Matrix3d& r = world_from_torch_.linear();
  const Vec3 target = world_from_torch_ * Vec3(0.6 * kLookAheadMm, 0.0, -0.3 * standoff_mm_);
  const Vec3 travel = r.col(0);
  const Vec3 up_torch = -r.col(2);
  Vec3 side(up_torch.x(), up_torch.y(), 0.0);
  if (side.norm() < 0.2) side = Vec3::UnitZ().cross(travel);
  Vec3 ahead(travel.x(), travel.y(), 0.0);
  if (ahead.norm() < 1e-6) ahead = Vec3::UnitX();
  const Vec3 from = ahead.normalized() + 0.3 * side.normalized() + 1.0 * Vec3::UnitZ();
  camera_ = camera_looking_at(target, from, 620.0);
}

void App::reset_torch() {
  world_from_torch_ = start_torch_;
  status_ = "torch back at the start pose";
}

// The sensor thread scans with the current scanner, mesh and source kind;
// scans in flight for the old ones are dropped.
void App::configure_worker() { worker_.configure(cell_.scanner, cell_.mesh(), source_kind_, options_.seed); }

void App::set_source(SourceKind kind) {
  if (kind == source_kind_) return;
  finish_recording();
  source_kind_ = kind;
  configure_worker();
  status_ = kind == SourceKind::Raster ? "source: raster emulator (OSMesa)"
                                       : "source: ray-cast reference (Embree)";
}

void App::set_sensor_preset(const std::string& name) {
  const auto preset = sensor_preset(name);
  if (!preset) {
    status_ = "unknown sensor preset " + name;
    return;
  }
  finish_recording();  // one file, one scanner
  set_sensor_fields(cell_.scanner, *preset);
  scanner_changed();
  status_ = "sensor preset " + name + ": " + sensor_preset_description(name);
}

void App::set_material(const std::string& name) {
  finish_recording();
  if (!apply_material(cell_.scanner, name)) {
    status_ = "unknown material " + name;
    return;
  }
  configure_worker();
  status_ = "material " + name + ": " + material_description(name);
}

void App::set_error_model(bool on) {
  if (on == !cell_.scanner.ideal) return;
  finish_recording();
  cell_.scanner.ideal = !on;
  configure_worker();  // the raster source skips its camera-shadow pass for ideal scanners
  status_ = on ? "error model on: profiles as the sensor measures them"
               : "error model off: ideal geometric profiles";
}

void App::set_camera_image(bool on) {
  if (on == camera_image()) return;
  finish_recording();
  cell_.scanner.camera_image = on;
  if (on) cell_.scanner.ideal = false;
  last_image_.reset();
  ++image_serial_;
  configure_worker();
  status_ = on ? "camera image: profiles read from the rendered stripe image (peaks per image column)"
               : "camera image off: profiles from the error model";
}

unsigned App::image_texture() {
  if (!last_image_) return 0;
  if (uploaded_serial_ != image_serial_) {
    const CameraImage& im = *last_image_;
    image_texture_ = renderer_.grey_texture(im.pixels, im.width, im.rows, im.bits);
    uploaded_serial_ = image_serial_;
  }
  return image_texture_;
}

// After a change of the scanner's sensor fields: column rays, rate, housing.
void App::scanner_changed() {
  column_dirs_ = column_directions(cell_.scanner);
  const double t = clock_.time_s;
  clock_ = ScanClock{cell_.scanner.rate_hz};
  clock_.time_s = t;
  clock_.next_scan = static_cast<std::int64_t>(std::ceil(t * cell_.scanner.rate_hz - 1e-9));
  have_profile_ = false;
  configure_worker();
  upload_meshes();
}

void App::set_joint_template(tracker::JointType joint) {
  tracker::TrackerParams params = tracker_.params();
  params.joint = joint;
  tracker_.set_params(params);
  if (have_profile_) {
    const tracker::ProfileView view{last_.y_mm, last_.z_mm, last_.valid};
    tracker_.track(view, track_);
  }
}

void App::update(const MotionInput& held, double dt_s) {
  take_scans();
  if (const std::string e = worker_.take_error(); !e.empty()) {
    status_ = "scan failed: " + e;
    paused = true;
  }
  if (paused || dt_s <= 0.0) return;
  // Half a second of scans outstanding: let the sensor thread catch up.
  sensor_behind_ = static_cast<double>(worker_.pending()) > 0.5 * cell_.scanner.rate_hz + 1.0;
  if (sensor_behind_) return;

  const double t0 = clock_.time_s;
  const auto due = clock_.advance(dt_s, kMaxScansPerFrame);
  const double used_s = clock_.time_s - t0;

  MotionInput motion = held;
  if (auto_travel) motion.translate.x() = std::clamp(motion.translate.x() + 1.0, -1.0, 1.0);
  const Pose from = world_from_torch_;
  Pose to = motion.any()
                ? move_torch(from, motion, speed_mm_s, turn_deg_s, used_s, world_axes && !auto_travel)
                : from;
  if (drive_torch) to = drive_torch(clock_.time_s).value_or(from);
  world_from_torch_ = to;

  requests_.clear();
  for (const auto& d : due)
    requests_.push_back({interpolate(from, to, d.fraction) * cell_.scanner.tool_from_laser, d.time_s, d.index});
  worker_.submit(requests_);
  if (sync_scans && !due.empty()) {
    worker_.wait_idle();
    take_scans();
  }
}

// The sensor thread gives each profile as measured (error model applied, or
// the ideal one when the scanner is ideal) and as the geometry gave it.
void App::take_scans() {
  ScanWorker::Results scanned = worker_.take_results();
  if (scanned.output.empty()) return;
  for (const Profile& measured : scanned.output) {
    if (recorder_ && measured.time_s >= recorder_->start_time_s) {
      Profile copy = measured;
      copy.index = static_cast<std::int64_t>(recorder_->profiles.size());
      copy.time_s = measured.time_s - recorder_->start_time_s;
      recorder_->bytes += profile_bytes(copy);
      recorder_->profiles.push_back(std::move(copy));
      if (recorder_->bytes > kMaxRecordingBytes) {
        finish_recording();
        status_ += " (stopped at the 1 GiB in-memory limit)";
      }
    }
  }
  // The image the latest profile was read from; none outside the image mode.
  if (scanned.image || last_image_) {
    last_image_ = std::move(scanned.image);
    ++image_serial_;
  }
  last_ideal_ = std::move(scanned.ideal.back());
  last_ = std::move(scanned.output.back());
  have_profile_ = true;
  const tracker::ProfileView view{last_.y_mm, last_.z_mm, last_.valid};
  tracker_.track(view, track_);
}

fs::path App::next_record_path() {
  ++recordings_;
  if (!options_.record.empty()) {
    if (recordings_ == 1) return options_.record;
    const fs::path& r = options_.record;
    return r.parent_path() / (r.stem().string() + "-" + std::to_string(recordings_) + r.extension().string());
  }
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
  const std::string label = options_.scene.empty() ? scene_label_ : options_.scene.stem().string();
  std::string name = "vts-view-" + file_safe(label) + "-" + stamp;
  if (recordings_ > 1) name += "-" + std::to_string(recordings_);
  return name + ".exr";
}

void App::toggle_recording() {
  if (recorder_) {
    finish_recording();
    return;
  }
  recorder_ = Recorder{next_record_path(), clock_.time_s, {}, 0};
  status_ = "recording to " + recorder_->path.string() + " (P stops)";
}

void App::finish_recording() {
  if (!recorder_) return;
  Recorder rec = std::move(*recorder_);
  recorder_.reset();
  if (rec.profiles.empty()) {
    status_ = "recording stopped: no profiles scanned, nothing written";
    return;
  }
  try {
    ProfileFileInfo info;
    info.scanner = cell_.scanner;
    info.scene_name = scene_label_;
    info.scene_text = scene_to_yaml(cell_);
    info.profiles = static_cast<int>(rec.profiles.size());
    info.seed = options_.seed;
    ProfileExrWriter writer(rec.path, info);
    for (const Profile& p : rec.profiles) writer.write(p);
    writer.finish();
    status_ = "wrote " + std::to_string(rec.profiles.size()) + " profiles to " + rec.path.string();
  } catch (const std::exception& e) {
    status_ = std::string("recording not written: ") + e.what();
  }
}

void App::press(Key key) {
  switch (key) {
    case Key::Faster: speed_mm_s = std::min(speed_mm_s * 1.5, 1000.0); turn_deg_s = std::min(turn_deg_s * 1.5, 360.0); break;
    case Key::Slower: speed_mm_s = std::max(speed_mm_s / 1.5, 0.5); turn_deg_s = std::max(turn_deg_s / 1.5, 0.5); break;
    case Key::Help: show_help = !show_help; break;
    case Key::Pause: paused = !paused; break;
    case Key::Record: toggle_recording(); break;
    case Key::AutoTravel: auto_travel = !auto_travel; break;
    case Key::FollowCamera: follow_camera = !follow_camera; break;
    case Key::ResetTorch: reset_torch(); break;
    case Key::ResetView: reset_camera(); break;
    case Key::LayBead: lay_bead(); break;
    case Key::CameraImage: set_camera_image(!camera_image()); break;
    case Key::Quit: quit_ = true; break;
    default: break;  // motion keys act through update()
  }
}

void App::build_scene(SceneView& v, int width, int height) {
  v.width = width;
  v.height = height;
  const Pose laser = world_from_laser();
  if (follow_camera) camera_.target_mm = world_from_torch_ * Vec3(0.5 * kLookAheadMm, 0.0, 0.0);
  const Eigen::Matrix4d clip = camera_.clip_from_world(static_cast<double>(width) / std::max(height, 1));
  v.clip_from_world = clip.cast<float>();
  v.eye_world = f3(camera_.eye_mm());

  const Pose camera_pose = laser * laser_from_camera(cell_.scanner);
  v.meshes = {
      {mesh_.workpieces, Eigen::Matrix4f::Identity(), kSteel},
      {mesh_.nozzle, matrix_of(world_from_torch_), kCopper},
      {mesh_.body, matrix_of(world_from_torch_), kTorchBody},
      {mesh_.bracket, matrix_of(world_from_torch_), kBracket},
      {mesh_.housing, matrix_of(laser), kHousing},
      {mesh_.camera, matrix_of(camera_pose), kCameraBody},
  };

  if (attachment_poses_) {
    const std::vector<Pose> poses = attachment_poses_(clock_.time_s);
    for (std::size_t i = 0; i < poses.size() && i < attachment_ids_.size(); ++i)
      v.meshes.push_back({attachment_ids_[i], matrix_of(poses[i]), attachments_[i].color});
  }

  v.lines.clear();
  const auto line = [&](const Vec3& a, const Vec3& b, Rgba c) {
    v.lines.push_back({f3(a), c});
    v.lines.push_back({f3(b), c});
  };

  // Floor grid under the work, 20 mm squares.
  if (has_bbox_) {
    const Eigen::Vector3f& lo = bbox_lo_;
    const Eigen::Vector3f& hi = bbox_hi_;
    const double step = 20.0, z = lo.z() - 0.5;
    const double x0 = std::floor((lo.x() - 60.0) / step) * step, x1 = std::ceil((hi.x() + 60.0) / step) * step;
    const double y0 = std::floor((lo.y() - 60.0) / step) * step, y1 = std::ceil((hi.y() + 60.0) / step) * step;
    for (double x = x0; x <= x1 + 1e-9; x += step) line(Vec3(x, y0, z), Vec3(x, y1, z), kGrid);
    for (double y = y0; y <= y1 + 1e-9; y += step) line(Vec3(x0, y, z), Vec3(x1, y, z), kGrid);
  }

  // The analytic seams (a mesh workpiece has none).
  for (const auto& w : cell_.workpieces)
    if (!w.is_mesh()) line(w.seam_origin(), w.seam_origin() + w.params.length_mm * w.seam_direction(), kSeam);
  for (const auto& path : seam_paths)
    for (std::size_t i = 1; i < path.size(); ++i) line(path[i - 1], path[i], kSeam);

  // Tool frame axes at the TCP.
  const Vec3 tcp = world_from_torch_.translation();
  const Eigen::Matrix3d& r = world_from_torch_.linear();
  line(tcp, tcp + 15.0 * r.col(0), {0.95f, 0.40f, 0.35f, 1.0f});
  line(tcp, tcp + 15.0 * r.col(1), {0.40f, 0.90f, 0.40f, 1.0f});

  v.translucent_triangles.clear();
  v.points.clear();
  if (have_profile_) {
    // The lit line and the fan are where the laser meets the work: the ideal
    // profile. The camera rays go to what the sensor measured.
    const Profile& p = last_ideal_;
    const Pose& s = p.world_from_sensor;
    const Vec3 origin = s.translation();
    const auto& dirs = column_dirs_;
    const int n = std::min(p.size(), static_cast<int>(dirs.size()));

    // Lit line: the valid samples, joined where neighbours are close.
    std::optional<Vec3> prev;
    for (int i = 0; i < n; ++i) {
      if (!p.valid[i]) {
        prev.reset();
        continue;
      }
      const Vec3 q = s * Vec3(0.0, p.y_mm[i], p.z_mm[i]);
      v.points.push_back({f3(q), kLaserLineColor});
      if (prev && (q - *prev).norm() < 2.0) line(*prev, q, kLaserLineColor);
      prev = q;
    }

    // The fan: out to the work where a column hit, else to 1.3 x the standoff.
    const double miss_mm = std::min(cell_.scanner.max_hit_mm, 1.3 * standoff_mm_);
    const int stride = std::max(1, n / 96);
    std::optional<Vec3> prev_end;
    for (int k = 0; n > 0; k += stride) {
      const int i = std::min(k, n - 1);
      const Vec3 d = s.linear() * dirs[static_cast<std::size_t>(i)].cast<double>();
      const Vec3 end = p.valid[i] ? s * Vec3(0.0, p.y_mm[i], p.z_mm[i]) : origin + miss_mm * d;
      if (prev_end) {
        v.translucent_triangles.push_back({f3(origin), kFan});
        v.translucent_triangles.push_back({f3(*prev_end), kFan});
        v.translucent_triangles.push_back({f3(end), kFan});
      }
      prev_end = end;
      if (i == n - 1) break;
    }

    // Camera rays to the ends and middle of the measured line, from the
    // camera where it was at the scan.
    const Profile& m = last_;
    int first_valid = -1, last_valid = -1;
    for (int i = 0; i < m.size(); ++i)
      if (m.valid[i]) {
        if (first_valid < 0) first_valid = i;
        last_valid = i;
      }
    if (first_valid >= 0) {
      const Vec3 lens = (m.world_from_sensor * laser_from_camera(cell_.scanner)).translation();
      const int mid = (first_valid + last_valid) / 2;
      for (int i : {first_valid, last_valid, mid}) {
        if (!m.valid[i]) continue;
        line(lens, m.world_from_sensor * Vec3(0.0, m.y_mm[i], m.z_mm[i]), kCameraRays);
      }
    }
  }

  const auto px = project_to_pixel(clip, tcp, width, height);
  const auto nz = project_to_pixel(clip, world_from_torch_ * Vec3(0.0, 0.0, -45.0), width, height);
  tcp_px_ = px.value_or(Vec2(-1, -1));
  nozzle_px_ = nz.value_or(Vec2(-1, -1));
}

}  // namespace vts::viewer
