#include "render/raster_source.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/parallel.h"
#include "render/gl_context.h"
#include "render/gl_program.h"
#include "sensor/error_model.h"
#include "sensor/mesh_bvh.h"
#include "sensor/planar_merge.h"
#include "sensor/rays.h"
#include "sensor/simd_clones.h"
#include "shaders/embedded.h"

namespace vts {
namespace {

// Surfaces closer than this to the laser are clipped away. Far below any
// usable min_range_mm, so it only matters for occluders touching the laser.
constexpr double kNearClipMm = 1e-3;

// Culling keeps triangles within this of the laser plane (and of the fan's
// box): far above float rounding of mesh-centred coordinates, far below a
// triangle; a few extra triangles cost nothing, a missing one a hole.
constexpr double kCullMarginMm = 0.01;

// Profiles drawn in one pass (one draw), per worker.
constexpr int kMaxRowsPerPass = 256;
// Profiles with parallel laser planes culled by one hierarchy query.
constexpr int kCullBlock = 16;
// Most parts a batch is split into (each with its own OpenGL context).
constexpr int kMaxThreads = 16;
// Below this many profiles per worker a batch is not split further.
constexpr std::size_t kMinProfilesPerThread = 32;

// Collinear runs of slice segments are joined when every end point lies
// within this of the run's line.
constexpr double kCollinearMm = 1e-4;

// The camera-shadow test splits the lit points into runs whose sight lines
// lie within kShadowSheetMm of one plane (one spatial query per run), runs
// of kMinShadowRun to kMaxShadowRun points. A candidate triangle crossing
// more than kFloatFilterColumns sight lines' image columns is tested in
// float first (docs/PERFORMANCE.md).
constexpr double kShadowSheetMm = 0.5;
constexpr int kMinShadowRun = 16;
constexpr int kMaxShadowRun = 1024;
constexpr int kFloatFilterColumns = 8;

// The mesh as the workers use it: non-degenerate triangles only, in a frame
// centred on the mesh (so float keeps precision far from the world origin),
// with their planes and the hierarchy that finds them.
struct PreparedMesh {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  MeshBvh bvh;                 // over the kept triangles (corners in the centred frame)
  // (nx, ny, nz, w) per hierarchy entry (kept triangles in the hierarchy's
  // leaf order: neighbours in space are neighbours in memory), centred world
  // mm. Entries are what the workers pass around and draw. Entry e faces the
  // point p when p lies strictly on the outward side of its plane,
  // n . p > w (cut_triangles).
  std::vector<double> planes;
  // Every edge of the kept triangles is used once in each direction: the
  // mesh bounds solids with consistent winding, so a triangle that faces away
  // from the laser is always behind one that faces it (from outside).
  bool closed = false;
};

bool closed_and_oriented(const std::vector<std::uint32_t>& indices) {
  if (indices.empty()) return false;
  std::vector<std::uint64_t> edges;
  edges.reserve(indices.size());
  for (std::size_t t = 0; t < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k)
      edges.push_back(std::uint64_t(indices[t + k]) << 32 | indices[t + (k + 1) % 3]);
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i + 1 < edges.size() && edges[i + 1] == edges[i]) return false;  // used twice one way
    const std::uint64_t reverse = edges[i] << 32 | edges[i] >> 32;
    if (!std::binary_search(edges.begin(), edges.end(), reverse)) return false;  // open edge
  }
  return true;
}

