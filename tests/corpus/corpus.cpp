// make_profile and make_recording: draw a sensor, a joint, a pose and the
// imperfections, cast, and write the truth.
#include "internal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vts_corpus {

using namespace detail;

const char* joint_name(Joint joint) {
  switch (joint) {
    case Joint::Fillet: return "fillet";
    case Joint::Corner: return "corner";
    case Joint::Lap: return "lap";
    case Joint::Butt: return "butt";
    case Joint::VGroove: return "vgroove";
    case Joint::Bevel: return "bevel";
    case Joint::UGroove: return "ugroove";
    case Joint::JGroove: return "jgroove";
    case Joint::VGrooveThick: return "vgroove-thick";
  }
  return "?";
}

std::optional<Joint> joint_from_name(std::string_view name) {
  for (Joint j : kAllJoints)
    if (name == joint_name(j)) return j;
  for (Joint j : kGrooveJoints)
    if (name == joint_name(j)) return j;
  if (name == "v-groove") return Joint::VGroove;
  return std::nullopt;
}

bool is_groove(Joint joint) {
  return std::find(kGrooveJoints.begin(), kGrooveJoints.end(), joint) != kGrooveJoints.end();
}

bool Truth::has_tag(std::string_view tag) const {
  return std::find(tags.begin(), tags.end(), tag) != tags.end();
}

const std::array<double, 2>* Truth::break_point(std::string_view name) const {
  for (const auto& [n, p] : break_points)
    if (n == name) return &p;
  return nullptr;
}

double Truth::param(std::string_view name) const {
  for (const auto& [n, v] : params)
    if (n == name) return v;
  return kNaN;
}

namespace {

// Default probabilities. Joint variants first, then the pose and the
// imperfections (shared by every joint).
const std::vector<std::pair<std::string, double>>& joint_defaults(Joint joint) {
  static const std::vector<std::pair<std::string, double>> fillet = {
      {"gap", 0.5}, {"rounded_edges", 0.3}, {"chamfered_edges", 0.2}, {"tack_weld", 0.1}};
  static const std::vector<std::pair<std::string, double>> corner = {
      {"gap", 0.5}, {"rounded_edges", 0.3}, {"chamfered_edges", 0.2}};
  static const std::vector<std::pair<std::string, double>> lap = {
      {"gap", 0.4}, {"tilt", 0.3}, {"rounded_edges", 0.3}, {"chamfered_edges", 0.2}};
  static const std::vector<std::pair<std::string, double>> butt = {
      {"gap", 0.75},         {"mismatch", 0.5},      {"unequal_thickness", 0.4}, {"backing_bar", 0.3},
      {"rounded_edges", 0.25}, {"chamfered_edges", 0.25}, {"tack_weld", 0.1}};
  static const std::vector<std::pair<std::string, double>> vgroove = {
      {"gap", 0.7},         {"root_face", 0.6},     {"mismatch", 0.4},
      {"backing_bar", 0.3}, {"rounded_edges", 0.3}, {"tack_weld", 0.1}};
  // Grooves (grooves.cpp): a thick plate (20-80 mm instead of 8-15, seen from
  // farther), beads in the groove, ripples on the last one's cap.
  static const std::vector<std::pair<std::string, double>> groove = {
      {"thick", 0.5},        {"gap", 0.6},          {"root_face", 0.6},     {"mismatch", 0.3},
      {"passes", 0.75},      {"bead_ripples", 0.4}, {"backing_bar", 0.2},   {"rounded_edges", 0.2}};
  static const std::vector<std::pair<std::string, double>> vgroove_thick(groove.begin() + 1, groove.end());
  switch (joint) {
    case Joint::Fillet: return fillet;
    case Joint::Corner: return corner;
    case Joint::Lap: return lap;
    case Joint::Butt: return butt;
    case Joint::VGroove: return vgroove;
    case Joint::Bevel:
    case Joint::UGroove:
    case Joint::JGroove: return groove;
    case Joint::VGrooveThick: return vgroove_thick;  // always thick
  }
  return fillet;
}

const std::vector<std::pair<std::string, double>>& common_defaults() {
  static const std::vector<std::pair<std::string, double>> common = {
      {"mirror", 0.5},       {"waviness", 0.5},        {"quantized", 0.3}, {"reflections", 0.4},
      {"dropout_runs", 0.5}, {"single_dropouts", 0.5}, {"shadow", 0.15}};
  return common;
}

bool is_imperfection(const std::string& name) { return name != "mirror"; }

}  // namespace

std::vector<std::string> variant_names(Joint joint) {
  std::vector<std::string> names;
  for (const auto& [n, p] : joint_defaults(joint)) names.push_back(n);
  for (const auto& [n, p] : common_defaults()) names.push_back(n);
  return names;
}

double default_probability(Joint joint, const std::string& variant) {
  for (const auto& [n, p] : joint_defaults(joint))
    if (n == variant) return p;
  for (const auto& [n, p] : common_defaults())
    if (n == variant) return p;
  throw std::invalid_argument("unknown variant '" + variant + "' for joint " + joint_name(joint));
}

