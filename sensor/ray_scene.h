#pragma once
// One Embree 3 scene over a mesh (world frame, mm): robust mode (rays lying
// in the plane of a row of mesh edges do not slip between triangles), high
// build quality, Embree's threads bounded by the thread limit
// (common/parallel.h). The ray-cast reference (sensor/reference_source.h)
// casts its column and camera-shadow packets into it; the camera image
// (sensor/camera_image.h) casts its rays (primary, bounce, mirror, the
// stripe's checks) 8 at a time and single ones pixel by pixel at edges.
// Queries are thread-safe. The scene is immutable once built, except for an
// optional moving part (a second mesh, an instance of its own scene) whose
// rigid motion move_part() sets between queries, never during them: the
// sim cell's wall lifting off its plate under thermal distortion
// (sensor/sim_cell.h).
#include <cstddef>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sensor/mesh.h"

// Embree's handle types (RTCScene is RTCSceneTy*), so that this header does
// not need Embree's.
struct RTCDeviceTy;
struct RTCSceneTy;
struct RTCGeometryTy;

namespace vts {

class RayScene {
 public:
  // Throws std::invalid_argument naming `who` if a triangle indexes a vertex
  // that does not exist, std::runtime_error with Embree's message if Embree
  // fails. An empty mesh gives a scene every ray misses.
  RayScene(const Mesh& mesh_world, const char* who);
  // `fixed` as above plus `moving`, placed where move_part() last put it
  // (at first: as given).
  RayScene(const Mesh& fixed, const Mesh& moving, const char* who);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  RTCSceneTy* scene() const { return scene_.get(); }
  // Throws std::runtime_error "Embree: <what> failed: ..." if the device
  // reports an error since the last check.
  void check(const char* what) const;

  struct Hit {
    float t = 0.0f;             // distance along the (unit) direction
    Eigen::Vector3f normal;     // unit geometric normal, facing the ray's origin
  };
  // The nearest hit of the ray o + t d (d unit) with tnear <= t <= tfar.
  bool intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear, float tfar,
                 Hit& hit) const;
  // Whether anything lies on the ray between tnear and tfar.
  bool occluded(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear, float tfar) const;
  // The same for n rays (any n >= 0), cast 8 at a time (rtcOccluded8):
  // blocked[k] = 1 when ray k is occluded, else 0.
  struct Segment {
    Eigen::Vector3f o, d;
    float tnear = 0.0f, tfar = 0.0f;
  };
  void occluded(const Segment* rays, std::size_t n, unsigned char* blocked) const;
  // The nearest hits of n rays (the unit direction d of each), 8 at a time
  // (rtcIntersect8): found[k] = 1 and hits[k] as intersect gives it, or 0.
  void intersect(const Segment* rays, std::size_t n, Hit* hits, unsigned char* found) const;

  // Puts the moving part where the rigid `motion` (world) takes its mesh as
  // given. Not thread-safe against queries. Throws std::logic_error without
  // a moving part.
  void move_part(const Eigen::Isometry3d& motion);
  bool has_moving_part() const { return instance_ != nullptr; }
  // A hit's geometric normal in world: Embree reports the normal of a hit on
  // an instance (instID != RTC_INVALID_GEOMETRY_ID) in the instanced mesh's
  // own frame.
  Eigen::Vector3f world_normal(const Eigen::Vector3f& ng, unsigned inst_id) const {
    return inst_id == kNoInstance ? ng : Eigen::Vector3f(moving_rotation_ * ng);
  }
  static constexpr unsigned kNoInstance = ~0u;  // RTC_INVALID_GEOMETRY_ID

 private:
  // A hit from Embree's geometric normal (of instance inst_id's mesh) and
  // distance along d: the unit world normal facing the ray's origin; false
  // for a degenerate normal.
  bool to_hit(const Eigen::Vector3f& ng, unsigned inst_id, float t, const Eigen::Vector3f& d, Hit& hit) const;
  struct DeviceDeleter {
    void operator()(RTCDeviceTy* d) const;
  };
  struct SceneDeleter {
    void operator()(RTCSceneTy* s) const;
  };
  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device_;
  std::unique_ptr<RTCSceneTy, SceneDeleter> moving_;  // the moving part's own scene
  std::unique_ptr<RTCSceneTy, SceneDeleter> scene_;   // released first
  RTCGeometryTy* instance_ = nullptr;          // the moving part in scene_ (owned by it)
  Eigen::Matrix3f moving_rotation_ = Eigen::Matrix3f::Identity();
};

}  // namespace vts
