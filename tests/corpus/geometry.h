// 2D cross-section geometry and the ray caster of the test corpus.
//
// Written for the tests alone, independent of sensor/ and render/: solids are
// closed polygons in a plane (y, z); rays and sight lines are cast against
// their edges. Coordinates in mm. Vectors are (y, z).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <vector>

namespace vts_corpus {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

// Matrix products written out: Eigen may use fused multiply-adds for its
// products where the target has them (-march=native, ARM), which would change
// the last bits from machine to machine (dmath.h).
inline Vec2 mul(const Mat2& A, const Vec2& p) {
  return Vec2(A(0, 0) * p.x() + A(0, 1) * p.y(), A(1, 0) * p.x() + A(1, 1) * p.y());
}
inline Mat2 mul(const Mat2& A, const Mat2& B) {
  Mat2 C;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j);
  return C;
}
inline Mat2 inverse(const Mat2& A) {
  const double det = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0);
  Mat2 inv;
  inv << A(1, 1) / det, -A(0, 1) / det, -A(1, 0) / det, A(0, 0) / det;
  return inv;
}

// z-component of the 3D cross product of (y, z) vectors: > 0 when b lies
// counter-clockwise of a.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Named faces: each polygon edge carries the id of the face it belongs to, so
// tests and truth can ask which surface a ray hit. Values are stable (used in
// debug output); numbering in the joint frame: 1 = the plate at -y, 2 = +y.
enum Face : int {
  kFaceOther = 0,     // back sides, far ends, clip edges
  kFaceRounding,      // arc or chamfer replacing a sharp corner
  kFaceFlangeTop,     // fillet
  kFaceWebOpen,       // fillet: the web's face on the open side
  kFaceWebBottom,     // fillet: the web's bottom (edge) face
  kFaceOuter1,        // corner: outer faces
  kFaceOuter2,
  kFaceEnd1,          // corner: mitred end faces (the notch walls)
  kFaceEnd2,
  kFaceLowerTop,      // lap
  kFaceUpperTop,
  kFaceUpperEdge,
  kFaceUpperBottom,
  kFaceTop1,          // butt, v-groove: plate tops
  kFaceTop2,
  kFaceEdge1,         // butt: edge faces (gap walls)
  kFaceEdge2,
  kFaceBevel1,        // v-groove; grooves: each wall's straight part (square or bevelled)
  kFaceBevel2,
  kFaceRoot1,         // v-groove: root faces
  kFaceRoot2,
  kFaceBacking,       // backing bar's top
  kFaceTack,          // tack-weld bump
  kFaceDecoy,         // the decoy feature's faces
  kFaceBody,          // torch or clamp
  kFaceArc1,          // U, J groove: the wall's arc at the root (1 = side a)
  kFaceArc2,
  kFaceCap,           // groove: the last bead's surface
  kFaceCount
};
const char* face_name(int face);

struct Polygon {
  std::vector<Vec2> pts;   // closed: edge i runs pts[i] -> pts[(i + 1) % n]
  std::vector<int> faces;  // face id of edge i
};

// A corner of a polygon to be built: the corner point, what happens to the
// sharp corner there, and the face id of the edge leaving it.
enum class CornerKind { Sharp, Round, Chamfer };
struct Corner {
  Vec2 p;
  int face_out = kFaceOther;
  CornerKind kind = CornerKind::Sharp;
  double size_mm = 0.0;  // radius (Round) or leg length along each edge (Chamfer)
};

// Builds a closed polygon, replacing rounded corners with arcs of at most
// max_arc_step_deg per segment (fine enough to look round, few enough edges
// to cast fast) and chamfered ones with a straight cut. Sizes are limited to
// 45 % of the shorter neighbouring edge. Zero-length edges are dropped.
Polygon make_polygon(const std::vector<Corner>& corners, double max_arc_step_deg = 6.0);
Polygon make_circle(const Vec2& centre, double radius_mm, int face, int segments);

