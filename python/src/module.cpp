// vts._vts: the C++ side of the Python package (python/vts/__init__.py wraps
// it). Only bindings here: every call goes to the library API the CLI uses
// (pipeline/scan_job.h, sensor/, tracker/, trackio/), so the package scans,
// reads and tracks exactly as `vts scan`, `vts track` do.
#include <chrono>
#include <limits>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "common/parallel.h"
#include "common/version.h"
#include "dataset/dataset.h"
#include "pipeline/profile_truth.h"
#include "pipeline/scan_job.h"
#include "pipeline/track_input.h"
#include "pipeline/track_recording.h"
#include "sensor/cell.h"
#include "sensor/presets.h"
#include "sensor/profile_exr.h"
#include "sensor/scene_file.h"
#include "tracker/tracker.h"
#include "trackio/params_yaml.h"
#include "trackio/result_json.h"
#include "pipeline/scenario.h"
#include "pipeline/sim_run.h"

namespace py = pybind11;
using namespace vts;

namespace {

// A JSON value (trackio's output) as Python objects.
py::object to_python(const trackio::Json& j) {
  switch (j.type()) {
    case trackio::Json::value_t::null: return py::none();
    case trackio::Json::value_t::boolean: return py::bool_(j.get<bool>());
    case trackio::Json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case trackio::Json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case trackio::Json::value_t::number_float:  // NaN (does not apply) as None, as it reads in JSON
      return std::isfinite(j.get<double>()) ? py::object(py::float_(j.get<double>())) : py::object(py::none());
    case trackio::Json::value_t::string: return py::str(j.get<std::string>());
    case trackio::Json::value_t::array: {
      py::list l;
      for (const auto& v : j) l.append(to_python(v));
      return l;
    }
    case trackio::Json::value_t::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = to_python(v);
      return d;
    }
    default: return py::none();
  }
}

using F32 = py::array_t<float, py::array::c_style>;
using U8 = py::array_t<bool, py::array::c_style>;
using F64 = py::array_t<double, py::array::c_style>;

// Row-major arrays of a recording, filled one profile at a time. Allocated
// with the GIL held; fill() touches only their raw buffers, so it runs with
// the GIL released.
struct Arrays {
  std::int64_t rows = 0;
  int cols = 0;
  bool truth = false, reference = false;
  F32 y, z, range, intensity, true_y, true_z, ref_y, ref_z, ref_range;
  U8 valid, true_valid, ref_valid;
  F64 pose, time;

  Arrays(std::int64_t p, int n, bool with_truth, bool with_reference)
      : rows(p), cols(n), truth(with_truth), reference(with_reference) {
    const std::vector<py::ssize_t> shape{p, n};
    y = F32(shape), z = F32(shape), range = F32(shape), valid = U8(shape);
    if (truth) intensity = F32(shape), true_y = F32(shape), true_z = F32(shape), true_valid = U8(shape);
    if (reference) ref_y = F32(shape), ref_z = F32(shape), ref_range = F32(shape), ref_valid = U8(shape);
    pose = F64(std::vector<py::ssize_t>{p, 7});
    time = F64(std::vector<py::ssize_t>{p});
  }

  template <class A, class T>
  static void row(A& a, std::int64_t r, const std::vector<T>& v) {
    std::memcpy(a.mutable_data() + r * static_cast<std::int64_t>(v.size()), v.data(), v.size() * sizeof(T));
  }

  void fill(std::int64_t r, const Profile& p, const Profile* ref) {
    if (p.size() != cols) throw std::runtime_error("profile of " + std::to_string(p.size()) + " points in a recording of " + std::to_string(cols));
    row(y, r, p.y_mm), row(z, r, p.z_mm), row(range, r, p.range_mm), row(valid, r, p.valid);
    if (truth) row(intensity, r, p.intensity), row(true_y, r, p.true_y_mm), row(true_z, r, p.true_z_mm), row(true_valid, r, p.true_valid);
    if (reference && ref) row(ref_y, r, ref->y_mm), row(ref_z, r, ref->z_mm), row(ref_range, r, ref->range_mm), row(ref_valid, r, ref->valid);
    double* q = pose.mutable_data() + 7 * r;
    const Eigen::Vector3d t = p.world_from_sensor.translation();
    const Eigen::Quaterniond rot = rotation_quat(p.world_from_sensor);
    q[0] = t.x(), q[1] = t.y(), q[2] = t.z(), q[3] = rot.w(), q[4] = rot.x(), q[5] = rot.y(), q[6] = rot.z();
    time.mutable_data()[r] = p.time_s;
  }