PreparedMesh prepare(const Mesh& mesh, bool merge_planar) {
  PreparedMesh out;
  const std::size_t nv = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t v : mesh.triangles[t])
      if (v >= nv)
        throw std::invalid_argument("raster source: mesh triangle " + std::to_string(t) +
                                    " uses vertex " + std::to_string(v) + " but the mesh has " +
                                    std::to_string(nv) + " vertices");

  // Centre of the bounding box of the vertices in use.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& tri : mesh.triangles)
    for (std::uint32_t v : tri) {
      const Eigen::Vector3d p = mesh.vertices[v].cast<double>();
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  if ((lo.array() <= hi.array()).all()) out.centre_mm = 0.5 * (lo + hi);

  std::vector<float> positions(3 * nv);  // xyz per vertex, centred world mm
  for (std::size_t v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = mesh.vertices[v].cast<double>() - out.centre_mm;
    for (int k = 0; k < 3; ++k) positions[3 * v + k] = static_cast<float>(p[k]);
  }

  std::vector<std::uint32_t> indices;  // 3 per kept triangle
  indices.reserve(3 * mesh.triangles.size());
  auto corner = [&](std::uint32_t v) -> Eigen::Vector3d {
    if (v < nv) return mesh.vertices[v].cast<double>() - out.centre_mm;
    return Eigen::Vector3d(positions[3 * std::size_t(v)], positions[3 * std::size_t(v) + 1],
                           positions[3 * std::size_t(v) + 2]);  // a fan centre of the merge
  };
  auto cross_of = [&](std::uint32_t v0, std::uint32_t v1, std::uint32_t v2) {
    const Eigen::Vector3d a = corner(v0);
    return Eigen::Vector3d((corner(v1) - a).cross(corner(v2) - a));
  };
  for (const auto& tri : mesh.triangles) {
    const double norm = cross_of(tri[0], tri[1], tri[2]).norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) continue;  // zero area or non-finite
    indices.insert(indices.end(), tri.begin(), tri.end());
  }
  if (merge_planar) indices = merge_planar_regions(positions, indices, planar_merge_tolerance(positions));
  out.planes.reserve(4 * indices.size() / 3);
  for (std::size_t t = 0; t < indices.size(); t += 3) {
    const Eigen::Vector3d a = corner(indices[t]), b = corner(indices[t + 1]), c = corner(indices[t + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    const double w = n.dot((a + b + c) / 3.0);
    out.planes.insert(out.planes.end(), {n.x(), n.y(), n.z(), w});
  }
  out.closed = closed_and_oriented(indices);
  out.bvh = MeshBvh(positions, indices);
  std::vector<double> by_entry(out.planes.size());
  for (std::uint32_t e = 0; e < out.bvh.triangle_count(); ++e)
    std::copy_n(&out.planes[4 * std::size_t(out.bvh.triangle(e))], 4, &by_entry[4 * std::size_t(e)]);
  out.planes = std::move(by_entry);
  return out;
}

// What every worker reads, built once per source and never changed after.
struct SharedScene {
  ScannerDesc desc;
  std::vector<Eigen::Vector3f> directions;  // sensor frame, unit, per column
  std::vector<Eigen::Vector3d> directions_d;
  std::vector<double> dir_x, dir_y, dir_z;  // directions_d by component
  PreparedMesh mesh;
  double tan_half_fan = 0.0;
  // How far out in NDC x (y/z over tan_half_fan) a triangle may reach and
  // still be cut (the hierarchy query's fan sides): the target's columns and
  // a pixel either side. emit() draws segments cut to NDC x in [-1, 1].
  double ndc_limit = 1.0;
  Eigen::Vector3d camera_mm = Eigen::Vector3d::Zero();  // camera centre, sensor frame
};

// One vertex of the per-pass stream: a triangle corner, and the row (profile
// of the pass) and the hierarchy entry of the triangle it is drawn for.
struct StreamVertex {
  float x, y, z;
  std::uint32_t row, entry;
};
static_assert(sizeof(StreamVertex) == 20);

// The float filter of the camera-shadow test (ShadowTester below): which
// sight lines j in [j0, j1) may cross the triangle given by its
// Moeller-Trumbore vectors k = (A, B, Q, tq), with a little slack so that
// it misses nothing the exact test would find. Branch-free, so the loop
// vectorizes (cloned for AVX2 and AVX-512 with GCC on x86-64; no FMA
// contraction in this file, so every clone gives the same answer).
VTS_SIMD_CLONES
int float_filter(const float* __restrict dx, const float* __restrict dy, const float* __restrict dz,
                 const float* __restrict tmax, int j0, int j1, std::array<float, 10> k,
                 int* __restrict maybe) {
  // Slack on the barycentric tests, and on t (a point's own face has t = 1,
  // which must stay out: 1 > tmax + kSlackT while |D| < 1 m).
  constexpr float kSlack = 1e-3f, kSlackT = 1e-5f;
  const float ax = k[0], ay = k[1], az = k[2], bx = k[3], by = k[4], bz = k[5];
  const float qx = k[6], qy = k[7], qz = k[8], tqf = k[9];
  int any = 0;
  for (int j = j0; j < j1; ++j) {
    const float det = dx[j] * ax + dy[j] * ay + dz[j] * az;
    const float sign = det < 0.0f ? -1.0f : 1.0f;
    const float adet = det * sign;
    const float slack = kSlack * adet;
    const float un = (dx[j] * bx + dy[j] * by + dz[j] * bz) * sign;
    const float vn = (dx[j] * qx + dy[j] * qy + dz[j] * qz) * sign;
    const float tn = tqf * sign;
    const int hit = int(adet > 0.0f) & int(un >= -slack) & int(vn >= -slack) &
                    int(un + vn <= adet + slack) & int(tn > -slack) & int(tn < adet * (tmax[j] + kSlackT));
    maybe[j] = hit;
    any |= hit;
  }
  return any;
}

// The exact camera-shadow test (ShadowTester::crosses) of the sight lines
// j in [j0, j1) against one triangle, OR-ed into hidden[j]: four sight
// lines at a time in vectors of four doubles (cloned like float_filter; the
// arrays hold three more entries past the last), with the dot products
// summed in the order Eigen's take them ((x + y) + z), so every answer is
// crosses()'s, bit for bit.
using Double4 = double __attribute__((vector_size(32)));
using Long4 = std::int64_t __attribute__((vector_size(32)));
VTS_SIMD_CLONES
void exact_crosses(int j0, int j1, const double* __restrict dx, const double* __restrict dy,
                   const double* __restrict dz, const double* __restrict tmax, const std::array<double, 10> k,
                   int* __restrict hidden) {
  const double ax = k[0], ay = k[1], az = k[2], bx = k[3], by = k[4], bz = k[5];
  const double qx = k[6], qy = k[7], qz = k[8], tq = k[9];
  // (Filled through a reference: GCC warns that returning them by value
  // changes with AVX.)
  auto load = [](const double* p, Double4& v) { std::memcpy(&v, p, sizeof v); };
  const Double4 one = Double4{} + 1.0, zero = Double4{};
  for (int j = j0; j < j1; j += 4) {
    Double4 x, y, z, tm;
    load(dx + j, x);
    load(dy + j, y);
    load(dz + j, z);
    load(tmax + j, tm);
    const Double4 sdet = (x * ax + y * ay) + z * az;
    const Long4 neg = sdet < zero;
    const Double4 sign = reinterpret_cast<Double4>((neg & reinterpret_cast<Long4>(-one)) |
                                                   (~neg & reinterpret_cast<Long4>(one)));
    const Double4 det = sdet * sign;
    const Double4 un = ((x * bx + y * by) + z * bz) * sign;
    const Double4 vn = ((x * qx + y * qy) + z * qz) * sign;
    const Double4 tn = tq * sign;
    const Long4 hit = (det > zero) & (un >= zero) & (vn >= zero) & (un + vn <= det) & (tn > zero) & (tn < det * tm);
    const int lanes = std::min(4, j1 - j);
    for (int l = 0; l < lanes; ++l) hidden[j + l] |= int(hit[l] & 1);
  }
}

// Cutting a triangle with a profile's laser plane x = 0 (sensor frame):
// Worker::pass cuts a profile's triangles in batches with cut_triangles and
// hands those with a corner exactly on the plane to Worker::slice. Both take
// the corners to the sensor frame with to_sensor and compute an edge's
// crossing with edge_crossing from its lexicographically smaller corner
// (lex_less), so the two triangles on an edge produce bit-identical end
// points and the slice stays watertight.
struct CutFrame {
  double r[9];  // sensor from mesh-centred world, row-major
  double o[3];  // laser origin, mesh-centred world
  bool closed;  // faces turned away from the laser are hidden (PreparedMesh::closed)
};

// p_s = R^T (c - o) in double, for a corner c as the hierarchy keeps it (the
// order of the operations is the one Eigen's product took here before).
inline void to_sensor(const CutFrame& f, float cx, float cy, float cz, double& x, double& y, double& z) {
  const double d0 = double(cx) - f.o[0], d1 = double(cy) - f.o[1], d2 = double(cz) - f.o[2];
  x = (f.r[0] * d0 + f.r[1] * d1) + f.r[2] * d2;
  y = (f.r[3] * d0 + f.r[4] * d1) + f.r[5] * d2;
  z = (f.r[7] * d1 + f.r[8] * d2) + f.r[6] * d0;
}

// Whether corner b comes before corner a, coordinates compared in turn.
inline bool lex_less(const float* b, const float* a) {
  return (b[0] < a[0]) | ((b[0] == a[0]) & ((b[1] < a[1]) | ((b[1] == a[1]) & (b[2] < a[2]))));
}

// Where the edge from a (its smaller corner) to b meets x = 0.
inline void edge_crossing(double xa, double ya, double za, double xb, double yb, double zb, double& y, double& z) {
  const double t = xa / (xa - xb);
  y = ya + t * (yb - ya);
  z = za + t * (zb - za);
}

// One profile's triangles in one branch-free loop that vectorizes (cloned
// like float_filter): corner k's coordinate q of triangle j at c[3 k + q][j],
// its plane's (nx, ny, nz, w) at plane[q][j] (PreparedMesh::planes). The cut
// runs through the two edges of the corner alone on its side. kind[j]: 0 no
// cut (turned away on a closed mesh, all on one side, or end points that are
// no finite numbers), 1 a cut from
// (y0, z0) to (y1, z1), 2 a corner lies on the plane (for Worker::slice).
constexpr int kCutBatch = 64;
struct CutBatch {
  alignas(64) float c[9][kCutBatch];
  alignas(64) double plane[4][kCutBatch];
  alignas(64) double y0[kCutBatch], z0[kCutBatch], y1[kCutBatch], z1[kCutBatch];
  alignas(64) int kind[kCutBatch];
};
VTS_SIMD_CLONES
void cut_triangles(int count, const CutFrame frame, CutBatch& __restrict b) {
  const CutFrame f = frame;  // a local: the loop then loads only the batch's arrays, and vectorizes
  for (int j = 0; j < count; ++j) {
    const bool faces = (b.plane[0][j] * f.o[0] + b.plane[1][j] * f.o[1]) + b.plane[2][j] * f.o[2] > b.plane[3][j];
    float c[9];
    for (int q = 0; q < 9; ++q) c[q] = b.c[q][j];
    double x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k) to_sensor(f, c[3 * k], c[3 * k + 1], c[3 * k + 2], x[k], y[k], z[k]);
    // Edge k runs from corner k to k + 1; its crossing (meaningless where
    // it does not cross).
    double ey[3], ez[3];
    for (int k = 0; k < 3; ++k) {
      const int a = k, e = (k + 1) % 3;
      const bool swap = lex_less(c + 3 * e, c + 3 * a);
      edge_crossing(swap ? x[e] : x[a], swap ? y[e] : y[a], swap ? z[e] : z[a], swap ? x[a] : x[e],
                    swap ? y[a] : y[e], swap ? z[a] : z[e], ey[k], ez[k]);
    }
    // The corner alone on its side and its two edges, in edge order (as
    // slice() finds them): corner 0: edges 0, 2; 1: edges 0, 1; 2: edges 1, 2.
    const bool n0 = x[0] < 0.0, n1 = x[1] < 0.0, n2 = x[2] < 0.0;
    const bool on = (x[0] == 0.0) | (x[1] == 0.0) | (x[2] == 0.0);
    const bool lone1 = n1 != n0 && n1 != n2, lone2 = n2 != n0 && n2 != n1;
    b.y0[j] = lone2 ? ey[1] : ey[0];
    b.z0[j] = lone2 ? ez[1] : ez[0];
    b.y1[j] = lone1 ? ey[1] : ey[2];
    b.z1[j] = lone1 ? ez[1] : ez[2];
    // A corner that did not reach the frame as a number (a float overflow
    // far from the part) cuts nothing: its crossings are no numbers either.
    const bool finite = (b.y0[j] - b.y0[j] == 0.0) & (b.z0[j] - b.z0[j] == 0.0) & (b.y1[j] - b.y1[j] == 0.0) &
                        (b.z1[j] - b.z1[j] == 0.0);
    const int cuts = ((n0 != n1) | (n1 != n2)) & finite;
    b.kind[j] = (faces | !f.closed) * (on ? 2 : cuts);
  }
}

