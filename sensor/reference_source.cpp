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
#include "sensor/ray_scene.h"
#include "sensor/rays.h"

namespace vts {
namespace {

constexpr int kPacket = 16;
// Below this many profiles per thread a batch is scanned on the calling thread.
constexpr std::size_t kMinProfilesPerThread = 64;

class ReferenceSource final : public ProfileSource {
 public:
  ReferenceSource(const ScannerDesc& desc, const Mesh& mesh, const Mesh& moving, int threads)
      : threads_(static_cast<std::size_t>(threads > 0 ? std::min(threads, thread_limit()) : thread_limit())),
        desc_(desc), dirs_(column_directions(desc)), camera_centre_(camera_model(desc).centre_mm),
        scene_(mesh, moving, "reference source") {
    dirs_d_.reserve(dirs_.size());
    for (const auto& d : dirs_) dirs_d_.push_back(d.cast<double>());
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

  void move_part(const Pose& motion) override {
    scene_.move_part(motion);  // throws without a moving part
  }
  const ScannerDesc& scanner() const override { return desc_; }
  std::string_view kind() const override { return "reference"; }

 private:
  std::size_t threads_;  // most threads a batch is spread over

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
      rtcIntersect16(valid, scene_.scene(), &context, &rh);
      const int count = std::min(kPacket, n - base);
      for (int k = 0; k < count; ++k) {
        const bool hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        const float t = hit ? rh.ray.tfar[k] : kNoHit;
        float cos_incidence = 0.0f;
        if (hit) {
          const Eigen::Vector3f ng =
              scene_.world_normal(Eigen::Vector3f(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]), rh.hit.instID[0][k]);
          const Eigen::Vector3f d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
          const float norm = ng.norm() * d.norm();
          cos_incidence = norm > 0.0f ? std::abs(ng.dot(d)) / norm : 0.0f;
        }
        set_column(desc_, dirs_[base + k], base + k, t, out, cos_incidence);
      }
    }
    scene_.check("rtcIntersect16");
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
      rtcOccluded16(valid, scene_.scene(), &context, &ray);
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
    scene_.check("rtcOccluded16");
  }

  ScannerDesc desc_;
  std::vector<Eigen::Vector3f> dirs_;  // sensor frame, unit, as cast
  std::vector<Eigen::Vector3d> dirs_d_;  // the same, widened for the rotation
  Eigen::Vector3d camera_centre_;        // sensor frame, mm
  RayScene scene_;
};

}  // namespace

std::unique_ptr<ProfileSource> make_reference_source(const ScannerDesc& desc,
                                                     const Mesh& mesh_world, int threads, const Mesh* moving) {
  if (const std::string why = validate(desc); !why.empty())
    throw std::invalid_argument("reference source: scanner " + why);
  return std::make_unique<ReferenceSource>(desc, mesh_world, moving ? *moving : Mesh{}, threads);
}

}  // namespace vts