  py::dict dict(const ProfileFileInfo& info) const {
    py::dict d;
    d["y"] = y, d["z"] = z, d["range"] = range, d["valid"] = valid;
    if (truth) d["intensity"] = intensity, d["true_y"] = true_y, d["true_z"] = true_z, d["true_valid"] = true_valid;
    if (reference) d["ref_y"] = ref_y, d["ref_z"] = ref_z, d["ref_range"] = ref_range, d["ref_valid"] = ref_valid;
    d["pose"] = pose, d["time"] = time;
    d["scanner"] = info.scanner;
    d["scene_name"] = info.scene_name;
    d["scene_text"] = info.scene_text;
    d["seed"] = info.seed;
    return d;
  }
};

template <class A>
A need(const py::dict& d, const std::string& key, std::int64_t rows, std::int64_t cols) {
  if (!d.contains(key)) throw py::value_error("missing array '" + key + "'");
  A a = A::ensure(d[key.c_str()]);
  if (!a) throw py::value_error("array '" + key + "' is not numeric");
  const bool shape_ok = cols < 0 ? (a.ndim() == 1 && a.shape(0) == rows)
                                 : (a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == cols);
  if (!shape_ok)
    throw py::value_error("array '" + key + "' has the wrong shape: expected (" + std::to_string(rows) +
                          (cols < 0 ? "" : ", " + std::to_string(cols)) + ")");
  return a;
}

std::pair<std::int64_t, int> shape_of(const py::dict& d) {
  if (!d.contains("y")) throw py::value_error("missing array 'y'");
  const F32 y = F32::ensure(d["y"]);
  if (!y || y.ndim() != 2 || y.shape(0) < 1 || y.shape(1) < 1)
    throw py::value_error("array 'y' must be 2-D (profiles, points) with at least one profile");
  return {y.shape(0), static_cast<int>(y.shape(1))};
}

// A recording's arrays as numpy hands them over (any dtype and layout),
// converted and checked once, for the writer and the tracker; profile(r)
// copies row r out. `prefix` "" reads the main channels with the pose and
// time, "ref_" the reference's samples (they share the row's pose and time).
struct InArrays {
  std::int64_t rows = 0;
  int cols = 0;
  bool truth = false;
  F32 y, z, range, intensity, true_y, true_z;
  U8 valid, true_valid;
  F64 pose, time;

  InArrays(const py::dict& d, const std::string& prefix, bool with_truth) : truth(with_truth) {
    std::tie(rows, cols) = shape_of(d);
    y = need<F32>(d, prefix + "y", rows, cols), z = need<F32>(d, prefix + "z", rows, cols);
    valid = need<U8>(d, prefix + "valid", rows, cols);
    if (d.contains(prefix + "range")) range = need<F32>(d, prefix + "range", rows, cols);
    if (truth)
      intensity = need<F32>(d, "intensity", rows, cols), true_y = need<F32>(d, "true_y", rows, cols),
      true_z = need<F32>(d, "true_z", rows, cols), true_valid = need<U8>(d, "true_valid", rows, cols);
    if (!prefix.empty()) return;
    if (d.contains("pose")) pose = need<F64>(d, "pose", rows, 7);
    if (d.contains("time")) time = need<F64>(d, "time", rows, -1);
  }

  bool has_pose() const { return static_cast<bool>(pose); }

  Profile profile(std::int64_t r) const {
    Profile p;
    p.resize(cols);
    auto copy = [&](auto& dst, const auto& a) {
      std::memcpy(dst.data(), a.data() + r * cols, cols * sizeof(dst[0]));
    };
    copy(p.y_mm, y), copy(p.z_mm, z), copy(p.valid, valid);
    if (range) copy(p.range_mm, range);
    else
      for (int i = 0; i < cols; ++i) p.range_mm[i] = p.valid[i] ? std::hypot(p.y_mm[i], p.z_mm[i]) : 0.0f;
    if (truth) copy(p.intensity, intensity), copy(p.true_y_mm, true_y), copy(p.true_z_mm, true_z), copy(p.true_valid, true_valid);
    if (pose) {
      const double* v = pose.data() + 7 * r;
      p.world_from_sensor = pose_from_quat({v[0], v[1], v[2]}, Eigen::Quaterniond(v[3], v[4], v[5], v[6]).normalized());
    }
    if (time) p.time_s = time.data()[r];
    p.index = r;
    return p;
  }
};