// The per-candidate set-up of the camera-shadow test (ShadowTester below)
// for a batch of candidate triangles, in one branch-free loop that
// vectorizes (cloned like float_filter), with the operations in the order
// Eigen's dot and cross products take them (so the same bits as before):
// corner k's coordinate q of candidate j at c[3 k + q][j]; out: whether all
// corners lie in front of the camera C (2), all behind (0) or neither (1);
// the corners' image columns y'/z' (meaningful when all are in front);
// Moeller-Trumbore's A = e2 x e1, B = e2 x T, Q = T x e1 (T = C - a) and
// tq = e2 . Q in the world frame.
constexpr int kShadowBatch = 64;
struct ShadowBatch {
  alignas(64) float c[9][kShadowBatch];
  alignas(64) int front[kShadowBatch];
  alignas(64) double lo[kShadowBatch], hi[kShadowBatch];
  alignas(64) double mt[10][kShadowBatch];  // A, B, Q (x, y, z each), tq
};
struct ShadowFrame {
  double c[3], za[3], ya[3];  // camera centre, its z' and y', mesh-centred world
};
VTS_SIMD_CLONES
void shadow_setup(int count, const ShadowFrame frame, ShadowBatch& __restrict b) {
  const ShadowFrame f = frame;  // a local: the loop then loads only the batch's arrays, and vectorizes
  auto dot = [](double x0, double x1, double x2, const double* y) { return (x0 * y[0] + x1 * y[1]) + x2 * y[2]; };
  for (int j = 0; j < count; ++j) {
    double p[3][3], v[3][3], z[3], col[3];
    for (int k = 0; k < 3; ++k) {
      for (int q = 0; q < 3; ++q) {
        p[k][q] = b.c[3 * k + q][j];
        v[k][q] = p[k][q] - f.c[q];
      }
      z[k] = dot(v[k][0], v[k][1], v[k][2], f.za);
      col[k] = dot(v[k][0], v[k][1], v[k][2], f.ya) / z[k];
    }
    const bool all_front = (z[0] > 0.0) & (z[1] > 0.0) & (z[2] > 0.0);
    const bool all_behind = (z[0] <= 0.0) & (z[1] <= 0.0) & (z[2] <= 0.0);
    b.front[j] = all_front ? 2 : all_behind ? 0 : 1;
    const double lo = col[1] < col[0] ? col[1] : col[0], hi = col[0] < col[1] ? col[1] : col[0];
    b.lo[j] = col[2] < lo ? col[2] : lo;
    b.hi[j] = hi < col[2] ? col[2] : hi;
    double e1[3], e2[3], t[3];
    for (int q = 0; q < 3; ++q) {
      e1[q] = p[1][q] - p[0][q];
      e2[q] = p[2][q] - p[0][q];
      t[q] = f.c[q] - p[0][q];
    }
    auto cross = [&](const double* x, const double* y, int m) {
      b.mt[m][j] = x[1] * y[2] - x[2] * y[1];
      b.mt[m + 1][j] = x[2] * y[0] - x[0] * y[2];
      b.mt[m + 2][j] = x[0] * y[1] - x[1] * y[0];
    };
    cross(e2, e1, 0);
    cross(e2, t, 3);
    cross(t, e1, 6);
    b.mt[9][j] = (e2[0] * b.mt[6][j] + e2[1] * b.mt[7][j]) + e2[2] * b.mt[8][j];
  }
}

// The sight lines of every column of a profile (ShadowTester below), in
// one branch-free loop that vectorizes (cloned like float_filter): D = P - C
// in the sensor frame with P = range * direction, its depth z' = D . za and
// image coordinates x'/z' (q) and y'/z' (image_col) as seen from C, D in the
// world frame (R D), and tmax = 1 - eps / |D|. Meaningless for unlit columns.
struct SightFrame {
  double cx, cy, cz, xax, xay, xaz, zax, zay, zaz;
  double r[9];  // row-major
};
VTS_SIMD_CLONES
void sight_lines(int n, const float* __restrict range, const double* __restrict dir_x,
                 const double* __restrict dir_y, const double* __restrict dir_z, const SightFrame f,
                 double* __restrict zc, double* __restrict q, double* __restrict image_col,
                 double* __restrict wx, double* __restrict wy, double* __restrict wz,
                 double* __restrict tmax) {
  for (int i = 0; i < n; ++i) {
    const double rg = range[i];
    const double x = rg * dir_x[i] - f.cx, y = rg * dir_y[i] - f.cy, z = rg * dir_z[i] - f.cz;
    const double depth = x * f.zax + y * f.zay + z * f.zaz;
    zc[i] = depth;
    q[i] = (x * f.xax + y * f.xay + z * f.xaz) / depth;
    image_col[i] = y / depth;
    wx[i] = f.r[0] * x + f.r[1] * y + f.r[2] * z;
    wy[i] = f.r[3] * x + f.r[4] * y + f.r[5] * z;
    wz[i] = f.r[6] * x + f.r[7] * y + f.r[8] * z;
    tmax[i] = 1.0 - kShadowEpsilonMm / std::sqrt(x * x + y * y + z * z);
  }
}

// The camera-shadow test of one profile, on the CPU. Sight lines run from
// the camera centre C to the lit points; the lit points are split into runs
// whose sight lines lie close to one plane (a Douglas-Peucker split of the
// sheet of sight lines: a straight run of points gives a thin sheet), one
// spatial query per run finds the triangles near its sheet, and each
// candidate is intersected with the sight lines it can cross: those whose
// image column (seen from C) lies within the candidate's, found by search
// since image columns grow with profile columns. Regions are set up
// in the sensor frame, the tests run in the mesh-centred world frame where
// the hierarchy keeps the corners. No allocation once the scratch has grown.
class ShadowTester {
 public:
  explicit ShadowTester(const SharedScene& scene) : s_(scene) {
    const Eigen::Vector3d c = s_.camera_mm;
    xa_ = c.normalized();
    za_ = xa_.cross(Eigen::Vector3d::UnitY());
    const std::size_t n = static_cast<std::size_t>(s_.desc.points);
    column_.resize(n);
    dx_.resize(n);
    dy_.resize(n);
    dz_.resize(n);
    tmax_.resize(n);
    hidden_.resize(n);
    maybe_.resize(n);
    dxd_.resize(n + 3);  // exact_crosses reads up to three past the last
    dyd_.resize(n + 3);
    dzd_.resize(n + 3);
    tmax_d_.resize(n + 3);
    image_col_.resize(n);
    for (auto* v : {&all_zc_, &all_q_, &all_image_col_, &all_wx_, &all_wy_, &all_wz_, &all_tmax_}) v->resize(n);
    lit_before_.resize(n);
    cos_theta_ = za_.z();
  }