namespace detail {

Probabilities::Probabilities(Joint joint, const Options& options) {
  for (const auto& [n, p] : joint_defaults(joint)) p_[n] = p;
  for (const auto& [n, p] : common_defaults()) p_[n] = p;
  for (const auto& [name, value] : options.probability) {
    if (!p_.count(name)) {
      std::string known;
      for (const auto& n : variant_names(joint)) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown variant '" + name + "' for joint " + joint_name(joint) +
                                  " (known: " + known + ")");
    }
    if (!(value >= 0.0 && value <= 1.0))
      throw std::invalid_argument("probability of '" + name + "' must lie in [0, 1], got " + std::to_string(value));
    p_[name] = value;
  }
  if (!options.imperfections)
    for (const auto& [n, p] : common_defaults())
      if (is_imperfection(n)) p_[n] = 0.0;
}

double Probabilities::operator()(const std::string& name) const {
  const auto it = p_.find(name);
  if (it == p_.end()) throw std::logic_error("corpus: no probability named " + name);
  return it->second;
}

SensorDraw draw_sensor(Rng& rng, const Options& options, double standoff_lo_mm, double standoff_hi_mm) {
  // Every value is drawn even when an option overrides it, so the draws that
  // follow stay the same.
  SensorDraw sd;
  const int columns = rng.uniform_int(256, 2048);
  sd.sensor.columns = options.columns > 0 ? options.columns : columns;
  sd.sensor.fan_deg = rng.uniform(30, 50);
  sd.sensor.tangent_spacing = rng.chance(0.5);
  const double standoff = rng.uniform(standoff_lo_mm, standoff_hi_mm);
  sd.standoff_mm = options.standoff_mm > 0 ? options.standoff_mm : standoff;
  sd.nominal_standoff_mm = sd.standoff_mm * rng.uniform(0.9, 1.1);
  // Measuring range: nominal standoff +- 40 %.
  sd.sensor.z_near_mm = 0.6 * sd.nominal_standoff_mm;
  sd.sensor.z_far_mm = 1.4 * sd.nominal_standoff_mm;
  sd.triangulation_deg = rng.uniform(20, 35);
  sd.camera_side = rng.sign() > 0 ? 1 : -1;
  sd.baseline_mm = sd.nominal_standoff_mm * dm::tan(rad(sd.triangulation_deg));
  return sd;
}

}  // namespace detail

