#include "sensor/ray_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/parallel.h"

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

}  // namespace

namespace {

void check_indices(const Mesh& mesh, const char* who) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t v : mesh.triangles[t])
      if (v >= mesh.vertices.size())
        throw std::invalid_argument(std::string(who) + ": triangle " + std::to_string(t) +
                                    " uses vertex " + std::to_string(v) + " but the mesh has " +
                                    std::to_string(mesh.vertices.size()) + " vertices");
}

RTCScene new_scene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);
  check(device, "rtcNewScene");
  // ROBUST: without it rays lying exactly in the plane of a row of mesh
  // edges slip between the triangles (docs: shared/notes/stack.md).
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  check(device, "scene setup");
  return scene;
}

void attach_mesh(RTCDevice device, RTCScene scene, const Mesh& mesh) {
  // Embree rejects zero-sized buffers; an empty scene simply misses.
  if (mesh.vertices.empty() || mesh.triangles.empty()) return;
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  check(device, "rtcNewGeometry");
  rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.vertices.size()));
  auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), mesh.triangles.size()));
  if (!v || !idx) {
    rtcReleaseGeometry(geom);
    check(device, "rtcSetNewGeometryBuffer");
    throw std::runtime_error("Embree: rtcSetNewGeometryBuffer returned no buffer");
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.vertices[i][k];
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  check(device, "geometry setup");
}

}  // namespace

RayScene::RayScene(const Mesh& mesh, const char* who) : RayScene(mesh, Mesh{}, who) {}

RayScene::RayScene(const Mesh& fixed, const Mesh& moving, const char* who) {
  check_indices(fixed, who);
  check_indices(moving, who);

  // The thread limit (common/parallel.h) bounds Embree's own threads too.
  const std::string config = embree_device_config();
  device_.reset(rtcNewDevice(config.empty() ? nullptr : config.c_str()));
  if (!device_) vts::check(nullptr, "rtcNewDevice");
  rtcSetDeviceErrorFunction(device_.get(), on_embree_error, nullptr);

  scene_.reset(new_scene(device_.get()));
  attach_mesh(device_.get(), scene_.get(), fixed);
  if (!moving.triangles.empty()) {
    // The moving part: a scene of its own, instanced into the main one with
    // a transform that move_part() changes (Embree's order: the instanced
    // scene committed, then the instance, then the scene holding it).
    moving_.reset(new_scene(device_.get()));
    attach_mesh(device_.get(), moving_.get(), moving);
    rtcCommitScene(moving_.get());
    check("rtcCommitScene (moving part)");
    RTCGeometry inst = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_INSTANCE);
    check("rtcNewGeometry (instance)");
    rtcSetGeometryInstancedScene(inst, moving_.get());
    rtcSetGeometryTimeStepCount(inst, 1);
    rtcAttachGeometry(scene_.get(), inst);
    rtcReleaseGeometry(inst);  // the scene holds it
    instance_ = inst;
    move_part(Eigen::Isometry3d::Identity());  // commits the scene
    return;
  }
  rtcCommitScene(scene_.get());
  check("rtcCommitScene");
}

static_assert(RayScene::kNoInstance == RTC_INVALID_GEOMETRY_ID);

void RayScene::move_part(const Eigen::Isometry3d& motion) {
  if (!instance_) throw std::logic_error("RayScene::move_part: the scene has no moving part");
  const Eigen::Matrix<float, 3, 4> xfm = motion.matrix().topRows<3>().cast<float>();  // column-major
  rtcSetGeometryTransform(instance_, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm.data());
  rtcCommitGeometry(instance_);
  rtcCommitScene(scene_.get());
  check("move_part");
  moving_rotation_ = motion.linear().cast<float>();
}

RayScene::~RayScene() = default;

void RayScene::DeviceDeleter::operator()(RTCDeviceTy* d) const { rtcReleaseDevice(d); }
void RayScene::SceneDeleter::operator()(RTCSceneTy* s) const { rtcReleaseScene(s); }

void RayScene::check(const char* what) const { vts::check(device_.get(), what); }