  // Clears out.camera_visible where a triangle hides the lit point from the
  // camera farther than kShadowEpsilonMm from the point.
  void apply(const Eigen::Matrix3d& r, const Eigen::Vector3d& origin_c, Profile& out) {
    const int n = s_.desc.points;
    const Eigen::Vector3d c = s_.camera_mm;
    camera_w_ = r * c + origin_c;  // mesh-centred world
    za_w_ = r * za_;
    ya_w_ = r.col(1);
    // Sight lines D = P - C of the lit points in front of the camera, in
    // column order, with their image coordinates as seen from C: column
    // y'/z' and row x'/z' (constant along a sight line).
    SightFrame frame{c.x(), c.y(), c.z(), xa_.x(), xa_.y(), xa_.z(), za_.x(), za_.y(), za_.z(), {}};
    for (int k = 0; k < 9; ++k) frame.r[k] = r(k / 3, k % 3);
    sight_lines(n, out.range_mm.data(), s_.dir_x.data(), s_.dir_y.data(), s_.dir_z.data(), frame,
                all_zc_.data(), all_q_.data(), all_image_col_.data(), all_wx_.data(), all_wy_.data(),
                all_wz_.data(), all_tmax_.data());
    // The lit points in front of the camera (the others have no sight line
    // to test), in column order.
    int m = 0;
    for (int i = 0; i < n; ++i) {
      lit_before_[i] = m;
      if (!out.valid[i] || !(all_zc_[i] > 0.0)) continue;
      column_[m] = i;
      image_col_[m] = all_image_col_[i];
      // The candidates are tested in the mesh-centred world frame, where
      // the hierarchy keeps their corners: no transform per candidate.
      dxd_[m] = all_wx_[i];
      dyd_[m] = all_wy_[i];
      dzd_[m] = all_wz_[i];
      dx_[m] = static_cast<float>(all_wx_[i]);
      dy_[m] = static_cast<float>(all_wy_[i]);
      dz_[m] = static_cast<float>(all_wz_[i]);
      // Occluders must cross the sight line before 1 - eps/|D| of the way.
      tmax_d_[m] = all_tmax_[i];
      tmax_[m] = static_cast<float>(all_tmax_[i]);
      hidden_[m] = 0;
      ++m;
    }
    if (m == 0) return;

    // Runs [a, b], split at the point farthest from the sheet through C and
    // the run's end points while that is farther than kShadowSheetMm (and
    // the run is longer than kMinShadowRun), and at most kMaxShadowRun long.
    int top = 0;
    runs_[top++] = {0, m - 1};
    while (top > 0) {
      const auto [a, b] = runs_[--top];
      Eigen::Vector3d sheet = Eigen::Vector3d::Zero();
      double dev = 0.0;
      int far = a;
      if (b > a) {
        sheet = d(b).cross(d(a));
        const double len = sheet.norm();
        if (len > 0.0) {
          sheet /= len;
          for (int j = a; j <= b; ++j) {
            const double e = std::abs(sheet.dot(d(j)));
            if (e > dev) {
              dev = e;
              far = j;
            }
          }
        } else {
          dev = std::numeric_limits<double>::infinity();  // D_a, D_b parallel: no sheet plane
          far = (a + b) / 2;
        }
      }
      const int count = b - a + 1;
      if (top + 2 <= static_cast<int>(runs_.size()) &&
          (count > kMaxShadowRun || (dev > kShadowSheetMm && count > kMinShadowRun))) {
        const int split = count > kMaxShadowRun || far <= a || far >= b ? a + count / 2 : far;
        runs_[top++] = {split, b};
        runs_[top++] = {a, split - 1};
        continue;
      }
      test_run(a, b, sheet, dev, r, origin_c);
    }
    for (int j = 0; j < m; ++j)
      if (hidden_[j]) out.camera_visible[column_[j]] = 0;
  }

 private:
  void test_run(int a, int b, const Eigen::Vector3d& sheet, double dev, const Eigen::Matrix3d& r,
                const Eigen::Vector3d& origin_c) {
    const Eigen::Vector3d c = s_.camera_mm;
    double q_lo = std::numeric_limits<double>::infinity(), q_hi = -q_lo, zc_max = 0.0;
    for (int j = a; j <= b; ++j) {
      const int i = column_[j];
      q_lo = std::min(q_lo, all_q_[i]);
      q_hi = std::max(q_hi, all_q_[i]);
      zc_max = std::max(zc_max, all_zc_[i]);
    }
    // The region holding every sight line of the run (sensor frame, kept
    // where n.p + w >= 0): between the epipolar planes of its first and last
    // columns (planes through the camera centre and the laser origin),
    // between the camera's directions to the extreme points (x'/z' = q), in
    // front of the camera and no deeper than the deepest point. Each plane
    // is moved kCullMarginMm outwards.
    int np = 0;
    auto add = [&](const Eigen::Vector3d& normal, double w) {
      const double len = normal.norm();
      if (!(len > 0.0)) return;
      planes_s_[np++] = Eigen::Vector4d(normal.x(), normal.y(), normal.z(), w + kCullMarginMm * len);
    };
    const Eigen::Vector3d& d0 = s_.directions_d[column_[a]];
    const Eigen::Vector3d& d1 = s_.directions_d[column_[b]];
    Eigen::Vector3d e0 = c.cross(d0), e1 = c.cross(d1);
    if (e0.dot(d1) < 0.0) e0 = -e0;
    if (e1.dot(d0) < 0.0) e1 = -e1;
    add(e0, 0.0);  // both planes pass through the laser origin
    add(e1, 0.0);
    const Eigen::Vector3d lo_n = xa_ - q_lo * za_, hi_n = q_hi * za_ - xa_;
    add(lo_n, -lo_n.dot(c));
    add(hi_n, -hi_n.dot(c));
    add(za_, -za_.dot(c));
    add(-za_, za_.dot(c) + zc_max);
    // Into the mesh-centred world frame: p_s = R^T (p_c - o_c).
    for (int k = 0; k < np; ++k) {
      const Eigen::Vector3d nw = r * planes_s_[k].head<3>();
      planes_w_[k] = Eigen::Vector4d(nw.x(), nw.y(), nw.z(), planes_s_[k][3] - nw.dot(origin_c));
    }
    // And around the sheet of sight lines (world frame already), thickened
    // by the farthest point's distance from it (a point at s along a sight
    // line is s times as far).
    if (b > a && std::isfinite(dev) && sheet.squaredNorm() > 0.0) {
      const double w = -sheet.dot(camera_w_) + dev + kCullMarginMm;
      planes_w_[np++] = Eigen::Vector4d(sheet.x(), sheet.y(), sheet.z(), w);
      planes_w_[np++] = Eigen::Vector4d(-sheet.x(), -sheet.y(), -sheet.z(),
                                        sheet.dot(camera_w_) + dev + kCullMarginMm);
    }
    candidates_.clear();
    // A sight line from outside into a closed solid crosses a face turned
    // towards the camera before any turned away: on a closed mesh the
    // hierarchy leaves out the faces turned away from the camera (all but
    // those within its rounding margin of facing it, which are tested like
    // the rest: a redundant test, never a wrong one).
    const MeshBvh::Box3 camera{camera_w_, camera_w_};
    s_.mesh.bvh.inside_planes(std::span(planes_w_.data(), static_cast<std::size_t>(np)), candidates_,
                              s_.mesh.closed ? &camera : nullptr);

    // Moeller-Trumbore with the common origin C: per triangle the vectors
    // A = e2 x e1, B = e2 x T, Q = T x e1 (T = C - a) and tq = e2 . Q; per
    // sight line D: det = D.A, u = D.B / det, v = D.Q / det, t = tq / det.
    // Set up in batches (shadow_setup), the corners gathered first.
    const ShadowFrame frame{{camera_w_.x(), camera_w_.y(), camera_w_.z()},
                            {za_w_.x(), za_w_.y(), za_w_.z()},
                            {ya_w_.x(), ya_w_.y(), ya_w_.z()}};
    for (std::size_t first = 0; first < candidates_.size(); first += kShadowBatch) {
      const int count = static_cast<int>(std::min<std::size_t>(kShadowBatch, candidates_.size() - first));
      for (int i = 0; i < count; ++i) {
        const std::array<float, 9>& k = s_.mesh.bvh.corners(candidates_[first + i]);
        for (int q = 0; q < 9; ++q) batch_.c[q][i] = k[q];
      }
      shadow_setup(count, frame, batch_);
      for (int i = 0; i < count; ++i) test_candidate(i, a, b);
    }
  }

