#include "viewer/geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace vts::viewer {
namespace {

using V3 = Eigen::Vector3f;

std::uint32_t add(Mesh& m, const V3& v) {
  m.vertices.push_back(v);
  return static_cast<std::uint32_t>(m.vertices.size() - 1);
}

}  // namespace

Mesh cone_z(float r0, float r1, float z0, float z1, int segments) {
  Mesh m;
  const float two_pi = 2.0f * std::numbers::pi_v<float>;
  // Side vertices first (shared around the ring for smooth normals), then
  // separate cap vertices so the caps stay flat.
  for (int i = 0; i < segments; ++i) {
    const float a = two_pi * static_cast<float>(i) / static_cast<float>(segments);
    add(m, V3(r0 * std::cos(a), r0 * std::sin(a), z0));
    add(m, V3(r1 * std::cos(a), r1 * std::sin(a), z1));
  }
  const auto s = static_cast<std::uint32_t>(segments);
  for (std::uint32_t i = 0; i < s; ++i) {
    const std::uint32_t j = (i + 1) % s;
    const bool up = z1 > z0;  // keep outward winding whichever way the cone runs
    if (up) {
      m.triangles.push_back({2 * i, 2 * j, 2 * j + 1});
      m.triangles.push_back({2 * i, 2 * j + 1, 2 * i + 1});
    } else {
      m.triangles.push_back({2 * i, 2 * j + 1, 2 * j});
      m.triangles.push_back({2 * i, 2 * i + 1, 2 * j + 1});
    }
  }
  for (int cap = 0; cap < 2; ++cap) {
    const float z = cap ? z1 : z0, r = cap ? r1 : r0;
    if (r <= 0.0f) continue;
    const std::uint32_t centre = add(m, V3(0, 0, z));
    const std::uint32_t first = static_cast<std::uint32_t>(m.vertices.size());
    for (int i = 0; i < segments; ++i) {
      const float a = two_pi * static_cast<float>(i) / static_cast<float>(segments);
      add(m, V3(r * std::cos(a), r * std::sin(a), z));
    }
    const bool top = (cap == 1) == (z1 > z0);
    for (std::uint32_t i = 0; i < s; ++i) {
      const std::uint32_t a = first + i, b = first + (i + 1) % s;
      if (top)
        m.triangles.push_back({centre, a, b});
      else
        m.triangles.push_back({centre, b, a});
    }
  }
  return m;
}

Mesh box(const V3& lo, const V3& hi) {
  Mesh m;
  // Four vertices per face so each face keeps its own normal.
  const V3 c[8] = {{lo.x(), lo.y(), lo.z()}, {hi.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), lo.z()},
                   {lo.x(), hi.y(), lo.z()}, {lo.x(), lo.y(), hi.z()}, {hi.x(), lo.y(), hi.z()},
                   {hi.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), hi.z()}};
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  for (const auto& f : faces) {
    const std::uint32_t base = static_cast<std::uint32_t>(m.vertices.size());
    for (int k : f) m.vertices.push_back(c[k]);
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  }
  return m;
}

Mesh beam(const V3& a, const V3& b, float width) {
  const V3 d = b - a;
  const float length = d.norm();
  Mesh m = box(V3(-0.5f * width, -0.5f * width, 0.0f), V3(0.5f * width, 0.5f * width, length));
  const Eigen::Quaternionf q = Eigen::Quaternionf::FromTwoVectors(V3::UnitZ(), d / length);
  for (auto& v : m.vertices) v = q * v + a;
  return m;
}

Mesh torch_nozzle_mesh() {
  Mesh m = cone_z(0.6f, 0.6f, 0.0f, -15.0f, 12);        // wire stick-out
  m.append(cone_z(2.5f, 3.5f, -15.0f, -21.0f, 16));     // contact tip
  m.append(cone_z(8.0f, 11.0f, -19.0f, -70.0f, 40));    // gas nozzle
  return m;
}

Mesh torch_body_mesh() {
  Mesh m = cone_z(11.5f, 12.5f, -70.0f, -80.0f, 40);    // insulator ring
  m.append(cone_z(12.0f, 16.0f, -80.0f, -260.0f, 40));  // neck and body
  return m;
}

Mesh sensor_housing_mesh(const V3& camera) {
  const float bottom = std::max(-4.0f, camera.z() - 3.0f);
  const float x0 = std::min(-10.0f, camera.x() - 10.0f), x1 = std::max(10.0f, camera.x() + 10.0f);
  return box(V3(x0, -22.0f, -60.0f), V3(x1, 22.0f, bottom));
}

Mesh camera_body_mesh() {
  // Lens barrel behind the lens; the rest of the camera is in the housing.
  Mesh m = cone_z(6.0f, 5.0f, 0.0f, -14.0f, 24);
  return m;
}

}  // namespace vts::viewer