bool RayScene::intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear, float tfar,
                         Hit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_.get(), &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  return to_hit(Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), rh.hit.instID[0], rh.ray.tfar, d, hit);
}

bool RayScene::to_hit(const Eigen::Vector3f& ng, unsigned inst_id, float t, const Eigen::Vector3f& d, Hit& hit) const {
  Eigen::Vector3f n = world_normal(ng, inst_id);
  const float norm = n.norm();
  if (!(norm > 0.0f)) return false;
  n /= norm;
  hit.t = t;
  hit.normal = n.dot(d) > 0.0f ? Eigen::Vector3f(-n) : n;
  return true;
}

bool RayScene::occluded(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear, float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  ray.org_x = o.x();
  ray.org_y = o.y();
  ray.org_z = o.z();
  ray.dir_x = d.x();
  ray.dir_y = d.y();
  ray.dir_z = d.z();
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.time = 0.0f;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(scene_.get(), &context, &ray);
  return ray.tfar < 0.0f;
}

namespace {

// Lanes 0 .. m - 1 (1 <= m <= 8) of an 8-ray packet from rays[0 .. m - 1];
// the other lanes are invalid (a copy of the last ray, not cast).
void set_lanes(const RayScene::Segment* rays, std::size_t m, int* valid, RTCRay8& ray) {
  for (std::size_t k = 0; k < 8; ++k) {
    const RayScene::Segment& r = rays[std::min(k, m - 1)];
    valid[k] = k < m ? -1 : 0;
    ray.org_x[k] = r.o.x();
    ray.org_y[k] = r.o.y();
    ray.org_z[k] = r.o.z();
    ray.dir_x[k] = r.d.x();
    ray.dir_y[k] = r.d.y();
    ray.dir_z[k] = r.d.z();
    ray.tnear[k] = r.tnear;
    ray.tfar[k] = r.tfar;
    ray.time[k] = 0.0f;
    ray.mask[k] = 0xFFFFFFFFu;
    ray.id[k] = 0;
    ray.flags[k] = 0;
  }
}

RTCRay8& ray_of(RTCRay8& p) { return p; }
RTCRay8& ray_of(RTCRayHit8& p) { return p.ray; }

// Casts rays[0 .. n - 1] as packets of 8 (Packet: RTCRay8 or RTCRayHit8):
// cast(valid, context, packet) then read(first, m, packet) for rays
// first .. first + m - 1.
template <class Packet, class Cast, class Read>
void in_packets(const RayScene::Segment* rays, std::size_t n, Cast cast, Read read) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t first = 0; first < n; first += 8) {
    const std::size_t m = std::min<std::size_t>(8, n - first);
    alignas(32) int valid[8];
    alignas(32) Packet packet;
    set_lanes(rays + first, m, valid, ray_of(packet));
    cast(valid, &context, packet);
    read(first, m, packet);
  }
}

}  // namespace

void RayScene::occluded(const Segment* rays, std::size_t n, unsigned char* blocked) const {
  in_packets<RTCRay8>(
      rays, n,
      [&](const int* valid, RTCIntersectContext* context, RTCRay8& ray) {
        rtcOccluded8(valid, scene_.get(), context, &ray);
      },
      [&](std::size_t first, std::size_t m, const RTCRay8& ray) {
        for (std::size_t k = 0; k < m; ++k) blocked[first + k] = ray.tfar[k] < 0.0f ? 1 : 0;
      });
}

void RayScene::intersect(const Segment* rays, std::size_t n, Hit* hits, unsigned char* found) const {
  in_packets<RTCRayHit8>(
      rays, n,
      [&](const int* valid, RTCIntersectContext* context, RTCRayHit8& rh) {
        for (int k = 0; k < 8; ++k) {
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, scene_.get(), context, &rh);
      },
      [&](std::size_t first, std::size_t m, const RTCRayHit8& rh) {
        for (std::size_t k = 0; k < m; ++k) {
          found[first + k] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID &&
                              to_hit(Eigen::Vector3f(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]),
                                     rh.hit.instID[0][k], rh.ray.tfar[k], rays[first + k].d, hits[first + k]);
        }
      });
}

}  // namespace vts