  // Candidate i of batch_ against the run [a, b]'s sight lines.
  void test_candidate(int i, int a, int b) {
    // The sight lines that can cross the triangle: a crossing point lies
    // in front of C, on the sight line's image column, and inside the
    // triangle, whose image (when all of it is in front) spans the
    // corners' image columns.
    if (batch_.front[i] == 0) return;  // all behind the camera
    int j0 = a, j1 = b + 1;
    if (batch_.front[i] == 2) {
      const double lo = batch_.lo[i], hi = batch_.hi[i];
      const double slack = 1e-9 * (1.0 + std::max(std::abs(lo), std::abs(hi)));
      j0 = first_image_col(lo - slack, a, b + 1, false);
      j1 = first_image_col(hi + slack, j0, b + 1, true);
      if (j0 >= j1) return;
    }
    const Eigen::Vector3d av(batch_.mt[0][i], batch_.mt[1][i], batch_.mt[2][i]);
    const Eigen::Vector3d bv(batch_.mt[3][i], batch_.mt[4][i], batch_.mt[5][i]);
    const Eigen::Vector3d qv(batch_.mt[6][i], batch_.mt[7][i], batch_.mt[8][i]);
    const double tq = batch_.mt[9][i];
    if (j1 - j0 > kFloatFilterColumns) {
      // Many sight lines: first in float, branch-free so the compiler
      // vectorizes it, with a little slack so it misses nothing; then
      // every candidate hit again in double. Float alone is not enough: a
      // face the camera sees almost edge-on puts the crossing with the
      // point's own face a few hundredths of a millimetre off the point.
      const float ax = float(av.x()), ay = float(av.y()), az = float(av.z());
      const float bx = float(bv.x()), by = float(bv.y()), bz = float(bv.z());
      const float qx = float(qv.x()), qy = float(qv.y()), qz = float(qv.z()), tqf = float(tq);
      const int any = float_filter(dx_.data(), dy_.data(), dz_.data(), tmax_.data(), j0, j1,
                                   {ax, ay, az, bx, by, bz, qx, qy, qz, tqf}, maybe_.data());
      if (!any) return;
      for (int j = j0; j < j1; ++j)
        if (maybe_[j] && !hidden_[j]) hidden_[j] = crosses(d(j), av, bv, qv, tq, tmax_d_[j]);
    } else if (j1 - j0 <= 2) {
      // One or two: the call would cost more than the tests.
      for (int j = j0; j < j1; ++j)
        if (!hidden_[j]) hidden_[j] = crosses(d(j), av, bv, qv, tq, tmax_d_[j]);
    } else {
      exact_crosses(j0, j1, dxd_.data(), dyd_.data(), dzd_.data(), tmax_d_.data(),
                    {av.x(), av.y(), av.z(), bv.x(), bv.y(), bv.z(), qv.x(), qv.y(), qv.z(), tq}, hidden_.data());
    }
  }

  // The exact test (double) of one sight line against one triangle.
  // The first j in [begin, end) with image_col_[j] >= v (or > v when
  // `above`): std::lower_bound (upper_bound) on the growing image columns,
  // started from the lit point of the profile column whose image column v
  // is (y'/z' = t / cos(theta) on the laser plane) and stepped from there.
  int first_image_col(double v, int begin, int end, bool above) const {
    const int n = s_.desc.points;
    const double column = (v * cos_theta_ / s_.tan_half_fan + 1.0) * 0.5 * n - 0.5;
    int j = !(column > 0.0) ? begin : column >= n ? end : lit_before_[static_cast<int>(column)];
    j = std::clamp(j, begin, end);
    auto before = [&](int k) { return above ? image_col_[k] <= v : image_col_[k] < v; };
    while (j > begin && !before(j - 1)) --j;
    while (j < end && before(j)) ++j;
    return j;
  }

  // Branch-free (the outcome is unpredictable).
  static int crosses(const Eigen::Vector3d& d, const Eigen::Vector3d& av, const Eigen::Vector3d& bv,
                     const Eigen::Vector3d& qv, double tq, double tmax) {
    const double sdet = d.dot(av);
    const double sign = sdet < 0.0 ? -1.0 : 1.0;
    const double det = sdet * sign, un = d.dot(bv) * sign, vn = d.dot(qv) * sign, tn = tq * sign;
    return int(det > 0.0) & int(un >= 0.0) & int(vn >= 0.0) & int(un + vn <= det) & int(tn > 0.0) &
           int(tn < det * tmax);
  }

  const SharedScene& s_;
  Eigen::Vector3d xa_, za_;  // camera x' (along the baseline) and z', sensor frame
  Eigen::Vector3d camera_w_, za_w_, ya_w_;  // camera centre, z' and y' in the world frame
  // Per lit point in front of the camera, in column order.
  std::vector<int> column_;
  std::vector<float> dx_, dy_, dz_, tmax_;  // sight line and tmax, float
  std::vector<int> hidden_, maybe_;
  std::vector<double> tmax_d_;      // tmax_ in double
  std::vector<double> dxd_, dyd_, dzd_;  // sight lines, world frame, double, by coordinate
  Eigen::Vector3d d(int j) const { return Eigen::Vector3d(dxd_[j], dyd_[j], dzd_[j]); }
  std::vector<double> image_col_;   // y'/z': grows with the column
  std::vector<int> lit_before_;  // per column: lit points in front of the camera before it
  double cos_theta_ = 1.0;        // z' . z: image column y'/z' = t / cos_theta on the laser plane
  // sight_lines' output, per column.
  std::vector<double> all_zc_, all_q_, all_image_col_, all_wx_, all_wy_, all_wz_, all_tmax_;
  std::array<std::pair<int, int>, 128> runs_{};
  std::array<Eigen::Vector4d, 8> planes_s_{}, planes_w_{};
  std::vector<std::uint32_t> candidates_;
  ShadowBatch batch_;  // shadow_setup's input and output
};

// One OpenGL context with its pipeline and scratch, used by one thread at a
// time. A pass scans up to rows() profiles with one draw.
class Worker {
 public:
  Worker(const SharedScene& scene, int max_rows)
      : s_(scene), context_(GlContext::After::Previous), shadow_(scene) {
    const GlContext::Binding bind(context_);
    const int n = s_.desc.points;
    GLint max_rb = 0, max_vp[2] = {0, 0};
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_vp);
    if (n > std::min(max_rb, max_vp[0]))
      throw std::runtime_error("raster source: " + std::to_string(n) +
                               " points exceed this OpenGL's largest target (" +
                               std::to_string(std::min(max_rb, max_vp[0])) + ")");
    rows_ = std::clamp(max_rows, 1, std::min(max_rb, max_vp[1]));
    const std::size_t slots = static_cast<std::size_t>(rows_) * n;
    readback_.resize(slots);

    program_ = link_program("raster source", shaders::raster_vert, "raster.vert", shaders::raster_frag, "raster.frag");
    glUseProgram(program_);