namespace {

struct PoseDraw {
  double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
  bool mirrored = false;
  double lateral_fraction = 0.5;
};

PoseDraw draw_pose(Rng& rng, const Probabilities& p) {
  PoseDraw pose;
  pose.roll_deg = rng.uniform(-15, 15);
  pose.pitch_deg = rng.uniform(-15, 15);
  pose.yaw_deg = rng.uniform(-15, 15);
  pose.mirrored = rng.chance(p("mirror"));
  pose.lateral_fraction = rng.uniform();
  return pose;
}

// Joint drift in a recording (added to the placement), zero for a profile.
struct Drift {
  double lateral_mm = 0, height_mm = 0;
  double margin_mm = 0;  // the largest lateral drift: kept inside the field
};

int nearest_column(const std::vector<double>& u, double value) {
  const auto it = std::lower_bound(u.begin(), u.end(), value);
  if (it == u.begin()) return 0;
  if (it == u.end()) return static_cast<int>(u.size()) - 1;
  const int i = static_cast<int>(it - u.begin());
  return (value - u[i - 1] < u[i] - value) ? i - 1 : i;
}

// A torch or clamp in front of the work (out of the measuring range, so its
// own points are never measured) blocking a run of laser rays or of the
// camera's sight lines. Returns "torch"/"clamp" or nullptr.
const char* add_body(Rng& rng, const Probabilities& p, const SensorDraw& sd, const std::vector<Vec2>& dirs,
                     const Section& sec, const Vec2& track, Scene& scene,
                     std::vector<std::pair<std::string, double>>& params) {
  const bool on = rng.chance(p("shadow"));
  const bool circle = rng.chance(0.5);
  bool camera_block = rng.chance(0.5);
  const bool near_joint = rng.chance(0.2);
  const int n_block = rng.uniform_int(10, 60);
  const double f_col = rng.uniform(), f_depth = rng.uniform(), f_lambda = rng.uniform();
  const double aspect = rng.uniform(1.5, 4.0), tilt = rad(rng.uniform(-30, 30));
  if (!on) return nullptr;

  const Sensor& s = sd.sensor;
  std::vector<double> u(dirs.size());
  for (std::size_t i = 0; i < dirs.size(); ++i) u[i] = dirs[i].x() / dirs[i].y();
  const int n = s.columns;
  const double du = (u.back() - u.front()) / std::max(1, n - 1);
  const int jt = nearest_column(u, track.x() / track.y());
  int j;
  if (near_joint) {
    j = std::clamp(jt + static_cast<int>(std::lround((f_col - 0.5) * n_block)), 0, n - 1);
  } else {
    const int k = static_cast<int>(std::ceil((sec.halfwidth_mm + 5) / (sd.standoff_mm * du))) + n_block / 2 + 1;
    const int left = std::max(0, jt - k + 1), right = std::max(0, n - (jt + k));
    if (left + right == 0) return nullptr;
    const int pick = std::min(left + right - 1, static_cast<int>(f_col * (left + right)));
    j = pick < left ? pick : jt + k + (pick - left);
  }
  const Vec2 cam = s.camera_yz;
  Vec2 centre;
  double half = 0;
  Vec2 along;
  if (camera_block) {
    int edge = -1;
    const double t = nearest_hit_bruteforce(scene, Vec2(0, 0), dirs[j], 1e-9, &edge);
    const Vec2 hit = t * dirs[j];
    if (!(t > 0) || hit.y() < s.z_near_mm || hit.y() > s.z_far_mm) {
      camera_block = false;
    } else {
      double lambda = 0.45 + 0.35 * f_lambda;
      lambda = std::max(lambda, 1.0 - 0.8 * s.z_near_mm / hit.y());  // nearer than the range
      centre = hit + lambda * (cam - hit);
      half = 0.5 * n_block * du * sd.standoff_mm * (cam - centre).norm() / (cam - hit).norm();
      along = (cam - hit).normalized();
    }
  }
  if (!camera_block) {
    const double z = (0.45 + 0.4 * f_depth) * s.z_near_mm;
    centre = dirs[j] * (z / dirs[j].y());
    half = 0.5 * n_block * du * z;
    along = dirs[j];
  }
  // Keep it in front of the measuring range and behind the camera.
  half = std::min(half, 0.5 * (s.z_near_mm - centre.y()));
  if (!(half > 0.05) || centre.y() - 3 * aspect * half < std::max(0.0, cam.y()) + 2) return nullptr;
  if (circle) {
    scene.add(make_circle(centre, half, kFaceBody, 24));
  } else {
    const Vec2 a = Vec2(along.x() * dm::cos(tilt) - along.y() * dm::sin(tilt),
                        along.x() * dm::sin(tilt) + along.y() * dm::cos(tilt));
    const Vec2 b(-a.y(), a.x());
    const double l = aspect * half;
    Polygon rect;
    rect.pts = {centre - l * a - half * b, centre + l * a - half * b, centre + l * a + half * b, centre - l * a + half * b};
    rect.faces.assign(4, kFaceBody);
    scene.add(rect);
  }
  params.emplace_back("body_y_mm", centre.x());
  params.emplace_back("body_z_mm", centre.y());
  params.emplace_back("body_half_mm", half);
  params.emplace_back("body_blocks_camera", camera_block ? 1 : 0);
  return circle ? "torch" : "clamp";
}

Imperfections draw_imperfections(Rng& rng, const Probabilities& p, const Cast& cast, int track_col,
                                 double standoff_mm, double noise_mm, std::vector<std::string>& tags,
                                 std::vector<std::pair<std::string, double>>& params) {
  Imperfections imp;
  imp.noise_mm = noise_mm;
  const int n = static_cast<int>(cast.dir.size());
  // Fixed number of draws per item, variable counts last.
  const bool quant = rng.chance(p("quantized"));
  const double q = rng.uniform(0.002, 0.01) * standoff_mm / 100.0;
  if (quant) {
    imp.quant_step_mm = q;
    tags.push_back("quantized");
    params.emplace_back("quant_step_mm", q);
  }
  const bool wavy = rng.chance(p("waviness"));
  const int n_waves = rng.uniform_int(2, 3);
  for (int k = 0; k < 3; ++k) {
    Imperfections::Wave w{rng.uniform(0.015, 0.03), rng.uniform(1.0, 10.0), rng.uniform(0, 2 * kPi)};
    if (wavy && k < n_waves) imp.waves.push_back(w);
  }
  if (wavy) tags.push_back("waviness");

  const bool reflect = rng.chance(p("reflections"));
  const int n_clusters = rng.uniform_int(1, 3);
  const double du = (cast.u.back() - cast.u.front()) / std::max(1, n - 1);
  const int near = std::max(2, static_cast<int>(std::lround(3.0 / (standoff_mm * du))));  // +-3 mm
  bool front = false, behind = false;
  for (int k = 0; k < 3; ++k) {
    const int count = rng.uniform_int(1, 5);
    const double offset = rng.uniform(1.5, 4.0) * rng.sign();
    const bool at_joint = rng.chance(0.5);
    const int j_near = track_col + rng.uniform_int(-near, near);
    const int j_any = rng.uniform_int(0, std::max(0, n - count));
    if (!reflect || k >= n_clusters) continue;
    const int first = std::clamp(at_joint ? j_near : j_any, 0, std::max(0, n - count));
    bool any = false;
    for (int i = first; i < first + count; ++i) any = any || cast.status[i] == kValid;
    if (!any) continue;
    imp.reflections.push_back({first, count, offset});
    (offset < 0 ? front : behind) = true;
  }
  if (front) tags.push_back("reflection_front");
  if (behind) tags.push_back("reflection_behind");

  const bool runs = rng.chance(p("dropout_runs"));
  const int n_runs = rng.uniform_int(1, 4);
  for (int k = 0; k < 4; ++k) {
    const int len = rng.uniform_int(1, 8), first = rng.uniform_int(0, n - 1);
    if (runs && k < n_runs) imp.dropout_runs.emplace_back(first, len);
  }
  if (runs) tags.push_back("dropout_runs");
  const bool singles = rng.chance(p("single_dropouts"));
  if (singles) {
    const int count = rng.uniform_int(1, std::max(2, n / 150));
    for (int k = 0; k < count; ++k) imp.single_dropouts.push_back(rng.uniform_int(0, n - 1));
    tags.push_back("single_dropouts");
  }
  return imp;
}

enum class Visibility { Visible, OutOfView, Covered, CameraShadow };

// Whether a truth point is seen: in the fan and the measuring range, the laser
// ray reaches it (a virtual corner in the air counts), and the camera sees it.
Visibility visibility(const Scene& scene, const Sensor& s, const std::vector<double>& u, const Vec2& p) {
  if (!(p.y() > 0)) return Visibility::OutOfView;
  const double up = p.x() / p.y();
  if (up < u.front() || up > u.back() || p.y() < s.z_near_mm || p.y() > s.z_far_mm) return Visibility::OutOfView;
  const double r = p.norm();
  const double t = nearest_hit_bruteforce(scene, Vec2(0, 0), p / r, 1e-9, nullptr);
  if (t < r - 1e-6) return Visibility::Covered;
  if (segment_blocker_bruteforce(scene, p, s.camera_yz) >= 0) return Visibility::CameraShadow;
  return Visibility::Visible;
}

void add_tag(std::vector<std::string>& tags, const std::string& tag) {
  if (std::find(tags.begin(), tags.end(), tag) == tags.end()) tags.push_back(tag);
}

struct Streams {
  Rng body, imperfections, noise;
};

// Everything after the draws: pose, scene, casting, imperfections, truth.
Profile render_joint(Joint joint, const Options& opt, const Probabilities& p, const SensorDraw& sd_in,
                     const JointSpec& spec, const DecoySpec& decoy, const Section* placement, const PoseDraw& pose,
                     const Drift& drift, Streams& rng, double noise_mm) {
  SensorDraw sd = sd_in;
  const Section sec = build_section(spec, decoy);
  // The lateral placement follows this section's extent and decoy (a recording
  // passes one for all its profiles, so the joint does not jump when the gap
  // opens or a decoy comes and goes).
  const Section& place = placement ? *placement : sec;

  // The pose for a roll: joint frame -> sensor axes (the optical axis along
  // the view direction, rolled about the seam, optionally mirrored: scanning
  // the other way), the oblique cut, the camera and the placement.
  const double cp = dm::cos(rad(pose.pitch_deg)), sp = dm::sin(rad(pose.pitch_deg));
  const double cy = dm::cos(rad(pose.yaw_deg)), sy = dm::sin(rad(pose.yaw_deg));
  const double D = sd.standoff_mm, tan_half = dm::tan(rad(sd.sensor.fan_deg / 2));
  double lateral = 0;
  auto pose_for = [&](double roll_deg) {
    const Vec2 view0 = sec.view_dir.normalized();
    const double roll = rad(roll_deg);
    const Vec2 view(dm::cos(roll) * view0.x() - dm::sin(roll) * view0.y(),
                    dm::sin(roll) * view0.x() + dm::cos(roll) * view0.y());
    Vec2 across(-view.y(), view.x());
    if (pose.mirrored) across = -across;
    Mat2 R2;
    R2.row(0) = across.transpose();
    R2.row(1) = view.transpose();
    // The laser plane cuts the prism obliquely: sensor axes u = R e_y, v = R e_z
    // with R = Ry(pitch) Rz(yaw) in (seam, y, z); a slice point a u + b v lies on
    // the section at M (a, b) (projected along the seam), so sensor = M^-1 section.
    Mat2 M;
    M << cy, 0.0, sp * sy, cp;
    const Mat2 A = mul(inverse(M), R2);
    // The camera's occlusion viewpoint: projected along the seam onto the laser plane.
    const Eigen::Vector3d seam(cp * cy, -cp * sy, sp);  // seam direction in sensor (x, y, z)
    const double b = sd.baseline_mm * sd.camera_side;
    sd.sensor.camera_yz = opt.camera_in_laser_plane ? Vec2(b, 0.0)
                                                    : Vec2(-b * seam.y() / seam.x(), -b * seam.z() / seam.x());
    // Placement: the track point at the standoff, anywhere in the middle 70 %
    // of the field with the joint's features inside it; with a decoy, both in
    // view where the field allows.
    // (At the plate tops for a groove: nearer, a narrower field.)
    const double field = 2 * (D - place.top_height_mm) * tan_half;
    const double lat_max =
        std::max(0.0, std::min(0.35 * field, 0.5 * field - 1.1 * place.halfwidth_mm) - drift.margin_mm);
    double lo = -lat_max, hi = lat_max;
    if (place.has_decoy) {
      const Vec2 off = mul(A, Vec2(place.decoy_point - place.track));
      const double field_d = 2 * (D + off.y()) * tan_half;
      const double lo2 = std::max(lo, -0.45 * field_d - off.x()), hi2 = std::min(hi, 0.45 * field_d - off.x());
      if (lo2 <= hi2) lo = lo2, hi = hi2;
    }
    lateral = lo + (hi - lo) * pose.lateral_fraction;
    Affine m;
    m.A = A;
    m.t = Vec2(lateral, D) - mul(A, sec.track);  // the drift is added below
    return m;
  };
  double roll_deg = pose.roll_deg * sec.max_roll_deg / 15.0;
  Affine map = pose_for(roll_deg);
  if (!std::isnan(sec.open_angle_deg)) {
    // A fillet's sensor is mounted so that the camera looks into the open
    // angle, 8 degrees inside either plate (else the whole profile can lie in
    // the camera's shadow): the roll nearest the drawn one that does it, with
    // a narrower triangulation angle where none does (without a recording's
    // drift, so that all its profiles get the same roll).
    auto camera_inside = [&](const Affine& m) {
      const Vec2 root = m(sec.pts.at("root")), f = m.dir(sec.dirs.at("flange")), w = m.dir(sec.dirs.at("web"));
      const Vec2 c = (sd.sensor.camera_yz - root).normalized();
      const double margin = dm::sin(rad(8));
      const double sign = cross(f, w) > 0 ? 1.0 : -1.0;
      return sign * cross(f, c) > margin && sign * cross(c, w) > margin && f.dot(c) + w.dot(c) > 0;
    };
    const double mr = sec.max_roll_deg;
    bool inside = camera_inside(map);
    for (int narrow = 0; !inside && narrow < 12; ++narrow) {
      if (narrow > 0) {
        sd.triangulation_deg = std::max(10.0, sd.triangulation_deg - 2.5);
        sd.baseline_mm = sd.nominal_standoff_mm * dm::tan(rad(sd.triangulation_deg));
      }
      for (int k = 0; !inside && k <= 120; ++k) {
        const double r = roll_deg + (k % 2 ? 0.25 : -0.25) * ((k + 1) / 2);  // 0, +0.25, -0.25, +0.5, ...
        if (std::abs(r) > mr) continue;
        map = pose_for(r);
        if ((inside = camera_inside(map))) roll_deg = r;
      }
    }
    if (!inside) map = pose_for(roll_deg);
  }
  // A recording's drift moves the joint after the pose is chosen: the roll
  // stays the same on every profile.
  map.t += Vec2(drift.lateral_mm, drift.height_mm);

  Scene scene;
  const double clip_z = std::max(0.0, sd.sensor.camera_yz.y()) + 1.0;
  for (const Polygon& solid : sec.solids) {
    const Polygon poly = clipped_above(transformed(solid, map.A, map.t), clip_z);
    if (!poly.pts.empty()) scene.add(poly);
  }
  const std::size_t work_edges = scene.edges.size();

  Profile out;
  Truth& t = out.truth;
  t.joint = joint;
  t.params = spec.params;
  compute_truth(spec, sec, map, t);
  const Vec2 track(t.track_y_mm, t.track_z_mm);
  t.tags = spec.tags;
  std::vector<Vec2> dirs = column_directions(sd.sensor);
  const char* body = add_body(rng.body, p, sd, dirs, sec, track, scene, t.params);

  const Cast cast = cast_scene(scene, sd.sensor, std::move(dirs));
  const int track_col = nearest_column(cast.u, track.x() / track.y());
  const Imperfections imp =
      draw_imperfections(rng.imperfections, p, cast, track_col, D, noise_mm, t.tags, t.params);
  std::vector<std::uint8_t> status;
  finish_profile(scene, cast, imp, rng.noise, out, status);

  // Truth record.
  t.noise_mm = noise_mm;
  t.columns = sd.sensor.columns;
  t.standoff_mm = t.track_z_mm;
  if (noise_mm > 0) add_tag(t.tags, "noise");
  if (pose.mirrored) add_tag(t.tags, "mirrored");
  bool body_shadow = false, camera_shadow = false, out_of_range = false;
  for (auto st : status) {
    body_shadow = body_shadow || st == kBodyShadow;
    camera_shadow = camera_shadow || st == kCameraShadow;
    out_of_range = out_of_range || st == kOutOfRange;
  }
  if (body) {
    t.params.emplace_back(std::string("body_") + body, 1);
    if (body_shadow) {
      add_tag(t.tags, "shadow");
      add_tag(t.tags, body);
    }
  }
  if (camera_shadow) add_tag(t.tags, "camera_shadow");
  if (out_of_range) add_tag(t.tags, "out_of_range");
  // Visibility of the break points and of the points the track point needs.
  const std::vector<double>& u = cast.u;
  for (const auto& [name, q] : t.break_points)
    if (visibility(scene, sd.sensor, u, Vec2(q[0], q[1])) != Visibility::Visible) add_tag(t.tags, "hidden_" + name);
  for (const std::string& name : sec.defining) {
    const Visibility v = visibility(scene, sd.sensor, u, map(sec.pts.at(name)));
    if (v == Visibility::Visible) continue;
    add_tag(t.tags, "joint_hidden");
    add_tag(t.tags, v == Visibility::Covered        ? "joint_covered"
                    : v == Visibility::CameraShadow ? "joint_camera_shadow"
                                                    : "joint_out_of_view");
  }
  for (int k = -1; k <= 1; ++k) {
    const int i = track_col + k;
    if (i >= 0 && i < t.columns && status[i] == kDropout) add_tag(t.tags, "joint_in_dropout");
  }
  // Points measured on the faces a reading needs.
  std::vector<int> per_face(kFaceCount, 0);
  for (std::size_t i = 0; i < status.size(); ++i)
    if (status[i] == kValid && cast.edge[i] >= 0 && static_cast<std::size_t>(cast.edge[i]) < work_edges)
      ++per_face[scene.edges[cast.edge[i]].face];
  std::vector<int> plates, bevels;
  switch (joint) {
    case Joint::Fillet: plates = {kFaceFlangeTop, kFaceWebOpen}; break;
    case Joint::Corner: plates = {kFaceOuter1, kFaceOuter2}; break;
    case Joint::Lap: plates = {kFaceLowerTop, kFaceUpperTop}; break;
    case Joint::Butt: plates = {kFaceTop1, kFaceTop2}; break;
    case Joint::VGroove:
      plates = {kFaceTop1, kFaceTop2};
      bevels = {kFaceBevel1, kFaceBevel2};
      break;
    case Joint::Bevel:
    case Joint::UGroove:
    case Joint::JGroove:
    case Joint::VGrooveThick: {
      plates = {kFaceTop1, kFaceTop2};
      // A groove's walls (a square wall is seen edge-on by the laser, a deep
      // one hides from the camera) are counted, not required: the toes are
      // the points a reading needs (Section::defining).
      for (int f : {kFaceBevel1, kFaceBevel2, kFaceArc1, kFaceArc2, kFaceCap})
        t.params.emplace_back(std::string("points_") + face_name(f), per_face[f]);
      if (per_face[kFaceBevel1] == 0 || per_face[kFaceBevel2] == 0) add_tag(t.tags, "wall_unseen");
      break;
    }
  }
  // A plate with fewer points than a segment needs (8), or a v-groove bevel
  // with fewer than 3, leaves nothing to read either: the joint counts as
  // hidden (a rejection is the right answer).
  for (int f : plates) {
    t.params.emplace_back(std::string("points_") + face_name(f), per_face[f]);
    if (per_face[f] < 8) {
      add_tag(t.tags, "plate_unseen");
      add_tag(t.tags, "joint_hidden");
    }
  }
  for (int f : bevels) {
    t.params.emplace_back(std::string("points_") + face_name(f), per_face[f]);
    if (per_face[f] < 3) {
      add_tag(t.tags, "bevel_unseen");
      add_tag(t.tags, "joint_hidden");
    }
  }
  if (joint == Joint::Corner) {
    // The notch of a corner's gap goes through; only points seen on its walls
    // tell a gap from a sharp edge (docs/JOINTS.md).
    t.params.emplace_back("points_end1", per_face[kFaceEnd1]);
    t.params.emplace_back("points_end2", per_face[kFaceEnd2]);
    if (spec.gap_mm > 0 && per_face[kFaceEnd1] + per_face[kFaceEnd2] == 0) add_tag(t.tags, "notch_unseen");
  }
  if (sec.has_decoy) {
    add_tag(t.tags, "decoy");
    const Vec2 d = map(sec.decoy_point);
    t.decoy_y_mm = d.x();
    t.decoy_z_mm = d.y();
    if (visibility(scene, sd.sensor, u, d) == Visibility::Visible) add_tag(t.tags, "decoy_in_view");
    t.params.emplace_back("decoy_distance_mm", decoy.distance_mm);
  }
  // Sensor and pose.
  auto prm = [&](const char* n, double v) { t.params.emplace_back(n, v); };
  prm("fan_deg", sd.sensor.fan_deg);
  prm("tangent_spacing", sd.sensor.tangent_spacing ? 1 : 0);
  prm("nominal_standoff_mm", sd.nominal_standoff_mm);
  prm("z_near_mm", sd.sensor.z_near_mm);
  prm("z_far_mm", sd.sensor.z_far_mm);
  prm("triangulation_deg", sd.triangulation_deg);
  prm("baseline_mm", sd.baseline_mm);
  prm("camera_y_mm", sd.sensor.camera_yz.x());
  prm("camera_z_mm", sd.sensor.camera_yz.y());
  prm("roll_deg", roll_deg);
  prm("pitch_deg", pose.pitch_deg);
  prm("yaw_deg", pose.yaw_deg);
  prm("lateral_mm", lateral + drift.lateral_mm);

  if (opt.keep_debug) out.debug = make_debug(scene, sd.sensor, cast, status, map.A, map.t);
  return out;
}

void validate(const Options& o) {
  if (!(std::abs(o.noise_mm) <= 5.0) && !(o.noise_mm < 0))
    throw std::invalid_argument("noise_mm must be at most 5 mm (negative: a random level), got " +
                                std::to_string(o.noise_mm));
  if (o.columns != 0 && (o.columns < 16 || o.columns > 4096))
    throw std::invalid_argument("columns must be 0 (random) or 16..4096, got " + std::to_string(o.columns));
  if (!(o.standoff_mm == 0 || (o.standoff_mm >= 10 && o.standoff_mm <= 2000)))
    throw std::invalid_argument("standoff_mm must be 0 (random) or 10..2000, got " + std::to_string(o.standoff_mm));
}

double draw_noise_level(std::uint64_t key, const Options& o) {
  Rng rng = Rng::stream(key, "noise_level");
  const int level = rng.uniform_int(0, static_cast<int>(kNoiseLevels_mm.size()) - 1);
  return o.noise_mm >= 0 ? o.noise_mm : kNoiseLevels_mm[level];
}

std::uint64_t joint_key(Joint joint, std::uint64_t seed) { return mix_seed(seed, name_key(joint_name(joint))); }

// A groove's plate class is drawn first (its own stream): a thick plate is
// seen from farther, standoff 100-400 mm instead of 50-250.
SensorDraw draw_sensor_for(Joint joint, std::uint64_t key, Rng& rs, const Options& options, const Probabilities& p) {
  bool thick = false;
  if (is_groove(joint)) {
    Rng rt = Rng::stream(key, "plate");
    const bool coin = rt.chance(joint == Joint::VGrooveThick ? 1.0 : p("thick"));
    thick = joint == Joint::VGrooveThick || coin;
  }
  SensorDraw sd = thick ? draw_sensor(rs, options, 100, 400) : draw_sensor(rs, options);
  sd.thick = thick;
  return sd;
}

}  // namespace

