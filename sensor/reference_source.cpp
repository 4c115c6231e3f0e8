#include "sensor/reference_source.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "common/parallel.h"
#include "sensor/error_model.h"
#include "sensor/rays.h"

namespace vts {
namespace {

// Embree reports the message through a callback on the thread that failed;
// rtcGetDeviceError only gives the code.
thread_local std::string t_embree_message;

void on_embree_error(void*, RTCError, const char* message) {
  t_embree_message = message ? message : "";
}

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
  }
  return "RTC_ERROR_?";
}

void check(RTCDevice device, const char* what) {
  const RTCError code = rtcGetDeviceError(device);
  if (code == RTC_ERROR_NONE) return;
  std::string msg = std::string("Embree: ") + what + " failed: " + error_name(code);
  if (!t_embree_message.empty()) msg += ": " + t_embree_message;
  t_embree_message.clear();
  throw std::runtime_error(msg);
}

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using DevicePtr = std::unique_ptr<std::remove_pointer_t<RTCDevice>, DeviceDeleter>;
using ScenePtr = std::unique_ptr<std::remove_pointer_t<RTCScene>, SceneDeleter>;

constexpr int kPacket = 16;
// Below this many profiles per thread a batch is scanned on the calling thread.
constexpr std::size_t kMinProfilesPerThread = 64;

class ReferenceSource final : public ProfileSource {
 public:
  ReferenceSource(const ScannerDesc& desc, const Mesh& mesh, int threads)
      : threads_(static_cast<std::size_t>(threads > 0 ? std::min(threads, thread_limit()) : thread_limit())),
        desc_(desc), dirs_(column_directions(desc)), camera_centre_(camera_model(desc).centre_mm) {
    dirs_d_.reserve(dirs_.size());
    for (const auto& d : dirs_) dirs_d_.push_back(d.cast<double>());
    build_scene(mesh);
  }

  void scan(const Pose& world_from_sensor, Profile& out) override {
    scan_one(world_from_sensor, out);
  }

  void scan_batch(std::span<const Pose> poses, std::span<Profile> out) override {
    assert(poses.size() == out.size());
    const std::size_t n = std::min(poses.size(), out.size());
    const std::size_t parts = std::max<std::size_t>(1, std::min(threads_, n / kMinProfilesPerThread));
    parallel_for(parts, [&](std::size_t t) {
      for (std::size_t i = n * t / parts, end = n * (t + 1) / parts; i < end; ++i) scan_one(poses[i], out[i]);
    });
  }

  const ScannerDesc& scanner() const override { return desc_; }
  std::string_view kind() const override { return "reference"; }

 private:
  std::size_t threads_;  // most threads a batch is spread over