    // The per-pass vertex stream: position, then (row, triangle) as integers.
    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    glGenBuffers(1, &stream_vbo_);
    glBindBuffer(GL_ARRAY_BUFFER, stream_vbo_);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(StreamVertex), nullptr);
    glEnableVertexAttribArray(0);
    glVertexAttribIPointer(1, 2, GL_UNSIGNED_INT, sizeof(StreamVertex),
                           reinterpret_cast<const void*>(offsetof(StreamVertex, row)));
    glEnableVertexAttribArray(1);

    // Target: one row per profile, the winning triangle's number + 1 per
    // column, and reversed float depth (near / z: the same relative precision
    // at every range).
    glGenRenderbuffers(1, &colour_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, n, rows_);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, n, rows_);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("raster source: R32UI + DEPTH32F framebuffer of " +
                               std::to_string(n) + "x" + std::to_string(rows_) +
                               " is incomplete (status " + std::to_string(status) + ")");
    glDrawBuffer(GL_COLOR_ATTACHMENT0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);

    // Not exported by libOSMesa (GL 4.5 core): fetched from the driver.
    const auto clip_control =
        reinterpret_cast<PFNGLCLIPCONTROLPROC>(OSMesaGetProcAddress("glClipControl"));
    if (!clip_control)
      throw std::runtime_error("raster source: this OpenGL has no glClipControl (GL 4.5)");
    clip_control(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    check_gl("raster source", "creating the raster pipeline");
    // The context is private to this worker, so all this state stays bound.
  }

  // GL objects go with the context (GlContext's destructor), which is
  // current nowhere between scans.
  ~Worker() = default;

  // Scans poses[i] into out[i], rows_ profiles per pass, with the context
  // current on the calling thread for the call only.
  void scan(std::span<const Pose> poses, std::span<Profile> out) {
    const GlContext::Binding bind(context_);
    for (std::size_t first = 0; first < poses.size(); first += static_cast<std::size_t>(rows_)) {
      const std::size_t count = std::min<std::size_t>(rows_, poses.size() - first);
      pass(poses.subspan(first, count), out.subspan(first, count));
    }
  }

 private:
  // One cut of a triangle with a laser plane: end points (y, z) in the
  // sensor frame, and the triangle.
  struct Segment {
    Eigen::Vector2d p0, p1;
    std::uint32_t entry;  // hierarchy entry of the triangle it was cut from
  };

  // Cuts the triangle at hierarchy entry e (facing the laser, if the mesh
  // is closed) with the laser plane and, if the cut is a segment, appends it
  // to segments_; for any triangle, while cut_triangles leaves it only those
  // with a corner on the plane (see there).
  void slice(std::uint32_t e, const CutFrame& f) {
    const float* c = s_.mesh.bvh.corners(e).data();
    double x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k) to_sensor(f, c[3 * k], c[3 * k + 1], c[3 * k + 2], x[k], y[k], z[k]);
    // End points: corners on the plane, and crossings of edges whose ends lie
    // strictly on opposite sides.
    Eigen::Vector2d ends[3];
    int count = 0;
    for (int k = 0; k < 3; ++k)
      if (x[k] == 0.0) ends[count++] = Eigen::Vector2d(y[k], z[k]);
    if (count == 3) return;  // lies in the plane: seen edge-on, covers no column
    for (int k = 0; k < 3 && count < 2; ++k) {
      int a = k, b = (k + 1) % 3;
      if (!((x[a] < 0.0 && x[b] > 0.0) || (x[a] > 0.0 && x[b] < 0.0))) continue;
      if (lex_less(c + 3 * b, c + 3 * a)) std::swap(a, b);
      edge_crossing(x[a], y[a], z[a], x[b], y[b], z[b], ends[count].x(), ends[count].y());
      ++count;
    }
    if (count < 2 || ends[0] == ends[1]) return;
    segments_.push_back({ends[0], ends[1], e});
  }

  // Joins runs of connected, collinear segments of one profile (a flat face
  // meshed finely cuts into many) into single segments: fewer triangles to
  // draw, the same coverage and, because a column's range is its ray's
  // intersection with the kept triangle's plane, which on a collinear run is
  // the run's line, the same ranges within kCollinearMm. Segments meet where
  // they share a bit-identical end point; a point shared by more than two is
  // not joined through.
  void join_collinear() {
    const std::size_t m = segments_.size();
    if (m < 2) return;
    std::size_t cap = 16;
    while (cap < 2 * m) cap *= 2;
    if (slots_.size() < cap) slots_.assign(cap, {});
    ++stamp_;
    link_.resize(2 * m);
    auto hash = [](const Eigen::Vector2d& p) {
      std::uint64_t a, b;
      std::memcpy(&a, &p.x(), 8);
      std::memcpy(&b, &p.y(), 8);
      std::uint64_t h = a * 0x9e3779b97f4a7c15ULL ^ (b + 0x632be59bd9b4e019ULL + (a << 6) + (a >> 2));
      return h ^ (h >> 29);
    };
    auto point = [&](std::uint32_t end) -> const Eigen::Vector2d& {
      return end & 1 ? segments_[end >> 1].p1 : segments_[end >> 1].p0;
    };
    // Every end into the table (each slot counts the ends at its point and
    // keeps the first two), then the ends of two-end points linked; where
    // three or more meet, none is.
    slot_of_.resize(2 * m);
    for (std::uint32_t end = 0; end < 2 * m; ++end) {
      const Eigen::Vector2d& p = point(end);
      for (std::size_t h = hash(p) & (cap - 1);; h = (h + 1) & (cap - 1)) {
        Slot& slot = slots_[h];
        if (slot.stamp != stamp_) {
          slot = {stamp_, end, kNone, 1};
        } else if (point(slot.first) != p) {
          continue;
        } else if (++slot.count == 2) {
          slot.second = end;
        }
        slot_of_[end] = static_cast<std::uint32_t>(h);
        break;
      }
    }
    for (std::uint32_t end = 0; end < 2 * m; ++end) {
      const Slot& slot = slots_[slot_of_[end]];
      link_[end] = slot.count != 2 ? kNone : slot.first == end ? slot.second : slot.first;
    }
    // Walk each chain from one of its ends; join while collinear.
    used_.assign(m, 0);
    joined_.clear();
    auto collinear = [](const Eigen::Vector2d& a, const Eigen::Vector2d& dir, double len,
                        const Eigen::Vector2d& q) {
      const Eigen::Vector2d d = q - a;
      return std::abs(dir.x() * d.y() - dir.y() * d.x()) <= kCollinearMm * len;
    };
    // The walk back tests collinearity against `start`'s line, the walk
    // forward against the run's first segment's: on a slightly wavy slice (a
    // tilted plate's float corners) the forward walk can stop short of
    // `start`, so a start is taken again until a run has covered it.
    for (std::size_t start = 0; start < m;) {
      if (used_[start]) {
        ++start;
        continue;
      }
      // Go back to the start of the collinear run containing `start`.
      std::uint32_t seg = static_cast<std::uint32_t>(start), out_end = 1;  // leave by p1
      {
        const Eigen::Vector2d a = segments_[seg].p0, dir = segments_[seg].p1 - a;
        const double len = dir.norm();
        std::uint32_t back = 2 * seg;  // the end we arrived through (p0)
        double reach_back = 0.0;       // how far back along dir the run reaches
        std::size_t guard = 0;
        while (link_[back] != kNone && guard++ < m) {
          const std::uint32_t other = link_[back];
          const std::uint32_t s2 = other >> 1;
          if (used_[s2] || s2 == start) break;
          const Eigen::Vector2d& far = (other & 1) ? segments_[s2].p0 : segments_[s2].p1;
          // Collinear and further back (two faces cut along a shared edge
          // lying in the plane give the same segment twice: not a run).
          const double along = (far - a).dot(dir);
          if (!collinear(a, dir, len, far) || !(along < reach_back)) break;
          reach_back = along;
          seg = s2;
          back = other ^ 1;  // its far end
        }
        out_end = back & 1 ? 0 : 1;
      }
      // Forward from `seg`, entering by its end (out_end ^ 1).
      const std::uint32_t first = seg;
      Eigen::Vector2d p0 = out_end ? segments_[seg].p0 : segments_[seg].p1;
      Eigen::Vector2d p1 = out_end ? segments_[seg].p1 : segments_[seg].p0;
      used_[seg] = 1;
      const Eigen::Vector2d dir = p1 - p0;
      const double len = dir.norm();
      std::uint32_t leave = 2 * seg + out_end;
      double reach = len * len;  // (p1 - p0) . dir
      for (std::size_t guard = 0; link_[leave] != kNone && guard < m; ++guard) {
        const std::uint32_t other = link_[leave];
        const std::uint32_t s2 = other >> 1;
        if (used_[s2]) break;
        const Eigen::Vector2d& far = (other & 1) ? segments_[s2].p0 : segments_[s2].p1;
        const double along = (far - p0).dot(dir);
        if (!collinear(p0, dir, len, far) || !(along > reach)) break;
        reach = along;
        used_[s2] = 1;
        p1 = far;
        leave = other ^ 1;
      }
      joined_.push_back({p0, p1, segments_[first].entry});
    }
    segments_.swap(joined_);
  }

  // Appends segment g to the stream, cut at the near plane, as one triangle
  // in row `row` of `rows`: p0 as an edge across the row, p1 as the apex on
  // the row's centre line, where the pixel centres lie, so that along them it
  // covers exactly the columns between p0 and p1 with depth interpolated
  // between theirs (half the triangles of a quad, the same pixels: llvmpipe's
  // cost is per triangle here).
  void emit(const Segment& g, std::uint32_t row, int rows) {
    Eigen::Vector2d p0 = g.p0, p1 = g.p1;
    if (p0.y() < kNearClipMm && p1.y() < kNearClipMm) return;
    if (p0.y() < kNearClipMm) p0 = p0 + (kNearClipMm - p0.y()) / (p1.y() - p0.y()) * (p1 - p0);
    if (p1.y() < kNearClipMm) p1 = p1 + (kNearClipMm - p1.y()) / (p0.y() - p1.y()) * (p0 - p1);
    // NDC x and reversed depth of the ends, cut to the target's edges, x = -1
    // and 1, half a pixel beyond the outer columns' centres (depth is affine
    // in x along the segment). Every vertex then lies inside the clip volume,
    // which keeps llvmpipe off its clipping path: a draw chunk holding one
    // vertex outside went through the draw module's primitive pipeline, whose
    // vertex-buffer flushes reset the ids of every vertex of the chunk (a
    // quarter of the CPU of a million-triangle curved mesh, perf); and a
    // triangle reaching far beyond the target, clipped there, lost coverage
    // of this thin one. Cutting at -1 and 1 instead of a pixel beyond gave
    // the same profiles, byte for byte (docs/PERFORMANCE.md, session 18).
    double x0 = p0.x() / p0.y() / s_.tan_half_fan, x1 = p1.x() / p1.y() / s_.tan_half_fan;
    double d0 = kNearClipMm / p0.y(), d1 = kNearClipMm / p1.y();
    const double lim = 1.0;
    if ((x0 < -lim && x1 < -lim) || (x0 > lim && x1 > lim)) return;
    auto cut = [lim](double& xa, double& da, double xb, double db) {
      const double x = std::clamp(xa, -lim, lim);
      if (x == xa) return;
      da += (x - xa) / (xb - xa) * (db - da);
      xa = x;
    };
    const double x0_uncut = x0, d0_uncut = d0;
    cut(x0, d0, x1, d1);
    cut(x1, d1, x0_uncut, d0_uncut);
    const float y_lo = static_cast<float>(2.0 * row / rows - 1.0);
    const float y_hi = static_cast<float>(2.0 * (row + 1) / rows - 1.0);
    const float y_mid = static_cast<float>(2.0 * (row + 0.5) / rows - 1.0);
    const std::uint32_t t = g.entry;
    const float fx0 = static_cast<float>(x0), fx1 = static_cast<float>(x1);
    const float fd0 = static_cast<float>(d0), fd1 = static_cast<float>(d1);
    stream_.push_back({fx0, y_lo, fd0, row, t});
    stream_.push_back({fx0, y_hi, fd0, row, t});
    stream_.push_back({fx1, y_mid, fd1, row, t});
  }

  void pass(std::span<const Pose> poses, std::span<Profile> out) {
    const int n = s_.desc.points;
    const int count = static_cast<int>(poses.size());
    const double reach = s_.desc.max_hit_mm;
    stream_.clear();
    // Only the triangles that cross a profile's laser plane inside the fan
    // can cover a column's ray. The fan (radius `reach`) lies inside the
    // triangle from the origin to (0, +-T reach, reach). Profiles whose laser
    // planes are parallel (a straight path at fixed orientation) are culled in
    // blocks: one hierarchy query for the slab between the block's planes,
    // then each triangle found is sorted to the planes it crosses.
    for (int k0 = 0; k0 < count;) {
      const Eigen::Vector3d n_world = poses[k0].linear().col(0);
      int k1 = k0 + 1;
      while (k1 < count && k1 - k0 < kCullBlock && poses[k1].linear().col(0) == n_world) ++k1;
      const int rows = k1 - k0;
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
      Eigen::Vector3d hi = -lo;
      MeshBvh::Box3 origins{lo, hi};  // of the block's laser origins
      for (int k = k0; k < k1; ++k) {
        const Eigen::Matrix3d r = poses[k].linear();
        const Eigen::Vector3d origin_c = poses[k].translation() - s_.mesh.centre_mm;
        origins.lo = origins.lo.cwiseMin(origin_c);
        origins.hi = origins.hi.cwiseMax(origin_c);
        const Eigen::Vector3d far = r.col(2) * reach;
        const Eigen::Vector3d side = r.col(1) * (reach * s_.tan_half_fan);
        lo = lo.cwiseMin(origin_c).cwiseMin(origin_c + far - side).cwiseMin(origin_c + far + side);
        hi = hi.cwiseMax(origin_c).cwiseMax(origin_c + far - side).cwiseMax(origin_c + far + side);
        plane_d_[k - k0] = n_world.dot(origin_c);
        row_entries_[k - k0].clear();
      }
      lo.array() -= kCullMarginMm;
      hi.array() += kCullMarginMm;
      // The sides of the fan: emit() drops every segment beyond the
      // target's columns and a pixel either side (|y / z| > T ndc_limit in
      // the sensor frame), so a triangle entirely beyond one side need not
      // be cut. When the block's profiles share their orientation, each
      // side is one plane direction and the block's union lies within the
      // half-space reaching out to its outermost origin.
      std::array<Eigen::Vector4d, 2> fan_sides;  // half-spaces n . p + w >= 0
      int sides = 0;
      bool same_orientation = true;
      for (int k = k0 + 1; k < k1; ++k) same_orientation = same_orientation && poses[k].linear() == poses[k0].linear();
      if (same_orientation) {
        const double tl = s_.tan_half_fan * s_.ndc_limit;
        for (const double y_sign : {-1.0, 1.0}) {
          const Eigen::Vector3d normal = poses[k0].linear() * Eigen::Vector3d(0.0, y_sign, tl);
          double w = std::numeric_limits<double>::infinity();
          for (int k = k0; k < k1; ++k) w = std::min(w, normal.dot(poses[k].translation() - s_.mesh.centre_mm));
          fan_sides[sides++] = Eigen::Vector4d(normal.x(), normal.y(), normal.z(), kCullMarginMm * normal.norm() - w);
        }
      }
      // Faces turned away from every laser origin of the block (closed
      // meshes: hidden behind the front) are left out here already; slice()
      // decides exactly for each profile.
      s_.mesh.bvh.crossing_planes(n_world, std::span(plane_d_.data(), rows), lo, hi, kCullMarginMm,
                                  std::span(row_entries_.data(), rows), s_.mesh.closed ? &origins : nullptr,
                                  std::span(fan_sides.data(), static_cast<std::size_t>(sides)));
      for (int k = k0; k < k1; ++k) {
        // Mesh-centred world -> sensor, in double: p_s = R^T (p_c + c - t).
        const Eigen::Matrix3d r = poses[k].linear();
        const Eigen::Vector3d origin_c = poses[k].translation() - s_.mesh.centre_mm;
        CutFrame frame{};
        for (int q = 0; q < 9; ++q) frame.r[q] = r(q % 3, q / 3);
        for (int q = 0; q < 3; ++q) frame.o[q] = origin_c[q];
        frame.closed = s_.mesh.closed;
        segments_.clear();
        // The triangles cut in batches (cut_triangles), their corners and
        // planes gathered first; the cuts collected in entry order, slice()
        // taking those with a corner on the plane.
        const std::vector<std::uint32_t>& entries = row_entries_[k - k0];
        for (std::size_t first = 0; first < entries.size(); first += kCutBatch) {
          const int m = static_cast<int>(std::min<std::size_t>(kCutBatch, entries.size() - first));
          for (int j = 0; j < m; ++j) {
            const std::uint32_t e = entries[first + j];
            const std::array<float, 9>& c = s_.mesh.bvh.corners(e);
            for (int q = 0; q < 9; ++q) cut_.c[q][j] = c[q];
            for (int q = 0; q < 4; ++q) cut_.plane[q][j] = s_.mesh.planes[4 * std::size_t(e) + q];
          }
          cut_triangles(m, frame, cut_);
          for (int j = 0; j < m; ++j) {
            if (cut_.kind[j] == 0) continue;
            if (cut_.kind[j] == 2) {
              slice(entries[first + j], frame);
              continue;
            }
            const Eigen::Vector2d p0(cut_.y0[j], cut_.z0[j]), p1(cut_.y1[j], cut_.z1[j]);
            if (p0 != p1) segments_.push_back({p0, p1, entries[first + j]});
          }
        }
        join_collinear();
        for (const Segment& g : segments_) emit(g, static_cast<std::uint32_t>(k), count);
      }
      k0 = k1;
    }

    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, n, count);
    const GLuint clear_triangle[4] = {0, 0, 0, 0};
    const GLfloat clear_depth = 0.0f;  // reversed depth: 0 is infinitely far
    glClearBufferuiv(GL_COLOR, 0, clear_triangle);
    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
    if (!stream_.empty()) {
      glBindBuffer(GL_ARRAY_BUFFER, stream_vbo_);
      const std::size_t bytes = stream_.size() * sizeof(StreamVertex);
      if (bytes > stream_capacity_) {
        stream_capacity_ = std::max(bytes, 2 * stream_capacity_);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(stream_capacity_), nullptr,
                     GL_STREAM_DRAW);
      }
      glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(bytes), stream_.data());
      glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(stream_.size()));
    }
    glReadPixels(0, 0, n, count, GL_RED_INTEGER, GL_UNSIGNED_INT, readback_.data());

    const bool shadows = !s_.desc.ideal && s_.mesh.bvh.triangle_count() > 0;
    for (int k = 0; k < count; ++k) {
      Profile& p = out[k];
      if (!p.sized(n)) p.resize(n);
      p.world_from_sensor = poses[k];
      const Eigen::Matrix3d r = poses[k].linear();
      const Eigen::Vector3d origin_c = poses[k].translation() - s_.mesh.centre_mm;
      const std::uint32_t* row = &readback_[std::size_t(k) * n];
      for (int i = 0; i < n; ++i) {
        float range = kNoHit, cos_incidence = 0.0f;
        if (row[i] != 0) {
          // Exact range along the column's ray to the winning triangle's plane.
          const double* plane = &s_.mesh.planes[4 * std::size_t(row[i] - 1)];
          const Eigen::Vector3d normal(plane[0], plane[1], plane[2]);
          const double along = normal.dot(r * s_.directions_d[i]);
          const double t = (plane[3] - normal.dot(origin_c)) / along;
          // Behind the laser, beyond the maximum hit distance, grazing (inf) or NaN.
          if (t > 0.0 && t <= s_.desc.max_hit_mm) {
            range = static_cast<float>(t);
            cos_incidence = static_cast<float>(std::abs(along));
          }
        }
        set_column(s_.desc, s_.directions[i], i, range, p, cos_incidence);
      }
      if (shadows) shadow_.apply(r, origin_c, p);
    }
  }

  const SharedScene& s_;
  GlContext context_;  // created before, destroyed after, every GL object below
  ShadowTester shadow_;
  int rows_ = 1;       // profiles per pass
  std::vector<StreamVertex> stream_;       // per pass, grows to its largest size
  std::size_t stream_capacity_ = 0;        // bytes allocated for stream_vbo_
  std::array<std::vector<std::uint32_t>, kCullBlock> row_entries_;  // per profile of a block
  std::array<double, kCullBlock> plane_d_{};  // laser plane offsets n . origin of a block
  struct Slot {
    std::uint32_t stamp = 0, first = 0, second = 0, count = 0;
  };
  static constexpr std::uint32_t kNone = ~0u;
  std::vector<Segment> segments_, joined_;  // one profile's cuts
  std::vector<Slot> slots_;                // end point hash table (stamped)
  std::uint32_t stamp_ = 0;
  std::vector<std::uint32_t> link_;        // per segment end: the end it meets, or kNone
  std::vector<std::uint32_t> slot_of_;     // per segment end: its point's slot
  std::vector<std::uint8_t> used_;
  CutBatch cut_;  // cut_triangles' input and output
  std::vector<std::uint32_t> readback_;    // per row, column: triangle + 1, 0 = no hit
  GLuint program_ = 0;
  GLuint vao_ = 0, stream_vbo_ = 0;
  GLuint colour_rb_ = 0, depth_rb_ = 0, fbo_ = 0;
};