// A scan job's sink writing straight into the numpy arrays.
struct ArraySink final : ScanSink {
  Arrays* arrays;
  explicit ArraySink(Arrays* a) : arrays(a) {}
  void begin(const ProfileFileInfo&) override {}
  void write(const ScanBatch& b) override {
    for (std::size_t k = 0; k < b.profiles.size(); ++k)
      arrays->fill(b.first + static_cast<std::int64_t>(k), b.profiles[k], b.reference.empty() ? nullptr : &b.reference[k]);
  }
  void finish() override {}
};

Pose pose_of(const Eigen::Matrix4d& m) {
  Pose p;
  p.matrix() = m;
  return p;
}

const Workpiece* first_joint(const Cell& c) {
  for (const Workpiece& w : c.workpieces)
    if (!w.is_mesh() && w.type != JointType::Plate) return &w;
  return nullptr;
}

py::dict shard_dict(const ShardInfo& s) {
  py::dict d;
  d["shard"] = s.shard, d["scenes"] = s.scenes, d["profiles"] = s.profiles;
  py::list files;
  for (const DatasetFile& f : s.files) {
    py::dict e;
    e["name"] = f.name, e["bytes"] = f.bytes, e["sha256"] = f.sha256;
    files.append(e);
  }
  d["files"] = files;
  return d;
}

ShardInfo shard_of(const py::handle& h) {
  const py::dict d = py::reinterpret_borrow<py::dict>(h);
  ShardInfo s;
  s.shard = d["shard"].cast<int>(), s.scenes = d["scenes"].cast<int>(), s.profiles = d["profiles"].cast<std::int64_t>();
  for (const py::handle f : d["files"])
    s.files.push_back({f["name"].cast<std::string>(), f["bytes"].cast<std::uint64_t>(), f["sha256"].cast<std::string>()});
  return s;
}

// Runs `job` without the GIL; Ctrl-C between batches stops it (KeyboardInterrupt).
template <class Job>
void without_gil(Job&& job) {
  bool interrupted = false;
  auto cancelled = [&] {
    py::gil_scoped_acquire gil;
    interrupted = PyErr_CheckSignals() != 0;
    return interrupted;
  };
  {
    py::gil_scoped_release release;
    try {
      job(cancelled);
    } catch (const Cancelled&) {
      if (!interrupted) throw;
    }
  }
  if (interrupted) throw py::error_already_set();
}

SourceKind source_of(const std::string& s) {
  if (s == "raster") return SourceKind::Raster;
  if (s == "reference") return SourceKind::Reference;
  throw py::value_error("source = '" + s + "': expected 'raster' or 'reference'");
}

tracker::TrackerParams params_of(const std::string& joint, const std::string& yaml, const std::string& name) {
  trackio::ParamsFile file;
  trackio::read_params(yaml, name, file);  // throws ParamsError naming the key
  if (!joint.empty()) {
    const auto j = tracker::joint_type_from_string(joint);
    if (!j) throw py::value_error("joint = '" + joint + "': expected fillet, corner, lap, butt, vgroove, bevel, ugroove or jgroove");
    file.params.joint = *j;
  } else if (file.joint) {
    file.params.joint = *file.joint;
  }
  return file.params;
}

}  // namespace