// p -> A p + t for every vertex.
Polygon transformed(const Polygon& poly, const Mat2& A, const Vec2& t);
// Keeps the part with z >= z_min (Sutherland-Hodgman against one half-plane;
// the cut edge gets kFaceOther). Empty when nothing is left.
Polygon clipped_above(const Polygon& poly, double z_min);

struct Edge {
  Vec2 a, b;
  int face = kFaceOther;
};

// Edges of all solids of a scene, flattened. add() orients every polygon
// counter-clockwise (the solid on the left of each edge a -> b), which lets
// FanIndex skip the edges facing away from its apex.
struct Scene {
  std::vector<Edge> edges;
  void add(const Polygon& poly);
};

// Robust ray-edge test used everywhere: the ray from `origin` along `dir`
// (any length) crosses edge (a, b) when a and b do not lie strictly on the same
// side of the ray's line. The side of a vertex is computed by the same
// operations for both edges that share it, so a ray through a vertex always
// meets at least one of them (no slip-through). Returns the ray parameter of
// the crossing in units of |dir| (NaN when no crossing or when the edge lies
// along the ray; its neighbours then catch the ray).
inline double ray_edge_param(const Vec2& origin, const Vec2& dir, const Edge& e) {
  const Vec2 a = e.a - origin, b = e.b - origin;
  const double sa = cross(dir, a), sb = cross(dir, b);
  if ((sa > 0 && sb > 0) || (sa < 0 && sb < 0) || sa == sb) return std::numeric_limits<double>::quiet_NaN();
  const double s = sa / (sa - sb);  // in [0, 1]
  const Vec2 q = a + s * (b - a);
  return q.dot(dir) / dir.squaredNorm();
}

// Nearest hit of the ray from origin along unit dir at t > t_min, testing every
// edge (for the few truth queries per profile). Returns t or NaN; *edge_index
// is the edge hit (-1 for none).
double nearest_hit_bruteforce(const Scene& scene, const Vec2& origin, const Vec2& dir,
                              double t_min, int* edge_index);
// First edge crossed by the segment from `from` to `to`, excluding crossings
// within a relative 1e-9 of `from` (the surface the point lies on); -1 if none.
int segment_blocker_bruteforce(const Scene& scene, const Vec2& from, const Vec2& to);

// Edges binned by their direction as seen from an apex: u = (y - apex.y) /
// (z - apex.z), the tangent of the angle from the +z axis. The central
// projection of an edge is the interval between its end points' u (every
// vertex must lie at z > apex.z), so a ray or sight line through the apex can
// only meet the edges whose interval holds its u. Bins are padded by a relative
// epsilon so rays through vertices keep both edges. Edges facing away from the
// apex are left out: a ray from outside every solid enters a solid through
// an edge facing it first (the scene's polygons must be closed and oriented,
// as Scene::add makes them).
class FanIndex {
 public:
  // Bins are the intervals between consecutive sorted `bin_u` values' midpoints
  // (one bin per column ray), or `bins` uniform bins over [u_lo, u_hi].
  void build_columns(const Scene& scene, const Vec2& apex, const std::vector<double>& column_u);
  void build_uniform(const Scene& scene, const Vec2& apex, double u_lo, double u_hi, int bins);
  // Edges that may meet the ray of column i / the sight line with direction u.
  const int* begin(int bin) const { return entries_.data() + start_[bin]; }
  const int* end(int bin) const { return entries_.data() + start_[bin + 1]; }
  int bin_of(double u) const {  // uniform index only; -1 outside
    const double f = (u - u_lo_) / du_;
    if (!(f >= 0) || f >= bins()) return -1;
    return static_cast<int>(f);
  }
  int bins() const { return static_cast<int>(start_.size()) - 1; }

 private:
  template <class BinRange>
  void fill(const Scene& scene, int bins, BinRange bin_range);
  Vec2 apex_{0, 0};
  double u_lo_ = 0, du_ = 1;
  std::vector<int> start_, entries_;
};

}  // namespace vts_corpus