class RasterSource final : public ProfileSource {
 public:
  RasterSource(const ScannerDesc& desc, const Mesh& mesh_world, const RasterOptions& options)
      : scene_(std::make_unique<SharedScene>()) {
    SharedScene& s = *scene_;
    s.desc = desc;
    s.directions = column_directions(desc);
    for (const auto& d : s.directions) {
      s.directions_d.push_back(d.cast<double>());
      s.dir_x.push_back(s.directions_d.back().x());
      s.dir_y.push_back(s.directions_d.back().y());
      s.dir_z.push_back(s.directions_d.back().z());
    }
    // Column i is the centre of pixel i of an n-wide image whose horizontal
    // half-angle is fan/2 (sensor/rays.h): NDC x = (y/z) / tan(fan/2).
    s.tan_half_fan = std::tan(0.5 * desc.fan_deg * std::numbers::pi / 180.0);
    s.ndc_limit = 1.0 + 2.0 / desc.points;
    s.camera_mm = camera_model(desc).centre_mm;
    s.mesh = prepare(mesh_world, options.merge_planar);

    rows_ = std::clamp(options.rows_per_pass, 1, kMaxRowsPerPass);
    const int limit = thread_limit();
    max_parts_ = static_cast<std::size_t>(std::min(options.threads > 0 ? std::min(options.threads, limit) : limit,
                                                   kMaxThreads));
    workers_.resize(static_cast<std::size_t>(limit) + 1);
    // One worker is built now, so a GL or shader failure shows at
    // construction; the first thread to need one takes it.
    spare_ = std::make_unique<Worker>(s, rows_);
  }