Profile make_profile(Joint joint, std::uint64_t seed, const Options& options) {
  validate(options);
  const Probabilities p(joint, options);
  const std::uint64_t key = joint_key(joint, seed);
  Rng rs = Rng::stream(key, "sensor"), rj = Rng::stream(key, "joint"), rd = Rng::stream(key, "decoy"),
      rp = Rng::stream(key, "pose");
  SensorDraw sd = draw_sensor_for(joint, key, rs, options, p);
  JointSpec spec = draw_joint(joint, rj, sd, p);
  if (is_groove(joint)) fit_groove_sensor(sd, spec, options);
  DecoySpec decoy = draw_decoy(joint, rd, sd);
  decoy.on = options.decoy;
  const PoseDraw pose = draw_pose(rp, p);
  Streams streams{Rng::stream(key, "body"), Rng::stream(key, "imperfections"), Rng::stream(key, "noise")};
  Profile out = render_joint(joint, options, p, sd, spec, decoy, nullptr, pose, Drift{}, streams,
                             draw_noise_level(key, options));
  out.truth.seed = seed;
  return out;
}

Profile make_recording_profile(Joint joint, std::uint64_t seed, int count, int index, const RecordingOptions& ro) {
  const Options& options = ro.profile;
  validate(options);
  if (count < 1 || index < 0 || index >= count)
    throw std::invalid_argument("recording index " + std::to_string(index) + " outside 0.." + std::to_string(count - 1));
  if (!(ro.ds_mm >= 0 && ro.ds_mm <= 100)) throw std::invalid_argument("ds_mm must be 0 (random) or up to 100");
  if (!(ro.lateral_drift_mm <= 50) || !(ro.height_drift_mm <= 50) || !(ro.gap_opening_mm <= 5))
    throw std::invalid_argument("drifts must be at most 50 mm, gap opening at most 5 mm");
  if (ro.decoy_every < 0) throw std::invalid_argument("decoy_every must be >= 0");
  const Probabilities p(joint, options);
  const std::uint64_t key = joint_key(joint, seed);
  Rng rs = Rng::stream(key, "sensor"), rj = Rng::stream(key, "joint"), rd = Rng::stream(key, "decoy"),
      rp = Rng::stream(key, "pose"), rr = Rng::stream(key, "recording");
  SensorDraw sd = draw_sensor_for(joint, key, rs, options, p);
  JointSpec spec = draw_joint(joint, rj, sd, p);
  if (is_groove(joint)) fit_groove_sensor(sd, spec, options);
  DecoySpec decoy = draw_decoy(joint, rd, sd);
  const PoseDraw pose = draw_pose(rp, p);

  // The recording: travel, drift (a line plus a slow sinusoid), gap opening, tacks.
  const double ds = ro.ds_mm > 0 ? ro.ds_mm : 0.0;
  const double ds_drawn = rr.uniform(0.1, 1.0);
  const double step = ds > 0 ? ds : ds_drawn;
  const double length = step * std::max(1, count - 1);
  const double s = step * index;
  const double lat_amp_drawn = rr.uniform(0, 5), h_amp_drawn = rr.uniform(0, 3);
  const double lat_amp = ro.lateral_drift_mm >= 0 ? ro.lateral_drift_mm : lat_amp_drawn;
  const double h_amp = ro.height_drift_mm >= 0 ? ro.height_drift_mm : h_amp_drawn;
  auto drift_shape = [&](double x) {  // in [-1, 1]
    const double w_line = rr.uniform(), sign = rr.sign();
    // Slow: a wavelength of at least the recording or 100 mm.
    const double wavelength = rr.uniform(1.0, 3.0) * std::max(length, 100.0), phase = rr.uniform(0, 2 * kPi);
    return w_line * sign * (2 * x / length - 1) + (1 - w_line) * dm::sin(2 * kPi * x / wavelength + phase);
  };
  Drift drift;
  drift.lateral_mm = lat_amp * drift_shape(s);
  drift.height_mm = h_amp * drift_shape(s);
  drift.margin_mm = lat_amp;
  const bool opening_coin = rr.chance(0.5);
  const double opening_drawn = rr.uniform(0.2, 1.0);
  const double opening = ro.gap_opening_mm >= 0 ? ro.gap_opening_mm : (opening_coin ? opening_drawn : 0.0);
  const double gap_max = joint == Joint::Butt || is_groove(joint) ? 3.0 : joint == Joint::Lap ? 1.5 : 2.0;
  // Placement from the widest section of the recording, with its decoy.
  JointSpec widest = spec;
  widest.gap_mm = std::max(spec.gap_mm, std::min(spec.gap_mm + opening, gap_max));
  DecoySpec any_decoy = decoy;
  any_decoy.on = ro.decoy_every > 0 || options.decoy;
  const Section placement = build_section(widest, any_decoy);
  spec.gap_mm = std::max(spec.gap_mm, std::min(spec.gap_mm + opening * s / length, gap_max));
  if (spec.gap_mm > 0 && std::find(spec.tags.begin(), spec.tags.end(), "gap") == spec.tags.end())
    spec.tags.push_back("gap");
  // Tack welds: 4-10 mm long every 40-120 mm, the first inside the recording.
  const double tack_first = rr.uniform(0.1, 0.9) * length, tack_spacing = rr.uniform(40, 120);
  const double tack_len = rr.uniform(4, 10);
  if (spec.tack) {
    const double k = std::round((s - tack_first) / tack_spacing);
    const bool on = std::abs(s - (tack_first + k * tack_spacing)) <= tack_len / 2;
    if (!on) {
      spec.tack = false;
      spec.tags.erase(std::remove(spec.tags.begin(), spec.tags.end(), "tack_weld"), spec.tags.end());
    }
  }
  decoy.on = ro.decoy_every > 0 ? (index + 1) % ro.decoy_every == 0 : options.decoy;
  const std::uint64_t profile_key = mix_seed(key, static_cast<std::uint64_t>(index) + 1);
  Streams streams{Rng::stream(profile_key, "body"), Rng::stream(profile_key, "imperfections"),
                  Rng::stream(profile_key, "noise")};
  Profile out = render_joint(joint, options, p, sd, spec, decoy, &placement, pose, drift, streams,
                             draw_noise_level(key, options));
  out.truth.seed = seed;
  out.truth.index = index;
  out.truth.s_mm = s;
  out.truth.params.emplace_back("ds_mm", step);
  out.truth.params.emplace_back("lateral_drift_mm", drift.lateral_mm);
  out.truth.params.emplace_back("height_drift_mm", drift.height_mm);
  out.truth.params.emplace_back("gap_opening_mm", opening);
  out.truth.tags.push_back("recording");
  return out;
}