  void build_scene(const Mesh& mesh) {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (std::uint32_t v : mesh.triangles[t])
        if (v >= mesh.vertices.size())
          throw std::invalid_argument("reference source: triangle " + std::to_string(t) +
                                      " uses vertex " + std::to_string(v) + " but the mesh has " +
                                      std::to_string(mesh.vertices.size()) + " vertices");

    // The thread limit (common/parallel.h) bounds Embree's own threads too.
    const std::string config = embree_device_config();
    device_.reset(rtcNewDevice(config.empty() ? nullptr : config.c_str()));
    if (!device_) check(nullptr, "rtcNewDevice");
    rtcSetDeviceErrorFunction(device_.get(), on_embree_error, nullptr);

    scene_.reset(rtcNewScene(device_.get()));
    check(device_.get(), "rtcNewScene");
    // ROBUST: without it rays lying exactly in the plane of a row of mesh
    // edges slip between the triangles (docs: shared/notes/stack.md).
    rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
    check(device_.get(), "scene setup");

    // Embree rejects zero-sized buffers; an empty scene simply misses.
    if (!mesh.vertices.empty() && !mesh.triangles.empty()) {
      RTCGeometry geom = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
      check(device_.get(), "rtcNewGeometry");
      rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
          geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
          mesh.vertices.size()));
      auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
          geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t),
          mesh.triangles.size()));
      if (!v || !idx) {
        rtcReleaseGeometry(geom);
        check(device_.get(), "rtcSetNewGeometryBuffer");
        throw std::runtime_error("Embree: rtcSetNewGeometryBuffer returned no buffer");
      }
      for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.vertices[i][k];
      for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
      rtcCommitGeometry(geom);
      rtcAttachGeometry(scene_.get(), geom);
      rtcReleaseGeometry(geom);
      check(device_.get(), "geometry setup");
    }
    rtcCommitScene(scene_.get());
    check(device_.get(), "rtcCommitScene");
  }

  void scan_one(const Pose& world_from_sensor, Profile& out) const {
    const int n = desc_.points;
    if (!out.sized(n)) out.resize(n);
    out.world_from_sensor = world_from_sensor;

    const Eigen::Matrix3d r = world_from_sensor.linear();
    const Eigen::Vector3f o = world_from_sensor.translation().cast<float>();
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    // All rays of a profile share their origin and fan out in one plane.
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;

    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[kPacket];
    for (int base = 0; base < n; base += kPacket) {
      for (int k = 0; k < kPacket; ++k) {
        const int col = base + k;
        valid[k] = col < n ? -1 : 0;
        const Eigen::Vector3f d =
            col < n ? (r * dirs_d_[col]).cast<float>() : Eigen::Vector3f(0.0f, 0.0f, 1.0f);
        rh.ray.org_x[k] = o.x();
        rh.ray.org_y[k] = o.y();
        rh.ray.org_z[k] = o.z();
        rh.ray.tnear[k] = 0.0f;
        rh.ray.dir_x[k] = d.x();
        rh.ray.dir_y[k] = d.y();
        rh.ray.dir_z[k] = d.z();
        rh.ray.time[k] = 0.0f;
        rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
        rh.ray.mask[k] = 0xFFFFFFFFu;
        rh.ray.id[k] = static_cast<unsigned>(k);
        rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene_.get(), &context, &rh);
      const int count = std::min(kPacket, n - base);
      for (int k = 0; k < count; ++k) {
        const bool hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        const float t = hit ? rh.ray.tfar[k] : kNoHit;
        float cos_incidence = 0.0f;
        if (hit) {
          const Eigen::Vector3f ng(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]);
          const Eigen::Vector3f d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
          const float norm = ng.norm() * d.norm();
          cos_incidence = norm > 0.0f ? std::abs(ng.dot(d)) / norm : 0.0f;
        }
        set_column(desc_, dirs_[base + k], base + k, t, out, cos_incidence);
      }
    }
    check(device_.get(), "rtcIntersect16");
    if (!desc_.ideal) cast_shadow_rays(world_from_sensor, out);
  }

  // Camera shadow: a ray from each lit point towards the camera centre; the
  // point is hidden if anything lies between kShadowEpsilonMm from the point
  // and the camera.
  void cast_shadow_rays(const Pose& world_from_sensor, Profile& out) const {
    const int n = desc_.points;
    const Eigen::Vector3f c = (world_from_sensor * camera_centre_).cast<float>();
    const Eigen::Vector3f o = world_from_sensor.translation().cast<float>();
    const Eigen::Matrix3d r = world_from_sensor.linear();
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);

    alignas(64) RTCRay16 ray;
    alignas(64) int valid[kPacket];
    int columns[kPacket];
    int count = 0;
    auto flush = [&] {
      // Unused lanes get a harmless ray too: left as they were (stack
      // garbage, or an earlier packet's occluded ray with tfar = -inf), they
      // can fail Embree's own ray checks (asserted in Debian's build) even
      // though they are masked off.
      for (int k = count; k < kPacket; ++k) {
        valid[k] = 0;
        ray.org_x[k] = ray.org_y[k] = ray.org_z[k] = 0.0f;
        ray.dir_x[k] = ray.dir_y[k] = 0.0f;
        ray.dir_z[k] = 1.0f;
        ray.tnear[k] = ray.tfar[k] = ray.time[k] = 0.0f;
      }
      rtcOccluded16(valid, scene_.get(), &context, &ray);
      for (int k = 0; k < count; ++k)
        if (ray.tfar[k] < 0.0f) out.camera_visible[columns[k]] = 0;
      count = 0;
    };
    for (int i = 0; i < n; ++i) {
      if (!out.valid[i]) continue;
      // The lit point exactly as the hit was found: origin + t * direction.
      const Eigen::Vector3f d = (r * dirs_d_[i]).cast<float>();
      const Eigen::Vector3f p = o + out.range_mm[i] * d;
      const Eigen::Vector3f to_camera = c - p;
      const float length = to_camera.norm();
      if (!(length > kShadowEpsilonMm)) continue;
      const int k = count;
      valid[k] = -1;
      columns[k] = i;
      ray.org_x[k] = p.x();
      ray.org_y[k] = p.y();
      ray.org_z[k] = p.z();
      ray.dir_x[k] = to_camera.x() / length;
      ray.dir_y[k] = to_camera.y() / length;
      ray.dir_z[k] = to_camera.z() / length;
      ray.tnear[k] = static_cast<float>(kShadowEpsilonMm);
      ray.tfar[k] = length;
      ray.time[k] = 0.0f;
      ray.mask[k] = 0xFFFFFFFFu;
      ray.id[k] = static_cast<unsigned>(k);
      ray.flags[k] = 0;
      if (++count == kPacket) flush();
    }
    if (count > 0) flush();
    check(device_.get(), "rtcOccluded16");
  }

  ScannerDesc desc_;
  std::vector<Eigen::Vector3f> dirs_;  // sensor frame, unit, as cast
  std::vector<Eigen::Vector3d> dirs_d_;  // the same, widened for the rotation
  Eigen::Vector3d camera_centre_;        // sensor frame, mm
  DevicePtr device_;
  ScenePtr scene_;  // declared after device_: released first
};

}  // namespace

std::unique_ptr<ProfileSource> make_reference_source(const ScannerDesc& desc,
                                                     const Mesh& mesh_world, int threads) {
  if (const std::string why = validate(desc); !why.empty())
    throw std::invalid_argument("reference source: scanner " + why);
  return std::make_unique<ReferenceSource>(desc, mesh_world, threads);
}

}  // namespace vts