  void scan(const Pose& world_from_sensor, Profile& out) override {
    worker().scan(std::span(&world_from_sensor, 1), std::span(&out, 1));
  }

  // Parts of a batch go to the arena's threads (common/parallel.h), each
  // with the worker of its slot; errors come back as exceptions.
  void scan_batch(std::span<const Pose> poses, std::span<Profile> out) override {
    const std::size_t total = std::min(poses.size(), out.size());
    // Called inside a parallel loop (a part of a batch split by the caller,
    // pipeline/scan_session.cpp), the part is scanned on this thread.
    const std::size_t parts =
        thread_slot() >= 0 ? 1 : std::clamp<std::size_t>(total / kMinProfilesPerThread, 1, max_parts_);
    const std::size_t per = (total + parts - 1) / parts;
    parallel_for(parts, [&](std::size_t t) {
      const std::size_t first = std::min(total, t * per);
      const std::size_t count = std::min(total, first + per) - first;
      if (count > 0) worker().scan(poses.subspan(first, count), out.subspan(first, count));
    });
  }

  const ScannerDesc& scanner() const override { return scene_->desc; }
  std::string_view kind() const override { return "raster"; }

 private:
  // The calling thread's worker: per arena slot (thread_slot() + 1; 0 for a
  // caller outside any parallel loop), built when first needed.
  Worker& worker() {
    std::unique_ptr<Worker>& w = workers_[static_cast<std::size_t>(thread_slot() + 1)];
    if (!w) {
      std::lock_guard lock(spare_mutex_);
      w = std::move(spare_);
    }
    if (!w) w = std::make_unique<Worker>(*scene_, rows_);
    return *w;
  }

  std::unique_ptr<SharedScene> scene_;  // read by the workers; outlives them
  int rows_ = 1;
  std::size_t max_parts_ = 1;                     // most parts a batch is split into
  std::vector<std::unique_ptr<Worker>> workers_;  // per slot, see worker()
  std::unique_ptr<Worker> spare_;                 // built with the source, not yet taken
  std::mutex spare_mutex_;
};

}  // namespace

std::unique_ptr<ProfileSource> make_raster_source(const ScannerDesc& desc,
                                                  const Mesh& mesh_world,
                                                  const RasterOptions& options) {
  if (const std::string problem = validate(desc); !problem.empty())
    throw std::invalid_argument("raster source: scanner " + problem);
  return std::make_unique<RasterSource>(desc, mesh_world, options);
}

}  // namespace vts