Profile make_groove_profile(const GrooveShape& g, const Sensor& sensor, double root_standoff_mm) {
  if (!is_groove(g.joint)) throw std::invalid_argument(std::string("not a groove joint: ") + joint_name(g.joint));
  const double D = g.thickness_mm - g.root_face_mm, level = g.passes * g.layer_mm;
  auto bad = [](const std::string& what) { throw std::invalid_argument("groove: " + what); };
  if (!(g.root_face_mm >= 0 && D > 0 && g.gap_mm >= 0 && g.angle_deg > 0 && g.angle_deg < 90 && g.passes >= 0))
    bad("needs thickness > root face >= 0, gap >= 0, 0 < angle < 90 degrees, passes >= 0");
  if ((g.joint == Joint::UGroove || g.joint == Joint::JGroove) && !(g.radius_mm > 0)) bad("a U or J needs a radius");
  if (g.passes > 0 && !(g.layer_mm > 0)) bad("layer_mm must be positive");
  if (g.passes > 0 && !(level + std::max(g.crown_mm, 0.0) < D + std::min(g.mismatch_mm, 0.0)))
    bad("the fill (level " + std::to_string(level) + " mm, crown " + std::to_string(g.crown_mm) +
        " mm) does not stay below the tops (" + std::to_string(D + std::min(g.mismatch_mm, 0.0)) + " mm above the root)");
  if (g.passes > 0 && level < std::max(g.mismatch_mm, 0.0)) bad("the fill does not reach the higher root edge");
  const JointSpec spec{.joint = g.joint, .plate_half_length_mm = 4.0 * root_standoff_mm + 100.0, .gap_mm = g.gap_mm,
                       .mismatch_mm = g.mismatch_mm, .angle_deg = g.angle_deg, .root_face_mm = g.root_face_mm,
                       .depth_mm = D, .radius_mm = g.radius_mm, .passes = g.passes, .layer_mm = g.layer_mm,
                       .crown_mm = g.crown_mm, .ripple_mm = g.ripple_mm};
  const Section sec = build_section(spec, DecoySpec{});
  Affine map;
  map.A << 1.0, 0.0, 0.0, -1.0;
  map.t = Vec2(0, root_standoff_mm);
  Scene scene;
  for (const Polygon& solid : sec.solids) scene.add(transformed(solid, map.A, map.t));
  Profile out;
  Truth& t = out.truth;
  t.joint = g.joint;
  compute_truth(spec, sec, map, t);
  t.standoff_mm = t.track_z_mm;
  t.columns = sensor.columns;
  const Cast cast = cast_scene(scene, sensor, column_directions(sensor));
  Rng noise(0);
  std::vector<std::uint8_t> status;
  finish_profile(scene, cast, Imperfections{}, noise, out, status);
  out.debug = make_debug(scene, sensor, cast, status, map.A, map.t);
  return out;
}

std::vector<Profile> make_recording(Joint joint, std::uint64_t seed, int count, const RecordingOptions& options) {
  std::vector<Profile> out;
  if (count < 0) throw std::invalid_argument("count must be >= 0");
  out.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) out.push_back(make_recording_profile(joint, seed, count, i, options));
  return out;
}

}  // namespace vts_corpus