PYBIND11_MODULE(_vts, m) {
  m.doc() = "vts: a virtual laser-triangulation seam sensor (C++ core). Use the `vts` package.";
  m.attr("__version__") = std::string(vts::version());

  py::register_exception<ExrError>(m, "ExrError", PyExc_ValueError);
  py::register_exception<SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<trackio::ParamsError>(m, "ParamsError", PyExc_ValueError);
  py::register_exception<TrackInputError>(m, "TrackInputError", PyExc_ValueError);
  py::register_exception<Cancelled>(m, "Cancelled", PyExc_KeyboardInterrupt);
  py::register_exception<DatasetSpecError>(m, "DatasetSpecError", PyExc_ValueError);
  py::register_exception<DatasetDrawError>(m, "DatasetDrawError", PyExc_ValueError);

  m.def("set_threads", &set_thread_limit, py::arg("n"),
        "Limit vts's thread pool to n threads (0: all cores); once per process, before the first scan.");
  m.def("threads", &thread_limit, "The thread pool's limit.");

  // ---- Scanner -----------------------------------------------------------
  py::class_<ScannerDesc> scanner(m, "Scanner", R"doc(
A scanner description: laser fan, measuring window, camera, surface and error
model switch. Lengths in mm, angles in degrees, rates in Hz (docs/SENSOR_MODEL.md).

Scanner(preset="mspot", material=None, ideal=False): a named sensor
(vts.sensors()) with a named material (vts.materials(), default matte-steel).
)doc");
  scanner
      .def(py::init([](const std::string& preset, const std::optional<std::string>& material, bool ideal) {
             auto d = sensor_preset(preset);
             if (!d) throw py::value_error("sensor '" + preset + "': unknown; valid names: " + join_names(sensor_preset_names()));
             if (material && !apply_material(*d, *material))
               throw py::value_error("material '" + *material + "': unknown; valid names: " + join_names(material_names()));
             d->ideal = ideal;
             return *d;
           }),
           py::arg("preset") = std::string(kDefaultSensor), py::arg("material") = py::none(), py::arg("ideal") = false)
      .def("set_material", [](ScannerDesc& d, const std::string& name) {
             if (!apply_material(d, name))
               throw py::value_error("material '" + name + "': unknown; valid names: " + join_names(material_names()));
           }, py::arg("name"), "Set the surface fields to a named material (vts.materials()).")
      .def("validate", [](const ScannerDesc& d) { return validate(d); },
           "Empty string when usable, else a message naming the first bad field.")
      .def("__copy__", [](const ScannerDesc& d) { return d; })
      .def("__repr__", [](const ScannerDesc& d) {
        return "<vts.Scanner " + d.name + ", " + std::to_string(d.points) + " points, " + d.material + (d.ideal ? ", ideal>" : ">");
      });
#define VTS_FIELD(f, doc) scanner.def_readwrite(#f, &ScannerDesc::f, doc)
  VTS_FIELD(name, "preset name (informational)");
  VTS_FIELD(fan_deg, "full opening angle of the laser fan, degrees");
  VTS_FIELD(points, "columns per profile, 16..4096");
  VTS_FIELD(rate_hz, "profile rate, Hz");
  VTS_FIELD(min_range_mm, "depth of field: nearest measurable z, mm");
  VTS_FIELD(max_range_mm, "depth of field: farthest measurable z, mm");
  VTS_FIELD(max_hit_mm, "longest ray distance that counts as a hit, mm");
  VTS_FIELD(roi_first_column, "first column of the image-processing region");
  VTS_FIELD(roi_last_column, "last column of the image-processing region");
  VTS_FIELD(max_incidence_deg, "laser incidence beyond which the return is lost, degrees");
  VTS_FIELD(baseline_mm, "camera centre's distance from the laser plane, mm");
  VTS_FIELD(triangulation_deg, "camera axis tilt from the laser's z axis, degrees");
  VTS_FIELD(focal_length_mm, "camera focal length, mm");
  VTS_FIELD(pixel_pitch_um, "camera pixel pitch, micrometres");
  VTS_FIELD(image_width_px, "image columns (along the laser line)");
  VTS_FIELD(image_height_px, "image rows (along the triangulation direction)");
  VTS_FIELD(subpixel_step_px, "peak detector resolution, pixels");
  VTS_FIELD(intensity_ref_range_mm, "range of intensity 1 for a white surface at normal incidence, mm");
  VTS_FIELD(material, "material preset name (informational)");
  VTS_FIELD(speckle_px, "standard deviation of the peak position (speckle), pixels");
  VTS_FIELD(reflectivity, "diffuse reflectance, 0..1");
  VTS_FIELD(shiny_cluster_prob, "per column: probability a reflection cluster starts");
  VTS_FIELD(shiny_cluster_max_points, "longest reflection cluster, columns");
  VTS_FIELD(shiny_offset_min_mm, "reflection cluster displacement along the ray, min |mm|");
  VTS_FIELD(shiny_offset_max_mm, "reflection cluster displacement along the ray, max |mm|");
  VTS_FIELD(rough_outlier_prob, "per column: probability of a rough-surface outlier");
  VTS_FIELD(rough_offset_min_mm, "rough outlier displacement, min |mm|");
  VTS_FIELD(rough_offset_max_mm, "rough outlier displacement, max |mm|");
  VTS_FIELD(dropout_prob_normal, "dropout probability at normal incidence");
  VTS_FIELD(dropout_prob_grazing, "dropout probability at grazing incidence");
  VTS_FIELD(ideal, "True: the error model is off, profiles are the ideal geometry");
#undef VTS_FIELD
  scanner.def_property(
      "tool_from_laser", [](const ScannerDesc& d) -> Eigen::Matrix4d { return d.tool_from_laser.matrix(); },
      [](ScannerDesc& d, const Eigen::Matrix4d& m) { d.tool_from_laser.matrix() = m; },
      "where the laser frame sits on the torch (4x4, mm)");

  m.def("sensors", &sensor_preset_names, "Names of the sensor presets.");
  m.def("sensor_description", &sensor_preset_description, py::arg("name"));
  m.def("materials", &material_names, "Names of the material presets.");
  m.def("material_description", &material_description, py::arg("name"));

  // ---- Path and cell -----------------------------------------------------
  py::class_<ScanPath>(m, "ScanPath", R"doc(
A straight scan path: profile i is taken at start translated by i * step_mm
along direction (orientation fixed), at time i / scanner.rate_hz.
)doc")
      .def_property("start", [](const ScanPath& p) -> Eigen::Matrix4d { return p.start.matrix(); },
                    [](ScanPath& p, const Eigen::Matrix4d& m) { p.start.matrix() = m; },
                    "world_from_sensor at profile 0 (4x4 homogeneous matrix, mm)")
      .def_property("direction", [](const ScanPath& p) -> Eigen::Vector3d { return p.direction; },
                    [](ScanPath& p, const Eigen::Vector3d& d) {
                      if (!(d.norm() > 1e-12)) throw py::value_error("direction must not be the zero vector");
                      p.direction = d.normalized();
                    }, "travel direction, world frame, unit")
      .def_readwrite("step_mm", &ScanPath::step_mm, "distance between profiles, mm")
      .def_readwrite("profiles", &ScanPath::profiles, "number of profiles")
      .def("pose_at", [](const ScanPath& p, std::int64_t i) -> Eigen::Matrix4d { return p.pose_at(i).matrix(); },
           py::arg("i"), "world_from_sensor of profile i (4x4)");

  py::class_<Cell>(m, "Cell", R"doc(
A cell: workpieces, a scanner and a straight scan path. Make one with
vts.cell(name) (built in), vts.load_scene(path) or vts.parse_scene(text).
)doc")
      .def_readwrite("name", &Cell::name)
      .def_readwrite("scanner", &Cell::scanner, "the Scanner (cell.scanner.points = 1024 changes the cell's)")
      .def_readwrite("path", &Cell::path, "the ScanPath (cell.path.profiles = 50 changes the cell's)")
      .def("copy", [](const Cell& c) { return c; }, "An independent copy of the cell.")
      .def("__copy__", [](const Cell& c) { return c; })
      .def("to_yaml", [](const Cell& c) { return scene_to_yaml(c); }, "The cell as a scene file (docs/SCENE_FORMAT.md).")
      .def_property_readonly("joint", [](const Cell& c) -> py::object {
        for (const Workpiece& w : c.workpieces)
          if (w.has_joint()) return py::str(std::string(to_string(w.type)));
        return py::none();
      }, "the first workpiece's joint name, or None")
      .def("look_from", [](Cell& c, double standoff_mm) {
        if (c.workpieces.empty()) throw py::value_error("the cell has no workpiece");
        if (!(standoff_mm > 0)) throw py::value_error("standoff_mm must be > 0");
        const ScanPath d = default_path(c.workpieces.front(), standoff_mm);
        c.path.start = d.start, c.path.direction = d.direction;
      }, py::arg("standoff_mm"), "Re-derive the path's start and direction at this standoff from the seam root, mm.")
      .def("truth", [](const Cell& c) {
        py::dict d;
        for (const Workpiece& w : c.workpieces) {
          if (w.is_mesh()) continue;
          const JointTruth& t = w.truth;
          d["joint"] = std::string(to_string(w.type));
          d["gap_mm"] = t.gap_mm, d["angle_deg"] = t.angle_deg, d["mismatch_mm"] = t.mismatch_mm;
          d["step_mm"] = t.step_mm, d["depth_mm"] = t.depth_mm, d["area_mm2"] = t.area_mm2;
          if (is_groove(w.type)) {
            d["wall_angle_a_deg"] = t.wall_angle_a_deg, d["wall_angle_b_deg"] = t.wall_angle_b_deg;
            d["top_width_mm"] = t.top_width_mm;
          }
          break;
        }
        return d;
      }, "The first joint's analytic truth (gap, angle, ...; grooves: walls, depth, area), joint frame.")
      .def("track_point", [](const Cell& c, const Eigen::Matrix4d& world_from_sensor) -> py::object {
        const Workpiece* w = first_joint(c);
        if (!w) return py::none();
        const Vec2 p = profile_truth(*w, c.scanner, pose_of(world_from_sensor)).track_point;
        return py::make_tuple(p.x(), p.y());
      }, py::arg("world_from_sensor"),
         "The first joint's true track point (y, z) in the profile of a sensor at this pose, mm; None without a joint.")
      .def("profile_truth", [](const Cell& c, const Eigen::Matrix4d& world_from_sensor) -> py::object {
        const Workpiece* w = first_joint(c);
        if (!w) return py::none();
        return to_python(profile_truth_json(profile_truth(*w, c.scanner, pose_of(world_from_sensor))));
      }, py::arg("world_from_sensor"),
         "The first joint's analytic truth as the profile of a sensor at this pose sees it (sensor frame, mm, "
         "degrees): track_point, break_points (the tracker's numbering), gap_mm, angle_deg, ...; None without "
         "a joint. The labels vts dataset writes (docs/DATASETS.md).");

  m.def("cells", [] { return builtin_cell_names(CellSet::All); }, "Names of the built-in cells.");
  m.def("cell_description", &builtin_cell_description, py::arg("name"));
  m.def("cell", [](const std::string& name) {
    auto c = builtin_cell(name);
    if (!c) throw py::value_error("cell '" + name + "': unknown; valid names: " + join_names(builtin_cell_names()));
    return *c;
  }, py::arg("name") = std::string(kDefaultCell), "A built-in cell by name (vts.cells()).");
  m.def("load_scene", [](const std::filesystem::path& p) { return load_scene(p); }, py::arg("path"),
        "A cell from a scene file (YAML, docs/SCENE_FORMAT.md).");
  m.def("parse_scene", [](const std::string& text, const std::string& name) { return parse_scene(text, name); },
        py::arg("text"), py::arg("name") = "<scene>", "A cell from scene YAML text; relative mesh paths resolve against name's directory.");

  // ---- Scanning ----------------------------------------------------------
  m.def("_scan", [](const Cell& cell, std::uint64_t seed, const std::string& source, bool reference, int batch) {
    ScanSpec spec;
    spec.cell = cell;
    spec.source = source_of(source);
    spec.with_reference = reference;
    spec.seed = seed;
    spec.batch_profiles = batch;
    if (const std::string why = validate(cell.scanner); !why.empty()) throw py::value_error("scanner: " + why);
    if (cell.path.profiles < 1) throw py::value_error("path.profiles = " + std::to_string(cell.path.profiles) + ": must be >= 1");
    const ProfileFileInfo info = scan_file_info(spec);
    Arrays arrays(cell.path.profiles, cell.scanner.points, info.error_model, reference);
    ArraySink sink(&arrays);
    without_gil([&](const std::function<bool()>& cancelled) {
      ScanCallbacks cb;
      cb.cancelled = cancelled;
      run_scan_job(spec, sink, cb);
    });
    return arrays.dict(info);
  });

  m.def("_read_exr", [](const std::filesystem::path& path) {
    ProfileRecording rec;
    {
      py::gil_scoped_release release;
      rec = read_profile_exr(path);
    }
    Arrays arrays(static_cast<std::int64_t>(rec.profiles.size()), rec.info.scanner.points, rec.info.error_model,
                  rec.info.has_reference);
    for (std::size_t r = 0; r < rec.profiles.size(); ++r)
      arrays.fill(static_cast<std::int64_t>(r), rec.profiles[r], rec.reference.empty() ? nullptr : &rec.reference[r]);
    return arrays.dict(rec.info);
  });

  m.def("_write_exr", [](const std::filesystem::path& path, const py::dict& d, const std::string& compression) {
    const auto method = exr_compression_from_string(compression);
    if (!method)
      throw py::value_error("compression '" + compression + "': expected one of " + join_names(exr_compression_names()));
    const auto [rows, cols] = shape_of(d);
    ProfileFileInfo info;
    info.scanner = d["scanner"].cast<ScannerDesc>();
    if (info.scanner.points != cols)
      throw py::value_error("scanner.points = " + std::to_string(info.scanner.points) + " but the arrays have " + std::to_string(cols) + " columns");
    info.scene_name = d["scene_name"].cast<std::string>();
    info.scene_text = d["scene_text"].cast<std::string>();
    info.seed = d["seed"].cast<std::uint64_t>();
    info.profiles = static_cast<int>(rows);
    info.error_model = d.contains("true_y");
    info.scanner.ideal = !info.error_model;
    info.has_reference = d.contains("ref_y");
    const InArrays main_arrays(d, "", info.error_model);
    std::optional<InArrays> ref_arrays;
    if (info.has_reference) ref_arrays.emplace(d, "ref_", false);
    ProfileExrWriter writer(path, info, *method);
    for (std::int64_t r = 0; r < rows; ++r) {
      const Profile p = main_arrays.profile(r);
      if (!ref_arrays) {
        writer.write(p);
        continue;
      }
      const Profile ref = ref_arrays->profile(r);
      writer.write(p, &ref);
    }
    writer.finish();
  });

  // ---- Tracking ----------------------------------------------------------
  py::class_<tracker::Tracker>(m, "_Tracker")
      .def(py::init([](const std::string& joint, const std::string& yaml, const std::string& name) {
             return tracker::Tracker(params_of(joint, yaml, name));
           }))
      .def_property_readonly("joint", [](const tracker::Tracker& t) { return std::string(tracker::to_string(t.params().joint)); })
      .def("track", [](tracker::Tracker& t, const py::array_t<float, py::array::c_style | py::array::forcecast>& y,
                       const py::array_t<float, py::array::c_style | py::array::forcecast>& z,
                       const py::array_t<bool, py::array::c_style | py::array::forcecast>& valid) {
        if (y.ndim() != 1 || z.ndim() != 1 || valid.ndim() != 1 || y.shape(0) != z.shape(0) || y.shape(0) != valid.shape(0))
          throw py::value_error("y, z and valid must be 1-D arrays of one length (one profile)");
        const auto n = static_cast<std::size_t>(y.shape(0));
        const tracker::ProfileView view{{y.data(), n}, {z.data(), n},
                                        {reinterpret_cast<const std::uint8_t*>(valid.data()), n}};
        trackio::Json j;
        {
          py::gil_scoped_release release;
          j = trackio::result_to_json(0, t.track(view));
        }
        j.erase("profile");
        return to_python(j);
      });

  m.def("_track_recording", [](const py::dict& d, const std::string& joint, const std::string& yaml,
                               const std::string& name, bool independent) {
    const InArrays arrays(d, "", false);
    TrackInput input;
    input.profiles.reserve(static_cast<std::size_t>(arrays.rows));
    for (std::int64_t r = 0; r < arrays.rows; ++r) input.profiles.push_back(arrays.profile(r));
    input.csv = !arrays.has_pose();
    const tracker::TrackerParams params = params_of(joint, yaml, name);
    TrackRecordingOptions options;
    options.independent = independent;
    std::vector<std::string> lines;
    {
      py::gil_scoped_release release;
      track_recording(input, params, options, [&](const std::string& line) { lines.push_back(line); });
    }
    py::list out;
    for (const std::string& l : lines) out.append(to_python(trackio::Json::parse(l)));
    return out;
  });

  // ---- vts sim (python/vts/__init__.py: sim, scenarios) -------------------
  m.def("scenarios", &scenario_names, "Names of the built-in vts sim scenarios (docs/SIM.md).");
  m.def("_sim", [](const std::string& name, const std::string& yaml, const std::string& file) {
    Scenario sc;
    try {
      sc = name.empty() ? parse_scenario(yaml, file) : builtin_scenario(name);
    } catch (const ScenarioError& e) {
      throw py::value_error(e.what());
    }
    SimRun run;
    double wall_s = 0.0;
    {
      py::gil_scoped_release release;
      const auto t0 = std::chrono::steady_clock::now();
      run = run_sim(sc.spec);
      wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    py::dict out = to_python(scenario_summary_json(sc, run, wall_s, wall_s));
    // Per master cycle: time, seam (0-based, -1 after the last), phase, the
    // real TCP, the commanded one, and while welding the errors of the weld
    // path's centre from the true seam (NaN otherwise).
    const auto& smp = run.result.samples;
    const py::ssize_t n = static_cast<py::ssize_t>(smp.size());
    F64 time(n), lateral(n), vertical(n), tcp({n, py::ssize_t{3}}), cmd({n, py::ssize_t{3}});
    py::array_t<int> seam(n);
    py::list phase;
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto& s = smp[static_cast<std::size_t>(i)];
      const std::size_t u = static_cast<std::size_t>(i);
      const Pose actual = sample_tcp(run.result, &run.actual_tcp, u);
      time.mutable_at(i) = s.time_s;
      seam.mutable_at(i) = s.seam;
      phase.append(std::string(tracker::to_string(s.phase)));
      for (int k = 0; k < 3; ++k) {
        tcp.mutable_at(i, k) = actual.translation()[k];
        cmd.mutable_at(i, k) = s.world_from_tool.translation()[k];
      }
      double lat = std::numeric_limits<double>::quiet_NaN(), ver = lat;
      if (s.phase == tracker::Phase::Weld && s.seam >= 0 && s.seam < static_cast<int>(run.cell.truth.size())) {
        const PointError e = seam_error(run.cell.truth[static_cast<std::size_t>(s.seam)], weld_centre(run.result, &run.actual_tcp, u));
        lat = e.lateral_mm;
        ver = e.vertical_mm;
      }
      lateral.mutable_at(i) = lat;
      vertical.mutable_at(i) = ver;
    }
    out["time_s"] = time;
    out["seam_index"] = seam;
    out["phase"] = phase;
    out["tcp_mm"] = tcp;
    out["commanded_mm"] = cmd;
    out["lateral_error_mm"] = lateral;
    out["vertical_error_mm"] = vertical;
    return out;
  });

  // ---- Datasets (python/vts/dataset.py wraps these) ----------------------
  // Parsing a spec takes milliseconds and each call below gets its text: the
  // last few parsed are kept (called with the GIL held, so one at a time).
  static std::vector<std::pair<std::string, std::shared_ptr<const DatasetSpec>>> parsed_specs;
  static const auto spec_of = [](const std::string& text) {
    for (const auto& [t, spec] : parsed_specs)
      if (t == text) return spec;
    auto spec = std::make_shared<const DatasetSpec>(parse_dataset_spec(text, "<spec>"));
    if (parsed_specs.size() >= 4) parsed_specs.erase(parsed_specs.begin());
    parsed_specs.emplace_back(text, spec);
    return spec;
  };
  m.def("dataset_canonical", [](const std::string& text, const std::string& name) {
    return dataset_spec_to_yaml(parse_dataset_spec(text, name));
  });
  m.def("dataset_shard_count", [](const std::string& text) { return shard_count(*spec_of(text)); });
  m.def("dataset_write_shard", [](const std::string& text, int k, const std::filesystem::path& out) {
    const std::shared_ptr<const DatasetSpec> spec = spec_of(text);
    ShardInfo info;
    without_gil([&](const std::function<bool()>& cancelled) {
      DatasetCallbacks cb;
      cb.cancelled = cancelled;
      info = write_shard(*spec, k, out, cb);
    });
    return shard_dict(info);
  });
  m.def("dataset_verified_shard", [](const std::string& text, int k, const std::filesystem::path& out) -> py::object {
    const std::shared_ptr<const DatasetSpec> spec = spec_of(text);
    std::optional<ShardInfo> info;
    {
      py::gil_scoped_release release;
      info = verified_shard(*spec, k, out);
    }
    return info ? py::object(shard_dict(*info)) : py::object(py::none());
  });
  m.def("dataset_write_manifest", [](const std::string& text, const py::list& records, const std::filesystem::path& out) {
    std::vector<ShardInfo> shards;
    for (const py::handle h : records) shards.push_back(shard_of(h));
    write_manifest(*spec_of(text), shards, out);
  });
}
