#include "tracker/tracker.h"

#include "tracker/noise.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <span>
#include <tuple>
#include <Eigen/Cholesky>

namespace vts::tracker {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Most points a butt gap's walls can show inside one merged segment.
constexpr int kMaxWallPoints = 16;

struct JointName {
  JointType type;
  std::string_view name;
};
constexpr JointName kJointNames[] = {{JointType::Fillet, "fillet"},
                                     {JointType::Corner, "corner"},
                                     {JointType::Lap, "lap"},
                                     {JointType::Butt, "butt"},
                                     {JointType::VGroove, "vgroove"},
                                     {JointType::Bevel, "bevel"},
                                     {JointType::UGroove, "ugroove"},
                                     {JointType::JGroove, "jgroove"}};

// Break point names per joint (docs/JOINTS.md).
constexpr std::string_view kBreakNames[8][kMaxBreakPoints] = {
    // Fillet
    {"flange outer end", "root", "flange end seen under the web", "web edge", "web outer end", "", "", ""},
    // Corner
    {"first face outer end", "first plate edge", "apex of the outer faces", "second plate edge",
     "second face outer end", "", "", ""},
    // Lap
    {"lower plate outer end", "foot of the step", "upper plate bottom edge", "upper plate top edge",
     "upper plate outer end", "", "", ""},
    // Butt
    {"first plate outer end", "first plate edge", "gap centre", "second plate edge", "second plate outer end", "",
     "", ""},
    // VGroove
    {"first top outer end", "first top edge", "first root edge", "root centre", "second root edge",
     "second top edge", "second top outer end", ""},
    // Bevel, UGroove, JGroove: the groove model (docs/JOINTS.md "Grooves and fill")
    {"first top outer end", "first top edge", "first toe", "bottom centre", "second toe", "second top edge",
     "second top outer end", ""},
    {"first top outer end", "first top edge", "first toe", "bottom centre", "second toe", "second top edge",
     "second top outer end", ""},
    {"first top outer end", "first top edge", "first toe", "bottom centre", "second toe", "second top edge",
     "second top outer end", ""},
};

// A plate: a run of kept points [first, last] and its fitted line. A curved
// plate (the fillet's, FilletParams::curved_plates: a pipe's section) is
// also a circular arc (centre, radius rho; bend +1: the centre in front of
// it, towards the sensor, -1 behind it), which is its surface to the
// evidence, and `line` is its tangent at the root. rho 0: straight, and
// every distance then exactly the line's.
struct Plate {
  int first = 0;
  int last = 0;
  Line line;
  Vec2 centroid = Vec2::Zero();
  double rho = 0.0;
  double bend = 0.0;
  Vec2 centre = Vec2::Zero();
  double line_rms = -1.0;  // the points' rms about `line` as fitted (-1: not known)
  int count() const { return last - first + 1; }
  // > 0 in front of the surface (towards the sensor), < 0 behind it.
  double signed_distance(const Vec2& q) const {
    if (rho == 0.0) return line.signed_distance(q);
    return bend * (rho - (q - centre).norm());
  }
  double distance(const Vec2& q) const { return std::abs(signed_distance(q)); }
  Vec2 project(const Vec2& q) const {
    if (rho == 0.0) return line.project(q);
    const Vec2 d = q - centre;
    const double len = d.norm();
    return len > 0.0 ? Vec2(centre + d * (rho / len)) : q;
  }
  // The surface's tangent line at the point nearest q (the line itself if
  // straight), its normal towards the sensor as line's.
  Line tangent_at(const Vec2& q) const {
    if (rho == 0.0) return line;
    const Vec2 f = project(q);
    Vec2 n = (centre - f) / rho;
    if (n.dot(line.n) < 0.0) n = -n;
    return Line{n, n.dot(f)};
  }
};

// A plate edge: an estimate and half the interval it can lie in, and the
// covariance of the estimate (mm^2; docs/JOINTS.md "Localization"): its
// line's fit, its end point's noise and that interval as a uniform spread.
struct Edge {
  Vec2 point = Vec2::Zero();
  double half_width_mm = 0.0;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  std::optional<Line> face = std::nullopt;  // the edge face as seen and fitted (Matcher::seen_face)
};

// What a reading's points say for it (Matcher::weigh, docs/JOINTS.md
// "Confidence"), in units of the noise.
struct Evidence {
  // How much better the reading explains the points near the joint than one
  // line through them (no joint): a robust log-likelihood ratio over the
  // points within ConfidenceParams::window_mm of the track point, each term
  // capped.
  double strength = 0.0;
  int points = 0;       // points in that window
  int unexplained = 0;  // of them, on no line of the reading and not inside its opening
  double fit = 0.0;     // the larger of the plates' rms about their lines there, in noise sigmas
  int w0 = -1, w1 = -1;  // the first and last kept point of that window (point indices)
};

// One way of reading the profile as the configured joint.
struct Candidate {
  std::array<std::optional<Vec2>, kMaxBreakPoints> bp;
  std::optional<Vec2> track;
  double gap = kNaN, gap_paper = kNaN, angle = kNaN, mismatch = kNaN, step = kNaN, depth = kNaN, area = kNaN;
  double wall_a = kNaN, wall_b = kNaN, top_width = kNaN;  // grooves (TrackResult)
  std::optional<Vec2> fill_lowest;
  bool weighed = false;  // the template set `evidence` itself (the groove model)
  double edge_unc = 0.0;
  double track_unc = 0.0;  // half the interval the track point can lie in, from its edges
  // The covariance of the track point (mm^2) from the fits that place it
  // (docs/JOINTS.md "Localization"), where the template works it out
  // (located).
  Eigen::Matrix2d track_cov = Eigen::Matrix2d::Zero();
  bool located = false;
  double score = 0.0;
  bool accepted = false;
  // Rejected by the model check only ("uncertain": the joint is there but
  // cannot be placed to 1 mm): still a reading the others are weighed
  // against (a weaker reading elsewhere is no surer for it).
  bool uncertain = false;
  char reason[160] = {};
  // The accept-range check that failed (check()), written into `reason`
  // only when it is read (reason_text(): most rejected candidates never are).
  struct Failed {
    const char* name = nullptr;
    double v = 0.0;
    Range r;
    const char* unit = nullptr;
  } failed;
  const char* reason_text() {
    if (failed.name) {
      std::snprintf(reason, sizeof reason, "%s %.3g %s outside [%g, %g]", failed.name, failed.v, failed.unit,
                    failed.r.min, failed.r.max);
      failed.name = nullptr;
    }
    return reason;
  }
  // The two plates the reading rests on, in scan order (fillet: the plates;
  // corner: the faces; lap: lower and upper; butt: the plates; v-groove: the
  // bevels), and the other lines it sees near the joint (v-groove: the plate
  // tops; lap: the edge face; corner: the end faces; fillet: the web's
  // bottom), for its evidence (Matcher::weigh).
  Plate pa, pb;
  std::array<Line, 3> more;
  int n_more = 0;
  void add_line(const Line& l) {
    if (n_more < static_cast<int>(more.size())) more[n_more++] = l;
  }
  // Rays between the plates may go into the joint (butt, v-groove): points
  // behind both plates inside its opening and invalid columns there are
  // evidence of it. The opening lies between its edges a and b, whose walls
  // run square to the plates (TrackerParams::square_edges); into_a, into_b:
  // unit directions along the surface from each edge into the opening;
  // slack: how far a point may lie outside (the edge's uncertainty and the
  // surface tolerance).
  bool open_joint = false;
  bool parallel = false;  // the plates are parallel (butt, lap): weighed as such
  // A groove reading (the groove model): the tops' line; everything between
  // the tops' ends not in front of it is its walls and bottom.
  std::optional<Line> groove_top;
  struct Opening {
    Vec2 a = Vec2::Zero(), b = Vec2::Zero(), into_a = Vec2::Zero(), into_b = Vec2::Zero();
    double slack_a = 0.0, slack_b = 0.0;
    bool contains(const Vec2& q) const { return (q - a).dot(into_a) >= -slack_a && (q - b).dot(into_b) >= -slack_b; }
    // On a wall within its slack, and within 15 degrees of square below the
    // edge: the wall as seen, noise along the rays and an edge not quite
    // square.
    bool on_wall(const Vec2& q) const {
      const Vec2 down_a(into_a.y(), -into_a.x()), down_b(into_b.y(), -into_b.x());
      const double lean = std::tan(15.0 * std::numbers::pi / 180.0);
      return std::abs((q - a).dot(into_a)) <= slack_a + lean * std::abs((q - a).dot(down_a)) ||
             std::abs((q - b).dot(into_b)) <= slack_b + lean * std::abs((q - b).dot(down_b));
    }
  } opening;
  Evidence evidence;
};

// Accepted readings first, then the stronger evidence (Matcher::weigh),
// then the template's own ranking.
bool better(const Candidate& a, const Candidate& b) {
  if (a.accepted != b.accepted) return a.accepted;
  if (a.accepted && a.evidence.strength != b.evidence.strength) return a.evidence.strength > b.evidence.strength;
  return a.score > b.score;
}

// Sets the reason "<name> <value> <unit> outside [min, max]" (written when
// read: Candidate::reason_text) if v is measured and out of range.
bool check(Candidate& c, const char* name, double v, const Range& r, const char* unit) {
  if (std::isnan(v) || r.contains(v)) return true;
  c.failed = {name, v, r, unit};  // formatted when read (Candidate::reason_text)
  return false;
}

// A gentle arc across a line (FilletParams::curved_plates): the points q
// (every stride-th) within `window` of o fitted with v = b0 + b1 u + b2 u^2
// by least squares in v, v the signed distance from `frame` and u along it
// from o. Curved when b2 is at least fp.curve_t standard errors, each
// point's error the larger of `sigma` and the fit's own residual, and the
// radius of curvature 1 / (2 |b2|) at least fp.min_curve_radius windows
// (curve_window_mm): a pipe's section, not the corner of a bead or a
// rounded edge; and the points lie within fp.curve_rms_sigma sigma (rms)
// of it (waviness does not). rms: the residual about the quadratic (over
// n).
struct QuadFit {
  double b0 = 0.0, b1 = 0.0, b2 = 0.0, rms = 0.0;
  bool fitted = false, curved = false;
  bool wiggly = false;  // the cubic term is significant too (curve_t standard errors)
};
QuadFit fit_quadratic(std::span<const Vec2> q, const Line& frame, const Vec2& o, double window, double sigma,
                      const FilletParams& fp, int min_points, int stride = 1) {
  QuadFit out;
  const double w2 = window * window;
  const Vec2 d = frame.direction();
  // u in units of the window (the normal equations' conditioning), and the
  // coefficients of u' = u / h scaled back: b1 = b1' / h, b2 = b2' / h^2.
  const double h = std::max(fp.curve_window_mm, 1e-3);
  // Twice: all points, then those within 3 rms (at least 3 sigma) of the
  // first fit (a point of the other plate at the root, a noisy point).
  double keep = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < 2; ++pass) {
    // With the cubic term too (`wiggly`): near the root the arc must be
    // the adequate model, not a wiggle (one wave of waviness on a short
    // plate) that a cubic follows better. The normal equations from the
    // power sums of u (to the 6th) and of v u^k.
    double su[7] = {}, sv[4] = {}, vv = 0.0;
    int n = 0;
    for (std::size_t k = 0; k < q.size(); k += static_cast<std::size_t>(stride)) {
      const Vec2& p = q[k];
      if ((p - o).squaredNorm() > w2) continue;
      const double u = d.dot(p - o) / h, v = frame.signed_distance(p);
      if (pass > 0 && std::abs(v - (out.b0 + (out.b1 + out.b2 * u * h) * u * h)) > keep) continue;
      const double u2 = u * u, u3 = u2 * u;
      su[1] += u, su[2] += u2, su[3] += u3, su[4] += u2 * u2, su[5] += u2 * u3, su[6] += u3 * u3;
      sv[0] += v, sv[1] += v * u, sv[2] += v * u2, sv[3] += v * u3;
      vv += v * v;
      ++n;
    }
    su[0] = n;
    if (n < std::max(min_points, 6)) return QuadFit{};
    Eigen::Matrix4d ata4;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) ata4(r, c) = su[r + c];
    const Eigen::Vector4d atv4(sv[0], sv[1], sv[2], sv[3]);
    const Eigen::Matrix3d ata = ata4.topLeftCorner<3, 3>();
    const Eigen::Vector3d atv = atv4.head<3>();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return QuadFit{};
    const Eigen::Vector3d b = ldlt.solve(atv);
    const double c22 = ldlt.solve(Eigen::Vector3d::UnitZ())(2);
    if (!b.allFinite() || !(c22 > 0.0)) return QuadFit{};
    const double rss = std::max(0.0, vv - b.dot(atv));
    out.b0 = b(0), out.b1 = b(1) / h, out.b2 = b(2) / (h * h), out.rms = std::sqrt(rss / n);
    keep = 3.0 * std::max(sigma, out.rms);
    const double s = std::max(sigma, std::sqrt(rss / (n - 3)));
    const double t = std::abs(b(2)) / (s * std::sqrt(c22));
    const double radius = 1.0 / (2.0 * std::abs(out.b2));
    out.fitted = true;
    out.curved = t >= fp.curve_t && radius >= fp.min_curve_radius * fp.curve_window_mm &&
                 out.rms <= fp.curve_rms_sigma * sigma;
    out.wiggly = false;
    if (n > 4) {
      const Eigen::LDLT<Eigen::Matrix4d> l4(ata4);
      if (l4.info() == Eigen::Success && l4.isPositive()) {
        const Eigen::Vector4d c = l4.solve(atv4);
        const double c33 = l4.solve(Eigen::Vector4d::UnitW())(3);
        const double s3 = std::max(sigma, std::sqrt(std::max(0.0, vv - c.dot(atv4)) / (n - 4)));
        out.wiggly = c.allFinite() && c33 > 0.0 && std::abs(c(3)) / (s3 * std::sqrt(c33)) >= fp.curve_t;
      }
    }
  }
  return out;
}

// The circle through points q (Kasa's algebraic fit: least squares in
// y^2 + z^2 + a y + b z + c, about `ref` for conditioning): centre, radius
// and the rms of the points' distances from it. Empty for fewer than 3
// points or points on a line.
struct CircleFit {
  Vec2 centre = Vec2::Zero();
  double rho = 0.0, rms = 0.0;
};
std::optional<CircleFit> fit_circle(std::span<const Vec2> q, const Vec2& ref) {
  if (q.size() < 3) return std::nullopt;
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atv = Eigen::Vector3d::Zero();
  for (const Vec2& p : q) {
    const Vec2 d = p - ref;
    const Eigen::Vector3d a(d.x(), d.y(), 1.0);
    ata += a * a.transpose();
    atv -= a * d.squaredNorm();
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  const Eigen::Vector3d b = ldlt.solve(atv);
  CircleFit f;
  f.centre = ref + Vec2(-0.5 * b(0), -0.5 * b(1));
  const double r2 = 0.25 * (b(0) * b(0) + b(1) * b(1)) - b(2);
  if (!b.allFinite() || !(r2 > 0.0)) return std::nullopt;
  f.rho = std::sqrt(r2);
  double ss = 0.0;
  for (const Vec2& p : q) ss += std::pow((p - f.centre).norm() - f.rho, 2);
  f.rms = std::sqrt(ss / static_cast<double>(q.size()));
  return f;
}

// The optional parts of Matcher::edge_at (see there).
struct EdgeOptions {
  std::span<const Vec2> more_faces = {};
  bool sharp = false;
  bool prep_not_faces = false;
  double max_width = kInf;
  const LineCov* line_cov = nullptr;
  int far_col = -1;
};

class Matcher {
 public:
  Matcher(const Segmentation& s, const TrackerParams& p, const std::vector<int>& longs, std::vector<Vec2>& scratch,
          std::vector<int>& bevels, std::vector<std::uint8_t>& off_plates, std::vector<int>& next_long,
          std::vector<int>& closed)
      : s_(s), p_(p), longs_(longs), scratch_(scratch), bevels_(bevels), off_plates_(off_plates), next_long_(next_long),
        closed_(closed),
        origin_(p.segmentation.ray_origin_yz), tol_(p.surface_tol_mm),
        sigma_(std::max(p.surface_tol_mm / std::max(1.0, p.noise.surface_k), 1e-6)) {
    // cost()'s bounds, and the distance up to which it is 0 found with its
    // own arithmetic.
    in2_ = p.confidence.noise_k * p.confidence.noise_k;
    cap2_ = std::max(p.confidence.cap_sigma * p.confidence.cap_sigma, in2_);
    {
      const auto zero = [&](double d) {
        const double x = d / sigma_;
        return x * x <= in2_;
      };
      double d = std::sqrt(in2_) * sigma_;
      for (int k = 0; k < 64 && std::isfinite(d) && !zero(d); ++k) d = std::nextafter(d, 0.0);
      if (std::isfinite(d) && zero(d)) zero_cost_d_ = d;
    }
    // Columns that look like a ray into a gap (events_between): invalid, or
    // a point (removed, or kept in a segment shorter than s_min) behind the
    // line of the nearer long segment beside it by more than the surface
    // tolerance.
    const int n = static_cast<int>(s.column_state.size());
    off_plates_.assign(n, 0);
    const int s_min = std::max(2, p.segmentation.segments.min_segment_points);
    int prev_long = -1;  // last long segment before the point at hand
    std::size_t next_seg = 0;
    // next_long[k]: the first long segment from segment k on (-1: none).
    next_long_.assign(s.segments.size() + 1, -1);
    for (int k = static_cast<int>(s.segments.size()) - 1; k >= 0; --k)
      next_long_[k] = s.segments[k].count() >= s_min ? k : next_long_[k + 1];
    auto behind = [&](const Vec2& q, int col) {
      const Segment* before = prev_long >= 0 ? &s.segments[prev_long] : nullptr;
      const Segment* after = nullptr;
      for (int k = next_long_[next_seg]; k >= 0 && !after; k = next_long_[k + 1])
        if (s.segments[k].first_col > col) after = &s.segments[k];
      const Segment* near = !before ? after
                            : !after ? before
                                     : (col - before->last_col <= after->first_col - col ? before : after);
      return near && near->line.signed_distance(q) < -tol_;
    };
    std::size_t o = 0;  // next removed point
    for (std::size_t k = 0; k < s.segments.size(); ++k) {
      const Segment& sg = s.segments[k];
      next_seg = k;
      for (; o < s.outlier_cols.size() && s.outlier_cols[o] < sg.first_col; ++o)
        off_plates_[s.outlier_cols[o]] = behind(s.outlier_points[o], s.outlier_cols[o]);
      if (sg.count() >= s_min) {
        prev_long = static_cast<int>(k);
        continue;
      }
      for (int i = sg.first; i <= sg.last; ++i) off_plates_[s.cols[i]] = behind(s.points[i], s.cols[i]);
    }
    next_seg = s.segments.size();
    for (; o < s.outlier_cols.size(); ++o) off_plates_[s.outlier_cols[o]] = behind(s.outlier_points[o], s.outlier_cols[o]);
    // Without branches, so that it vectorises (values 0, 1, 2); restrict:
    // the stores could otherwise alias the state vector's own pointers.
    std::uint8_t* __restrict off = off_plates_.data();
    const std::uint8_t* __restrict state = s.column_state.data();
    for (int col = 0; col < n; ++col) off[col] = state[col] == kColumnInvalid ? kInvalidEvent : off[col];
    // The events of both kinds in one pass (events_between counts one kind).
    if (!s.cols.empty()) {
      span_ = s.cols.back() - s.cols.front() - 1;
      const int c0 = s.cols.front() + 1, c1 = s.cols.back();
      if (c0 < c1 && off[c0] != 0) ++gone_[off[c0] - 1], ++events_[off[c0] - 1];
      int g1 = 0, g2 = 0, e1 = 0, e2 = 0;
      // Eight columns at a time in a 64-bit word: bit 0 of each byte is set
      // for a point event (1), bit 1 for an invalid one (2); each count is
      // the sum of the bytes' bits (a multiply adds the eight bytes, each 0
      // or 1, into the top byte).
      constexpr std::uint64_t kLow = 0x0101010101010101ull;
      auto byte_sum = [](std::uint64_t bits) { return static_cast<int>((bits * kLow) >> 56); };
      int col = c0 + 1;
      for (; col + 8 <= c1; col += 8) {
        std::uint64_t k, prev;
        std::memcpy(&k, off + col, sizeof k);
        std::memcpy(&prev, off + col - 1, sizeof prev);
        const std::uint64_t k1 = k & kLow, k2 = (k >> 1) & kLow, p1 = prev & kLow, p2 = (prev >> 1) & kLow;
        g1 += byte_sum(k1), g2 += byte_sum(k2);
        e1 += byte_sum(k1 & ~p1), e2 += byte_sum(k2 & ~p2);
      }
      for (; col < c1; ++col) {
        const std::uint8_t k = off[col], prev = off[col - 1];
        g1 += k == kPointEvent, g2 += k == kInvalidEvent;
        e1 += (k == kPointEvent) & (prev != kPointEvent), e2 += (k == kInvalidEvent) & (prev != kInvalidEvent);
      }
      gone_[0] += g1, gone_[1] += g2, events_[0] += e1, events_[1] += e2;
    }
  }

  // The noise of single points for the fillet's curvature test
  // (fit_quadratic): the estimate from neighbouring columns, not raised by
  // the long segments' rms (a curved plate's segments deviate from their
  // lines by their curvature; each fit's own residual counts instead).
  void set_point_sigma(double sigma) { point_sigma_ = sigma; }

  // Fills `best` with the best candidate; returns false if there is none.
  bool run(JointType joint, Candidate& best, const TrackPrior* prior = nullptr) {
    found_ = false;
    best_ = &best;
    prior_ = prior;
    n_readings_ = 0;
    n_kept_ = 0;
    n_unplaced_ = 0;
    outside_mm_ = std::numeric_limits<double>::infinity();
    switch (joint) {
      case JointType::Fillet: fillet(); break;
      case JointType::Corner: corner(); break;
      case JointType::Lap: lap(); break;
      case JointType::Butt: butt(); break;
      case JointType::VGroove: vgroove_or_fill(best); break;
      case JointType::Bevel:
      case JointType::UGroove:
      case JointType::JGroove: groove(joint); break;
    }
    return found_;
  }

 private:
  const Segmentation& s_;
  const TrackerParams& p_;
  const std::vector<int>& longs_;
  std::vector<Vec2>& scratch_;
  std::vector<int>& bevels_;
  std::vector<std::uint8_t>& off_plates_;  // per column: looks like a ray into a gap (events_between)
  std::vector<int>& next_long_;            // scratch of the constructor
  std::vector<int>& closed_;               // the pieces of a groove's bottom polyline that close a notch
  Vec2 origin_;
  double tol_;
  double sigma_;  // the noise across the surface, for the evidence (Matcher::weigh)
  double point_sigma_ = 0.0;  // set_point_sigma
  // cov_of's last answers for a line and a point range: the checks that
  // place a point on a plate ask for the same plate's again and again.
  struct CovMemo {
    Line line;
    int first = 0, last = -1;
    LineCov cov;
    bool used = false;
  };
  mutable std::array<CovMemo, 8> cov_memo_{};
  mutable std::size_t cov_memo_next_ = 0;
  // cost() is 0 for distances up to this: found with cost()'s own arithmetic
  // (d / sigma_ and its square are monotonic in d), so the same.
  double zero_cost_d_ = -1.0;
  // cost()'s bounds in squared sigmas: noise_k^2, and cap_sigma^2 (at least that).
  double in2_ = 0.0, cap2_ = 0.0;
  // Columns between the first and last kept point, and the random events
  // among them and their columns (events_between).
  int span_ = 0, events_[2] = {0, 0}, gone_[2] = {0, 0};
  Candidate* best_ = nullptr;
  bool found_ = false;
  // Grooves (their top edges B1, B5) the groove model found but could not
  // place the track point in: a wall's foot not seen (groove_pair).
  static constexpr int kMaxUnplaced = 4;
  std::array<std::pair<Vec2, Vec2>, kMaxUnplaced> unplaced_{};
  int n_unplaced_ = 0;
  const TrackPrior* prior_ = nullptr;
  // The accepted readings' track points and strengths (the strongest
  // kMaxReadings), for the rival of the best one.
  struct Reading {
    Vec2 track;
    double strength;
  };
  static constexpr int kMaxReadings = 32;
  std::array<Reading, kMaxReadings> readings_;
  int n_readings_ = 0;
  // The strongest accepted readings whole (kMaxKept of them), to weigh
  // rivals over the same points (common_log_ratio).
  static constexpr int kMaxKept = 6;
  std::array<Candidate, kMaxKept> kept_;
  int n_kept_ = 0;
  double outside_mm_ = 0.0;  // distance of the nearest reading outside the prior's region

  // Runs of columns that look like rays into a gap (invalid, or a point off
  // the plates behind them) strictly between columns a and b: random events
  // (dropout runs, reflection clusters) to "no joint". `gone` counts their
  // columns.
  // Events of two kinds, counted apart (a sensor's dropout runs and its
  // reflection clusters come at their own rates): runs of invalid columns,
  // and runs of points off the plates behind them.
  static constexpr std::uint8_t kPointEvent = 1, kInvalidEvent = 2;
  int events_between(int a, int b, std::uint8_t type, int* gone = nullptr) const {
    int runs = 0, cols = 0;
    bool in_run = false;
    for (int col = a + 1; col < b; ++col) {
      const bool g = off_plates_[col] == type;
      runs += g && !in_run;
      cols += g;
      in_run = g;
    }
    if (gone) *gone = cols;
    return runs;
  }

  const Vec2& pt(int i) const { return s_.points[i]; }
  const Segment& seg(int q) const { return s_.segments[longs_[q]]; }
  int n_long() const { return static_cast<int>(longs_.size()); }

  void offer(Candidate& c) {
    if (prior_ && c.track) {
      const double d = (*c.track - prior_->track_point).norm();
      if (d > prior_->radius_mm) {
        outside_mm_ = std::min(outside_mm_, d);
        return;
      }
    }
    if ((c.accepted || c.uncertain) && c.track) {
      if (!c.weighed) c.evidence = weigh(c);
      const Reading r{*c.track, c.evidence.strength};
      if (n_readings_ < kMaxReadings) {
        readings_[n_readings_++] = r;
      } else {
        auto weakest = std::min_element(readings_.begin(), readings_.end(),
                                        [](const Reading& x, const Reading& y) { return x.strength < y.strength; });
        if (weakest->strength < r.strength) *weakest = r;
      }
      if (c.evidence.w0 >= 0 && c.evidence.w1 >= c.evidence.w0) {
        if (n_kept_ < kMaxKept) {
          kept_[n_kept_++] = c;
        } else {
          auto weakest = std::min_element(kept_.begin(), kept_.end(), [](const Candidate& x, const Candidate& y) {
            return x.evidence.strength < y.evidence.strength;
          });
          if (weakest->evidence.strength < c.evidence.strength) *weakest = c;
        }
      }
    }
    if (!found_ || better(c, *best_)) *best_ = c;
    found_ = true;
  }

 public:
  // Calls f(track, strength) for each accepted reading farther than
  // ConfidenceParams::distinct_mm from the best one's track point. A rival
  // kept whole is weighed against the best over the same points (the union
  // of their windows, common_log_ratio): its strength is the best's plus
  // that log-likelihood ratio. The others (weaker than the kept ones) by
  // their own evidence.
  template <class F>
  void for_each_rival(const Candidate& best, F f) const {
    const Vec2& track = *best.track;
    // Each kept rival's ratio once (a reading offered twice is listed twice).
    std::array<double, kMaxKept> ratio;
    std::array<bool, kMaxKept> have{};
    for (int k = 0; k < n_readings_; ++k) {
      if ((readings_[k].track - track).norm() <= p_.confidence.distinct_mm) continue;
      double strength = readings_[k].strength;
      for (int j = 0; j < n_kept_; ++j)
        if (*kept_[j].track == readings_[k].track && kept_[j].evidence.strength == strength) {
          if (!have[j]) ratio[j] = common_log_ratio(best, kept_[j]), have[j] = true;
          strength = best.evidence.strength + ratio[j];
          break;
        }
      f(readings_[k].track, strength);
    }
  }
  template <class F>
  void for_each_reading(F f) const {
    for (int k = 0; k < n_readings_; ++k) f(readings_[k].track, readings_[k].strength);
  }
  // Distance from the prior's point to the nearest reading outside its region
  // (infinite if none).
  double outside_mm() const { return outside_mm_; }

  // What reading c leaves unexplained beyond its joint: the long segments
  // outside the plates' facing ends, each within the butt's plate angle
  // (ButtParams::max_plate_angle_deg) of the plate on its side, whose points
  // mostly lie on none of the reading's lines, extended: a step to a third
  // plate, where the joint may be instead (a plate's end face, square to
  // it, is no such thing). Returns the robust cost of the strongest under c
  // (cost(), as Evidence::strength weighs a point; 0: none) and its columns.
  double unexplained_beyond(const Candidate& c, int& first_col, int& last_col) const {
    double best = 0.0;
    for (int q = 0; q < n_long(); ++q) {
      const Segment& sg = seg(q);
      if (sg.last >= c.pa.last && sg.first <= c.pb.first) continue;  // the joint's own
      const Plate& side = sg.last < c.pa.last ? c.pa : c.pb;
      // (a curved plate's direction where the segment lies)
      if (!sg.fitted || acute_angle_deg(sg.line, side.tangent_at(sg.centroid)) > p_.butt.max_plate_angle_deg) continue;
      const int stride = std::max(1, sg.count() / 32);
      int n = 0, n_off = 0;
      double sum = 0.0;
      for (int i = sg.first; i <= sg.last; i += stride) {
        const Vec2& q_pt = pt(i);
        double d = std::min(c.pa.distance(q_pt), c.pb.distance(q_pt));
        for (int k = 0; k < c.n_more; ++k) d = std::min(d, c.more[k].distance(q_pt));
        ++n;
        n_off += d > 2.0 * tol_;
        sum += std::min(stride, sg.last - i + 1) * cost(d);
      }
      if (2 * n_off > n && sum > best) best = sum, first_col = sg.first_col, last_col = sg.last_col;
    }
    return best;
  }

  // A bump beyond reading c's joint: a run of kept points outside its
  // plates' facing ends off the line that explains them under c, between
  // two points on it, with more of them than a reflection cluster (2
  // max_cluster_points) more than 2 surface tolerances and noise_k sigmas
  // in front of that line (towards the sensor), no gap of more than
  // max_merge_gap_points columns among them: a cap standing on the
  // surface (a tack weld, a bead), under
  // which the joint may be. A step to a third plate does not come back to
  // the line (unexplained_beyond weighs it); a reflection cluster is
  // shorter. Returns the strongest one's cost under c (as cost_under
  // weighs a point; 0: none), its columns and its height (mm).
  double bump_beyond(const Candidate& c, int& first_col, int& last_col, double& height_mm) const {
    const int n = static_cast<int>(s_.cols.size());
    if (n == 0) return 0.0;
    const int ca = s_.cols[c.pa.last], cb = s_.cols[c.pb.first];
    const int max_cluster = max_cluster_run();
    const int max_gap = std::max(1, p_.segmentation.segments.max_merge_gap_points);
    // 1: on the reading's line there, 2: in front of it (off), 0: neither
    // (behind it, or off by less than the bump's margin: ends nothing).
    auto state = [&](int i, double& front) {
      const Vec2& q = pt(i);
      const int col = s_.cols[i];
      double d = std::numeric_limits<double>::infinity(), sd = 0.0;
      auto take = [&](double signed_d) {
        if (std::abs(signed_d) < d) d = std::abs(signed_d), sd = signed_d;
      };
      if (col < ca) take(c.pa.signed_distance(q));
      if (col > cb) take(c.pb.signed_distance(q));
      for (int k = 0; k < c.n_more; ++k) take(c.more[k].signed_distance(q));
      front = sd;
      if (cost(d) == 0.0) return 1;
      return sd > 2.0 * tol_ ? 2 : 0;
    };
    // Runs of points off the line (in front, or off by less than the
    // margin: noise over a cap's feet) between two points on it, none of
    // the joint's own columns or a gap of more than max_gap columns among
    // them; a bump when more than max_cluster of them stand in front. Such
    // a run is more than max_cluster points long, so looking at every
    // (max_cluster + 1)-th point finds one of its points: only around a
    // point off the line are the run and its ends looked for (the first
    // strongest run in column order, as a scan of every point finds it).
    auto joint = [&](int i) { return s_.cols[i] >= ca && s_.cols[i] <= cb; };
    auto gap_before = [&](int i) { return i > 0 && s_.cols[i] - s_.cols[i - 1] > max_gap; };
    const int stride = max_cluster + 1;
    double best = 0.0;
    for (int i = 0; i < n;) {
      double f = 0.0;
      if (joint(i) || state(i, f) == 1) {
        i += stride;
        continue;
      }
      // The point on the line before the run, none if the run starts at a
      // gap, the joint or the profile's start.
      int left = -1;
      for (int k = i;;) {
        if (gap_before(k) || k == 0) break;
        --k;
        if (joint(k)) break;
        if (state(k, f) == 1) {
          left = k;
          break;
        }
      }
      // The run to the point on the line after it (or to where it ends
      // without one): its points in front.
      int fronts = 0, run_first = -1, run_last = -1, right = -1, k = (left >= 0 ? left : i) + 1;
      double sum = 0.0, top = 0.0;
      for (; k < n && !joint(k) && !gap_before(k); ++k) {
        const int st = state(k, f);
        if (st == 1) {
          right = k;
          break;
        }
        if (st == 2) {
          if (run_first < 0) run_first = k;
          run_last = k, ++fronts, sum += cost(std::abs(f)), top = std::max(top, f);
        }
      }
      if (left >= 0 && right >= 0 && fronts > max_cluster && sum > best)
        best = sum, first_col = s_.cols[run_first], last_col = s_.cols[run_last], height_mm = top;
      // Next: from the point on the line that ended it (the next run's
      // start), or where the run was cut.
      i = right >= 0 ? right + 1 : std::max(k, i + 1);
    }
    return best;
  }

 private:
  // The most points a reflection cluster holds: twice what step 1 removes
  // as one (OutlierParams::max_cluster_points). A longer run off every line
  // is a surface.
  int max_cluster_run() const { return 2 * std::max(1, p_.segmentation.outliers.max_cluster_points); }

  // A point's cost at distance d from the line that explains it: nothing
  // within noise_k sigmas (noise, waviness: no evidence either way), then
  // growing as the Gaussian's x^2 / 2 up to cap_sigma (an outlier).
  double cost(double d) const {
    if (std::abs(d) <= zero_cost_d_) return 0.0;  // within noise_k sigmas, without the division
    const double x = d / sigma_;
    return x * x <= in2_ ? 0.0 : 0.5 * (std::min(x * x, cap2_) - in2_);
  }

  // The cost of a random event of `cols` columns (a dropout run, a
  // reflection cluster): ln(1 / p) for its start, p the rate of such events
  // per column among the profile's span_ columns (`events` of them, Laplace's
  // rule), and ln(1 / q) for each further column, q the share of their
  // `gone` columns that continue one.
  double event_cost(int cols, double events, double gone, bool invalid = false) const {
    if (cols <= 0) return 0.0;
    const double p = (events + 1.0) / (span_ + 2.0), q = (gone - events + 1.0) / (gone + 2.0);
    const double run = (cols - 1) * std::log(1.0 / q);
    // A run of invalid columns may also be one shadow (a clamp's, the
    // torch's, a wall's towards the camera): its length then follows no
    // rate of the profile's other runs, P(k) = w / (k (k + 1)) for k
    // columns, w = ConfidenceParams::shadow_weight; the cheaper of the two.
    const double w = p_.confidence.shadow_weight;
    if (invalid && w > 0.0 && cols > 1)
      return std::log(1.0 / p) + std::min(run, std::log(cols * (cols + 1.0) / w));
    return std::log(1.0 / p) + run;
  }
  // One of the profile's events of that kind, priced by the rate of the
  // profile's other events (as weigh() leaves a reading's own out: an
  // event must not make itself likely, a wide gap's columns the share
  // that continue a run).
  double event_cost(int cols, std::uint8_t type) const {
    return event_cost(cols, std::max(0, events_[type - 1] - 1), std::max(0, gone_[type - 1] - cols),
                      type == kInvalidEvent);
  }

  // The cost of the kept points i0..i1 (every stride-th, weighted), the
  // points removed among them and their invalid columns under reading c, in
  // one noise model for every reading: a point on a line of the reading
  // costs cost() of its distance; a run of points off every line is
  // priced as the cheaper of their costs and a random event (a reflection
  // cluster) when it is short enough to be one; a run of invalid columns
  // as a random event (a dropout). What the reading explains between its
  // plates' ends costs nothing: the rays into an open joint's opening
  // (points behind both plates inside it), a groove's walls and bottom
  // (everything not in front of its tops' line), and any invalid columns
  // there (the opening, a shadow at the joint).
  double cost_under(const Candidate& c, int i0, int i1, int stride) const {
    const int ca = s_.cols[c.pa.last], cb = s_.cols[c.pb.first];
    // The reading's lines: its plates' (each on its own side of the joint)
    // and those it sees beside them.
    std::array<Line, 2 + std::tuple_size_v<decltype(c.more)>> lines;
    int n_lines = 0;
    lines[n_lines++] = c.pa.line, lines[n_lines++] = c.pb.line;
    for (int k = 0; k < c.n_more; ++k) lines[n_lines++] = c.more[k];
    auto explained = [&](const Vec2& q, int col) {
      if (col <= ca || col >= cb) return false;
      if (c.groove_top) return c.groove_top->signed_distance(q) <= tol_;
      return c.open_joint && std::min(c.pa.line.signed_distance(q), c.pb.line.signed_distance(q)) < -tol_ &&
             c.opening.contains(q);
    };
    double total = 0.0, run = 0.0;
    int run_n = 0, prev_col = -2;
    // A reflection cluster is a few points: a longer run off every line is
    // a surface the reading misses.
    const int max_cluster = max_cluster_run();
    auto close = [&] {
      if (run_n > 0) total += run_n <= max_cluster ? std::min(run, event_cost(run_n, kPointEvent)) : run;
      run = 0.0, run_n = 0;
    };
    auto point = [&](const Vec2& q, int col, int w, bool removed) {
      if (removed && col != prev_col + 1) close();  // removed points: a run ends where their columns do
      prev_col = col;
      if (explained(q, col)) return close();
      // Each plate explains the points on its side of the joint only: the
      // reading says where each ends, and a point between the ends that lies
      // on a plate's line says the plate goes on (lines[0], lines[1]: the
      // plates'; the others, the lines it sees beside them, anywhere).
      double d = std::numeric_limits<double>::infinity();
      if (col <= ca) d = c.pa.distance(q);  // lines[0], or the curved plate
      if (col >= cb) d = c.pb.distance(q);
      for (int k = 2; k < n_lines; ++k) d = std::min(d, lines[k].distance(q));
      const double x = cost(d);
      if (x > 0.0) run += w * x, run_n += w;
      else close();
    };
    for (int i = i0; i <= i1; i += stride) point(pt(i), s_.cols[i], std::min(stride, i1 - i + 1), false);
    close();
    const int c0 = s_.cols[i0], c1 = s_.cols[i1];
    prev_col = -2;
    const auto removed = outliers_between(c0, c1);
    for (std::size_t k = 0; k < removed.size(); ++k)
      point(removed[k], s_.outlier_cols[static_cast<std::size_t>(&removed[k] - s_.outlier_points.data())], 1, true);
    close();
    // Each run of invalid columns outside the plates' ends, in column order
    // (memchr finds the next invalid column: most are valid).
    const std::uint8_t* state = s_.column_state.data();
    for (int col = c0 + 1; col < c1;) {
      const void* hit = std::memchr(state + col, kColumnInvalid, static_cast<std::size_t>(c1 - col));
      if (!hit) break;
      col = static_cast<int>(static_cast<const std::uint8_t*>(hit) - state);
      int gone = 0;
      for (; col < c1 && state[col] == kColumnInvalid && (col <= ca || col >= cb); ++col) ++gone;
      if (gone > 0) total += event_cost(gone, kInvalidEvent);
      else ++col;
    }
    return total;
  }

  // How much better reading b explains the points than reading a, over the
  // same points: the union of their windows (cost_under of a less that of
  // b, a log-likelihood ratio; > 0: b is the better reading).
  double common_log_ratio(const Candidate& a, const Candidate& b) const {
    const int i0 = std::min(a.evidence.w0, b.evidence.w0), i1 = std::max(a.evidence.w1, b.evidence.w1);
    if (i0 < 0 || i1 < i0) return b.evidence.strength - a.evidence.strength;
    const int stride = std::max(1, (i1 - i0) / 192);
    return cost_under(a, i0, i1, stride) - cost_under(b, i0, i1, stride);
  }

  // The evidence for reading c (see Evidence): over the points within
  // ConfidenceParams::window_mm of the track point, the robust cost of "no
  // joint: one line through them" less that of "the joint as read" (each
  // point on the nearest of its lines; in an open joint, a point between the
  // plates behind both, inside its opening, on a wall or deep enough, or an
  // invalid column, counts as a ray into the joint).
  Evidence weigh(const Candidate& c) const {
    Evidence ev;
    const ConfidenceParams& cp = p_.confidence;
    const double sig = sigma_;
    const Vec2 t = *c.track;
    const int n = static_cast<int>(s_.points.size());
    // The window: the kept points from the plates' facing ends outwards while
    // within window_mm of the track point (past up to 8 beyond it: a
    // surface can turn back towards it), and everything between the ends.
    auto reach_out = [&](int from, int step) {
      int last = from, beyond = 0;
      for (int i = from; i >= 0 && i < n && beyond <= 8; i += step) {
        if ((pt(i) - t).squaredNorm() <= cp.window_mm * cp.window_mm) last = i, beyond = 0;
        else ++beyond;
      }
      return last;
    };
    const int w0 = reach_out(c.pa.last, -1), w1 = reach_out(c.pb.first, +1);
    // "No joint": one line through the window, the best of either plate's
    // line continued and the fit to the plates' points in it (not that fit
    // alone: a few points of a gap or a bead pull it off).
    // The plates' points there (a plate's index range can hold a short
    // piece off its line: a reflection cluster), every stride-th (about 48 a
    // side on dense profiles).
    const int stride = std::max(1, std::max(c.pa.last - w0, w1 - c.pb.first) / 48);
    // (a curved plate's: also their squared distances from its arc, in ss)
    auto on_plate = [&](int from, int to, const Plate& pl, double& ss) {
      PointSums ps;
      ss = 0.0;
      for (int i = from; i <= to; i += stride)
        if (const double d = pl.distance(pt(i)); d <= 2.0 * tol_) ps.add(pt(i) - s_.ref_), ss += d * d;
      return ps;
    };
    double ssa = 0.0, ssb = 0.0;
    const PointSums sa = on_plate(std::max(w0, c.pa.first), c.pa.last, c.pa, ssa);
    const PointSums sb = on_plate(c.pb.first, std::min(w1, c.pb.last), c.pb, ssb);
    PointSums sums = sa;
    sums += sb;
    const auto both = s_.fit(sums);
    Plate one = c.pa;  // one line through both plates' points
    one.rho = 0.0;
    if (both) one.line = both->line;
    const Plate nulls[3] = {c.pa, c.pb, one};
    // The joint: its plates' lines (or arcs), or for parallel plates (butt,
    // lap) the two parallel lines that fit the plates' points there best
    // (one direction, two offsets): two free lines would also fit a wavy
    // plate split at a crest much better than one.
    Plate la = c.pa, lb = c.pb;
    if (c.parallel && sa.n >= 2 && sb.n >= 2) {
      const Moments ma = s_.moments(sa), mb = s_.moments(sb);
      Moments pooled;
      pooled.count = ma.count + mb.count;
      pooled.syy = ma.syy + mb.syy, pooled.szz = ma.szz + mb.szz, pooled.syz = ma.syz + mb.syz;
      if (const auto f = fit_line(pooled)) {
        Line l = f->line;
        l.c = l.n.dot(ma.mean);
        l.orient_towards(origin_);
        la.line = l, la.rho = 0.0;
        l = f->line;
        l.c = l.n.dot(mb.mean);
        l.orient_towards(origin_);
        lb.line = l, lb.rho = 0.0;
      }
    }
    // Each plate a line there: the rms about its line (or arc), in noise sigmas.
    auto rms_of = [&](const PointSums& ps, double ss, const Plate& pl) {
      if (ps.n < 2) return 0.0;
      if (pl.rho != 0.0) return std::sqrt(ss / ps.n) / sig;
      const Line& l = pl.line;
      const Moments m = s_.moments(ps);
      const Vec2 d = l.direction();
      // Second moment across the line about the points' own mean, and the
      // mean's offset from it.
      const double across = d.y() * d.y() * m.syy + d.x() * d.x() * m.szz - 2.0 * d.x() * d.y() * m.syz;
      const double off = l.signed_distance(m.mean);
      return std::sqrt(std::max(0.0, across / ps.n + off * off)) / sig;
    };
    ev.fit = std::max(rms_of(sa, ssa, la), rms_of(sb, ssb, lb));
    double r0[3] = {0.0, 0.0, 0.0}, r1 = 0.0, event = 0.0;
    int into = 0;   // rays into the open joint that found something
    int stray = 0;  // points between the plates of an open joint that fit nothing of it
    // Each point counts `w` times (the plates' points are sampled, below).
    // `side`: 0 between the plates' ends; -1 or +1 beside the joint, on
    // plate a's or b's side, where a point is explained by the plate on its
    // own side or a line seen beside them (ConfidenceParams::own_side_only),
    // as in cost_under.
    auto weigh_point = [&](const Vec2& q, int side, int w = 1) {
      const bool between = side == 0;
      ev.points += w;
      const double da = c.pa.line.signed_distance(q), db = c.pb.line.signed_distance(q);
      // A ray into the joint: between the plates' ends, inside the opening,
      // behind a plate (the higher plate's edge face stands in front of the
      // lower one). Part of the one event weighed below.
      if (between && c.open_joint && std::min(da, db) < -tol_ && c.opening.contains(q)) {
        ++into;
        return;
      }
      const int own = cp.own_side_only ? side : 0;
      double d = own < 0 ? la.distance(q) : own > 0 ? lb.distance(q) : std::min(la.distance(q), lb.distance(q));
      for (int k = 0; k < c.n_more; ++k) d = std::min(d, c.more[k].distance(q));
      if (d > tol_) ev.unexplained += w;
      if (between && c.open_joint && d > tol_) {
        ++stray;  // weighed below as a random event under either reading
        return;
      }
      for (int k = 0; k < 3; ++k) r0[k] += w * cost(nulls[k].distance(q));
      r1 += w * cost(d);
    };
    // The plates' points beside the joint, every stride-th, weighted;
    // everything between the plates' ends.
    for (int i = c.pa.last; i >= w0; i -= stride) weigh_point(pt(i), -1, std::min(stride, i - w0 + 1));
    for (int i = c.pa.last + 1; i < c.pb.first && i <= w1; ++i) weigh_point(pt(i), 0);
    for (int i = c.pb.first; i <= w1; i += stride) weigh_point(pt(i), +1, std::min(stride, w1 - i + 1));
    const int ca = s_.cols[c.pa.last], cb = s_.cols[c.pb.first];
    for (const Vec2& o : outliers_between(s_.cols[w0], s_.cols[w1])) {
      // Removed points count between the plates' ends only (elsewhere they
      // are the outliers that step 1 found).
      const auto k = &o - s_.outlier_points.data();
      const int col = s_.outlier_cols[static_cast<std::size_t>(k)];
      if (col > ca && col < cb) weigh_point(o, 0);
    }
    // "No joint" must explain the rays into the joint (invalid columns and
    // the points counted above) and the stray points between the plates as
    // random events: the invalid columns as a dropout run, the points as a
    // reflection cluster (both, where the rays found both: a dropout alone
    // shows no points behind the plates). Each, of k columns, costs
    // ln(1 / p) for its start, p the rate of such events per column elsewhere
    // in the profile, and ln(1 / q) for each further column, q the share of
    // their columns that continue one (Laplace's rule for both). The joint
    // must explain its stray points so too (a reflection in the gap, or the
    // part of a reflection cluster that no gap there could show).
    if (c.open_joint && ca < cb) {
      const int invalid = s_.invalid_columns_between(ca, cb);
      auto random_event = [&](int cols, std::uint8_t type) {
        if (cols <= 0) return 0.0;
        int own_gone = 0;
        const int own_events = events_between(ca, cb, type, &own_gone);
        return event_cost(cols, std::max(0, events_[type - 1] - own_events), std::max(0, gone_[type - 1] - own_gone),
                          type == kInvalidEvent);
      };
      event = random_event(invalid, kInvalidEvent) + random_event(into + stray, kPointEvent) - random_event(stray, kPointEvent);
    }
    ev.strength = std::min({r0[0], r0[1], r0[2]}) - r1 + event;
    ev.w0 = w0, ev.w1 = w1;
    return ev;
  }

  static Plate plate_of(const Segment& sg) {
    Plate pl{sg.first, sg.last, sg.line, sg.centroid};
    pl.line_rms = sg.rms_mm;
    return pl;
  }
  std::optional<Plate> plate_of(int first, int last) const {
    const auto f = s_.fit(first, last);
    if (!f) return std::nullopt;
    return Plate{first, last, f->line, f->centroid};
  }

  // The facing end points of two plates are close enough to be one joint.
  bool near_enough(const Plate& a, const Plate& b) const {
    return (pt(b.first) - pt(a.last)).norm() <= p_.max_joint_width_mm;
  }

  // Where column `col`'s ray meets line l.
  std::optional<Vec2> ray_hit(int col, const Line& l) const {
    const double t = s_.column_tan(col);
    if (!std::isfinite(t)) return std::nullopt;
    const Vec2 d(t, 1.0);
    const double den = l.n.dot(d);
    if (std::abs(den) < 1e-12) return std::nullopt;
    const double u = (l.c - l.n.dot(origin_)) / den;
    if (!(u > 0.0)) return std::nullopt;
    return origin_ + u * d;
  }

  // The unit direction of column col's ray (from the ray origin).
  Vec2 ray_dir(int col) const {
    const double t = s_.column_tan(col);
    return std::isfinite(t) ? Vec2(t, 1.0).normalized() : Vec2(0.0, 1.0);
  }

  // How precisely plate pl's line is known (LineCov): its points' residuals
  // about it pooled with the profile's noise worth kPriorDof degrees of
  // freedom (a bevel of four points has two of its own). The points of
  // [first, last] farther than kOutlierSigma noise sigmas from the line are
  // not the plate's (a plate extended over pieces of one line spans the
  // short pieces between them). A line with no spread along it is taken
  // as known to 1000 radians.
  static constexpr double kPriorDof = 2.0;
  static constexpr double kOutlierSigma = 5.0;
  LineCov cov_of(const Plate& pl) const { return cov_of(pl.line, pl.first, pl.last); }
  LineCov cov_of(const Line& line, int first, int last) const {
    for (const CovMemo& m : cov_memo_)
      if (m.used && m.first == first && m.last == last && m.line.c == line.c && m.line.n == line.n) return m.cov;
    const PointSums sums = s_.sums_near(line, kOutlierSigma * sigma_, first, last);
    const LineCov lc = cov_of(line, sums);
    cov_memo_[cov_memo_next_++ % cov_memo_.size()] = {line, first, last, lc, true};
    return lc;
  }
  // The same for a line fitted to the points of `sums` (relative to s_.ref_).
  LineCov cov_of(const Line& line, const PointSums& sums) const {
    const Moments m = s_.moments(sums);
    LineCov lc = line_cov(line, m, residual_variance(line, m, sigma_ * sigma_, kPriorDof));
    lc.var_angle = std::min(lc.var_angle, 1e6);
    return lc;
  }
  // The covariance of a point x on plate pl's line placed along it by
  // something of covariance `cov` (of which only the part along the line
  // counts): across the line the line's own (a butt's or a lap's track
  // point on the lower plate).
  Eigen::Matrix2d on_plate_cov(const Plate& pl, const Vec2& x, const Eigen::Matrix2d& cov) const {
    const Vec2 d = pl.line.direction(), n = pl.line.n;
    const Eigen::Matrix2d along = d * d.transpose();
    return along * cov * along + cov_of(pl).across_var(x) * n * n.transpose();
  }
  // The covariance of a point q = p + J_o o + J_a a moved by a line's
  // offset o and angle a (LineCov, independent).
  static Eigen::Matrix2d moved(const LineCov& lc, const Vec2& j_offset, const Vec2& j_angle) {
    return lc.var_offset * j_offset * j_offset.transpose() + lc.var_angle * j_angle * j_angle.transpose();
  }

  // Where a plate ends along its line, when the surface beyond meets it at a
  // shallow angle (a v-groove's bevel and its root face, 30 degrees): the
  // last points of the plate may lie on that surface instead, within the
  // surface tolerance of the plate's line (docs/JOINTS.md "Localization").
  // For each t = 2..kEndPoints (leaving at least 4 on the plate), the t
  // points at its end (at_last: its last points, else its first) are
  // weighed on a line of each direction `dirs` (free offset) against the
  // plate's line (Gaussian, the profile's noise); "none of them" has prior
  // 1/2, the splits share the other half. The edge then lies between the
  // split's two points. Returns the posterior mean square (mm^2) of the
  // edge's distance along the plate from `edge` (as read).
  static constexpr int kEndPoints = 12;
  double end_spread(const Plate& pl, bool at_last, const Vec2& edge, std::span<const Vec2> dirs) const {
    const int tmax = std::min(kEndPoints, pl.count() - 4);
    if (tmax < 2 || dirs.empty()) return 0.0;
    const Vec2 d = pl.line.direction();
    const double s2 = 2.0 * sigma_ * sigma_;
    const double prior = std::log(0.5 / ((tmax - 1) * static_cast<double>(std::min(dirs.size(), std::size_t{2}))));
    auto q = [&](int j) { return pt(at_last ? pl.last - j : pl.first + j); };
    const double a_edge = edge.dot(d);
    // log weights and squared distances: "none" first (log(1/2), distance 0).
    double lw_max = std::log(0.5), sum_w = 0.0, sum_wd = 0.0;
    double on_plate = 0.0;
    constexpr std::size_t kDirs = 2;
    std::array<double, kDirs * kEndPoints> lw{}, dd{};
    int k = 0;
    std::array<double, kDirs> sg{}, sg2{};  // per direction: sum and sum of squares of the points' offsets
    for (int t = 1; t <= tmax; ++t) {
      const Vec2 p = q(t - 1);
      on_plate += pl.line.signed_distance(p) * pl.line.signed_distance(p);
      for (std::size_t f = 0; f < dirs.size() && f < sg.size(); ++f) {
        const double o = p.dot(Vec2(-dirs[f].y(), dirs[f].x()));
        sg[f] += o, sg2[f] += o * o;
        if (t < 2) continue;
        const double alt = std::max(sg2[f] - sg[f] * sg[f] / t, 0.0);
        const double a = 0.5 * (q(t - 1).dot(d) + q(t).dot(d)) - a_edge;
        lw[k] = prior - (alt - on_plate) / s2, dd[k] = a * a;
        lw_max = std::max(lw_max, lw[k]);
        ++k;
      }
    }
    sum_w = std::exp(std::log(0.5) - lw_max);
    for (int i = 0; i < k; ++i) {
      // exp is 0 below about -745.13 (the least subnormal): no call there.
      const double x = lw[i] - lw_max, w = x < -746.0 ? 0.0 : std::exp(x);
      sum_w += w, sum_wd += w * dd[i];
    }
    return sum_wd / sum_w;
  }

  // X lies between the rays of columns a and b (seen from the ray origin).
  bool between_rays(const Vec2& x, int a, int b) const {
    const double dz = x.y() - origin_.y();
    if (!(dz > 0.0)) return false;
    const double t = (x.x() - origin_.x()) / dz;
    const double ta = s_.column_tan(a), tb = s_.column_tan(b);
    const double slack = 1e-9 + 1e-6 * std::abs(tb - ta);
    return t >= std::min(ta, tb) - slack && t <= std::max(ta, tb) + slack;
  }

  // Along the plate's line, away from its centroid, at `end`.
  static Vec2 outward(const Plate& pl, const Vec2& end) {
    Vec2 d = pl.line.direction();
    return d.dot(end - pl.centroid) < 0.0 ? Vec2(-d) : d;
  }

  // The edge of a plate at its end point `end_point`: between that point and
  // where the ray of column `far_col` (the first beyond it that missed the
  // plate, first_missed; -1: `beyond_col`, the next column) meets the
  // plate's line. If square_edges and a point of `faces` lies on the edge
  // face (behind the plate, on a line along face_dir that meets the plate
  // inside that interval), the edge is where that face meets the plate.
  // Rounded or chamfered edges are looked for (rounding()) from `beyond_col` on unless `sharp`
  // (a bevel's root edge: its root face falls away from the bevel too).
  // The edge lies at most `max_width` past the end point's foot (where what
  // is seen beyond bounds it more closely than the next ray). `line_cov`:
  // how precisely the plate's line is known, if not from its points
  // (cov_of). `more_faces` (EdgeOptions): further points that may lie on
  // the edge face.
  Edge edge_at(const Plate& pl, const Vec2& end_point, int beyond_col, const Vec2* face_dir,
               std::span<const Vec2> faces, const EdgeOptions& opt = {}) const {
    const std::span<const Vec2> more_faces = opt.more_faces;
    const bool sharp = opt.sharp, prep_not_faces = opt.prep_not_faces;
    const double max_width = opt.max_width;
    const LineCov* line_cov = opt.line_cov;
    const int far_col = opt.far_col < 0 ? beyond_col : opt.far_col;
    const Vec2 near = pl.line.project(end_point);
    const Vec2 dir = outward(pl, near);
    Vec2 far = near;
    if (const auto x = ray_hit(far_col, pl.line); x && (*x - near).dot(dir) > 0.0)
      far = (*x - near).dot(dir) > max_width ? Vec2(near + max_width * dir) : *x;
    double width = (far - near).dot(dir);
    // A rounded or chamfered edge: the points in the columns right beyond
    // the plate's end fall away behind its line, moving on along it. The
    // edge (where the plate's top and its edge face would meet) lies past
    // them: where a wall below them starts, or for a circular rounding
    // tangent to the plate at (a, h) along and behind it, r = (a^2 + h^2) /
    // 2h along; the interval [a, r] is the edge's uncertainty.
    // A face point seen below it still fixes the edge exactly.
    const Rounding rd = sharp ? Rounding{} : rounding(pl, near, dir, beyond_col);
    double r = 0.0;
    if (rd.along > 0.0) {
      r = rd.wall ? rd.along
                  : std::clamp((rd.along * rd.along + rd.depth * rd.depth) / (2.0 * rd.depth), rd.along,
                               rd.along + kMaxRoundingMm);
      width = std::max(width, r + tol_);
    }
    if (face_dir && p_.square_edges) {
      Vec2 sum = Vec2::Zero();
      double sum_a = 0.0, sum_aa = 0.0;
      int k = 0;
      const double den = pl.line.n.dot(*face_dir);
      for (const auto span : {faces, more_faces}) {
        for (const Vec2& q : span) {
          const double h = -pl.line.signed_distance(q);
          if (h < tol_ || std::abs(den) < 0.2) continue;  // not behind the plate
          // Past a rounding or chamfer (rounding()), its own points are no
          // face points: a face drops more than it runs on from the end.
          if (prep_not_faces && rd.along > 0.0 && h <= (q - near).dot(dir) + tol_) continue;
          const Vec2 f = q + (pl.line.c - pl.line.n.dot(q)) / den * *face_dir;
          const double a = (f - near).dot(dir);
          if (a < -tol_ || a > width + tol_) continue;
          sum += f;
          sum_a += a, sum_aa += a * a;
          ++k;
        }
      }
      if (k > 0) {
        // The faces' feet move with the plate's line along the face; each
        // face point has the profile's noise.
        const Vec2 e = sum / k, g = *face_dir / den;
        const LineCov lc = line_cov ? *line_cov : cov_of(pl);
        const double u = (e - lc.mean).dot(lc.direction());
        Eigen::Matrix2d cov = moved(lc, g, u * g) + sigma_ * sigma_ / k * Eigen::Matrix2d::Identity();
        // On a square face the feet coincide but for the noise; spread
        // along the plate beyond that, they are no face but a chamfer, a
        // rounding or a sheared face, and the edge may lie anywhere among
        // them: their variance beyond the noise's is added (a uniform
        // spread's, as an edge interval's).
        if (k > 1) {
          const double spread =
              std::max(0.0, (sum_aa - sum_a * sum_a / k) / (k - 1) - sigma_ * sigma_ / (den * den));
          cov += spread * pl.line.direction() * pl.line.direction().transpose();
        }
        return Edge{e, 0.0, cov};
      }
    }
    // The covariance (docs/JOINTS.md "Localization"): the line's offset and
    // angle move the end point's foot across the line and the ray's hit
    // along that ray; the end point's own noise (along its ray, the
    // profile's noise) moves its foot along the line; the interval the edge
    // can lie in counts as a uniform spread (its half width h: h^2 / 3).
    const LineCov lc = line_cov ? *line_cov : cov_of(pl);
    const Vec2 n = pl.line.n, d = pl.line.direction();
    const Vec2 ray = ray_dir(beyond_col);
    const double end_var = sigma_ * sigma_ * ray.dot(d) * ray.dot(d);
    const double u_near = (near - lc.mean).dot(d);
    if (rd.along > 0.0) {
      const Vec2 e = near + r * dir;
      const double h = std::max(0.5 * (r - rd.along), tol_), u = (e - lc.mean).dot(d);
      return Edge{e, h, moved(lc, n, u * n) + (end_var + h * h / 3.0) * d * d.transpose()};
    }
    const double h = 0.5 * (far - near).dot(dir);
    if (!(h > 0.0)) return Edge{near, 0.0, moved(lc, n, u_near * n) + end_var * d * d.transpose()};
    const Vec2 ray_far = far_col == beyond_col ? ray : ray_dir(far_col);
    const double rn = ray_far.dot(n);
    if (!(std::abs(rn) > 1e-9))
      return Edge{0.5 * (near + far), h, Eigen::Matrix2d::Constant(std::numeric_limits<double>::infinity())};
    const Vec2 g = ray_far / rn;  // the ray's hit moves along it by the line's shift / (ray . n)
    const double u_far = (far - lc.mean).dot(d);
    return Edge{0.5 * (near + far), h,
                moved(lc, 0.5 * (n + g), 0.5 * (u_near * n + u_far * g)) +
                    (0.25 * end_var + h * h / 3.0) * d * d.transpose()};
  }

  // The edge face as seen past plate pl's end `near` (outwards `dir`), at
  // any slant (a corner's mitred end): the kept points in consecutive
  // columns from beyond_col on, behind the plate's line, not on `other`'s
  // (the other plate's line, if given) and going no shallower behind both
  // lines (past a notch's bottom they climb its other side; as far as 64
  // columns), up to the deepest of them, end in a run on one line, grown
  // from the deepest point (or the one before it: noise past a notch's
  // bottom) back while each point lies within the surface tolerance of the
  // line through the run so far. That run is the plate's own edge face when
  // it has at least kFacePoints points; lies more than 20 degrees off the
  // plate; reaches deeper than a rounding or chamfer can (kMaxRoundingMm),
  // or else lies within kSquareFaceDeg of square to the plate or goes back
  // under it; its seen side faces away from the plate (not the other
  // plate's end seen through a gap, which faces back); lies more than 5
  // degrees off the rays if it is that shallow; and meets the plate's line
  // past the points before it (the rounding or chamfer it runs into),
  // within kMaxRoundingMm of the end. The edge is then where the two lines
  // meet (Edge::face: the run's line).
  // Otherwise, with kFacePoints of the plate's own points
  // walked or more (a rounding or chamfer seen over several columns, not a
  // ray or two into a gap; up to the other plate's face where one was seen
  // through the gap): the edge lies past all of them and short of where the
  // next column's ray, which passed them, meets the plate's line (at most
  // kMaxRoundingMm further), read at the middle. Where a run that cannot be
  // the face still leaves the edge unknown (along the rays; meeting the
  // plate short of the points before it): nothing.
  static constexpr int kFacePoints = 4;
  static constexpr double kSquareFaceDeg = 15.0;
  // `end_point`, `beyond_col`: as edge_at's; `other`: the other plate's line.
  std::optional<Edge> seen_face(const Plate& pl, const Vec2& end_point, int beyond_col, const Line* other) const {
    const Vec2 near = pl.line.project(end_point);
    const Vec2 dir = outward(pl, near);
    const auto start = walk_start(beyond_col, near, dir);
    if (!start) return std::nullopt;
    const int i0 = start->first, step = start->second;  // (no structured binding: clang 14 cannot capture one)
    const int n = static_cast<int>(s_.points.size());
    int last = -1;
    double deepest = 0.0;
    for (int i = i0, prev_col = beyond_col - step;
         i >= 0 && i < n && s_.cols[i] == prev_col + step && std::abs(i - i0) < 64; prev_col = s_.cols[i], i += step) {
      // Depth behind the plate, and behind the other plate too where
      // given (past a notch's bottom the points climb the other side).
      const double h = -pl.line.signed_distance(pt(i));
      const double d = other ? std::min(h, -other->signed_distance(pt(i))) : h;
      if (d < deepest - tol_) break;
      if ((h <= tol_ && last >= 0) || (other && other->distance(pt(i)) <= tol_)) break;
      if (d > deepest + 0.5 * tol_ || last < 0) deepest = d, last = i;  // the walk ends at its deepest point
    }
    if (last < 0) return std::nullopt;
    const LineCov lc = cov_of(pl);
    // How far along the walked points reach, up to (not including) `stop`.
    const auto reach_to = [&](int stop) {
      double r = 0.0;
      for (int i = i0; i != stop; i += step) r = std::max(r, (pt(i) - near).dot(dir));
      return r;
    };
    // end: the last of the plate's own points walked (the one before the
    // other plate's face, where one was seen through a gap).
    const auto in_interval = [&](int end) -> std::optional<Edge> {
      if (std::abs(end - i0) + 1 < kFacePoints) return std::nullopt;
      const double lo = reach_to(end + step);
      double hi = lo;
      if (const auto x = ray_hit(s_.cols[end] + step, pl.line)) hi = std::max(hi, (*x - near).dot(dir));
      hi = std::min(hi, lo + kMaxRoundingMm);
      const Vec2 e = near + 0.5 * (lo + hi) * dir, d = pl.line.direction();
      const double h = std::max(0.5 * (hi - lo), tol_), u = (e - lc.mean).dot(d);
      return Edge{e, h, moved(lc, pl.line.n, u * pl.line.n) + (h * h / 3.0) * d * d.transpose()};
    };
    // The run on one line, from the deepest point back: each point within
    // the surface tolerance of the line through the points after it (from
    // three on), their rms within it too.
    const auto grow = [&](int from) {
      PointSums sums;
      std::optional<LineFit> run, so_far;
      for (int i = from;; i -= step) {
        if (so_far && so_far->count >= 3 && so_far->line.distance(pt(i)) > tol_) break;
        const PointSums more = s_.with_point(sums, i);
        if (i != from) {
          const auto f = s_.fit(more);
          if (!f || f->rms_mm > tol_) break;
          so_far = f;
          if (f->count >= kFacePoints) run = f;
        }
        sums = more;
        if (i == i0) break;
      }
      return run;
    };
    std::optional<LineFit> run = grow(last);
    // The deepest point may lie just past a notch's bottom (noise): the
    // run from the one before it.
    if (!run && last != i0 && (run = grow(last - step))) last -= step;
    if (!run) return in_interval(last);
    // A shallow run slanting outwards off square is a chamfer as much as a
    // face (a run that goes back under the plate as it goes deeper is no
    // chamfer: a chamfer cuts the edge, going outwards).
    const bool shallow = -pl.line.signed_distance(pt(last)) <= kMaxRoundingMm;
    const int first = last - step * (run->count - 1);
    const bool receding = (pt(last) - pt(first)).dot(dir) < 0.0;
    if (shallow && !receding && acute_angle_deg(run->line, pl.line) < 90.0 - kSquareFaceDeg) return in_interval(last);
    Line face = run->line;
    face.orient_towards(origin_);
    const Vec2 ray = ray_dir(s_.cols[first]), fd = face.direction();
    // Facing back: the other plate's end face, seen through the gap past
    // this plate's edge (the ray to its first point passed the edge).
    if (face.n.dot(dir) <= 0.0) return first != i0 ? in_interval(first - step) : std::nullopt;
    if (acute_angle_deg(face, pl.line) < 20.0) return in_interval(last);
    // A shallow run along the rays may be an arc's end turning out of view,
    // and a face whose line meets the plate's short of the points before it
    // a piece of a face that noise cut: neither says where the edge is.
    if (shallow && std::abs(fd.x() * ray.y() - fd.y() * ray.x()) < std::sin(5.0 * kDeg)) return std::nullopt;
    const auto x = intersect(pl.line, face, std::sin(20.0 * kDeg));
    if (!x) return in_interval(last);
    const double along = (*x - near).dot(dir);
    if (along < reach_to(first) - tol_ || along < -tol_ || along > kMaxRoundingMm + tol_) return std::nullopt;
    return Edge{*x, 0.0, intersection_cov(lc, cov_of(run->line, s_.sums(std::min(first, last), std::max(first, last))), *x),
                face};
  }

  // Where a walk past a plate's end starts (rounding(), seen_face()): the
  // kept point of column beyond_col, and the direction (+1, -1) in point
  // order that leads away from the plate's end `near` along `dir`. Empty
  // if that column holds no kept point.
  std::optional<std::pair<int, int>> walk_start(int beyond_col, const Vec2& near, const Vec2& dir) const {
    const auto it = std::lower_bound(s_.cols.begin(), s_.cols.end(), beyond_col);
    if (it == s_.cols.end() || *it != beyond_col) return std::nullopt;
    const int i = static_cast<int>(it - s_.cols.begin());
    const int n = static_cast<int>(s_.points.size());
    const int step = (pt(i) - near).dot(dir) >= 0.0 && i + 1 < n && (pt(i + 1) - near).dot(dir) >= (pt(i) - near).dot(dir)
                         ? +1
                         : -1;
    return std::pair{i, step};
  }

  // Rounded and chamfered edges are at most this wide (mm).
  static constexpr double kMaxRoundingMm = 3.0;
  // A closed corner's faces are each this many times longer than its
  // rounded or chamfered notch is wide.
  static constexpr double kClosedNotchFaces = 3.0;
  struct Rounding {
    double along = 0.0;  // the farthest point's distance along the plate past its end (0: none)
    double depth = 0.0;  // its depth behind the plate's line
    bool wall = false;   // below it the points go straight down: the edge face
    int col = -1;        // the farthest point's column
  };
  // The kept points in consecutive columns from beyond_col on (away from the
  // plate) that lie behind plate pl's line, past its end `near` along `dir`,
  // within kMaxRoundingMm.
  Rounding rounding(const Plate& pl, const Vec2& near, const Vec2& dir, int beyond_col) const {
    Rounding rd;
    const auto start = walk_start(beyond_col, near, dir);
    if (!start) return rd;
    auto [i, step] = *start;
    const int n = static_cast<int>(s_.points.size());
    for (int prev_col = beyond_col - step; i >= 0 && i < n && s_.cols[i] == prev_col + step; prev_col = s_.cols[i], i += step) {
      const double a = (pt(i) - near).dot(dir), h = -pl.line.signed_distance(pt(i));
      if (h <= tol_ || a < -tol_ || a > kMaxRoundingMm) break;
      // A rounding or a 45-degree chamfer never drops more than it runs on
      // (h <= a); a point that does is on the edge face below it, or a ray
      // into a gap past a sharp edge.
      if (h > a + tol_) {
        rd.wall = rd.along > 0.0;
        break;
      }
      // Rising again: past the bottom of a notch, on the other plate's side.
      if (h < rd.depth - tol_) break;
      if (a > rd.along) rd.along = a, rd.depth = h, rd.col = s_.cols[i];
    }
    return rd;
  }

  // Kept points [from, to] (empty if from > to).
  std::span<const Vec2> span_of(int from, int to) const {
    if (from > to) return {};
    return {s_.points.data() + from, static_cast<std::size_t>(to - from + 1)};
  }
  // No surface of a lap: behind its lower plate or in front of its upper
  // one (a reflection cluster displaced along its rays).
  bool no_surface_pt(const Plate& lower, const Plate& upper, const Vec2& q) const {
    return lower.line.signed_distance(q) < -tol_ || upper.line.signed_distance(q) > tol_;
  }

  // Points removed as outliers strictly between columns a and b.
  std::span<const Vec2> outliers_between(int a, int b) const {
    const auto lo = std::upper_bound(s_.outlier_cols.begin(), s_.outlier_cols.end(), a);
    const auto hi = std::lower_bound(lo, s_.outlier_cols.end(), b);
    return {s_.outlier_points.data() + (lo - s_.outlier_cols.begin()), static_cast<std::size_t>(hi - lo)};
  }

  // Outer end of a plate: its far end point on its line.
  static std::optional<Vec2> outer(const Plate& pl, const Vec2& p) { return pl.project(p); }

  // Consecutive long segments q, q+1 as plates, with their lines' intersection
  // and the directions from it to each plate.
  struct Pair {
    Plate a, b;
    Vec2 x;
    Vec2 ua, ub;
    bool valley;          // the open side faces the sensor (inside corner)
    bool trimmed = false;  // end points past x were dropped (see trimmed())
  };
  // Segments i and j (indices into the segment list) as a pair of plates.
  std::optional<Pair> pair_of(int i, int j) const { return pair_of(plate_of(s_.segments[i]), plate_of(s_.segments[j])); }
  // Plates a and b (a first in scan order) as a pair.
  std::optional<Pair> pair_of(const Plate& a, const Plate& b) const {
    if (!near_enough(a, b)) return std::nullopt;
    return meet(a, b);
  }
  // Plates a and b as a pair wherever their lines meet (at more than 5 degrees).
  std::optional<Pair> meet(const Plate& a, const Plate& b) const {
    Pair pr{a, b, Vec2::Zero(), Vec2::Zero(), Vec2::Zero(), false};
    const auto x = intersect(pr.a.line, pr.b.line, std::sin(5.0 * kDeg));
    if (!x) return std::nullopt;
    pr.x = *x;
    pr.ua = (pr.a.centroid - pr.x).normalized();
    pr.ub = (pr.b.centroid - pr.x).normalized();
    pr.valley = (pr.ua + pr.ub).dot(origin_ - pr.x) > 0.0;
    return pr;
  }
  std::optional<Pair> pair(int q) const { return pair_of(longs_[q], longs_[q + 1]); }

  // The lines of plates a and b meet at x between two neighbouring rays seen
  // on the plates: a sharp edge. Noise can put a point at the edge on the
  // wrong plate, so the facing end points that also fit the other plate's
  // line (within the surface tolerance) are not taken as its end.
  bool meet_between_rays(const Plate& a, const Plate& b, const Vec2& x) const {
    int lo = a.last, hi = b.first;
    while (lo > a.first && b.line.distance(pt(lo)) <= tol_) --lo;
    while (hi < b.last && a.line.distance(pt(hi)) <= tol_) ++hi;
    return between_rays(x, s_.cols[lo], s_.cols[hi]);
  }

  // A segment's line fit, as s_.fit(sg.sums) gives it (refit keeps its
  // line, rms and centroid so; checked in builds with assertions).
  std::optional<LineFit> fit_of(const Segment& sg) const {
    assert(same_fit(sg));
    if (!sg.fitted) return std::nullopt;
    LineFit f;
    f.line = sg.line;
    f.rms_mm = sg.rms_mm;
    f.count = sg.count();
    f.centroid = sg.centroid;
    return f;
  }
  // Whether the segment's fit is, bit for bit, what its sums give.
  bool same_fit(const Segment& sg) const {
    const auto f = sg.count() >= 2 ? s_.fit(sg.sums) : std::nullopt;
    if (f.has_value() != sg.fitted) return false;
    return !f || (f->line.n == sg.line.n && f->line.c == sg.line.c && f->rms_mm == sg.rms_mm &&
                  f->centroid == sg.centroid);
  }

  // Two runs of points (their sums s1, s2 and line fits p, q) lie on one
  // line: the shorter run's centroid lies on the longer one's line, and the
  // lines are close in angle or (a short run's angle is mostly noise) the
  // fit through both runs is hardly worse than either alone. O(1).
  bool same_line(const PointSums& s1, const std::optional<LineFit>& p, const PointSums& s2,
                 const std::optional<LineFit>& q) const {
    if (!p || !q) return false;
    const bool on = s2.n >= s1.n ? q->line.distance(p->centroid) <= tol_ : p->line.distance(q->centroid) <= tol_;
    if (!on) return false;
    if (acute_angle_deg(p->line, q->line) <= 5.0) return true;
    PointSums all = s1;
    all += s2;
    const auto u = s_.fit(all);
    return u && u->rms_mm <= std::max({1.2 * p->rms_mm, 1.2 * q->rms_mm, 0.5 * tol_});
  }
  bool same_line(const Segment& a, const Segment& b) const { return same_line(a.sums, fit_of(a), b.sums, fit_of(b)); }

  // Long segment q as a plate, extended outwards (dir -1: towards the start of
  // the profile, +1: towards its end) over the long segments that continue its
  // line (noise can cut a plate in pieces), fitted to their points.
  Plate extended(int q, int dir) const { return extended(plate_of(seg(q)), seg(q).sums, fit_of(seg(q)), q, dir); }
  // The same for plate pl (points pl.first..pl.last, sums `sums`, line fit
  // `fit`) cut from long segment q.
  Plate extended(const Plate& pl, PointSums sums, std::optional<LineFit> fit, int q, int dir) const {
    int first = pl.first, last = pl.last;
    for (int r = q + dir; r >= 0 && r < n_long(); r += dir) {
      const Segment& nx = seg(r);
      if (!same_line(sums, fit, nx.sums, fit_of(nx))) break;
      sums += nx.sums;
      fit = s_.fit(sums);
      first = std::min(first, nx.first), last = std::max(last, nx.last);
    }
    if (first == pl.first && last == pl.last) return pl;
    if (!fit) return pl;
    Plate out{first, last, fit->line, fit->centroid};
    out.line_rms = fit->rms_mm;
    return out;
  }

  // A long segment between two plates is their edge face only if it does not
  // continue either plate (noise can cut a plate in two: then the pair that
  // skips a piece of it would read a wrong edge).
  bool continues_either(const Segment& mid, int q1, int q2) const {
    // ...and its fitted line stays on the plate's line over its whole length.
    return continues(mid, seg(q1)) || continues(mid, seg(q2));
  }
  bool continues(const Segment& mid, const Segment& pl) const {
    return same_line(mid, pl) && pl.line.distance(mid.line.project(pt(mid.first))) <= tol_ &&
           pl.line.distance(mid.line.project(pt(mid.last))) <= tol_;
  }

  // Long segments q < q2 end within two roundings' reach of each other (the
  // last point of q to the first of q2): what lies between them can be the
  // rounded or chamfered edges of the plates they are.
  bool within_roundings(int q, int q2) const {
    return (pt(seg(q2).first) - pt(seg(q).last)).norm() <= 2.0 * kMaxRoundingMm;
  }

  // Every column strictly between columns a and b holds a kept point (none
  // invalid, none removed as an outlier).
  bool no_gone_between(int a, int b) const {
    for (int col = a + 1; col < b; ++col)
      if (s_.column_state[col] != kColumnKept) return false;
    return true;
  }

  // Some point of [from, to] lies off both lines (more than the tolerance).
  bool off_both(int from, int to, const Line& a, const Line& b) const {
    for (int i = from; i <= to; ++i)
      if (a.distance(pt(i)) > tol_ && b.distance(pt(i)) > tol_) return true;
    return false;
  }

  // Point `end` of plate `a` lies beyond line `l`: on the other side of it from
  // a's centroid, by more than the surface tolerance.
  bool beyond(const Plate& a, int end, const Line& l) const { return beyond_line(a.centroid, pt(end), l); }
  // Point p lies on the other side of line l from `centroid`, by more than the
  // surface tolerance.
  bool beyond_line(const Vec2& centroid, const Vec2& p, const Line& l) const {
    const double c = l.signed_distance(centroid), e = l.signed_distance(p);
    return std::abs(e) > tol_ && (c > 0.0) != (e > 0.0);
  }

  // A plate near the corner: v = b0 + b1 u + b2 u^2, with v the signed
  // distance from the plate's line and u along it from o (the corner).
  struct Quad {
    Line frame;
    Vec2 o = Vec2::Zero();
    double b0 = 0.0, b1 = 0.0, b2 = 0.0;
    bool curved = false;
    double f(const Vec2& q) const {
      const double u = frame.direction().dot(q - o);
      return frame.signed_distance(q) - (b0 + (b1 + b2 * u) * u);
    }
    Vec2 grad(const Vec2& q) const {
      const double u = frame.direction().dot(q - o);
      return frame.n - (b1 + 2.0 * b2 * u) * frame.direction();
    }
  };
  // Plate pl is a gentle arc: its line does not explain it to the noise,
  // and the quadratic through all its points (every k-th, at most about
  // 128) is curved (fit_quadratic: the arc explains the whole plate, to the
  // noise).
  bool arc(const Plate& pl) const {
    // A plate its line explains to within the noise (curve_rms_sigma) is a
    // line: the simpler model.
    if (pl.line_rms >= 0.0 && pl.line_rms <= p_.fillet.curve_rms_sigma * point_noise()) return false;
    const auto pts = std::span<const Vec2>(s_.points).subspan(pl.first, pl.count());
    return fit_quadratic(pts, pl.line, pl.centroid, std::numeric_limits<double>::infinity(), point_noise(), p_.fillet,
                         p_.segmentation.segments.min_segment_points, std::max(1, pl.count() / 128))
        .curved;
  }
  double point_noise() const { return point_sigma_ > 0.0 ? point_sigma_ : sigma_; }
  // An arc plate near x: the quadratic through its points within
  // FilletParams::curve_window_mm of x; a line (not curved) when a cubic
  // follows those better (a wave of waviness, not an arc).
  Quad quad_near(const Plate& pl, const Vec2& x) const {
    const FilletParams& fp = p_.fillet;
    Quad qd{pl.line, x};
    const auto pts = std::span<const Vec2>(s_.points).subspan(pl.first, pl.count());
    const QuadFit f =
        fit_quadratic(pts, pl.line, x, fp.curve_window_mm, point_noise(), fp, p_.segmentation.segments.min_segment_points);
    if (f.fitted && !f.wiggly) qd.b0 = f.b0, qd.b1 = f.b1, qd.b2 = f.b2, qd.curved = true;
    return qd;
  }
  // The fillet's pair with its plates as lines or gentle arcs (arc(),
  // quad_near): the corner where the two curves meet (Newton's method from
  // the lines' corner), an arc plate's line its tangent there and its
  // surface a circle (below). The pair as it is when neither plate is an
  // arc or the curves do not meet near the lines' corner.
  // Plate pl with the long segment just beyond it on side dir (< 0: before
  // it) joined to it, with their line fit: a gentle arc the segmenter cut
  // in two (each piece straight to the surface tolerance) is tested whole.
  // Empty when there is no such segment.
  std::optional<Plate> joined_beyond(const Plate& pl, int dir) const {
    const Segment* next = nullptr;
    for (int q = 0; q < n_long(); ++q) {
      const Segment& sg = seg(q);
      if (dir < 0 && sg.last < pl.first) next = &sg;  // the last one before
      if (dir > 0 && sg.first > pl.last) {
        next = &sg;
        break;
      }
    }
    if (!next) return std::nullopt;
    const int first = std::min(pl.first, next->first), last = std::max(pl.last, next->last);
    const auto f = s_.fit(first, last);
    if (!f) return std::nullopt;
    // With its line's rms: arc() takes a joined plate its line explains to
    // the noise for a line without fitting the quadratic (most plates with a
    // segment beyond them are straight).
    Plate out{first, last, f->line, f->centroid};
    out.line_rms = f->rms_mm;
    return out;
  }
  Pair bent(const Pair& given) const {
    const FilletParams& fp = p_.fillet;
    if (!fp.curved_plates) return given;
    Pair pr = given;
    bool arc_a = arc(pr.a), arc_b = arc(pr.b);
    // A plate that is straight alone may be the near piece of an arc cut in
    // two: the plate with the piece beyond it, when that is an arc.
    if (!arc_a)
      if (const auto w = joined_beyond(pr.a, -1); w && arc(*w)) pr.a = *w, arc_a = true;
    if (!arc_b)
      if (const auto w = joined_beyond(pr.b, +1); w && arc(*w)) pr.b = *w, arc_b = true;
    if (!arc_a && !arc_b) return given;
    Vec2 x = pr.x;
    Quad qa, qb;
    for (int pass = 0; pass < 2; ++pass) {
      qa = arc_a ? quad_near(pr.a, x) : Quad{pr.a.line, x};
      qb = arc_b ? quad_near(pr.b, x) : Quad{pr.b.line, x};
      if (!qa.curved && !qb.curved) return given;
      Vec2 y = x;
      bool met = false;
      for (int it = 0; it < 20 && !met; ++it) {
        // Solve [ga; gb] step = (fa, fb) (Cramer's rule).
        const Vec2 ga = qa.grad(y), gb = qb.grad(y);
        const double det = ga.x() * gb.y() - ga.y() * gb.x();
        if (!(std::abs(det) > std::sin(5.0 * kDeg) * 0.5)) return given;
        const double fa = qa.f(y), fb = qb.f(y);
        const Vec2 step((fa * gb.y() - ga.y() * fb) / det, (ga.x() * fb - fa * gb.x()) / det);
        y -= step;
        met = step.norm() < 1e-9;
      }
      if (!met || !y.allFinite() || (y - pr.x).norm() > 0.5 * fp.curve_window_mm) return given;
      x = y;
    }
    Pair out = pr;
    out.x = x;
    // A curved plate: its tangent at the root from its quadratic there; its
    // surface the circle through its points and those of the long segments
    // beyond it that continue that circle (the circle through both fits
    // within the noise: curve_rms_sigma sigma rms, or 1.2 times the
    // plate's own).
    auto shape = [&](Plate& pl, const Quad& qd, int dir) {
      if (!qd.curved) return true;
      const Vec2 d = qd.frame.direction();
      const double u = d.dot(x - qd.o), m = qd.b1 + 2.0 * qd.b2 * u;
      const Vec2 n = (qd.frame.n - m * d).normalized();
      pl.line = Line{n, n.dot(x)};
      std::vector<Vec2>& pts = scratch_;  // (the lap's and the grooves' scratch; not in use here)
      pts.assign(s_.points.begin() + pl.first, s_.points.begin() + pl.last + 1);
      auto circle = fit_circle(pts, x);
      if (!circle) return false;
      for (int q = dir < 0 ? n_long() - 1 : 0; q >= 0 && q < n_long(); q += dir) {
        const Segment& sg = seg(q);
        if (dir < 0 ? sg.last >= pl.first : sg.first <= pl.last) continue;  // not beyond the plate
        const std::size_t before = pts.size();
        pts.insert(pts.end(), s_.points.begin() + sg.first, s_.points.begin() + sg.last + 1);
        const auto joint = fit_circle(pts, x);
        if (!joint || joint->rms > std::max(fp.curve_rms_sigma * sigma_, 1.2 * circle->rms)) {
          pts.resize(before);
          break;
        }
        circle = joint;
      }
      pl.rho = circle->rho;
      pl.centre = circle->centre;
      pl.bend = pl.line.signed_distance(circle->centre) > 0.0 ? 1.0 : -1.0;
      return true;
    };
    if (!shape(out.a, qa, -1) || !shape(out.b, qb, +1)) return given;
    auto along = [&](const Plate& pl) {
      const Vec2 t = pl.line.direction();
      return t.dot(pl.centroid - x) < 0.0 ? Vec2(-t) : t;
    };
    out.ua = along(out.a), out.ub = along(out.b);
    out.valley = (out.ua + out.ub).dot(origin_ - out.x) > 0.0;
    return out;
  }

  void fillet() {
    for (int q = 0; q + 1 < n_long(); ++q) {
      fillet_pair(q, q + 1);
      // Or across one short segment at the root that continues neither
      // plate, within a rounding's reach of both plates' ends: a web's
      // rounded or chamfered bottom edge (its arc, set back from the web's
      // face line, is a segment of its own).
      if (p_.fillet.across_edge && q + 2 < n_long() && !continues_either(seg(q + 1), q, q + 2) &&
          within_roundings(q, q + 2))
        fillet_pair(q, q + 2);
    }
  }

  // The fillet read from long segments q and q2 (> q) as its plates.
  void fillet_pair(int q, int q2) {
    const FilletParams& fp = p_.fillet;
    // Each plate over the long segments beyond it that continue its line
    // (noise can cut a plate in pieces; the short piece at the root alone
    // gives a wrong angle).
    auto pr = fp.extend_plates ? pair_of(extended(q, -1), extended(q2, +1)) : pair_of(longs_[q], longs_[q2]);
    if (!pr || !pr->valley) return;
    // Either plate may be a gentle arc near the root (a pipe's section).
    pr = bent(*pr);
    if (!pr->valley) return;
    const Plate& a = pr->a;
    const Plate& b = pr->b;
    // A gap shows as the flange seen beyond the web's line, under its edge.
    // The points seen there can be few and off the line of their neighbours
    // (removed as an outlier cluster): those on the flange's line count too.
    int a_end_col = s_.cols[a.last], b_end_col = s_.cols[b.first];
    Vec2 a_end_pt = pt(a.last), b_end_pt = pt(b.first);
    bool a_past = beyond(a, a.last, b.line);
    bool b_past = beyond(b, b.first, a.line);
    {
      // A point on a plate's line beyond the other's moves that plate's end
      // there: a's to the last such point in column order, b's to the first.
      auto consider = [&](const Vec2& o, int col) {
        if (col > a_end_col && a.line.distance(o) <= tol_ && beyond_line(a.centroid, o, b.line)) {
          a_past = true;
          a_end_col = col, a_end_pt = o;
        }
        if (col < b_end_col && b.line.distance(o) <= tol_ && beyond_line(b.centroid, o, a.line)) {
          b_past = true;
          b_end_col = col, b_end_pt = o;
        }
      };
      const auto removed = outliers_between(s_.cols[a.last], s_.cols[b.first]);
      const std::size_t off =
          removed.empty() ? 0 : static_cast<std::size_t>(removed.data() - s_.outlier_points.data());
      for (std::size_t k = 0; k < removed.size(); ++k) consider(removed[k], s_.outlier_cols[off + k]);
      // So do the points kept between the plates (a short piece of the
      // flange seen through the gap, cut off by a dropout or a noisy point).
      for (int k = a.last + 1; fp.flange_pieces && k < b.first; ++k) consider(pt(k), s_.cols[k]);
    }
    bool web_is_b = true;
    if (fp.web == WebSide::First) web_is_b = false;
    else if (fp.web == WebSide::Auto) web_is_b = a_past || !b_past;
    const Plate& flange = web_is_b ? a : b;
    const Plate& web = web_is_b ? b : a;
    const int f_out = web_is_b ? a.first : b.last;
    const int f_end_col = web_is_b ? a_end_col : b_end_col;
    const Vec2 f_end_pt = web_is_b ? a_end_pt : b_end_pt;
    const int w_out = web_is_b ? b.last : a.first;
    const bool gap_seen = web_is_b ? a_past : b_past;
    // The web reaches over the points towards the flange that lie on its
    // line (noise can cut its last points off the long segment), and over
    // the points removed as outliers there that lie on its line, in front
    // of the flange (a few web points cut off by dropouts form an island).
    int w_end = web_is_b ? b.first : a.last;
    Vec2 w_end_pt = pt(w_end);
    if (gap_seen && fp.web_reaches) {
      w_end = web_is_b ? reach(web.line, w_end, -1, a.last) : reach(web.line, w_end, +1, b.first);
      w_end_pt = pt(w_end);
      const auto removed = web_is_b ? outliers_between(s_.cols[a.last], s_.cols[w_end])
                                    : outliers_between(s_.cols[w_end], s_.cols[b.first]);
      for (std::size_t k = 0; k < removed.size(); ++k) {
        // Towards the flange: from the web's end backwards when the web is b.
        const Vec2& o = removed[web_is_b ? removed.size() - 1 - k : k];
        if (web.line.distance(o) > tol_ || flange.line.signed_distance(o) <= tol_) break;
        w_end_pt = o;
      }
    }

    Candidate c;
    c.angle = angle_between_deg(pr->ua, pr->ub);
    c.track = pr->x;
    c.track_cov = intersection_cov(cov_of(a), cov_of(b), pr->x), c.located = true;
    c.bp[0] = outer(flange, pt(f_out));
    c.bp[1] = pr->x;
    c.bp[4] = outer(web, pt(w_out));
    if (gap_seen) {
      // The web's edge lies between its last point and the ray of the last
      // flange point, which passed under it.
      const Vec2 near = web.line.project(w_end_pt);
      Vec2 toe = near;
      if (const auto far = ray_hit(f_end_col, web.line); far && (*far - near).dot(outward(web, near)) > 0.0) {
        toe = 0.5 * (near + *far);
        c.edge_unc = 0.5 * (*far - near).norm();
      }
      c.gap = flange.line.distance(toe);
      c.gap_paper = flange.line.distance(near);
      c.bp[2] = flange.line.project(f_end_pt);
      c.bp[3] = toe;
      c.add_line(Line{flange.line.n, flange.line.n.dot(toe)});  // the web's bottom, if seen
    } else {
      c.gap = 0.0;
      c.gap_paper = 0.0;
      c.bp[2] = pr->x;
      c.bp[3] = pr->x;
    }
    c.score = std::min(a.count(), b.count());
    c.pa = a, c.pb = b;
    c.accepted = check(c, "angle", c.angle, fp.angle_deg, "deg") && check(c, "gap", c.gap, fp.gap_mm, "mm");
    offer(c);
  }

  void corner() {
    const CornerParams& cp = p_.corner;
    // The faces are neighbouring long segments, or have up to
    // CornerParams::max_between between them that continue neither (the
    // notch of a gap, seen close up: each plate's end face, and its rounding
    // or chamfer, can be a long segment), or more, within two
    // roundings' reach of each other, when they are a closed corner's notch
    // (below: a rounded edge's arc cut in short pieces).
    for (int q = 0; q + 1 < n_long(); ++q) {
      for (int q2 = q + 1; q2 < n_long(); ++q2) {
        const bool many = q2 > q + 1 + std::max(0, cp.max_between);
        if (many && (!cp.closed_notch || !within_roundings(q, q2)))
          break;
        bool notch = true;
        for (int m = q + 1; m < q2 && notch; ++m) notch = !continues_either(seg(m), q, q2);
        if (!notch) continue;
        // Two pieces of one face (noise cut it) are no corner.
        if (same_line(seg(q), seg(q2))) continue;
        // Each face over the long segments beyond it that continue its line
        // (noise can cut a face in pieces; the piece at the corner alone
        // would give a wrong angle).
        auto pr = pair_of(extended(q, -1), extended(q2, +1));
        if (!pr || pr->valley) continue;
        pr = trimmed(*pr);
        if (!pr || pr->valley) continue;
        const Plate& a = pr->a;
        const Plate& b = pr->b;
        const int from = a.last + 1, to = b.first - 1;
        Candidate c;
        const Eigen::Matrix2d x_cov = intersection_cov(cov_of(a), cov_of(b), pr->x);
        Edge el{pr->x, 0.0, x_cov}, er{pr->x, 0.0, x_cov};
        Edge el0 = el, er0 = er;
        bool open = false;
        // Faces that meet between two neighbouring rays (or in a run of
        // invalid columns) are one sharp edge: missing points are no gap.
        if (pr->trimmed || off_both(from, to, a.line, b.line) || !meet_between_rays(a, b, pr->x)) {
          open = true;
          // A face reaches as far as the points after it that lie on its
          // line (within the surface tolerance, on its side of the lines'
          // apex), over single points off it (noise): a dropout or a noisy
          // point can end its segment early, and the few face points after
          // it then fall into the notch's segment.
          auto on_face = [&](const Plate& f, const Vec2& u, int i) {
            return f.line.distance(pt(i)) <= tol_ && (pt(i) - pr->x).dot(u) > 0.0;
          };
          auto reach = [&](const Plate& f, const Vec2& u, int end, int step, int stop) {
            for (int i = end + step; i != stop; i += step) {
              if (on_face(f, u, i)) end = i;
              else if (i + step == stop || !on_face(f, u, i + step)) break;
            }
            return end;
          };
          const int a_end = reach(a, pr->ua, a.last, +1, b.first);
          const int b_end = reach(b, pr->ub, b.first, -1, a_end);
          el = el0 = edge_at(a, pt(a_end), s_.cols[a_end] + 1, &a.line.n, span_of(a_end + 1, b_end - 1),
                             {.far_col = first_missed(a.line, b.line, s_.cols[a_end] + 1, +1)});
          er = er0 = edge_at(b, pt(b_end), s_.cols[b_end] - 1, &b.line.n, span_of(a_end + 1, b_end - 1),
                             {.far_col = first_missed(b.line, a.line, s_.cols[b_end] - 1, -1)});
          if (cp.fit_end_faces) {
            // The end faces as seen, at any slant, or the interval their
            // rounding or chamfer leaves (seen_face); square end faces as
            // before where neither is seen. The closed notch's test below
            // keeps the square faces' edges (el0, er0).
            if (const auto e = seen_face(a, pt(a_end), s_.cols[a_end] + 1, &b.line)) el = *e;
            if (const auto e = seen_face(b, pt(b_end), s_.cols[b_end] - 1, &a.line)) er = *e;
          }
        }
        c.angle = angle_between_deg(pr->ua, pr->ub);
        c.gap = (er.point - el.point).norm();
        c.edge_unc = el.half_width_mm + er.half_width_mm;
        c.track_unc = 0.5 * c.edge_unc;
        c.track = 0.5 * (el.point + er.point);
        c.track_cov = open ? Eigen::Matrix2d(0.25 * (el.cov + er.cov)) : x_cov, c.located = true;
        c.bp[0] = outer(a, pt(a.first));
        c.bp[1] = el.point;
        c.bp[2] = pr->x;
        c.bp[3] = er.point;
        c.bp[4] = outer(b, pt(b.last));
        c.score = std::min(a.count(), b.count());
        c.pa = a, c.pb = b;
        // The end faces in a notch, square to the outer faces at the edges
        // (or as seen).
        c.add_line(el.face ? *el.face : Line{a.line.direction(), a.line.direction().dot(el.point)});
        c.add_line(er.face ? *er.face : Line{b.line.direction(), b.line.direction().dot(er.point)});
        c.accepted = check(c, "angle", c.angle, cp.angle_deg, "deg") && check(c, "gap", c.gap, cp.gap_mm, "mm");
        // A notch whose points all lie within a rounding's or chamfer's
        // reach (kMaxRoundingMm) behind the faces is also what a closed
        // corner with rounded or chamfered outer edges shows; a gap's slot
        // goes deeper (rays into it meet the end faces far down, or
        // nothing). Both readings then compete, the closed one at the apex,
        // with the same lines: as strong as each other, the profile is
        // ambiguous (rejected), not read 1-2 mm below the apex.
        bool shallow = c.gap > 0.0 && from <= to;
        int deepest = from;
        double depth = -std::numeric_limits<double>::infinity();
        for (int i = from; i <= to && shallow; ++i) {
          const double d = -std::max(a.line.signed_distance(pt(i)), b.line.signed_distance(pt(i)));
          shallow = d <= kMaxRoundingMm;
          if (d > depth) depth = d, deepest = i;
        }
        // A shallow notch closed at its bottom, not on the end faces: every
        // ray between the faces found the surface (no invalid column, no
        // point removed), the deepest point has notch points on both sides,
        // and most notch points lie off the open reading's end faces
        // (square to the outer faces at the edges). A gap between the
        // plates is a slot (rays into it go deep or find nothing, or, seen
        // at a slant, show the far end face only) or a notch of square end
        // faces running into each other; flanks meeting at a bottom off
        // those faces are a closed corner's rounded or chamfered edges: the
        // closed reading alone, its notch explained as those edges. The
        // faces must be plates, each kClosedNotchFaces times longer than the
        // notch is wide (a rounding or a chamfer is small beside them); the
        // notch may be wider than a gap's accept range (the closed reading
        // has no gap).
        const double notch_mm = (pt(b.first) - pt(a.last)).norm();
        bool closed_bottom = cp.closed_notch && shallow && cp.angle_deg.contains(c.angle) && deepest > from &&
                             deepest < to &&
                             (pt(a.last) - pt(a.first)).norm() > kClosedNotchFaces * notch_mm &&
                             (pt(b.last) - pt(b.first)).norm() > kClosedNotchFaces * notch_mm &&
                             no_gone_between(s_.cols[a.last], s_.cols[b.first]);
        if (closed_bottom) {
          const Line end_a{a.line.direction(), a.line.direction().dot(el0.point)};
          const Line end_b{b.line.direction(), b.line.direction().dot(er0.point)};
          int on_ends = 0;
          for (int i = from; i <= to; ++i) on_ends += std::min(end_a.distance(pt(i)), end_b.distance(pt(i))) <= tol_;
          closed_bottom = 2 * on_ends < to - from + 1;
        }
        if (many && !closed_bottom) continue;
        if (!closed_bottom) offer(c);
        shallow = shallow && c.accepted;
        if (shallow || closed_bottom) {
          Candidate closed = c;
          closed.gap = 0.0;
          closed.edge_unc = closed.track_unc = 0.0;
          closed.track = closed.bp[1] = closed.bp[3] = pr->x;
          closed.track_cov = x_cov;
          closed.score = c.score - 1;
          if (closed_bottom) {
            // The notch is the closed reading's own: its rounded or
            // chamfered edges, between the faces' ends and behind both.
            const Vec2 across = (er0.point - el0.point).normalized();
            closed.open_joint = true;
            closed.opening = {el0.point, er0.point, across, -across, tol_, tol_};
            closed.n_more = 0;
            closed.accepted = true, closed.failed = {};
          } else if (c.accepted) {
            closed.evidence = weigh(c), closed.weighed = true;  // over the same points
          }
          offer(closed);
        }
      }
    }
  }

  void lap() {
    const LapParams& lp = p_.lap;
    for (int q1 = 0; q1 + 1 < n_long(); ++q1) {
      // Each plate over the long segments beyond it that continue its line
      // (noise can cut a plate in pieces; the piece at the step alone can be
      // several degrees off).
      const Plate a = lp.extend_plates ? extended(q1, -1) : plate_of(seg(q1));
      // The edge face may itself be a long segment between the plates, and
      // so may the upper plate's rounded or chamfered top edge, in pieces
      // (LapParams::max_between); none of them continues a plate.
      for (int q2 = q1 + 1; q2 <= std::min(q1 + 1 + std::max(0, lp.max_between), n_long() - 1); ++q2) {
        const Plate b = lp.extend_plates ? extended(q2, +1) : plate_of(seg(q2));
        if (!near_enough(a, b) || acute_angle_deg(a.line, b.line) > lp.max_plate_angle_deg) continue;
        bool between = false;
        for (int m = q1 + 1; m < q2 && !between; ++m) between = continues_either(seg(m), q1, q2);
        if (between) continue;
        bool upper_is_b;
        if (a.line.signed_distance(pt(b.first)) > tol_) upper_is_b = true;
        else if (b.line.signed_distance(pt(a.last)) > tol_) upper_is_b = false;
        else continue;
        const Plate& lower = upper_is_b ? a : b;
        const Plate& upper = upper_is_b ? b : a;
        const int l_end = upper_is_b ? a.last : b.first, l_out = upper_is_b ? a.first : b.last;
        const int u_end = upper_is_b ? b.first : a.last, u_out = upper_is_b ? b.last : a.first;
        const int from = a.last + 1, to = b.first - 1;

        // Points on the edge face: between the plates and on neither. With
        // LapParams::upper_reaches, only those between the lower plate and
        // the points the upper plate reaches over (on its line, as a butt
        // plate reaches): noise cuts the upper plate near its edge into
        // short pieces, and their points off its line were read as face points.
        int f_from = from, f_to = to;
        if (lp.upper_reaches) {
          if (upper_is_b) f_to = reach(upper.line, b.first, -1, a.last) - 1;
          else f_from = reach(upper.line, a.last, +1, b.first) + 1;
        }
        scratch_.clear();
        // With square edges a face drops more than it runs on from the upper
        // plate's end (as far as it reaches): the points between that do not
        // are its rounding or chamfer, not the face.
        const Vec2 u_near = upper.line.project(pt(upper_is_b ? f_to + 1 : f_from - 1));
        const Vec2 u_dir = outward(upper, u_near);
        for (int i = f_from; i <= f_to; ++i) {
          if (lower.line.distance(pt(i)) <= tol_ || upper.line.distance(pt(i)) <= tol_) continue;
          // In front of the upper plate or behind the lower one: no surface
          // of a lap (a reflection cluster), no face point.
          if (upper.line.signed_distance(pt(i)) > tol_ || lower.line.signed_distance(pt(i)) < -tol_) continue;
          if (p_.square_edges && -upper.line.signed_distance(pt(i)) <= (pt(i) - u_near).dot(u_dir) + tol_) continue;
          scratch_.push_back(pt(i));
        }

        Candidate c;
        Vec2 top, foot;
        std::optional<Vec2> bottom;
        std::optional<LineFit> wall;
        if (scratch_.size() >= 3) wall = fit_line(scratch_);
        std::optional<Vec2> wf, wt;
        // With square edges the face must be near square to the upper
        // plate (LapParams::max_face_off_square_deg): points between the
        // plates on a slanted line are a chamfered or rounded top edge, the
        // face itself hidden below it.
        if (wall && p_.square_edges && acute_angle_deg(wall->line, upper.line) < 90.0 - lp.max_face_off_square_deg)
          wall.reset();
        if (wall) {
          wall->line.orient_towards(origin_);
          wf = intersect(wall->line, lower.line, std::sin(20.0 * kDeg));
          wt = intersect(wall->line, upper.line, std::sin(20.0 * kDeg));
        }
        if (wf && wt) {
          const Line& wl = wall->line;
          foot = *wf;
          // The track point: the face's line and the lower plate's meeting.
          PointSums face;
          for (const Vec2& q : scratch_) face.add(q - s_.ref_);
          c.track_cov = intersection_cov(cov_of(wl, face), cov_of(lower), foot), c.located = true;
          top = *wt;
          c.angle = angle_between_deg(lower.centroid - foot, top - foot);
          // A gap shows as the lower plate seen beyond the face's line.
          const Plate wp{0, 0, wl, wall->centroid};
          if (beyond(lower, l_end, wl)) {
            const Vec2& w_low = upper_is_b ? scratch_.front() : scratch_.back();
            const Vec2 near = wl.project(w_low);
            Vec2 b_edge = near;
            if (const auto far = ray_hit(s_.cols[l_end], wl); far && (*far - near).dot(outward(wp, near)) > 0.0) {
              b_edge = 0.5 * (near + *far);
              c.edge_unc = 0.5 * (*far - near).norm();
            }
            bottom = b_edge;
            c.gap = lower.line.distance(b_edge);
          } else {
            bottom = foot;
            c.gap = 0.0;
          }
        } else {
          // Edge face hidden or too short to fit: the top edge lies between
          // the upper plate's end and the next ray; the face is square to it.
          // Points between the plates on the upper plate's line (a noisy
          // piece too short to be a segment of its own) still belong to it.
          // Points behind the lower plate or in front of the upper one are
          // no surface of a lap (reflection clusters displaced along their
          // rays): the upper plate reaches past them to its points beyond.
          int u_edge = u_end;
          auto on_upper = [&](int i) {
            return upper.line.distance(pt(i)) <= tol_ && lower.line.distance(pt(i)) > tol_;
          };
          auto no_surface = [&](int i) { return no_surface_pt(lower, upper, pt(i)); };
          const int step = upper_is_b ? -1 : +1;
          for (int i = u_edge + step; i >= from && i <= to; i += step) {
            if (no_surface(i)) continue;
            if (!on_upper(i)) break;
            u_edge = i;
          }
          // So do the points removed as outliers there (a few upper plate
          // points cut off by a noisy point and the step: an island).
          Vec2 u_pt = pt(u_edge);
          int u_col = s_.cols[u_edge];
          reach_removed(upper.line, &lower.line, upper_is_b ? -1 : +1, s_.cols[l_end], u_pt, u_col, &lower.line);
          const int beyond_col = upper_is_b ? u_col - 1 : u_col + 1;
          int far_col = beyond_col;
          // Nor do the columns beyond it that saw no surface of a lap show
          // where it ends: whether their rays met the upper plate is not
          // known (a reflection cluster hid it). The edge lies short of the
          // first column beyond that saw a surface, or nothing.
          if (p_.edge_past_reflections)
            for (auto q = point_at_col(far_col); q && no_surface_pt(lower, upper, *q); q = point_at_col(far_col))
              far_col += upper_is_b ? -1 : +1;
          const Edge e = edge_at(upper, u_pt, beyond_col, &upper.line.n, span_of(from, to),
                                 {.prep_not_faces = true, .far_col = far_col});
          top = e.point;
          c.edge_unc = c.track_unc = e.half_width_mm;
          foot = lower.line.project(top);
          // Along the lower plate the upper plate's edge, across it its line.
          c.track_cov = on_plate_cov(lower, foot, e.cov), c.located = true;
          // The hidden face is square to the plates only to hidden_face_deg:
          // its foot moves along the lower plate by the step times that.
          const double shear = lower.line.distance(top) * std::tan(p_.hidden_face_deg * kDeg);
          c.track_cov += shear * shear * lower.line.direction() * lower.line.direction().transpose();
          if (lp.upper_thickness_mm > 0.0) {
            bottom = top - lp.upper_thickness_mm * upper.line.n;
            c.gap = lower.line.signed_distance(*bottom);
            if (c.gap < 0.0 && c.gap > -tol_) c.gap = 0.0;
          }
        }
        c.step = lower.line.distance(top);
        c.track = foot;
        c.bp[0] = outer(lower, pt(l_out));
        c.bp[1] = foot;
        c.bp[2] = bottom;
        c.bp[3] = top;
        c.bp[4] = outer(upper, pt(u_out));
        c.score = std::min(a.count(), b.count());
        // (Weighed on the plates' own lines, unless held parallel: an upper
        // plate resting on its edge lies off parallel.)
        c.pa = a, c.pb = b, c.parallel = !lp.tilted_upper;
        if (wall) c.add_line(wall->line);
        c.accepted = check(c, "step", c.step, lp.step_mm, "mm") && check(c, "gap", c.gap, lp.gap_mm, "mm") &&
                     check(c, "angle", c.angle, lp.angle_deg, "deg");
        // The model check: with the face hidden, the top edge as read must
        // lie where the points around it allow (LapParams::check_edge).
        if (!wall && lp.check_edge && c.accepted) {
          const EdgeInterval iv = edge_interval(lower, upper, upper_is_b ? b.first : a.last,
                                                upper_is_b ? a.last : b.first, top);
          if (iv.past > lp.edge_past_mm) {
            c.accepted = false;
            std::snprintf(c.reason, sizeof c.reason,
                          "uncertain: points %.2g mm past the upper plate's edge as read lie between the plates "
                          "(a rounded or chamfered edge?)",
                          iv.past);
          } else if (std::max(iv.after, iv.before) > lp.edge_interval_mm) {
            c.accepted = false;
            std::snprintf(c.reason, sizeof c.reason,
                          "uncertain: the upper plate's edge may lie %.2g mm from where it is read (between its "
                          "last point and the first ray past it)",
                          std::max(iv.after, iv.before));
          }
        }
        offer(c);
      }
    }
  }

  // Where a lap's top edge can lie, along the upper plate's line from the
  // edge `top` as read (outwards positive), from the columns between the
  // upper plate's end (point u_i) and the lower plate's (l_i): the last point
  // of the upper plate or its edge preparation (on the upper line, or
  // between the plates' levels) before the first point on the lower plate's
  // line, whose ray has passed the edge.
  struct EdgeInterval {
    double past = 0.0;    // how far that last point lies past `top` (0: not past it)
    double after = 0.0;   // how far past `top` that ray crosses the upper line
    double before = 0.0;  // how far `top` lies past that last point
  };
  EdgeInterval edge_interval(const Plate& lower, const Plate& upper, int u_i, int l_i, const Vec2& top) const {
    const Vec2 dir = outward(upper, top);
    const double at = top.dot(dir);
    const int c0 = s_.cols[u_i], c1 = s_.cols[l_i], step = c1 > c0 ? 1 : -1;
    double last = pt(u_i).dot(dir) - at;
    std::optional<double> passed;
    // The points of the plate and its edge preparation (on the upper line,
    // or behind it by at most kMaxRoundingMm and off the lower plate) first:
    // a ray that reached the lower plate before one of them did not pass the
    // edge (a reflection cluster can lie there).
    int last_col = c0;
    for (int col = c0 + step; col != c1; col += step) {
      if (s_.column_state[col] == kColumnInvalid) continue;
      const auto q = point_at_col(col);
      if (!q) continue;
      const double du = upper.line.signed_distance(*q), dl = lower.line.signed_distance(*q);
      if (std::abs(du) <= tol_ || (du < -tol_ && du >= -kMaxRoundingMm && dl > tol_)) {
        last = std::max(last, q->dot(dir) - at);
        last_col = col;
      }
    }
    for (int col = last_col + step; col != c1 && !passed; col += step) {
      if (s_.column_state[col] == kColumnInvalid) continue;
      const auto q = point_at_col(col);
      if (q && lower.line.distance(*q) <= tol_) passed = hit_along(col, upper.line, dir, at);
    }
    if (!passed) passed = hit_along(c1, upper.line, dir, at);
    return EdgeInterval{std::max(0.0, last), std::max(0.0, *passed), std::max(0.0, -last)};
  }

  // Where column col's ray meets line l, along dir from `at` (0: it does not).
  double hit_along(int col, const Line& l, const Vec2& dir, double at) const {
    const auto x = ray_hit(col, l);
    return x ? x->dot(dir) - at : 0.0;
  }

  // The point seen in a column: kept, or removed as an outlier.
  std::optional<Vec2> point_at_col(int col) const {
    const auto it = std::lower_bound(s_.cols.begin(), s_.cols.end(), col);
    if (it != s_.cols.end() && *it == col) return pt(static_cast<int>(it - s_.cols.begin()));
    const auto jt = std::lower_bound(s_.outlier_cols.begin(), s_.outlier_cols.end(), col);
    if (jt != s_.outlier_cols.end() && *jt == col)
      return s_.outlier_points[static_cast<std::size_t>(jt - s_.outlier_cols.begin())];
    return std::nullopt;
  }

  // Where a butt plate's edge can lie, along the plate's line from the edge
  // `edge` as read (outwards positive), from the columns between the plate's
  // end (end_pt, in column end_col) and the other plate's (other_end, in
  // column other_col): past the plate's edge preparation (rounding(): the
  // run of points right after its end behind its line that drop no more
  // than they run on) and its own points beyond a dropout or a shadow (runs
  // on its line, short of the other plate's edge preparation), and short of
  // where the ray of the first column after them crosses its line (a point
  // on the other plate, its edge face, in the gap, or an invalid column: a
  // ray into the gap). Points in front of both plates (a reflection
  // cluster) say nothing. `past`: how far the plate's own points lie past
  // the edge as read.
  static constexpr int kMinPlateRun = 3;
  EdgeInterval butt_edge_interval(const Plate& pl, const Plate& other, const Vec2& end_pt, int end_col,
                                  const Vec2& other_end, int other_col, const Vec2& edge) const {
    const Vec2 near = pl.line.project(end_pt);
    const Vec2 dir = outward(pl, near);
    const double at = edge.dot(dir);
    const int step = other_col > end_col ? 1 : -1;
    const Rounding rd = rounding(pl, near, dir, end_col + step);
    double last = near.dot(dir) - at + rd.along;
    double past = -std::numeric_limits<double>::infinity();  // the plate's own points past the edge
    int last_col = rd.along > 0.0 ? rd.col : end_col;
    auto in_front = [&](const Vec2& q) {
      return pl.line.signed_distance(q) > tol_ && other.line.signed_distance(q) > tol_;
    };
    // The plate's points past a dropout or a shadow: runs of at least
    // kMinPlateRun points in consecutive columns on its line (an edge face
    // crossing it leaves one or two), short of the other plate's edge
    // preparation.
    const Rounding ro = rounding(other, other.line.project(other_end), outward(other, other.line.project(other_end)),
                                 other_col - step);
    const int stop = ro.along > 0.0 && (ro.col - end_col) * step > 0 && (other_col - ro.col) * step >= 0 ? ro.col : other_col;
    int run = 0;
    double run_far = -std::numeric_limits<double>::infinity();
    for (int col = end_col + step; (stop - col) * step > 0; col += step) {
      const auto q = point_at_col(col);
      if (!q || pl.line.distance(*q) > tol_ || other.line.distance(*q) <= tol_) {
        run = 0, run_far = -std::numeric_limits<double>::infinity();
        continue;
      }
      run_far = std::max(run_far, q->dot(dir) - at);
      if (++run >= kMinPlateRun) {
        last = std::max(last, run_far), past = std::max(past, run_far);
        if ((col - last_col) * step > 0) last_col = col;
      }
    }
    std::optional<double> passed;
    for (int col = last_col + step; (other_col - col) * step > 0 && !passed; col += step) {
      const auto q = point_at_col(col);
      if (s_.column_state[col] != kColumnInvalid && (!q || in_front(*q))) continue;
      passed = hit_along(col, pl.line, dir, at);
    }
    if (!passed) passed = hit_along(other_col, pl.line, dir, at);
    return EdgeInterval{std::max(0.0, past), std::max(0.0, *passed), std::max(0.0, -last)};
  }

  // The first column from `col` on, stepping by `step`, whose ray shows that
  // it missed the plate on line l (TrackerParams::edge_past_reflections): a
  // point removed as an outlier in front of l and of the other plate's line
  // (a reflection cluster) does not, as its ray may have met the plate.
  int first_missed(const Line& l, const Line& other, int col, int step) const {
    if (!p_.edge_past_reflections) return col;
    const int n = static_cast<int>(s_.column_state.size());
    const int max_cluster = max_cluster_run();
    for (int k = 0; k <= max_cluster; ++k, col += step) {
      if (col < 0 || col >= n || s_.column_state[col] != kColumnOutlier) return col;
      const auto q = point_at_col(col);
      if (!q || l.signed_distance(*q) <= tol_ || other.signed_distance(*q) <= tol_) return col;
    }
    return col - (max_cluster + 1) * step;  // a longer run: no reflection
  }

  // Longest run of consecutive invalid columns strictly between columns a < b.
  int invalid_run(int a, int b) const {
    int best = 0, run = 0;
    for (int c = a + 1; c < b; ++c) {
      run = s_.column_state[c] == kColumnInvalid ? run + 1 : 0;
      best = std::max(best, run);
    }
    return best;
  }

  // `evidence` 1: invalid columns, a jump or walls separate the plates
  // (rather than only points off their lines, which noise can fake); such
  // readings rank first (see evidence()).
  void butt_pair(const Plate& a, const Plate& b, int from, int to, int evidence) {
    const ButtParams& bp = p_.butt;
    if (acute_angle_deg(a.line, b.line) > bp.max_plate_angle_deg) return;
    // Points between the plates in front of both (kept, or removed as
    // outliers: a reflection over the gap or over a plate) do not rule a gap
    // out: weigh() counts them against the joint as a random event, as it
    // does against no joint. Walls are square to the plates: kept points
    // between them all off both lines, on a line at 45 degrees or more to
    // the plates, are walls seen in the gap (evidence of it).
    bool all_off = from < to;
    for (int i = from; i <= to && all_off; ++i)
      all_off = a.line.distance(pt(i)) > tol_ && b.line.distance(pt(i)) > tol_;
    if (all_off) {
      const auto f = s_.fit(from, to);
      if ((f ? acute_angle_deg(f->line, a.line) : 90.0) >= 45.0) evidence = 1;
    }
    const auto removed = outliers_between(s_.cols[a.last], s_.cols[b.first]);
    // Each plate reaches over the points removed as outliers right after its
    // end that lie on its line (TrackerParams::reach_removed_points).
    Vec2 a_end = pt(a.last), b_end = pt(b.first);
    int a_col = s_.cols[a.last], b_col = s_.cols[b.first];
    reach_removed(a.line, nullptr, +1, s_.cols[b.first], a_end, a_col);
    reach_removed(b.line, nullptr, -1, a_col, b_end, b_col);
    const Edge el = edge_at(a, a_end, a_col + 1, &a.line.n, span_of(from, to),
                            {.more_faces = removed, .far_col = first_missed(a.line, b.line, a_col + 1, +1)});
    const Edge er = edge_at(b, b_end, b_col - 1, &b.line.n, span_of(from, to),
                            {.more_faces = removed, .far_col = first_missed(b.line, a.line, b_col - 1, -1)});
    const bool b_higher = a.line.signed_distance(er.point) > 0.0;
    const Plate& lower = b_higher ? a : b;
    const Vec2& high_edge = b_higher ? er.point : el.point;
    Candidate c;
    c.mismatch = lower.line.distance(high_edge);
    c.gap = std::abs((er.point - el.point).dot(lower.line.direction()));
    c.angle = angle_between_deg(a.centroid - el.point, b.centroid - er.point);
    c.edge_unc = el.half_width_mm + er.half_width_mm;
    c.track_unc = 0.5 * c.edge_unc;
    c.track = lower.line.project(0.5 * (el.point + er.point));
    // Along the lower plate the edges' midpoint, across it the plate's line.
    c.track_cov = on_plate_cov(lower, *c.track, 0.25 * (el.cov + er.cov));
    c.located = true;
    c.bp[0] = outer(a, pt(a.first));
    c.bp[1] = el.point;
    c.bp[2] = c.track;
    c.bp[3] = er.point;
    c.bp[4] = outer(b, pt(b.last));
    c.score = 1e6 * evidence + c.gap + c.mismatch;
    c.pa = a, c.pb = b, c.open_joint = true, c.parallel = true;
    // The opening reaches back to the plates' ends: the points of a rounded
    // or chamfered edge (between a plate's last point and its edge, behind
    // it) are the joint's, as its walls are, not strays.
    const Vec2 ia = outward(a, el.point), ib = outward(b, er.point);
    const double back_a = (el.point - a.line.project(a_end)).dot(ia), back_b = (er.point - b.line.project(b_end)).dot(ib);
    c.opening = {el.point, er.point, ia, ib, std::max(el.half_width_mm, back_a) + tol_,
                 std::max(er.half_width_mm, back_b) + tol_};
    c.accepted = check(c, "gap", c.gap, bp.gap_mm, "mm") && check(c, "mismatch", c.mismatch, bp.mismatch_mm, "mm");
    // The model check: each edge as read must lie where the points around
    // it allow, and the track point (their midpoint) be placed to
    // track_interval_mm (ButtParams::check_edges).
    if (bp.check_edges && c.accepted) {
      const EdgeInterval ia_ = butt_edge_interval(a, b, a_end, a_col, b_end, b_col, el.point);
      const EdgeInterval ib_ = butt_edge_interval(b, a, b_end, b_col, a_end, a_col, er.point);
      // Along a's outward direction (towards b) the track point moves by
      // half of each edge's shift, b's outward direction being the opposite.
      const double reach = 0.5 * std::max(ia_.after + ib_.before, ia_.before + ib_.after);
      if (std::max(ia_.past, ib_.past) > bp.edge_past_mm) {
        c.accepted = false, c.uncertain = true;
        std::snprintf(c.reason, sizeof c.reason,
                      "uncertain: a plate's points lie %.2g mm past its edge as read (beyond a dropout or a "
                      "shadow: the edge is not where it is read)",
                      std::max(ia_.past, ib_.past));
      } else if (reach > bp.track_interval_mm) {
        c.accepted = false, c.uncertain = true;
        std::snprintf(c.reason, sizeof c.reason,
                      "uncertain: the gap centre may lie %.2g mm from where it is read (the plates' edges lie "
                      "between their last points and the first rays past them)",
                      reach);
      }
    }
    // The plates' model check: each plate is straight up to its edge (its
    // edge preparation aside). Its own points near the edge that a parabola
    // fits as a cap convex towards the sensor, as the v-groove's root check
    // fits the root (root_bump), are no plate but a tack weld's or a bead's
    // crest (ButtParams::check_plate_caps).
    if (bp.check_plate_caps && c.accepted) {
      const double window = p_.confidence.window_mm;
      const RootBump ca = plate_bump(a, el.point, true, window, c.opening.slack_a + bp.edge_past_mm);
      const RootBump cb = plate_bump(b, er.point, false, window, c.opening.slack_b + bp.edge_past_mm);
      auto cap = [&](const RootBump& r) {
        return r.points >= bp.plate_cap_points && r.curvature_t >= bp.plate_cap_t && r.height_mm > tol_;
      };
      if (cap(ca) || cap(cb)) {
        const RootBump& r = cap(ca) ? ca : cb;
        c.accepted = false, c.uncertain = true;
        std::snprintf(c.reason, sizeof c.reason,
                      "uncertain: a plate bulges %.2g mm near its edge (%d points, curvature %.0f standard "
                      "errors from straight: a tack weld or a bead?)",
                      r.height_mm, r.points, r.curvature_t);
      }
    }
    offer(c);
  }

  // root_bump (the v-groove's open root check) over a butt plate's own
  // points near its edge `edge` (at the plate's last point if at_last, else
  // at its first): the run of points from the plate's end back that lie
  // within reach_mm of the edge along the plate and within 2 surface
  // tolerances of its line (not past a reflection cluster or a piece of
  // another surface inside an extended plate), less those within skip_mm
  // of the edge (its edge preparation), in the frame of the chord through
  // the run's end points: the fit's height above it is the bulge's sagitta.
  struct RootBump;  // below, with root_bump
  RootBump plate_bump(const Plate& pl, const Vec2& edge, bool at_last, double reach_mm, double skip_mm) const {
    const Vec2 out = outward(pl, edge), e = pl.line.project(edge);
    auto back = [&](int i) { return (e - pt(i)).dot(out); };  // from the edge back along the plate
    auto on = [&](int i) { return back(i) <= reach_mm && pl.line.distance(pt(i)) <= 2.0 * tol_; };
    int from = at_last ? pl.last : pl.first, to = from;
    if (at_last) {
      while (from > pl.first && on(from - 1)) --from;
      while (to > from && back(to) < skip_mm) --to;
    } else {
      while (to < pl.last && on(to + 1)) ++to;
      while (from < to && back(from) < skip_mm) ++from;
    }
    if (to - from < 2) return {};
    const Vec2 lo = pt(from), hi = pt(to), d = (hi - lo).normalized();
    // A cap higher than the surface tolerance above the chord lifts the
    // middle half of its points by most of that on average: where they lie
    // lower than a quarter of it, no fit is needed (most plates).
    const Vec2 n = Vec2(-d.y(), d.x()).dot(origin_ - lo) < 0.0 ? Vec2(d.y(), -d.x()) : Vec2(-d.y(), d.x());
    const int q = (to - from) / 4;
    double lift = 0.0;
    for (int i = from + q; i <= to - q; ++i) lift += (pt(i) - lo).dot(n);
    if (lift < 0.25 * tol_ * (to - from - 2 * q + 1)) return {};
    return root_bump(lo - 1e-9 * d, hi + 1e-9 * d, from, to);
  }

  // With TrackerParams::reach_removed_points: moves a plate's end (end_pt, in
  // column end_col) over the points removed as outliers in the columns right
  // after it (dir +1: towards higher columns; no column missing or kept
  // between, short of column `stop`) that lie on its line `l` (and off
  // `other`, if given), also past removed points in front of the line (a
  // reflection cluster displaced towards the sensor), not past one behind it
  // (a ray into a gap).
  // With `floor` (a lap's lower plate), it also reaches past removed points
  // behind that line: no surface lies there (a reflection cluster).
  void reach_removed(const Line& l, const Line* other, int dir, int stop, Vec2& end_pt, int& end_col,
                     const Line* floor = nullptr) const {
    if (!p_.reach_removed_points) return;
    const int lo = dir > 0 ? end_col : stop, hi = dir > 0 ? stop : end_col;
    const auto removed = outliers_between(lo, hi);
    if (removed.empty()) return;
    const std::size_t off = static_cast<std::size_t>(removed.data() - s_.outlier_points.data());
    const int n = static_cast<int>(removed.size());
    for (int k = dir > 0 ? 0 : n - 1, col = end_col; k >= 0 && k < n; k += dir) {
      if (s_.outlier_cols[off + k] != col + dir) break;
      col += dir;
      const Vec2& o = removed[k];
      const double d = l.signed_distance(o);
      if (std::abs(d) <= tol_ && (!other || other->distance(o) > tol_)) end_pt = o, end_col = col;
      else if (d < 0.0 && !(floor && floor->signed_distance(o) < -tol_)) break;
    }
  }

  // The last of the consecutive points from `end` on, stepping by `step` (not
  // reaching `stop`), that lie on line l (within the surface tolerance), over
  // single points off it that lie at most 2 tolerances behind it (noise; a ray
  // into a gap goes deeper), between two points on the line in the
  // neighbouring columns (no column missing or removed on either side).
  int reach(const Line& l, int end, int step, int stop) const {
    for (int i = end + step; i != stop; i += step) {
      if (l.distance(pt(i)) <= tol_) {
        end = i;
        continue;
      }
      const int next = i + step;
      if (!p_.reach_over_single_points || next == stop || l.signed_distance(pt(i)) < -2.0 * tol_ ||
          l.distance(pt(next)) > tol_ || std::abs(s_.cols[next] - s_.cols[i - step]) != 2)
        break;
      end = i = next;
    }
    return end;
  }

  // Evidence (see butt_pair) that plates a and b, whose facing end points are
  // a_end and b_end, are separated; `missing`: invalid columns or a jump lie
  // between them. Missing columns with both sides on one line and nothing
  // seen between them are strong evidence only on clean profiles: on noisy
  // ones a dropout (or points removed as outliers) looks the same, unless
  // the rays found nothing over a run of min_hole_columns (dropouts on a
  // plate are isolated columns). a_fit, b_fit: the plates' fits to their
  // points [first, last], if the caller has them.
  int evidence(const Plate& a, const Plate& b, int a_end, int b_end, bool missing, const LineFit* a_fit = nullptr,
               const LineFit* b_fit = nullptr) const {
    if (!missing) return 0;
    if (b_end != a_end + 1 || b.line.distance(pt(a_end)) > tol_ || a.line.distance(pt(b_end)) > tol_) return 1;
    if (invalid_run(s_.cols[a_end], s_.cols[b_end]) >= std::max(1, p_.butt.min_hole_columns)) return 1;
    const auto fa = a_fit ? std::optional<LineFit>(*a_fit) : s_.fit(a.first, a.last);
    const auto fb = b_fit ? std::optional<LineFit>(*b_fit) : s_.fit(b.first, b.last);
    const bool noisy = fa && fb && std::max(fa->rms_mm, fb->rms_mm) > 0.25 * tol_;
    return noisy ? 0 : 1;
  }

  void butt() {
    const int s_min = std::max(2, p_.segmentation.segments.min_segment_points);
    // A hole between points k and k + 1: a run of min_hole_columns invalid
    // columns (see evidence()).
    const int hole = std::max(1, p_.butt.min_hole_columns);
    auto is_hole = [&](int k) { return s_.cuts[k] && invalid_run(s_.cols[k], s_.cols[k + 1]) >= hole; };
    // Two plates in neighbouring long segments (or with one between them, an
    // edge face) with something between them...
    for (int q1 = 0; q1 + 1 < n_long(); ++q1) {
      // The edge preparation (chamfers, roundings) and walls seen in the gap
      // can be long segments between them: any number, while the plates'
      // facing ends are near enough, none continuing either plate.
      for (int q2 = q1 + 1; q2 < n_long(); ++q2) {
        if ((pt(seg(q2).first) - pt(seg(q1).last)).norm() > p_.max_joint_width_mm) break;
        Plate a = extended(q1, -1), b = extended(q2, +1);
        if (!near_enough(a, b)) continue;
        bool pieces = false;
        for (int m = q1 + 1; m < q2 && !pieces; ++m) pieces = continues_either(seg(m), q1, q2);
        if (pieces) continue;
        // Each plate reaches over the consecutive points between them that lie
        // on its line (within the surface tolerance): noise cuts a far plate
        // into pieces too short to be segments. Not across a hole (a run of
        // min_hole_columns invalid columns): plates on one line each reach
        // over the other's points, and past the hole it would be lost.
        int a_stop = a.last + 1;
        while (a_stop < b.first && !is_hole(a_stop - 1)) ++a_stop;
        a.last = reach(a.line, a.last, +1, a_stop);
        int b_stop = b.first - 1;
        while (b_stop > a.last && !is_hole(b_stop)) --b_stop;
        b.first = reach(b.line, b.first, -1, b_stop);
        // Something between them off both lines (walls in the gap), missing
        // columns, or a jump; a few noisy points on the plates' line are not a gap.
        bool strong = s_.invalid_columns_between(s_.cols[a.last], s_.cols[b.first]) > 0;
        // A jump counts when the step leaves the plates' surface (across
        // the plates by more than the tolerance): noise alone can make a
        // step long enough to cut the profile, along the surface.
        for (int k = a.last; k < b.first && !strong; ++k)
          strong = s_.cuts[k] && std::abs(a.line.n.dot(pt(k + 1) - pt(k))) > tol_;
        if (strong || off_both(a.last + 1, b.first - 1, a.line, b.line))
          butt_pair(a, b, a.last + 1, b.first - 1, evidence(a, b, a.last, b.first, strong));
      }
    }
    // ...or one segment with a hole or a step in it (plates merged across the
    // gap). A hole: a cut (invalid columns, a jump) or points removed as
    // outliers behind the plate (rays that went into the gap). A step: the
    // next point leaves the line of the s_min points before it, and a few
    // points later a straight run of s_min points starts, parallel to it,
    // with every point between off both lines (the gap's walls).
    // Fits of the s_min points from a point on, by that point modulo 32: the
    // test below fits the window before each candidate point and up to
    // kMaxWallPoints + 1 after it, and neighbouring candidates share them.
    std::array<int, 32> window_first;
    window_first.fill(-1);
    std::array<std::optional<LineFit>, 32> window_fit;
    auto window = [&](int first) {
      const std::size_t w = static_cast<std::size_t>(first) % window_first.size();
      if (window_first[w] != first) window_first[w] = first, window_fit[w] = s_.fit(first, first + s_min - 1);
      return window_fit[w];
    };
    for (int q = 0; q < n_long(); ++q) {
      const Segment& sg = seg(q);
      // Sums of points [sg.first, head_last], grown with k: the first part's
      // sums at a hole, added in the order Segmentation::sums adds them.
      PointSums head;
      int head_last = sg.first - 1;
      // All points on one line: only cuts and missing columns can be holes.
      const bool straight = sg.rms_mm <= 0.25 * tol_;
      if (straight && sg.last_col - sg.first_col == sg.count() - 1 &&
          !std::memchr(s_.cuts.data() + sg.first, 1, static_cast<std::size_t>(sg.count() - 1)))
        continue;  // no missing column, no jump: nothing to split at
      // Cheap tests first: a cut or a missing column after k, or (unless all
      // points are on one line) the next point leaving the chord of the
      // s_min points before it. Most points fail them: they run in a tight
      // loop on locals.
      const Vec2* points = s_.points.data();
      const std::uint8_t* cuts = s_.cuts.data();
      const int* cols = s_.cols.data();
      const double tol2 = tol_ * tol_;
      auto candidate = [&](int k) {
        const bool joined = !cuts[k] && cols[k + 1] == cols[k] + 1;
        if (!joined) return true;
        if (straight) return false;
        const Vec2& pk = points[k];
        const Vec2 chord = pk - points[k - s_min + 1], step = points[k + 1] - pk;
        const double c = chord.x() * step.y() - chord.y() * step.x();
        return c * c > tol2 * chord.squaredNorm();
      };
      const int k_last = sg.last - s_min;
      for (int k = sg.first + s_min - 1; k <= k_last; ++k) {
        while (k <= k_last && !candidate(k)) ++k;
        if (k > k_last) break;
        const auto local = window(k - s_min + 1);
        if (!local) continue;
        bool hole = s_.cuts[k];
        // A jump only over points removed as outliers, with the next point
        // still on the plate's line, is a noise cluster unless some of those
        // points lie well behind the plate (rays that went into the gap).
        const bool on_line = sg.line.distance(pt(k)) <= tol_ && sg.line.distance(pt(k + 1)) <= tol_;
        if (s_.cols[k + 1] > s_.cols[k] + 1 && on_line &&
            s_.invalid_columns_between(s_.cols[k], s_.cols[k + 1]) == 0) {
          hole = false;
          for (const Vec2& o : outliers_between(s_.cols[k], s_.cols[k + 1]))
            hole = hole || sg.line.signed_distance(o) < -2.0 * tol_;
        } else if (!hole && s_.cols[k + 1] > s_.cols[k] + 1)
          for (const Vec2& o : outliers_between(s_.cols[k], s_.cols[k + 1]))
            hole = hole || local->line.signed_distance(o) < -tol_;
        int e = k + 1;  // first point of the second plate
        if (!hole) {
          if (local->line.distance(pt(k + 1)) <= tol_) continue;
          // Walls end at the first point back on the local line: no later e
          // has walls before it (on noisy plates that is a point or two on).
          int e_max = std::min(k + 1 + kMaxWallPoints, sg.last - s_min + 1);
          for (int i = k + 2; i < e_max; ++i) {
            if (local->line.distance(pt(i)) <= tol_) {
              e_max = i;
              break;
            }
          }
          for (e = k + 1; e <= e_max; ++e) {
            const auto next = window(e);
            if (!next || next->rms_mm > 0.5 * tol_ || next->line.distance(pt(k)) <= tol_ ||
                acute_angle_deg(next->line, local->line) > p_.butt.max_plate_angle_deg)
              continue;
            // Every point in (k, e) is off the local line already (k + 1
            // tested above, the others by e_max's scan): off the next one too?
            bool walls = true;
            for (int i = k + 1; i < e && walls; ++i) walls = next->line.distance(pt(i)) > tol_;
            if (walls) {
              hole = true;
              break;
            }
          }
        }
        if (!hole) continue;
        while (head_last < k) head.add(pt(++head_last) - s_.ref_);
        PointSums tail = sg.sums - head;
        for (int i = k + 1; i < e; ++i) tail.add(pt(i) - s_.ref_, -1.0);  // the walls
        const auto fa = s_.fit(head), fb = s_.fit(tail);
        if (!fa || !fb) continue;
        Plate a{sg.first, k, fa->line, fa->centroid}, b{e, sg.last, fb->line, fb->centroid};
        // Each part over the long segments beyond it on its line, as above.
        if (p_.butt.extend_split_plates) {
          a = extended(a, head, fa, q, -1);
          b = extended(b, tail, fb, q, +1);
        }
        // Missing columns with both sides on one line are strong evidence only
        // on clean profiles: on noisy ones a dropout looks the same.
        const bool missing = s_.cuts[k] || s_.cols[k + 1] > s_.cols[k] + 1;
        // evidence() fits a part again only if it was extended.
        const bool a_own = a.first == sg.first && a.last == k, b_own = b.first == e && b.last == sg.last;
        butt_pair(a, b, k + 1, e - 1,
                  evidence(a, b, k, e, missing, a_own ? &*fa : nullptr, b_own ? &*fb : nullptr));
      }
    }
    // ...or a dip in one segment (ButtParams::dip_in_segment): a run of at
    // least 3 consecutive points behind its line by more than the surface
    // tolerance, s_min points or more from either end (a closed joint's
    // rounded or chamfered edges, shallower than the split threshold and
    // too smooth for the step test above, which looks for a corner).
    if (p_.butt.dip_in_segment)
      for (int q = 0; q < n_long(); ++q) {
        const Segment& sg = seg(q);
        if (sg.count() < 2 * s_min + 3) continue;
        const Line& line = sg.line;  // normal towards the sensor
        for (int i = sg.first + s_min; i <= sg.last - s_min;) {
          if (!(line.signed_distance(pt(i)) < -tol_)) {
            ++i;
            continue;
          }
          int r1 = i;
          while (r1 + 1 <= sg.last - s_min && line.signed_distance(pt(r1 + 1)) < -tol_) ++r1;
          const int r0 = i;
          i = r1 + 1;
          if (r1 - r0 + 1 < 3) continue;
          const auto a = plate_of(sg.first, r0 - 1), b = plate_of(r1 + 1, sg.last);
          if (!a || !b) continue;
          butt_pair(*a, *b, r0, r1, evidence(*a, *b, r0 - 1, r1 + 1, false));
        }
      }
    // ...or a hole (a run of min_hole_columns invalid columns) fewer than s_min
    // points from a long segment's end: noise cut the plate beyond the hole
    // into pieces, and the merge joined the first of them, a stub, to this
    // segment across the hole. That plate is the next long segment, which
    // must reach back over the pieces and the stub to the hole (see reach()).
    // Likewise at the segment's start with the long segment before it.
    if (p_.butt.stub_across_hole) {
      for (int q = 0; q < n_long(); ++q) {
        const Segment& sg = seg(q);
        if (q + 1 < n_long())
          for (int k = std::max(sg.first + s_min - 1, sg.last - s_min + 1); k < sg.last; ++k) {
            if (!is_hole(k)) continue;
            Plate b = extended(q + 1, +1);
            if (reach(b.line, b.first, -1, k) != k + 1) continue;
            b.first = k + 1;
            const PointSums sums = s_.sums(sg.first, k);
            const auto fit = s_.fit(sums);
            if (!fit) continue;
            const Plate a{sg.first, k, fit->line, fit->centroid};
            butt_pair(extended(a, sums, fit, q, -1), b, k + 1, k, evidence(a, b, k, k + 1, true, &*fit));
          }
        if (q > 0)
          for (int k = sg.first; k < std::min(sg.first + s_min - 1, sg.last - s_min + 1); ++k) {
            if (!is_hole(k)) continue;
            Plate a = extended(q - 1, -1);
            if (reach(a.line, a.last, +1, k + 1) != k) continue;
            a.last = k;
            const PointSums sums = s_.sums(k + 1, sg.last);
            const auto fit = s_.fit(sums);
            if (!fit) continue;
            const Plate b{k + 1, sg.last, fit->line, fit->centroid};
            butt_pair(a, extended(b, sums, fit, q, +1), k + 1, k, evidence(a, b, k, k + 1, true, nullptr, &*fit));
          }
      }
    }
  }

  // The v-groove: its own template (the root: root faces, gaps, bevels seen
  // edge-on), and the groove model (tops, walls, the bottom whatever it is).
  // With GrooveParams::vgroove_fill (beads laid in the groove: multi-pass)
  // the model's accepted reading stands unless the template's agrees with
  // it (top edges and track point within agree_mm). Without, the
  // template's stands, with the model's wall angles and top width where
  // their top edges agree; a template reading that lies on the bottom of
  // the model's wider groove without seeing its tops is rejected (it read
  // a bead's or a tack weld's bumps as bevels: a bead and a tack weld in
  // the root look the same, so only the user knows beads are expected).
  void vgroove_or_fill(Candidate& best) {
    vgroove();
    const bool had = found_;
    const auto readings = readings_;
    const int n_readings = n_readings_;
    const auto kept = kept_;
    const int n_kept = n_kept_;
    Candidate g;
    found_ = false, best_ = &g, n_readings_ = 0, n_kept_ = 0;
    groove(JointType::VGroove);
    const bool g_ok = found_ && g.accepted;
    best_ = &best;
    auto near = [&](const std::optional<Vec2>& x, const std::optional<Vec2>& y) {
      return x && y && (*x - *y).norm() <= p_.groove.agree_mm;
    };
    const bool tops_agree = had && best.accepted && g_ok && near(best.bp[1], g.bp[1]) && near(best.bp[5], g.bp[5]);
    if (p_.groove.vgroove_fill && g_ok && !(tops_agree && near(best.track, g.track))) {
      best = g;
      found_ = true;
      return;
    }
    // Beads are laid, and the model has no reading: the template's stands
    // only with both plate tops seen (without, it is a V the noise or a
    // bead's bumps make anywhere: 120 mm off on a plate at 0.2 mm noise).
    // And where the model found this groove but cannot place its track point
    // (a wall's foot unseen), the template, which knows no beads, reading a
    // root between the same top edges is no better placed (it took a toe's
    // corner for a closed root, 5.6 mm off).
    if (p_.groove.vgroove_fill && !g_ok && had && best.accepted) {
      if (!best.bp[1] || !best.bp[5]) {
        best.accepted = false;
        std::snprintf(best.reason, sizeof best.reason,
                      "no groove with its plate tops (with beads laid, the v-groove template's reading needs both)");
      }
      for (int k = 0; best.accepted && best.track && k < n_unplaced_; ++k) {
        const auto& [e1, e5] = unplaced_[k];
        const Vec2 along = (e5 - e1).normalized();
        const double u = (*best.track - e1).dot(along);
        if (u > -p_.groove.agree_mm && u < (e5 - e1).norm() + p_.groove.agree_mm) {
          best.accepted = false;
          std::snprintf(best.reason, sizeof best.reason,
                        "a wall's foot is not seen (the groove model, with beads laid): the track point cannot be "
                        "placed");
        }
      }
    }
    found_ = had;
    readings_ = readings, n_readings_ = n_readings;
    kept_ = kept, n_kept_ = n_kept;
    if (tops_agree) {
      best.wall_a = g.wall_a, best.wall_b = g.wall_b, best.top_width = g.top_width;
      if (p_.groove.vgroove_fill) best.fill_lowest = g.fill_lowest;
      return;
    }
    // The template's reading lies on the bottom of a wider groove whose tops
    // it does not see: it read a bead's (or a tack weld's) bumps as bevels.
    // Not this groove's root: say so.
    if (had && best.accepted && best.track && g_ok && (!best.bp[1] || !best.bp[5]) && !near(best.track, g.track)) {
      const Vec2 along = (*g.bp[5] - *g.bp[1]).normalized();
      const Vec2 down(along.y(), -along.x());
      const double u = (*best.track - *g.bp[1]).dot(along), v = (*best.track - *g.track).dot(down);
      if (u >= (*g.bp[2] - *g.bp[1]).dot(along) - p_.groove.agree_mm &&
          u <= (*g.bp[4] - *g.bp[1]).dot(along) + p_.groove.agree_mm && std::abs(v) <= 3.0) {
        best.accepted = false;
        std::snprintf(best.reason, sizeof best.reason,
                      "inside a wider groove (walls %.3g and %.3g deg, %.3g mm wide at the top): beads laid in it? "
                      "(read its fill with GrooveParams::vgroove_fill)",
                      g.wall_a, g.wall_b, g.top_width);
      }
    }
  }

  // The groove model (docs/JOINTS.md "Grooves and fill"): two plate tops
  // (long segments, parallel, the groove between them deeper than
  // GrooveParams::depth_mm), a wall below each top edge (a straight run from
  // the top's end down; a square wall may be hidden from the camera), and
  // the bottom between the walls' feet (the toes), whatever its shape: the
  // root, a U's or J's radius, or the last bead laid. Every pair of tops is
  // a reading; they compete by their evidence as the other templates' do.
  void groove(JointType joint) {
    const GrooveParams& gp = p_.groove;
    const double max_sin = std::sin(gp.max_top_angle_deg * std::numbers::pi / 180.0);
    for (int qa = 0; qa + 1 < n_long(); ++qa) {
      for (int qb = qa + 1; qb < n_long(); ++qb) {
        const Segment& sa = seg(qa);
        const Segment& sb = seg(qb);
        if ((pt(sb.first) - pt(sa.last)).norm() > gp.top_width_mm.max + 2.0 * gp.max_edge_mm) break;
        if (std::abs(sa.line.n.x() * sb.line.n.y() - sa.line.n.y() * sb.line.n.x()) > max_sin) continue;
        // Both tops of one plate surface, give or take the mismatch (a bead's
        // flat cap deep in the groove is parallel to them too).
        if (sa.line.distance(pt(sb.first)) > gp.mismatch_mm.max + tol_) continue;
        // A long segment between them on the tops' line: the tops of another
        // groove, or the plate's own top cut by a dropout (extended() joins it).
        bool inner_top = false;
        for (int q = qa + 1; q < qb && !inner_top; ++q)
          inner_top = continues(seg(q), sa) || continues(seg(q), sb);
        if (inner_top) continue;
        groove_pair(joint, extended(qa, -1), extended(qb, +1));
      }
    }
  }

  // A wall below a top edge: the first fitted segment from the top's end
  // towards the groove (dir +1: after top a; -1: before top b) with
  // min_wall_points points, starting within max_edge_mm of the top's end and
  // at least min_wall_deg to the top, joined with the segments after it on
  // its line. Returns its point range and fit; empty if none.
  struct Wall {
    int first = 0, last = 0;  // point indices, scan order
    Line line;
    PointSums sums;  // its points (relative to the segmentation's reference)
  };
  std::optional<Wall> wall_below(const Plate& top, int end, int dir, int stop) const {
    const GrooveParams& gp = p_.groove;
    const int n_seg = static_cast<int>(s_.segments.size());
    // The segment holding the first point past the top's end.
    int k = 0;
    while (k < n_seg && s_.segments[k].last < end + dir) ++k;
    if (dir < 0) {
      k = n_seg - 1;
      while (k >= 0 && s_.segments[k].first > end + dir) --k;
    }
    // Of the segments starting within max_edge_mm, the one reaching
    // farthest from its first point to its last (GrooveParams::
    // wall_by_reach; noise cuts short pieces at any angle off the edge, a
    // rounded or chamfered top edge is no longer than its size, and a wall
    // the laser sees edge-on has few points spread down its depth), or
    // with the most points.
    int pick = -1;
    auto reach = [&](const Segment& g) { return (pt(g.last) - pt(g.first)).norm(); };
    for (; k >= 0 && k < n_seg; k += dir) {
      const Segment& sg = s_.segments[k];
      if (dir > 0 ? sg.first >= stop : sg.last <= stop) break;
      const Vec2& near = pt(dir > 0 ? sg.first : sg.last);
      if ((near - pt(end)).norm() > gp.max_edge_mm) break;
      if (!sg.fitted || sg.count() < gp.min_wall_points || acute_angle_deg(sg.line, top.line) < gp.min_wall_deg)
        continue;
      if (pick < 0 || (gp.wall_by_reach ? reach(sg) > reach(s_.segments[pick])
                                        : sg.count() > s_.segments[pick].count()))
        pick = k;
    }
    if (pick >= 0) {
      k = pick;
      const Segment& sg = s_.segments[k];
      Wall w{sg.first, sg.last, sg.line, sg.sums};
      PointSums& sums = w.sums;
      double w_rms = sg.rms_mm;  // of its line as fitted to `sums`
      // Past up to two pieces of at most 8 points off its line (a reflection
      // cluster on the wall), or more while they hold no more points than
      // a reflection cluster (with GrooveParams::wall_joins_one_line: a
      // cluster and a dropout's single points around it), to the next
      // segment on it.
      int skipped = 0, skipped_points = 0;
      const int cluster = max_cluster_run();
      for (int m = k + dir; m >= 0 && m < n_seg; m += dir) {
        const Segment& nx = s_.segments[m];
        if (dir > 0 ? nx.first >= stop : nx.last <= stop) break;
        // On it: a line of 3 or more points along it (a few points of the
        // bottom at the corner also lie within the tolerance of it).
        bool on = nx.fitted && nx.count() >= 3 && acute_angle_deg(nx.line, w.line) <= 15.0;
        for (int i = nx.first; i <= nx.last && on; ++i) on = w.line.distance(pt(i)) <= tol_;
        // Or the two are one line (GrooveParams::wall_joins_one_line): a
        // segment of more points than a reflection cluster whose joint fit
        // with the wall is within the tolerance and no worse than 1.5 times
        // the rougher part's (a short piece's line, off in angle, misses a
        // long wall's points far below it by more than the tolerance).
        if (!on && gp.wall_joins_one_line && nx.fitted && nx.count() > cluster &&
            acute_angle_deg(nx.line, w.line) <= 15.0) {
          PointSums both = sums;
          both += nx.sums;
          const auto f = s_.fit(both);
          on = f && f->rms_mm <= tol_ && f->rms_mm <= 1.5 * std::max(w_rms, nx.rms_mm);
        }
        if (!on && nx.count() <= 8) {
          skipped_points += nx.count();
          if (++skipped <= 2 || (gp.wall_joins_one_line && skipped_points <= cluster)) continue;
        }
        if (!on) break;
        sums += nx.sums;
        if (const auto f = s_.fit(sums)) w.line = f->line, w_rms = f->rms_mm;
        w.first = std::min(w.first, nx.first), w.last = std::max(w.last, nx.last);
      }
      w.line.orient_towards(origin_);
      return w;
    }
    return std::nullopt;
  }

  // The bottom at B3 must be one surface (groove_pair): B3's neighbours
  // within kB3OffMm of the line most points within kB3SupportMm lie on.
  static constexpr double kB3SupportMm = 1.5;
  static constexpr double kB3OffMm = 0.5;
  void groove_pair(JointType joint, const Plate& a, const Plate& b) {
    const GrooveParams& gp = p_.groove;
    Candidate c;
    c.pa = a, c.pb = b;
    // Along the tops from a to b, and "down" into the work (away from the sensor).
    Vec2 along = a.line.direction();
    if (along.dot(b.centroid - a.centroid) < 0.0) along = -along;
    const Vec2 down = -a.line.n;
    const auto depth_below = [&](const Line& top, const Vec2& q) { return -top.signed_distance(q); };
    // The groove: something between the tops deeper than depth_mm.min.
    double deepest = 0.0;
    for (int i = a.last + 1; i < b.first; ++i) deepest = std::max(deepest, depth_below(a.line, pt(i)));
    if (deepest < gp.depth_mm.min) return;
    // Seen by fewer points than two walls' and one of the bottom, a groove
    // is not told from a reflection cluster behind a plate (5 points 3.5 mm
    // behind a plate, read as a J 170 mm from the joint).
    if (b.first - a.last - 1 < 2 * gp.min_wall_points + 1) return;
    const auto wa = wall_below(a, a.last, +1, b.first);
    const auto wb = wall_below(b, b.first, -1, wa ? wa->last : a.last);
    // Which walls may be square and hidden: a bevel's or J's square side is
    // the one not seen, or the steeper of the two.
    const bool one_square = joint == JointType::Bevel || joint == JointType::JGroove;
    if (!wa && !wb) return;
    if ((!wa || !wb) && !one_square) {
      std::snprintf(c.reason, sizeof c.reason, "the %s wall is not seen", wa ? "second" : "first");
      c.track = a.line.project(0.5 * (pt(a.last) + pt(b.first)));
      offer(c);
      return;
    }
    const double ang_a = wa ? acute_angle_deg(wa->line, a.line) : 90.0;
    const double ang_b = wb ? acute_angle_deg(wb->line, b.line) : 90.0;
    const bool square_a = one_square && (!wa || (wb && ang_a >= ang_b));
    // A top edge: where the top meets its wall's line, or for a hidden
    // square wall the top's edge (between the rays) with the wall through it,
    // square to the top.
    double unc = 0.0;
    // `wall_cov`: how precisely the wall's line is known (docs/JOINTS.md
    // "Localization"): from its points, or for a hidden square wall from
    // the top's edge (its offset, along the top) and the top's direction.
    auto top_edge = [&](const Plate& top, const std::optional<Wall>& w, int end, int beyond_col, Line& wall,
                        LineCov& wall_cov) -> std::optional<Vec2> {
      if (w) {
        wall = w->line;
        wall_cov = cov_of(w->line, w->sums);
        return intersect(top.line, wall, 0.1);
      }
      const Edge e = edge_at(top, pt(end), beyond_col, nullptr, {});
      wall.n = top.line.direction();
      wall.c = wall.n.dot(e.point);
      wall.orient_towards(origin_);
      wall_cov.mean = e.point, wall_cov.n = wall.n;
      wall_cov.var_offset = wall.n.dot(e.cov * wall.n);
      // Square to the top to within the top's direction and the angle a
      // hidden face may lie from square (TrackerParams::hidden_face_deg).
      wall_cov.var_angle = cov_of(top).var_angle + std::pow(p_.hidden_face_deg * kDeg, 2);
      unc += e.half_width_mm;
      return e.point;
    };
    Line la, lb;
    LineCov ca, cb;
    const auto e1 = top_edge(a, wa, a.last, s_.cols[a.last] + 1, la, ca);
    const auto e5 = top_edge(b, wb, b.first, s_.cols[b.first] - 1, lb, cb);
    if (!e1 || !e5) return;
    const Vec2 b1 = *e1, b5 = *e5;
    if ((b5 - b1).dot(along) <= 0.0) return;
    // The bottom's points: between the walls' feet (or the tops' ends where
    // a wall is hidden).
    const int bot_first = wa ? wa->last + 1 : a.last + 1, bot_last = wb ? wb->first - 1 : b.first - 1;
    // The bottom must be seen: a few points of it, or the walls' seen ends
    // within a notch of each other (a closed or narrow root). A wall that
    // leaves the camera's view or the laser's reach partway down says
    // nothing about what lies below it.
    {
      // (A hidden wall's end could be anywhere on its line; measured to it,
      // the bevel's false reads on the corpus' development seeds rose from
      // 127 to 178: the root under a hidden square wall is not where the
      // other wall's foot says.)
      const Vec2 end_a = wa ? pt(wa->last) : pt(a.last), end_b = wb ? pt(wb->first) : pt(b.first);
      const double apart = (end_b - end_a).norm();
      if (bot_last - bot_first + 1 < 3 && apart > gp.max_notch_mm) {
        std::snprintf(c.reason, sizeof c.reason,
                      "the groove's bottom is not seen (%d points between the walls' ends, %.3g mm apart)",
                      std::max(0, bot_last - bot_first + 1), apart);
        c.track = a.line.project(0.5 * (end_a + end_b));
        offer(c);
        return;
      }
    }
    // A toe: where the wall meets the bottom: the wall's line and the line of
    // the bottom's first few points, if they cross near the wall's last point;
    // else that point on the wall's line.
    // `bare`: the toe is the wall's last seen point with no bottom seen
    // beside it (nothing within 1 mm): the wall may run on unseen below it.
    // `cov`: the toe's covariance (docs/JOINTS.md "Localization"), from the
    // wall's line (wall_cov; `wall_pts`: its points, absent for a hidden
    // wall) and what places the toe along it.
    auto toe = [&](const Line& wall, const LineCov& wall_cov, const Wall* wall_pts, const Vec2& top_edge, int wall_end,
                   int from, int step, bool& bare, Eigen::Matrix2d& cov) {
      const Vec2 foot = wall.project(pt(wall_end));
      const Vec2 wn = wall.n, wd = wall.direction();
      const bool in_bottom = from >= bot_first && from <= bot_last;
      const double reach = in_bottom ? (pt(from) - foot).norm() : 0.0;
      // At the wall's last seen point: the toe lies between its foot and
      // where the next column's ray (which did not see the wall: an invalid
      // column's went past it) meets the wall's line, as a plate's edge
      // does (edge_at), and, with the bottom seen beside it (within 1 mm),
      // no deeper below the tops than the bottom's first point. Its mean
      // square distance from the foot is that edge's covariance plus the
      // edge's offset from the foot squared. A hidden wall: across it its
      // line, along it the point's noise.
      cov = wall_cov.across_var(foot) * wn * wn.transpose() + sigma_ * sigma_ * wd * wd.transpose();
      if (wall_pts) {
        const int beyond_col = s_.cols[wall_end] + step;
        const Plate wp{wall_pts->first, wall_pts->last, wall, s_.moments(wall_pts->sums).mean};
        double max_width = std::numeric_limits<double>::infinity();
        if (const double slope = outward(wp, foot).dot(down); in_bottom && reach <= 1.0 && slope > 0.2)
          max_width = std::max(0.0, (pt(from) - foot).dot(down) / slope);
        const Edge e = edge_at(wp, pt(wall_end), beyond_col, nullptr, {},
                                 {.sharp = true, .max_width = max_width, .line_cov = &wall_cov});
        const Vec2 off = e.point - foot;
        cov = e.cov + off * off.transpose();
      }
      // Where the columns between the wall's last point and the bottom's
      // first are invalid (a dropout hid the corner), the bottom's first
      // point may lie farther from the foot (up to 2 max_edge_mm): the wall
      // runs on unseen down to the bottom, and the toe is where they meet
      // within that unseen stretch (taken at the wall's last point, it lay
      // 2-4 mm up the wall). The bottom is then looked at from its first
      // point on instead of from the foot.
      // Invalid columns between the wall's last point and the bottom's first
      // (looked at only where those lie more than 1 mm apart).
      const bool gap_invalid = in_bottom && reach > 1.0 &&
                               s_.invalid_columns_between(std::min(s_.cols[wall_end], s_.cols[from]),
                                                          std::max(s_.cols[wall_end], s_.cols[from])) > 0;
      const bool unseen = gap_invalid && reach <= 2.0 * gp.max_edge_mm;
      const Vec2 anchor = unseen ? pt(from) : foot;
      const auto within_unseen = [&](const Vec2& x) {
        return (x - foot).norm() <= reach + tol_ && (x - pt(from)).norm() <= reach + tol_;
      };
      // A radius at the foot (U, J): the bottom's points next to the wall lie
      // on a circle tangent to it; the toe is where it touches the wall.
      double along_var = 0.0;
      if (const auto t = tangent_toe(wall, foot, anchor, (top_edge - foot).normalized(), unseen ? reach : 0.0, from,
                                     step, bot_first, bot_last, &along_var)) {
        if (unseen && !within_unseen(*t)) return foot;
        cov = wall_cov.across_var(*t) * wn * wn.transpose() + along_var * wd * wd.transpose();
        return *t;
      }
      // Bare: no bottom, or its first point farther than 1 mm and than 2.5
      // times the points' spacing there, or with invalid columns between
      // (sparse columns on a wall seen at a grazing angle leave more than
      // 1 mm between seen points).
      if (!in_bottom) {
        bare = true;
      } else if (reach > 1.0) {
        const int prev = wall_end - step;  // the wall's point before its last
        const bool prev_ok = prev >= 0 && prev < static_cast<int>(s_.points.size());
        const bool next_ok = from + step >= bot_first && from + step <= bot_last;
        const double spacing = std::max(prev_ok ? (pt(wall_end) - pt(prev)).norm() : 0.0,
                                        next_ok ? (pt(from + step) - pt(from)).norm() : 0.0);
        bare = gap_invalid || reach > 2.5 * spacing;
      }
      // The bottom's points within 3 mm of the wall's foot (or of the
      // bottom's first point past a dropout) that lie clearly off the wall's
      // line (2 tolerances: the corner's points are both), at least 4, on a
      // line, the first right beside the foot.
      if (!in_bottom || (reach > 1.0 && !unseen)) return foot;
      PointSums sums;
      for (int i = from; i >= bot_first && i <= bot_last && (pt(i) - anchor).norm() <= 3.0; i += step)
        if (wall.distance(pt(i)) > 2.0 * tol_) sums.add(pt(i) - s_.ref_);
      if (sums.n < 4) return foot;
      const auto f = s_.fit(sums);
      if (!f || f->rms_mm > tol_) return foot;
      const auto x = intersect(wall, f->line, 0.2);
      if (!x) return foot;
      const Eigen::Matrix2d x_cov = intersection_cov(wall_cov, cov_of(f->line, sums), *x);
      // Past a dropout the bottom's line must lie across the wall, within 45
      // degrees of the tops (a bead's cap, a root's land): rays into a root
      // gap (the other plate's root face, steep) are no bottom to meet.
      if (unseen) {
        if (!within_unseen(*x) || acute_angle_deg(f->line, a.line) > 45.0) return foot;
        bare = false;
        cov = x_cov;
        return *x;
      }
      if ((*x - foot).norm() > 2.0 * gp.max_edge_mm) return foot;
      cov = x_cov;
      return *x;
    };
    bool bare_a = false, bare_b = false, unused = false;
    Eigen::Matrix2d c2, c4;
    Vec2 b2 = wa ? toe(la, ca, &*wa, b1, wa->last, bot_first, +1, bare_a, c2)
                 : toe(la, ca, nullptr, b1, bot_first <= bot_last ? bot_first : b.first, bot_first, +1, unused, c2);
    Vec2 b4 = wb ? toe(lb, cb, &*wb, b5, wb->first, bot_last, -1, bare_b, c4)
                 : toe(lb, cb, nullptr, b5, bot_first <= bot_last ? bot_last : a.last, bot_last, -1, unused, c4);
    if ((b4 - b2).dot(along) < -tol_) return;
    // A bevel's square wall runs on straight down as its root face, and a
    // square wall seen edge-on is seen only partway down or not at all (its
    // points, too few for a wall, are then the bottom's): with nothing
    // between the walls' feet but a gap (no bottom of its own), its toe is
    // the root edge at the other toe's level, above or below its last point.
    if (joint == JointType::Bevel) {
      Vec2& sq = square_a ? b2 : b4;
      const Vec2& other = square_a ? b4 : b2;
      const double deeper = (sq - other).dot(down);
      bool bottomless = true;
      const Line& sq_line = square_a ? la : lb;
      for (int i = bot_first; i <= bot_last && bottomless; ++i)
        bottomless = (pt(i) - other).dot(down) > tol_ || sq_line.distance(pt(i)) <= tol_;
      Vec2 dn = sq_line.direction();  // down the square wall
      if (dn.dot(down) < 0.0) dn = -dn;
      if (std::abs(deeper) > tol_ && bottomless) {
        const double k = std::max(0.2, dn.dot(down));
        sq -= deeper / k * dn;
        // Across its wall the wall's line, along it the other toe's depth.
        const LineCov& sq_cov = square_a ? ca : cb;
        (square_a ? c2 : c4) = sq_cov.across_var(sq) * sq_line.n * sq_line.n.transpose() +
                               down.dot((square_a ? c4 : c2) * down) / (k * k) * dn * dn.transpose();
      }
    }
    // A J's square wall seen through the root gap runs on down as its root
    // face, and its seen end is the root face's foot; its toe is the root
    // edge, at the level of the bottom's shoulder across the gap (the
    // radius' lowest point): the first bottom point from the square wall
    // that is not on it and lies above its seen end, with rays into the gap
    // between (invalid columns, or points deeper than the shoulder). A bead
    // meeting the wall leaves no gap there.
    if (joint == JointType::JGroove) {
      Vec2& sq = square_a ? b2 : b4;
      const Line& sq_line = square_a ? la : lb;
      const int step = square_a ? +1 : -1, first = square_a ? bot_first : bot_last;
      const int foot_i = square_a ? (wa ? wa->last : a.last) : (wb ? wb->first : b.first);
      bool deep_between = false;
      for (int i = first; i >= bot_first && i <= bot_last; i += step) {
        if (sq_line.distance(pt(i)) <= tol_) continue;
        const double above = (sq - pt(i)).dot(down);
        if (above <= tol_) {
          deep_between = true;  // a ray into the gap
          continue;
        }
        const bool gap = deep_between || s_.invalid_columns_between(std::min(s_.cols[foot_i], s_.cols[i]),
                                                                    std::max(s_.cols[foot_i], s_.cols[i])) > 0;
        if (gap) {
          Vec2 dn = sq_line.direction();
          if (dn.dot(down) < 0.0) dn = -dn;
          const double k = std::max(0.2, dn.dot(down));
          sq -= above / k * dn;
          // Across its wall the wall's line, along it the shoulder point's
          // noise.
          (square_a ? c2 : c4) = (square_a ? ca : cb).across_var(sq) * sq_line.n * sq_line.n.transpose() +
                                 sigma_ * sigma_ / (k * k) * dn * dn.transpose();
        }
        break;
      }
    }
    // A toe at a wall's last seen point, with no bottom seen beside it, may
    // lie anywhere further down the wall (a shadow or a dropout ends it, and
    // rays into a root gap or reflections are all that follow). It is where
    // the groove's bottom is only if it lies about as deep as the other toe:
    // below its own top as the other below its own (plates offset by a
    // mismatch), or below the line B1-B5 as the other (plates of unequal
    // thickness). Higher than both by more than agree_mm, the wall was cut
    // short and the track point cannot be placed.
    // (top: the line B1-B5, normal towards the sensor; the bottom's frame below.)
    Line top;
    top.n = Vec2(-(b5 - b1).y(), (b5 - b1).x()).normalized();
    top.c = top.n.dot(b1);
    top.orient_towards(origin_);
    // A toe is where a wall ends and the bottom begins: the bottom (a bead's
    // cap, the root, a U's or J's radius) does not run on from it as a
    // straight run down at a wall's angle, deeper than a notch
    // (max_notch_mm: rays into a root gap, a root face) and deeper than the
    // wall read above the toe (a U's or J's radius seen by a few points
    // lies within the noise of a line, 4-6 mm deep below a wall tens of mm
    // deep). One that does is the wall going on below a piece of it that
    // was read as the whole wall (a bent top, noise cutting the wall into
    // pieces): the toe and the track point midway between the toes are not
    // where they are read. The run is as steep as the wall read (within 15
    // degrees, as wall_below joins a wall's pieces) or steeper: a radius
    // or a bead's flank turns from the wall towards the bottom, less steep.
    // The run: the longest from the bottom's first point beside the toe
    // whose line the points fit within the surface tolerance (rms). Not at
    // a bevel's or J's square wall, which runs on down as its root face
    // (placed above).
    {
      const double max_sin = std::sin(gp.min_wall_deg * std::numbers::pi / 180.0);
      for (int side = 0; side < 2; ++side) {
        const bool is_a = side == 0;
        if (!(is_a ? wa : wb) || (one_square && square_a == is_a)) continue;
        if (bot_last - bot_first + 1 < gp.min_wall_points) continue;
        const Vec2& t = is_a ? b2 : b4;
        int run_end = -1;
        std::optional<LineFit> run_fit;
        PointSums run_sums;  // the run's sums, one point added per step (linear, not quadratic)
        for (int k = 0; k <= bot_last - bot_first; ++k) {
          const int lo = is_a ? bot_first : bot_last - k, hi = is_a ? bot_first + k : bot_last;
          run_sums = s_.with_point(run_sums, is_a ? hi : lo);
          if (k + 1 < gp.min_wall_points) continue;
          const auto f = s_.fit(run_sums);
          if (!f) continue;
          if (f->rms_mm > 2.0 * tol_) break;
          if (f->rms_mm <= tol_) run_end = is_a ? hi : lo, run_fit = f;
        }
        if (run_end < 0) continue;
        const double sin_top = std::abs(run_fit->line.n.x() * a.line.n.y() - run_fit->line.n.y() * a.line.n.x());
        const double descent = depth_below(top, pt(run_end)) - depth_below(top, t);
        const double wall_descent = depth_below(top, t) - depth_below(top, is_a ? b1 : b5);
        const double run_deg = std::asin(std::min(1.0, sin_top)) * 180.0 / std::numbers::pi;
        const double wall_deg = acute_angle_deg(is_a ? la : lb, is_a ? a.line : b.line);
        if (sin_top >= max_sin && run_deg >= wall_deg - 15.0 && descent > std::max(gp.max_notch_mm, wall_descent)) {
          std::snprintf(c.reason, sizeof c.reason,
                        "the %s wall goes on below its toe: the bottom beside it runs straight down %.3g mm at %.3g "
                        "deg to the tops (its foot is not where it is read)",
                        is_a ? "first" : "second", descent, run_deg);
          c.track = 0.5 * (b2 + b4);
          offer(c);
          return;
        }
      }
    }
    {
      const double limit = std::max(gp.agree_mm, 3.0 * tol_);
      for (int side = 0; side < 2; ++side) {
        const bool is_a = side == 0;
        if (!(is_a ? bare_a : bare_b) || (one_square && square_a == is_a)) continue;
        const Vec2& t = is_a ? b2 : b4;
        const Vec2& o = is_a ? b4 : b2;
        const double own = depth_below(is_a ? b.line : a.line, o) - depth_below(is_a ? a.line : b.line, t);
        const double common = depth_below(top, o) - depth_below(top, t);
        const double above = std::min(own, common);
        if (above > limit) {
          std::snprintf(c.reason, sizeof c.reason,
                        "the %s wall's foot is not seen: it is seen down to %.3g mm above the other toe, and nothing "
                        "beside its last point",
                        is_a ? "first" : "second", above);
          c.track = 0.5 * (b2 + b4);
          if (n_unplaced_ < kMaxUnplaced) unplaced_[n_unplaced_++] = {b1, b5};
          offer(c);
          return;
        }
      }
    }
    // The bottom as a polyline from toe to toe, in the tops' frame (u along,
    // v down from the line B1-B5), narrow notches closed at their shoulders.
    auto& poly = scratch_;
    poly.clear();
    poly.push_back(b2);
    for (int i = bot_first; i <= bot_last; ++i) {
      const double u = (pt(i) - b2).dot(along);
      if (u > 0.0 && u < (b4 - b2).dot(along)) poly.push_back(pt(i));
    }
    poly.push_back(b4);
    drop_clusters(poly, along, down);
    const bool hidden_toe[2] = {!wa, !wb};
    close_notches(poly, along, down, gp.max_notch_mm, gp.bottom_steps ? &closed_ : nullptr, hidden_toe);
    // B3: the bottom midway between the toes. It must rest on the bottom as
    // seen: the polyline's piece under it no longer than a notch (a root
    // gap closed at its shoulders, a dropout run); a longer piece joins
    // points far apart (a wall seen to its end and nothing below it, a
    // toe taken from a hidden wall), and B3 on it is a guess.
    const double u_mid = 0.5 * ((b2 - b1).dot(along) + (b4 - b1).dot(along));
    Vec2 b3 = 0.5 * (b2 + b4);
    double under = (b4 - b2).norm();
    std::size_t under_k = poly.size();  // B3 lies between poly[under_k] and the next
    // B3's covariance (docs/JOINTS.md "Localization"): along the tops the
    // toes' midpoint (the toes independent), which moves it along the
    // bottom (the slope of the line through the bottom's points within
    // kB3SupportMm of it: the piece under it, between two noisy points,
    // has the noise's slope); across the tops the noise of that piece's
    // ends (a toe's, or a point's: the profile's noise), interpolated.
    const auto down_var = [&](std::size_t k) {
      if (k == 0) return down.dot(c2 * down);
      if (k + 1 == poly.size()) return down.dot(c4 * down);
      return sigma_ * sigma_;
    };
    const double var_u = 0.25 * (along.dot(c2 * along) + along.dot(c4 * along));
    Eigen::Matrix2d b3_cov = var_u * along * along.transpose() +
                             0.5 * (down_var(0) + down_var(poly.size() - 1)) * down * down.transpose();
    // B3 at a step of the bottom (GrooveParams::bottom_steps): a piece
    // joining two seen points (no closed notch), steeper than 2:1, between
    // levels (each from up to 3 points) farther apart than
    // track_interval_mm, within 3 standard deviations of B3's place along
    // the tops: a closed root with the plates' mismatch, whose track point
    // the line midway between the toes puts on either level.
    const double reach_u = 3.0 * std::sqrt(std::max(0.0, var_u));
    std::size_t step_k = poly.size();
    auto at_step = [&](std::size_t k, double u0, double u1) {
      if (!gp.bottom_steps || step_k < poly.size() || u_mid < std::min(u0, u1) - reach_u ||
          u_mid > std::max(u0, u1) + reach_u ||
          std::binary_search(closed_.begin(), closed_.end(), static_cast<int>(k)))
        return;
      const Vec2 e = poly[k + 1] - poly[k];
      const double rise = std::abs(e.dot(down)), limit = p_.confidence.track_interval_mm;
      if (rise <= limit || rise <= 2.0 * std::abs(e.dot(along))) return;
      double s0 = 0.0, s1 = 0.0;  // the levels: mean depths of up to 3 points on each side
      int n0 = 0, n1 = 0;
      for (std::size_t m = k + 1; m-- > 0 && n0 < 3;) s0 += poly[m].dot(down), ++n0;
      for (std::size_t m = k + 1; m < poly.size() && n1 < 3; ++m) s1 += poly[m].dot(down), ++n1;
      if (n0 >= 2 && n1 >= 2 && std::abs(s1 / n1 - s0 / n0) > limit) step_k = k;
    };
    for (std::size_t k = 0; k + 1 < poly.size(); ++k) {
      const double u0 = (poly[k] - b1).dot(along), u1 = (poly[k + 1] - b1).dot(along);
      if (u0 <= u_mid && u1 >= u_mid) {
        const double t = u1 > u0 ? (u_mid - u0) / (u1 - u0) : 0.5;
        b3 = poly[k] + t * (poly[k + 1] - poly[k]);
        under = (poly[k + 1] - poly[k]).norm();
        under_k = k;
        Vec2 g = (poly[k + 1] - poly[k]) / std::max(u1 - u0, 1e-9);  // per mm along
        double rough = 0.0;
        {
          std::vector<Vec2> near_b3;
          for (const Vec2& q : poly)
            if (std::abs((q - b1).dot(along) - u_mid) <= kB3SupportMm) near_b3.push_back(q);
          if (near_b3.size() >= 3)
            if (const auto f = fit_line(near_b3)) {
              const Vec2 d = f->line.direction();
              if (std::abs(d.dot(along)) > 0.1) g = d / d.dot(along);
              // Its depth is known no better than the bottom's points there
              // lie on a line: a step (the plates' mismatch at a closed
              // root), a bead's ripples (their scatter about it beyond the
              // noise's).
              rough = std::max(0.0, f->rms_mm * f->rms_mm - sigma_ * sigma_);
            }
        }
        b3_cov = var_u * g * g.transpose() +
                 ((1.0 - t) * (1.0 - t) * down_var(k) + t * t * down_var(k + 1) + rough) * down * down.transpose();
        break;
      }
    }
    for (std::size_t k = 0; k + 1 < poly.size() && gp.bottom_steps && step_k == poly.size(); ++k)
      at_step(k, (poly[k] - b1).dot(along), (poly[k + 1] - b1).dot(along));
    if (step_k < poly.size()) {
      std::snprintf(c.reason, sizeof c.reason,
                    "uncertain: the track point lies at a step of %.3g mm in the groove's bottom (a closed root's "
                    "mismatch?)",
                    std::abs((poly[step_k + 1] - poly[step_k]).dot(down)));
      c.track = 0.5 * (b2 + b4);
      c.uncertain = true;
      offer(c);
      return;
    }
    if (under > gp.max_notch_mm) {
      std::snprintf(c.reason, sizeof c.reason,
                    "the groove's bottom is not seen under the track point (its nearest points %.3g mm apart)", under);
      c.track = b3;
      offer(c);
      return;
    }
    // Nor on a step: the bottom under B3 is the root (its gap closed at
    // the root edges, level but for the plates' mismatch) or the fill,
    // smooth there. Two neighbours on the polyline farther apart in depth
    // than track_interval_mm beyond the mismatch (a square wall's seen end
    // and the other toe with the root between unseen, a dropout over a
    // bead's edge) leave B3's depth unknown between them.
    if (under_k + 1 < poly.size()) {
      const double step = std::abs((poly[under_k + 1] - poly[under_k]).dot(down));
      const double mismatch = std::abs(a.line.signed_distance(b5));
      if (step > p_.confidence.track_interval_mm + mismatch) {
        std::snprintf(c.reason, sizeof c.reason,
                      "the track point lies on a step of %.3g mm in the groove's bottom (its points there %.3g mm "
                      "apart; plates' mismatch %.3g mm): its depth is not known",
                      step, under, mismatch);
        c.track = b3;
        offer(c);
        return;
      }
    }
    // And on the bottom's surface: B3's neighbours on the polyline must lie
    // on the line that most of the bottom's points within kB3SupportMm of it
    // (along the tops) lie on, within kB3OffMm (a bead's cap, a radius or a
    // root is smooth over that length): a reflection cluster in front of or
    // behind the bottom there put B3 on the cluster (3.4 mm off) while the
    // bottom beside it was seen. The line: of the lines through two of those
    // points about kB3SupportMm apart, the one most of them lie on.
    if (under_k + 1 < poly.size()) {
      const double off_mm = std::max(kB3OffMm, 3.0 * tol_);
      std::size_t lo_k = under_k, hi_k = under_k + 1;
      while (lo_k > 0 && std::abs((poly[lo_k - 1] - b3).dot(along)) <= kB3SupportMm) --lo_k;
      while (hi_k + 1 < poly.size() && std::abs((poly[hi_k + 1] - b3).dot(along)) <= kB3SupportMm) ++hi_k;
      int best_in = -1;
      Line best_line;
      // About 16 lines, each counted on about 32 of the points (dense
      // profiles have hundreds there).
      const std::size_t m = hi_k - lo_k + 1, stride = std::max<std::size_t>(1, m / 16),
                        every = std::max<std::size_t>(1, m / 32);
      std::size_t j = lo_k + 1;
      for (std::size_t i = lo_k; i <= hi_k; i += stride) {
        j = std::max(j, i + 1);
        while (j < hi_k && (poly[j] - poly[i]).dot(along) < kB3SupportMm) ++j;
        if (j > hi_k || (poly[j] - poly[i]).norm() < 1e-9) continue;
        Line l;
        const Vec2 d = (poly[j] - poly[i]).normalized();
        l.n = Vec2(-d.y(), d.x());
        l.c = l.n.dot(poly[i]);
        int in = 0;
        for (std::size_t k = lo_k; k <= hi_k; k += every) in += l.distance(poly[k]) <= off_mm;
        if (in > best_in) best_in = in, best_line = l;
      }
      // B3's piece inside a run of the polyline with no neighbours farther
      // apart than off_mm, of more points than a reflection cluster and at
      // least kB3SupportMm long, rests on the bottom (beside a step:
      // GrooveParams::bottom_steps), not on a cluster.
      auto on_bottom = [&] {
        if (!gp.bottom_steps) return false;
        auto apart = [&](std::size_t k) { return (poly[k + 1] - poly[k]).squaredNorm() > off_mm * off_mm; };
        if (apart(under_k)) return false;
        std::size_t r0 = under_k, r1 = under_k + 1;
        while (r0 > 0 && !apart(r0 - 1)) --r0;
        while (r1 + 1 < poly.size() && !apart(r1)) ++r1;
        return static_cast<int>(r1 - r0 + 1) > max_cluster_run() &&
               std::abs((poly[r1] - poly[r0]).dot(along)) >= kB3SupportMm;
      };
      if (best_in >= 3 &&
          (best_line.distance(poly[under_k]) > off_mm || best_line.distance(poly[under_k + 1]) > off_mm) &&
          !on_bottom()) {
        std::snprintf(c.reason, sizeof c.reason,
                      "the track point rests on points %.3g mm off the groove's bottom beside it (a reflection?)",
                      std::max(best_line.distance(poly[under_k]), best_line.distance(poly[under_k + 1])));
        c.track = b3;
        offer(c);
        return;
      }
    }
    // The lowest point of the bottom (each inner point smoothed over its
    // neighbours within 10 noise sigmas along, at most 0.5 mm: noise would
    // pick its deepest sample; more would round off a cap's corner at a
    // wall).
    std::size_t low = 0;
    double low_v = -std::numeric_limits<double>::infinity();
    const double smooth = std::min(0.5, 10.0 * sigma_);
    // The inner points run along the bottom in order: a window of
    // neighbours [lo, hi) slides with k.
    std::size_t lo = 1, hi = 1;
    double window_sum = 0.0;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      double v = depth_below(top, poly[k]);
      if (k > 0 && k + 1 < poly.size()) {
        const double uk = poly[k].dot(along);
        while (hi + 1 < poly.size() && poly[hi].dot(along) - uk <= smooth) window_sum += depth_below(top, poly[hi++]);
        while (lo < k && uk - poly[lo].dot(along) > smooth) window_sum -= depth_below(top, poly[lo++]);
        v = hi > lo ? window_sum / static_cast<double>(hi - lo) : v;
      }
      if (v > low_v + 1e-9) low_v = v, low = k;
    }
    // The bottom is the root or the fill, below the tops. A straight run of
    // it at the tops' level, parallel to them, is a plate top going on past
    // a "wall" that is none: a dent or a dropout's edge in the top read as a
    // wall, the groove's real wall then lying inside the "bottom".
    const double plate_level_mm = plate_level_run(bot_first, bot_last, top, along, low_v);
    // B3 in the groove's upper half on the way from one toe up to the other
    // rests on a wall read as the bottom (a bump of a plate top taken for
    // the other wall: 8.7-10.5 mm off at 0.2 mm noise).
    {
      const double d2 = depth_below(top, b2), d3 = depth_below(top, b3), d4 = depth_below(top, b4);
      if (low_v > 0.0 && d3 < gp.min_track_depth_share * low_v && d3 >= std::min(d2, d4) - tol_ &&
          d3 <= std::max(d2, d4) + tol_) {
        std::snprintf(c.reason, sizeof c.reason,
                      "the track point lies %.3g mm below the tops of a groove %.3g mm deep, between toes %.3g and "
                      "%.3g mm deep: a wall read as the bottom?",
                      d3, low_v, std::max(d2, d4), std::min(d2, d4));
        c.track = b3;
        offer(c);
        return;
      }
    }
    // The open cross-section: B1, B2, the bottom, B4, B5.
    double area2 = 0.0;
    auto edge = [&](const Vec2& p, const Vec2& q) { area2 += p.x() * q.y() - p.y() * q.x(); };
    edge(b1, poly.front());
    for (std::size_t k = 0; k + 1 < poly.size(); ++k) edge(poly[k], poly[k + 1]);
    edge(poly.back(), b5);
    edge(b5, b1);
    c.bp[0] = outer(a, pt(a.first));
    c.bp[1] = b1, c.bp[2] = b2, c.bp[3] = b3, c.bp[4] = b4, c.bp[5] = b5;
    c.bp[6] = outer(b, pt(b.last));
    c.track = b3;
    c.track_cov = b3_cov, c.located = true;
    c.fill_lowest = poly[low];
    c.depth = low_v;
    c.area = 0.5 * std::abs(area2);
    c.wall_a = acute_angle_deg(la, a.line), c.wall_b = acute_angle_deg(lb, b.line);
    c.angle = 180.0 - c.wall_a - c.wall_b;
    c.top_width = (b5 - b1).norm();
    c.mismatch = std::abs(a.line.signed_distance(b5));
    c.edge_unc = unc;
    c.track_unc = 0.5 * unc;
    c.score = c.area;
    // Accept ranges: each wall by what it is.
    const Range& sloped = joint == JointType::UGroove ? gp.u_wall_deg : gp.bevel_wall_deg;
    const Range& ra = square_a && one_square ? gp.square_wall_deg : sloped;
    const Range& rb = !square_a && one_square ? gp.square_wall_deg : sloped;
    c.accepted = check(c, "first wall", c.wall_a, ra, "deg") && check(c, "second wall", c.wall_b, rb, "deg") &&
                 check(c, "top width", c.top_width, gp.top_width_mm, "mm") &&
                 check(c, "mismatch", c.mismatch, gp.mismatch_mm, "mm") && check(c, "depth", c.depth, gp.depth_mm, "mm");
    if (c.accepted && plate_level_mm > 0.0) {
      c.accepted = false;
      std::snprintf(c.reason, sizeof c.reason,
                    "a plate top goes on inside the groove (%.3g mm of its bottom lie straight at the tops' level): "
                    "a wall read is none",
                    plate_level_mm);
    }
    if (c.accepted) {
      c.groove_top = top;
      c.evidence = weigh_groove(c, wa ? wa->first : -1, wa ? wa->last : -1, wb ? wb->first : -1, wb ? wb->last : -1, la,
                                lb, top);
      c.weighed = true;
      // Tops are the work's surface: beyond a top's outer end (within
      // window_mm of that end) nothing of the work stands in front of the
      // tops' line. Points there are a surface the reading cannot explain:
      // its "top" lies inside a wider groove (a bead's flat cap or crest
      // paired with a plate top), and the groove that explains them is
      // another reading. (Measured from the top edges instead, a top longer
      // than window_mm, a fill surface paired with a plate, went unchecked.)
      const ConfidenceParams& cp = p_.confidence;
      int outside = 0;
      const int above = in_front_beyond(top, pt(a.first), a.first - 1, -1, outside) +
                        in_front_beyond(top, pt(b.last), b.last + 1, +1, outside);
      if (above > cp.unexplained_points + cp.unexplained_share * (c.evidence.points + outside)) {
        c.accepted = false;
        std::snprintf(c.reason, sizeof c.reason,
                      "a top lies inside a wider groove: %d points beyond the tops stand in front of them", above);
      }
    }
    offer(c);
  }

  // The longest straight piece of the bottom (a fitted segment within the
  // bottom's points [first, last]) that lies at the tops' level: its line
  // parallel to the tops' line `top` within max_top_angle_deg, both its ends
  // (on its line) no deeper below `top` than GrooveParams::plate_level_share
  // of the groove's depth `depth` (or 2 surface tolerances), and at least
  // plate_level_mm long along the tops. Its length; 0 if there is none.
  double plate_level_run(int first, int last, const Line& top, const Vec2& along, double depth) const {
    const GrooveParams& gp = p_.groove;
    const double shallow = std::max(2.0 * tol_, gp.plate_level_share * depth);
    double longest = 0.0;
    for (const Segment& sg : s_.segments) {
      if (sg.last < first) continue;
      if (sg.first > last) break;
      if (sg.first < first || sg.last > last || !sg.fitted) continue;
      const Vec2 p0 = sg.line.project(pt(sg.first)), p1 = sg.line.project(pt(sg.last));
      const double len = std::abs((p1 - p0).dot(along));
      if (len < gp.plate_level_mm || len <= longest || acute_angle_deg(sg.line, top) > gp.max_top_angle_deg) continue;
      if (-top.signed_distance(p0) <= shallow && -top.signed_distance(p1) <= shallow) longest = len;
    }
    return longest;
  }

  // Where a circle through the bottom's points from `from` on (stepping by
  // `step`, up to 3 mm from the wall's foot, at least 6 points) touches the
  // wall line (`up`: along it from the foot towards the top edge): if the circle fits them (rms within the surface tolerance),
  // its radius is 0.5-50 mm, the points turn 15 degrees or more on it, it
  // is tangent to the wall (its centre's distance to the wall within 2
  // tolerances of its radius) and it touches the wall at or above the
  // wall's last point (or at most `below_mm` below it, where a dropout hid
  // the wall's lower end). The points are taken within 3 mm of `near` (the
  // foot, or the bottom's first point past such a dropout). Empty otherwise.
  // `along_var`: the variance (mm^2) of where it touches, along the wall,
  // from the circle's centre: the algebraic fit's residual at a point moved
  // by e across the circle is 2 R e, so its centre is known to R^2 s^2
  // times the first two rows and columns of the inverse of the fit's normal
  // matrix (s^2 the points' residual variance pooled with the profile's
  // noise, as a line's).
  std::optional<Vec2> tangent_toe(const Line& wall, const Vec2& foot, const Vec2& near, const Vec2& up,
                                  double below_mm, int from, int step, int lo, int hi,
                                  double* along_var = nullptr) const {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    int n = 0;
    for (int i = from; i >= lo && i <= hi && (pt(i) - near).norm() <= 3.0; i += step) {
      const Vec2 q = pt(i) - foot;
      const Eigen::Vector3d row(q.x(), q.y(), 1.0);
      m += row * row.transpose();
      r -= row * q.squaredNorm();
      ++n;
    }
    if (n < 6) return std::nullopt;
    const Eigen::Vector3d x = m.ldlt().solve(r);
    const Vec2 centre(-0.5 * x(0), -0.5 * x(1));
    const double r2 = centre.squaredNorm() - x(2);
    if (!(r2 > 0.25) || r2 > 2500.0) return std::nullopt;
    const double radius = std::sqrt(r2);
    double ss = 0.0;
    for (int i = from, k = 0; k < n; i += step, ++k) {
      const double e = (pt(i) - foot - centre).norm() - radius;
      ss += e * e;
    }
    if (std::sqrt(ss / n) > tol_) return std::nullopt;
    // The points must turn on it (15 degrees or more): a flat bottom with
    // noise fits a huge circle that may touch the wall anywhere.
    const Vec2 q0 = pt(from) - foot - centre, q1 = pt(from + (n - 1) * step) - foot - centre;
    if (std::abs(std::atan2(q0.x() * q1.y() - q0.y() * q1.x(), q0.dot(q1))) < 15.0 * std::numbers::pi / 180.0)
      return std::nullopt;
    const Vec2 c = centre + foot;
    if (std::abs(wall.distance(c) - radius) > 2.0 * tol_) return std::nullopt;
    // The straight wall ends where the radius starts: not below its last
    // point (a sharp corner with noise fits a small circle touching the
    // wall's line below it).
    const Vec2 t = wall.project(c);
    if ((t - foot).dot(up) < -tol_ - below_mm) return std::nullopt;
    if (along_var) {
      const double s2 = (ss + kPriorDof * sigma_ * sigma_) / std::max(n - 3 + kPriorDof, 1.0);
      const Eigen::Matrix2d centre_cov = r2 * s2 * m.ldlt().solve(Eigen::Matrix3d::Identity()).topLeftCorner<2, 2>();
      const Vec2 d = wall.direction();
      *along_var = d.dot(centre_cov * d);
    }
    return t;
  }

  // Removes from the polyline (not its ends, the toes) each run of 1 to
  // kMaxClusterPoints points that a steep jump (more than 3 surface
  // tolerances across, twice as far as along) leaves and another, the
  // other way, comes back from to about where it left: a reflection cluster
  // displaced in front of or behind the bottom (the outlier step keeps it
  // when its neighbours are no straight line: a bead's cap, a radius). A
  // root face or a wall, each step the same way, is no such run.
  static constexpr int kMaxClusterPoints = 5;
  void drop_clusters(std::vector<Vec2>& poly, const Vec2& along, const Vec2& down) const {
    auto jump = [&](const Vec2& d) {
      const double v = d.dot(down);
      return std::abs(v) > std::max(3.0 * tol_, 2.0 * std::abs(d.dot(along))) ? (v > 0.0 ? 1 : -1) : 0;
    };
    std::size_t out = 1;
    for (std::size_t i = 1; i + 1 < poly.size();) {
      const int in = jump(poly[i] - poly[out - 1]);
      std::size_t end = 0;  // one past the run, if it is a cluster
      for (std::size_t j = i; in != 0 && j + 1 < poly.size() && j < i + kMaxClusterPoints; ++j) {
        if (jump(poly[j + 1] - poly[j]) != -in) continue;
        const double left = (poly[i] - poly[out - 1]).dot(down), gap = (poly[j + 1] - poly[out - 1]).dot(down);
        if (std::abs(gap) < 0.5 * std::abs(left)) {
          end = j + 1;
          break;
        }
      }
      if (end) {
        i = end;
        continue;
      }
      poly[out++] = poly[i++];
    }
    if (poly.size() > 1) poly[out++] = poly.back();
    poly.resize(out);
  }

  // Closes each notch of the polyline narrower than max_mm along `along`
  // whose inner points all lie on or deeper (along `down`) than the chord
  // between its shoulders, the deepest by half its width or more: the points
  // go between
  // the shoulders (a root gap: the bottom is at the root edges' level).
  // `closed` (if given): the pieces of the polyline left that close a notch
  // (the index of each one's first point, ascending). `hidden_toe`: whether
  // the polyline's first and last points are the toes of walls not seen
  // (GrooveParams::radius_not_notch). Kept out of groove_pair
  // (docs/PERFORMANCE.md, session 28).
  [[gnu::noinline]] void close_notches(std::vector<Vec2>& poly, const Vec2& along, const Vec2& down, double max_mm,
                                       std::vector<int>* closed = nullptr, const bool* hidden_toe = nullptr) const {
    const bool radius = p_.groove.radius_not_notch &&
                        (p_.joint == JointType::UGroove || p_.joint == JointType::JGroove);
    if (closed) closed->clear();
    std::size_t out = 0;
    for (std::size_t i = 0; i < poly.size();) {
      poly[out++] = poly[i];
      std::size_t best = i + 1;
      // A notch starts with a drop steeper than 45 degrees (cheap: most
      // points start none).
      const Vec2 first = i + 1 < poly.size() ? Vec2(poly[i + 1] - poly[i]) : Vec2::Zero();
      const bool drops = first.dot(down) > std::max(tol_, std::abs(first.dot(along)));
      const Vec2 pi = poly[i];
      // The points after i as (along, down) from it, their upper convex hull
      // grown with j while their along offsets increase: the most any lies
      // below the chord to j is at most the hull's maximum of down - slope *
      // along (exact, up to rounding far below kSlack), so a j whose bound
      // stays under the notch depth is no notch without the loop over its
      // points. Where the offsets do not increase, every j is tested.
      constexpr std::size_t kMaxHull = 512;
      constexpr double kSlack = 1e-6;
      std::array<Vec2, kMaxHull> hull;
      std::size_t n_hull = 0, added = i + 1, top = 0;
      bool bounded = drops;
      for (std::size_t j = i + 2; drops && j < poly.size() && (poly[j] - poly[i]).dot(along) <= max_mm; ++j) {
        const Vec2 d = poly[j] - poly[i];
        const double du = d.dot(along);
        for (; bounded && added < j; ++added) {
          const Vec2 q((poly[added] - pi).dot(along), (poly[added] - pi).dot(down));
          if ((n_hull > 0 && !(q.x() > hull[n_hull - 1].x())) || n_hull == kMaxHull) {
            bounded = false;
            break;
          }
          while (n_hull >= 2) {
            const Vec2 e = hull[n_hull - 1] - hull[n_hull - 2], f = q - hull[n_hull - 2];
            if (e.x() * f.y() - e.y() * f.x() < 0.0) break;
            --n_hull;
          }
          hull[n_hull++] = q;
        }
        if (du <= 0.0) continue;
        if (bounded && n_hull > 0 && du >= 1e-3) {
          const double slope = d.dot(down) / du;
          auto value = [&](std::size_t k) { return hull[k].y() - slope * hull[k].x(); };
          // The hull is convex: climb from the last j's maximum (the
          // chords' slopes change little from one j to the next).
          // (Each value once: the same arithmetic as evaluating it anew.)
          top = std::min(top, n_hull - 1);
          double v_top = value(top);
          for (; top + 1 < n_hull; ++top) {
            const double v = value(top + 1);
            if (!(v > v_top)) break;
            v_top = v;
          }
          for (; top > 0; --top) {
            const double v = value(top - 1);
            if (!(v > v_top)) break;
            v_top = v;
          }
          if (v_top + kSlack < std::max(0.5 * du, 2.0 * tol_)) continue;
        }
        bool below = true;
        double deepest = 0.0;
        // In blocks: first the divisions, independent of each other (the
        // loop vectorises), then the tests. On dense profiles a U's radius
        // drops steeply over hundreds of points within max_mm: this loop
        // ran over each pair of them. Same arithmetic as one point at a time.
        constexpr std::size_t kBlock = 16;
        for (std::size_t m0 = i + 1; m0 < j && below; m0 += kBlock) {
          const std::size_t nb = std::min(kBlock, j - m0);
          double t[kBlock];
          for (std::size_t k = 0; k < nb; ++k) {
            const Vec2& q = poly[m0 + k];
            t[k] = ((q.x() - pi.x()) * along.x() + (q.y() - pi.y()) * along.y()) / du;
          }
          for (std::size_t k = 0; k < nb && below; ++k) {
            const Vec2& q = poly[m0 + k];
            const double v =
                (q.x() - (pi.x() + t[k] * d.x())) * down.x() + (q.y() - (pi.y() + t[k] * d.y())) * down.y();
            below = v > -tol_;
            deepest = std::max(deepest, v);
          }
        }
        // A notch is steep (a gap's walls, rays into it): a curved bottom
        // (a U's radius) is no notch.
        if (below && deepest >= std::max(0.5 * du, 2.0 * tol_)) best = j;
      }
      // A U's or J's radius (GrooveParams::radius_not_notch): the inside one
      // circle that the bottom on one side goes on along.
      if (radius && best >= i + 7) {
        const auto f = fit_circle(std::span<const Vec2>(poly.data() + i + 1, best - i - 1), poly[i]);
        bool bowl = false;
        if (f && f->rms <= tol_) {
          auto on = [&](const Vec2& q) { return std::abs((q - f->centre).norm() - f->rho) <= 2.0 * tol_; };
          const bool on_i = on(poly[i]), on_b = on(poly[best]);
          bool before = on_i, after = on_b;  // the kept points before (poly[out - 1] is poly[i])
          for (std::size_t m = out >= 4 ? out - 4 : 0; m + 1 < out && before; ++m) before = on(poly[m]);
          for (std::size_t m = best + 1; m < std::min(poly.size(), best + 4) && after; ++m) after = on(poly[m]);
          const bool toe_off = hidden_toe && ((i == 0 && !on_i && hidden_toe[0]) ||
                                              (best + 1 == poly.size() && !on_b && hidden_toe[1]));
          bowl = (before || after) && !toe_off;
        }
        if (bowl) {  // kept as seen: its points up to the last inside one, which the loop takes next
          for (std::size_t m = i + 1; m + 1 < best; ++m) poly[out++] = poly[m];
          i = best - 1;
          continue;
        }
      }
      if (closed && best > i + 1) closed->push_back(static_cast<int>(out - 1));
      i = best;
    }
    poly.resize(out);
  }

  // The groove reading's evidence (Evidence): over the tops' points within
  // window_mm of the top edges and every point between them, the robust cost
  // of "no groove: the tops' line through all" less that of the reading (the
  // tops and walls their lines; the bottom is what it is: no cost). Points
  // in front of the tops' line between the edges fit nothing (unexplained).
  Evidence weigh_groove(const Candidate& c, int wa0, int wa1, int wb0, int wb1, const Line& la, const Line& lb,
                        const Line& top) const {
    Evidence ev;
    const double w = p_.confidence.window_mm;
    const Vec2 b1 = *c.bp[1], b5 = *c.bp[5];
    double null_cost = 0.0, cost_model = 0.0, rms_a = 0.0, rms_b = 0.0;
    int na = 0, nb = 0;
    // A top's points lie on a line from its edge outwards: those within w
    // of the edge are the run next to it (found from the edge, not by
    // looking at every point of a long top).
    int first = c.pa.last + 1;
    while (first > c.pa.first && (pt(first - 1) - b1).squaredNorm() <= w * w) --first;
    ev.w0 = first;
    for (int i = first; i <= c.pb.last; ++i) {
      const Vec2& q = pt(i);
      const bool on_a = i <= c.pa.last, on_b = i >= c.pb.first;
      if (on_b && (q - b5).squaredNorm() > w * w) break;
      ev.w1 = i;
      ++ev.points;
      const double d0 = top.distance(q);
      double d;
      if (on_a) {
        d = c.pa.line.distance(q);
        rms_a += d * d, ++na;
      } else if (on_b) {
        d = c.pb.line.distance(q);
        rms_b += d * d, ++nb;
      } else if ((i >= wa0 && i <= wa1) || (i >= wb0 && i <= wb1)) {
        d = std::min(la.distance(q), lb.distance(q));
      } else if (top.signed_distance(q) > tol_) {
        ++ev.unexplained;  // in front of the tops inside the groove: a reflection, a body
        continue;
      } else {
        d = 0.0;  // the bottom
      }
      null_cost += cost(d0);
      cost_model += cost(d);
    }
    ev.strength = null_cost - cost_model;
    ev.fit = std::max(na ? std::sqrt(rms_a / na) : 0.0, nb ? std::sqrt(rms_b / nb) : 0.0) / sigma_;
    return ev;
  }

  void vgroove() {
    const VGrooveParams& vp = p_.vgroove;
    // Bevels may be short (seen at a grazing angle); the tops must be long.
    // A root face seen between the bevels can be a segment of its own, so a
    // bevel pair may have one segment between them.
    // A bevel seen edge-on can keep even fewer points after dropouts: a
    // shorter segment is a bevel candidate when a plate top (a long segment)
    // follows or precedes it directly, or across short pieces (top_of);
    // vgroove_pair then requires that top.
    const int min_bevel = std::max(2, vp.min_bevel_points);
    const int n_seg = static_cast<int>(s_.segments.size());
    bevels_.clear();
    for (int j = 0; j < n_seg; ++j) {
      const Segment& sg = s_.segments[j];
      if (!sg.fitted) continue;
      if (sg.count() >= min_bevel || (sg.count() >= 2 && (top_of(j, -1) >= 0 || top_of(j, +1) >= 0)))
        bevels_.push_back(j);
    }
    // Pairs: a candidate with the next two, and any with at most two segments
    // between them: both root faces seen (short segments that are bevel
    // candidates too, beside a long bevel) put the true pair three apart.
    for (std::size_t qi = 0; qi + 1 < bevels_.size(); ++qi) {
      for (std::size_t qj = qi + 1; qj < bevels_.size() && (qj <= qi + 2 || bevels_[qj] - bevels_[qi] <= 3); ++qj) {
        vgroove_pair(bevels_[qi], bevels_[qj]);
      }
    }
  }

  // A pair whose facing end points lie past the lines' intersection (a point
  // of another surface that happens to lie on a line's extension, or a plate
  // seen past the other's edge) is refitted without them; then the plates do
  // not meet at x, so there is a gap or step between them.
  // With `keep_own`, a plate's end points past x are kept when every one
  // lies on its own line and at least kMinPlateRun of them off the other's
  // (near x a point lies on both): the plate goes on past the crossing (a v-groove's lower
  // bevel below the crossing of the bevels' lines, where the other plate's
  // root face stands: a mismatch with a root face), not one stray point.
  std::optional<Pair> trimmed(const Pair& pr, bool keep_own = false) const {
    int a_last = pr.a.last, b_first = pr.b.first;
    while (a_last > pr.a.first + 1 && (pt(a_last) - pr.x).dot(pr.ua) < -tol_) --a_last;
    while (b_first < pr.b.last - 1 && (pt(b_first) - pr.x).dot(pr.ub) < -tol_) ++b_first;
    auto own = [&](int from, int to, const Plate& self, const Plate& other) {
      if (!keep_own) return false;
      int off_other = 0;
      for (int i = from; i <= to; ++i) {
        if (self.line.distance(pt(i)) > tol_) return false;
        off_other += other.line.distance(pt(i)) > tol_;
      }
      return off_other >= kMinPlateRun;
    };
    if (own(a_last + 1, pr.a.last, pr.a, pr.b)) a_last = pr.a.last;
    if (own(pr.b.first, b_first - 1, pr.b, pr.a)) b_first = pr.b.first;
    if (a_last == pr.a.last && b_first == pr.b.first) return pr;
    const auto a = plate_of(pr.a.first, a_last), b = plate_of(b_first, pr.b.last);
    if (!a || !b) return std::nullopt;
    auto out = meet(*a, *b);
    if (out) out->trimmed = true;
    return out;
  }

  // The plate top of a short bevel candidate, segment k, on its outer side
  // (dir -1: before it in scan order, +1: after it): the long segment
  // directly beside it, or (VGrooveParams::short_bevel_across_pieces) the
  // first long segment beyond at most two short pieces whose points all lie
  // on the bevel's line or on that top's line (within the surface tolerance):
  // noise at the top edge of a bevel seen edge-on cuts a short piece off the
  // top there, or leaves a piece across the edge. -1 if none.
  int top_of(int k, int dir) const {
    const int n_seg = static_cast<int>(s_.segments.size());
    const int s_min = std::max(2, p_.segmentation.segments.min_segment_points);
    auto is_long = [&](int m) {
      return m >= 0 && m < n_seg && s_.segments[m].fitted && s_.segments[m].count() >= s_min;
    };
    if (is_long(k + dir)) return k + dir;
    const Segment& sb = s_.segments[k];
    if (!p_.vgroove.short_bevel_across_pieces || !sb.fitted) return -1;
    int m = k + dir, pieces = 0;
    for (; m >= 0 && m < n_seg && !is_long(m); m += dir)
      if (++pieces > 2) return -1;
    if (!is_long(m)) return -1;
    const Segment& st = s_.segments[m];
    const int lo = dir > 0 ? sb.last + 1 : st.last + 1, hi = dir > 0 ? st.first - 1 : sb.first - 1;
    for (int i = lo; i <= hi; ++i)
      if (sb.line.distance(pt(i)) > tol_ && st.line.distance(pt(i)) > tol_) return -1;
    return m;
  }

  // A bevel segment shorter than min_bevel_points (seen edge-on, thinned by
  // dropouts) next to its plate top (long segment `top`, see top_of):
  // refitted through its points and the points removed as outliers, or kept
  // in short pieces, between it and the top that lie on its line and off the
  // top's (the island filter removes single bevel points cut off by
  // dropouts). Empty if fewer than min_short_bevel_points in all.
  std::optional<Plate> short_bevel(int b, int top) const {
    const Segment& sb = s_.segments[b];
    const Segment& st = s_.segments[top];
    const auto removed =
        b < top ? outliers_between(sb.last_col, st.first_col) : outliers_between(st.last_col, sb.first_col);
    PointSums sums = sb.sums;
    for (const Vec2& o : removed)
      if (sb.line.distance(o) <= tol_ && st.line.distance(o) > tol_) sums.add(o - s_.ref_);
    const int lo = b < top ? sb.last + 1 : st.last + 1, hi = b < top ? st.first - 1 : sb.first - 1;
    for (int i = lo; i <= hi; ++i)
      if (sb.line.distance(pt(i)) <= tol_ && st.line.distance(pt(i)) > tol_) sums.add(pt(i) - s_.ref_);
    if (sums.n < std::max(2, p_.vgroove.min_short_bevel_points)) return std::nullopt;
    if (sums.n == sb.count()) return plate_of(sb);
    const auto f = s_.fit(sums);
    if (!f) return std::nullopt;
    return Plate{sb.first, sb.last, f->line, f->centroid};
  }

  void vgroove_pair(int i, int j) {
    const VGrooveParams& vp = p_.vgroove;
    {
      // A short bevel must have its plate top right beside it, on its outer side.
      const int min_bevel = std::max(2, vp.min_bevel_points);
      const int s_min = std::max(2, p_.segmentation.segments.min_segment_points);
      const int n_seg = static_cast<int>(s_.segments.size());
      const bool i_short = s_.segments[i].count() < min_bevel, j_short = s_.segments[j].count() < min_bevel;
      std::optional<Plate> pi = plate_of(s_.segments[i]), pj = plate_of(s_.segments[j]);
      if (i_short) {
        const int t = top_of(i, -1);
        pi = t >= 0 ? short_bevel(i, t) : std::nullopt;
      }
      if (j_short) {
        const int t = top_of(j, +1);
        pj = t >= 0 ? short_bevel(j, t) : std::nullopt;
      }
      if (!pi || !pj) return;
      // Noise can cut a bevel in pieces: a long piece between the bevels on
      // either one's line is not a root face (the reading that skips it is
      // wrong), and each bevel extends outwards over the pieces on its line.
      for (int m = i + 1; m < j; ++m) {
        const Segment& sm = s_.segments[m];
        if (sm.fitted && sm.count() >= s_min && (continues(sm, s_.segments[i]) || continues(sm, s_.segments[j])))
          return;
      }
      int i0 = i, j1 = j;
      auto grow = [&](int k, int dir, std::optional<Plate>& pl) {
        PointSums sums = s_.segments[k].sums;
        auto fit = fit_of(s_.segments[k]);
        int first = pl->first, last = pl->last, end = k;
        for (int m = k + dir; m >= 0 && m < n_seg; m += dir) {
          const Segment& nx = s_.segments[m];
          if (!nx.fitted || nx.count() < 2 || !same_line(sums, fit, nx.sums, fit_of(nx))) break;
          sums += nx.sums;
          fit = s_.fit(sums);
          first = std::min(first, nx.first), last = std::max(last, nx.last), end = m;
        }
        if (end != k && fit) pl = Plate{first, last, fit->line, fit->centroid};
        return end;
      };
      if (!i_short) i0 = grow(i, -1, pi);
      if (!j_short) j1 = grow(j, +1, pj);
      auto pr = pair_of(*pi, *pj);
      if (!pr || !pr->valley) return;
      pr = trimmed(*pr, p_.vgroove.keep_past_crossing);
      if (!pr || !pr->valley) return;
      const Plate& bl = pr->a;
      const Plate& br = pr->b;
      // Plate tops: the nearest long segments outside the bevels, meeting them
      // at an outside edge, roughly square to the groove's bisector.
      const Vec2 bisector = (pr->ua + pr->ub).normalized();
      const double max_tilt = std::sin(30.0 * kDeg);
      // Past long segments within two roundings' reach of the bevel's end
      // that are no top, or a top no longer than that reach while a longer
      // one follows (VGrooveParams::tops_past_rounding). (Rounding pieces
      // left between are explained by neither, as before.)
      const bool past = vp.tops_past_rounding;
      const double reach = 2.0 * kMaxRoundingMm;
      // dir -1: the top before bevel bl in scan order; +1: after br.
      auto top_beside = [&](int dir) -> std::optional<Plate> {
        const Plate& bevel = dir < 0 ? bl : br;
        const Vec2& bevel_end = pt(dir < 0 ? bl.first : br.last);
        std::optional<Plate> short_top;
        for (int q = dir < 0 ? n_long() - 1 : 0; q >= 0 && q < n_long(); q += dir) {
          if (dir < 0 ? longs_[q] >= i0 : longs_[q] <= j1) continue;
          const Segment& sq = s_.segments[longs_[q]];
          const auto t = dir < 0 ? pair_of(plate_of(sq), bevel) : pair_of(bevel, plate_of(sq));
          if (t && !t->valley && std::abs((dir < 0 ? t->a : t->b).line.direction().dot(bisector)) < max_tilt) {
            if (!past || (pt(sq.last) - pt(sq.first)).norm() > reach) return dir < 0 ? t->a : t->b;
            if (!short_top) short_top = dir < 0 ? t->a : t->b;
          }
          if (!past || (pt(dir < 0 ? sq.last : sq.first) - bevel_end).norm() > reach) break;
        }
        return short_top;
      };
      std::optional<Plate> tl = top_beside(-1), tr = top_beside(+1);
      if ((i_short && !tl) || (j_short && !tr)) return;
      // The tops must be one plane: parallel (VGrooveParams::max_top_angle_deg)
      // and apart by no more than the mismatch (a bead's cap deep in a thick
      // groove, paired with the real plate top, is parallel to it too; the
      // groove model asks the same of its tops).
      if (tl && tr && (acute_angle_deg(tl->line, tr->line) > vp.max_top_angle_deg ||
                       tl->line.distance(pt(tr->first)) > vp.mismatch_mm.max + tol_)) {
        if (!i_short) tl.reset();
        if (!j_short) tr.reset();
      }
      const int from = bl.last + 1, to = br.first - 1;
      const Eigen::Matrix2d x_cov = intersection_cov(cov_of(bl), cov_of(br), pr->x);
      Edge el{pr->x, 0.0, x_cov}, er{pr->x, 0.0, x_cov};
      bool open_root = false;
      // Bevels that meet between two neighbouring rays are a closed root; a run
      // of invalid columns between them is the root opening (the rays went
      // through it and found nothing).
      if (pr->trimmed || off_both(from, to, bl.line, br.line) ||
          s_.invalid_columns_between(s_.cols[bl.last], s_.cols[br.first]) > 0 ||
          !between_rays(pr->x, s_.cols[bl.last], s_.cols[br.first])) {
        // A bevel's last points next to the root opening can be cut off by
        // dropouts and removed as an island: those on its line still mark
        // how far it reaches.
        Vec2 l_end = pt(bl.last), r_end = pt(br.first);
        int l_col = s_.cols[bl.last], r_col = s_.cols[br.first];
        bool r_found = false;
        const auto removed = outliers_between(s_.cols[bl.last], s_.cols[br.first]);
        const std::size_t off =
            removed.empty() ? 0 : static_cast<std::size_t>(removed.data() - s_.outlier_points.data());
        for (std::size_t k = 0; k < removed.size(); ++k) {
          const Vec2& o = removed[k];
          const int col = s_.outlier_cols[off + k];
          if (bl.line.distance(o) <= tol_ && (o - pr->x).dot(pr->ua) > 0.0) l_end = o, l_col = col;  // the last
          if (!r_found && br.line.distance(o) <= tol_ && (o - pr->x).dot(pr->ub) > 0.0)
            r_end = o, r_col = col, r_found = true;  // the first
        }
        el = edge_at(bl, l_end, l_col + 1, tl ? &tl->line.n : nullptr, span_of(from, to),
                     {.sharp = true, .far_col = first_missed(bl.line, br.line, l_col + 1, +1)});
        er = edge_at(br, r_end, r_col - 1, tr ? &tr->line.n : nullptr, span_of(from, to),
                     {.sharp = true, .far_col = first_missed(br.line, bl.line, r_col - 1, -1)});
        open_root = true;
      }
      // The plates' surface direction: from the tops, else square to the bisector.
      Vec2 dp;
      if (tl && tr) {
        const Vec2 d1 = tl->line.direction(), d2 = tr->line.direction();
        dp = (d1 + (d1.dot(d2) < 0.0 ? Vec2(-d2) : d2)).normalized();
      } else if (tl || tr) {
        dp = (tl ? tl : tr)->line.direction();
      } else {
        const Vec2 bis = (pr->ua + pr->ub).normalized();
        dp = Vec2(-bis.y(), bis.x());
      }
      Vec2 np(-dp.y(), dp.x());
      if (np.dot(origin_ - pr->x) < 0.0) np = -np;
      const Vec2& low = np.dot(el.point) <= np.dot(er.point) ? el.point : er.point;
      if (open_root) {
        // Each bevel's last points may be its root face (square to the
        // plates) or what is seen through the gap (along them).
        const Vec2 dirs[2] = {np, dp};
        const Vec2 dl = bl.line.direction(), dr = br.line.direction();
        el.cov += end_spread(bl, true, el.point, dirs) * dl * dl.transpose();
        er.cov += end_spread(br, false, er.point, dirs) * dr * dr.transpose();
        // The root edges lie as far apart across the plates as the tops
        // do (VGrooveParams::unseen_root_extension): where one stands
        // higher than that, its bevel may go on unseen down to the other's
        // level (a shadow, a tack weld or a dropout over its foot), unless
        // a ray between the edges saw past that extension. Its edge lies
        // anywhere on it: a spread of len^2 / 3 along the bevel.
        if (vp.unseen_root_extension && tl && tr) {
          const Vec2 x0 = 0.5 * (el.point + er.point);
          auto height = [&](const Line& l) {  // the line's height along np above x0
            const double nn = l.n.dot(np);
            return std::abs(nn) > 1e-6 ? -l.signed_distance(x0) / nn : 0.0;
          };
          // Beyond twice the edges' own rms across the plates (noise moves
          // them too).
          double excess = np.dot(er.point - el.point) - (height(tr->line) - height(tl->line));
          const double sd = std::sqrt(std::max(0.0, np.dot((el.cov + er.cov) * np)));
          excess = excess > 0.0 ? std::max(0.0, excess - 2.0 * sd) : std::min(0.0, excess + 2.0 * sd);
          const bool right = excess > 0.0;
          Edge& e = right ? er : el;
          const Vec2 down = right ? Vec2(-pr->ub) : Vec2(-pr->ua);
          const double slope = std::abs(np.dot(down));
          // Down the bevel to the other edge's level, not past the crossing.
          const double len = std::min(slope > 1e-6 ? std::abs(excess) / slope : 0.0,
                                      std::max(0.0, (pr->x - e.point).dot(down)));
          if (len > tol_ && !seen_past(e.point, down, len, from, to))
            e.cov += (len * len / 3.0) * down * down.transpose();
        }
      }
      const Vec2 mid = 0.5 * (el.point + er.point);

      Candidate c;
      c.angle = angle_between_deg(pr->ua, pr->ub);
      c.gap = std::abs(dp.dot(er.point - el.point));
      c.mismatch = std::abs(np.dot(er.point - el.point));
      c.edge_unc = el.half_width_mm + er.half_width_mm;
      c.track_unc = 0.5 * c.edge_unc;
      c.track = low + dp.dot(mid - low) * dp;
      if (open_root) {
        // T = P_n low + P_d (el + er) / 2, P_n and P_d the projections across
        // and along the plates; the two edges come from different bevels.
        const Eigen::Matrix2d pd = dp * dp.transpose(), pn = np * np.transpose();
        const bool l_low = &low == &el.point;
        const Eigen::Matrix2d m_low = pn + 0.5 * pd, m_other = 0.5 * pd;
        const Eigen::Matrix2d& c_low = l_low ? el.cov : er.cov;
        const Eigen::Matrix2d& c_other = l_low ? er.cov : el.cov;
        c.track_cov = m_low * c_low * m_low.transpose() + m_other * c_other * m_other.transpose();
      } else {
        c.track_cov = x_cov;
      }
      c.located = true;
      double depth = 0.0;
      int sides = 0;
      if (tl) depth += tl->line.distance(el.point), ++sides;
      if (tr) depth += tr->line.distance(er.point), ++sides;
      if (sides) c.depth = depth / sides;
      std::optional<Vec2> tle, tre;
      if (tl) tle = intersect(tl->line, bl.line, std::sin(5.0 * kDeg));
      if (tr) tre = intersect(br.line, tr->line, std::sin(5.0 * kDeg));
      if (tle && tre) {
        const Vec2 poly[4] = {el.point, er.point, *tre, *tle};
        double a2 = 0.0;
        for (int k = 0; k < 4; ++k) {
          const Vec2& u = poly[k];
          const Vec2& v = poly[(k + 1) % 4];
          a2 += u.x() * v.y() - v.x() * u.y();
        }
        c.area = 0.5 * std::abs(a2);
      }
      if (tl) c.bp[0] = outer(*tl, pt(tl->first));
      c.bp[1] = tle;
      c.bp[2] = el.point;
      c.bp[3] = c.track;
      c.bp[4] = er.point;
      c.bp[5] = tre;
      if (tr) c.bp[6] = outer(*tr, pt(tr->last));
      // Prefer readings with both plate tops, then the best supported bevels.
      c.score = 1e6 * (tl.has_value() + tr.has_value()) + std::min(bl.count(), br.count());
      c.pa = bl, c.pb = br, c.open_joint = true;
      if (tl) c.add_line(tl->line);
      if (tr) c.add_line(tr->line);
      const Vec2 across = dp.dot(er.point - el.point) >= 0.0 ? dp : Vec2(-dp);
      c.opening = {el.point, er.point, across, -across, el.half_width_mm + tol_, er.half_width_mm + tol_};
      c.accepted = check(c, "angle", c.angle, vp.angle_deg, "deg") && check(c, "gap", c.gap, vp.gap_mm, "mm") &&
                   check(c, "mismatch", c.mismatch, vp.mismatch_mm, "mm") &&
                   check(c, "depth", c.depth, vp.depth_mm, "mm");
      // With beads laid, tops are the work's surface, as the groove model
      // asks of its own ("a top lies inside a wider groove"): beyond a top's
      // outer end, within window_mm of it, nothing of the work stands in
      // front of that top's line. If it does, the "top" is a fill's or a
      // bead's cap inside a wider groove whose wall was not seen. (Without
      // beads the tops are the plates; a top that is one piece of a noisy
      // plate has the rest of it beyond, and the check only trades readings.)
      if (vp.check_tops_outside && p_.groove.vgroove_fill && c.accepted && (tl || tr)) {
        const ConfidenceParams& cp = p_.confidence;
        int outside = 0, above = 0;
        auto beyond = [&](const Plate& t, bool left) {
          Line line = t.line;
          line.orient_towards(origin_);
          return left ? in_front_beyond(line, pt(t.first), t.first - 1, -1, outside)
                      : in_front_beyond(line, pt(t.last), t.last + 1, +1, outside);
        };
        if (tl) above += beyond(*tl, true);
        if (tr) above += beyond(*tr, false);
        if (above > cp.unexplained_points + cp.unexplained_share * outside) {
          c.accepted = false;
          std::snprintf(c.reason, sizeof c.reason,
                        "a top lies inside a wider groove: %d points beyond the tops stand in front of them", above);
        }
      }
      if (vp.check_root_cover && c.accepted && open_root) {
        if (const RootBump rb = root_bump(el.point, er.point, from, to);
            rb.points >= vp.root_cover_points && rb.share >= vp.root_cover_share && rb.height_mm > tol_ &&
            rb.curvature_t >= vp.root_bump_t) {
          c.accepted = false, c.uncertain = true;
          std::snprintf(c.reason, sizeof c.reason,
                        "uncertain: a bump %.2g mm high over %.0f %% of the root opening (%d points; a tack weld "
                        "or a bead in the root?)",
                        rb.height_mm, 100.0 * rb.share, rb.points);
        }
      }
      if (vp.check_root_past && c.accepted && open_root) {
        const double past = std::max(bevel_past(bl, br, el.point, pr->ua, from, to, vp.root_past_mm),
                                     bevel_past(br, bl, er.point, pr->ub, from, to, vp.root_past_mm));
        if (past > vp.root_past_mm) {
          c.accepted = false, c.uncertain = true;
          std::snprintf(c.reason, sizeof c.reason,
                        "uncertain: a bevel's points lie %.2g mm past its root edge as read (beyond a dropout or "
                        "a shadow: the root is not where it is read)",
                        past);
        }
      }
      offer(c);
    }
  }

  // The points from index `from` on, stepping by `step` (+1 or -1), while
  // within ConfidenceParams::window_mm of `end` (beyond a plate top's outer
  // end): how many stand more than the surface tolerance on `line`'s
  // positive side (in front of it); `looked` grows by how many were looked at.
  int in_front_beyond(const Line& line, const Vec2& end, int from, int step, int& looked) const {
    const double w2 = p_.confidence.window_mm * p_.confidence.window_mm;
    int above = 0;
    for (int i = from; i >= 0 && i < static_cast<int>(s_.points.size()) && (pt(i) - end).squaredNorm() <= w2;
         i += step)
      ++looked, above += line.signed_distance(pt(i)) > tol_;
    return above;
  }

  // Whether the ray to a kept point from..to crossed the segment from edge
  // to edge + len u (unit u) before reaching it, by more than the surface
  // tolerance: nothing stands there, or that ray would have stopped on it.
  bool seen_past(const Vec2& edge, const Vec2& u, double len, int from, int to) const {
    const Vec2 b = edge - origin_;
    for (int i = from; i <= to; ++i) {
      const Vec2 r = pt(i) - origin_;
      // origin + t r = edge + s u, by Cramer's rule.
      const double det = u.x() * r.y() - u.y() * r.x();
      if (std::abs(det) < 1e-12) continue;
      const double t = (u.x() * b.y() - u.y() * b.x()) / det;
      const double s = (r.x() * b.y() - r.y() * b.x()) / det;
      if (t > 0.0 && s >= 0.0 && s <= len && (1.0 - t) * r.norm() > tol_) return true;
    }
    return false;
  }

  // How far bevel pl's own points lie past its root edge `edge` as read,
  // towards the root (u: the unit direction up the bevel, away from the
  // root): runs of at least kMinPlateRun kept points from..to in
  // consecutive columns on its line and off the other bevel's, spanning at
  // least `extent` mm along it (a surface crossing the line, a backing bar
  // under the root, has a few points on it only where it crosses; 0: none).
  double bevel_past(const Plate& pl, const Plate& other, const Vec2& edge, const Vec2& u, int from, int to,
                    double extent) const {
    double past = 0.0, lo = 0.0, hi = 0.0;
    int run = 0, prev_col = -2;
    for (int i = from; i <= to; ++i) {
      const Vec2& q = pt(i);
      const int col = s_.cols[i];
      if (col != prev_col + 1) run = 0;
      prev_col = col;
      if (pl.line.distance(q) > tol_ || other.line.distance(q) <= tol_) {
        run = 0;
        continue;
      }
      const double along = (edge - q).dot(u);
      if (run++ == 0) lo = hi = along;
      lo = std::min(lo, along), hi = std::max(hi, along);
      if (run >= kMinPlateRun && hi - lo >= extent) past = std::max(past, hi);
    }
    return past;
  }

  // The kept points from..to between an open root's edges a and b (their
  // projections on the line a -> b inside it), as heights h in front of
  // that line (on the sensor's side) against the distance s along it, fitted
  // by h = c0 + c1 s + c2 s^2 (least squares): their number, the share of
  // the opening their projections span, the fit's highest point above the
  // line, and how many standard errors (from the noise sigma_) its
  // curvature is convex towards the sensor (-c2 / se(c2); 0 if concave or
  // too few points). A backing bar or a root face seen through the opening
  // is straight or concave; a tack weld or a bead is a convex cap.
  struct RootBump {
    int points = 0;
    double share = 0.0, height_mm = 0.0, curvature_t = 0.0;
  };
  RootBump root_bump(const Vec2& a, const Vec2& b, int from, int to) const {
    RootBump rb;
    const Vec2 ab = b - a;
    const double len = ab.norm();
    if (!(len > 0.0) || from > to) return rb;
    const Vec2 u = ab / len;
    Vec2 n(-u.y(), u.x());
    if (n.dot(origin_ - a) < 0.0) n = -n;
    // The normal equations of the fit, x = (1, s, s^2): x x^T and x h summed
    // (the symmetric matrix's six distinct entries, each the same product
    // x_i x_j).
    double s00 = 0.0, s01 = 0.0, s02 = 0.0, s11 = 0.0, s12 = 0.0, s22 = 0.0, t0 = 0.0, t1 = 0.0, t2 = 0.0;
    double lo = len, hi = 0.0;
    for (int i = from; i <= to; ++i) {
      const Vec2 q = pt(i);
      const double sa = (q - a).dot(u), h = (q - a).dot(n);
      if (sa <= 0.0 || sa >= len) continue;
      const double s2 = sa * sa;
      s00 += 1.0, s01 += sa, s02 += s2, s11 += sa * sa, s12 += sa * s2, s22 += s2 * s2;
      t0 += h, t1 += sa * h, t2 += s2 * h;
      ++rb.points;
      lo = std::min(lo, sa), hi = std::max(hi, sa);
    }
    if (rb.points < 4) return rb;
    Eigen::Matrix3d ata;
    ata << s00, s01, s02, s01, s11, s12, s02, s12, s22;
    const Eigen::Vector3d aty(t0, t1, t2);
    rb.share = (hi - lo) / len;
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
    if (ldlt.info() != Eigen::Success) return rb;
    const Eigen::Vector3d c = ldlt.solve(aty);
    const double var2 = ldlt.solve(Eigen::Vector3d::UnitZ())(2);
    if (!(var2 > 0.0) || !std::isfinite(c(2))) return rb;
    for (const double sa : {lo, hi, std::clamp(-c(1) / (2.0 * c(2)), lo, hi)})
      rb.height_mm = std::max(rb.height_mm, c(0) + c(1) * sa + c(2) * sa * sa);
    if (c(2) < 0.0) rb.curvature_t = -c(2) / (sigma_ * std::sqrt(var2));
    return rb;
  }
};

const char* shape_of(JointType joint) {
  switch (joint) {
    case JointType::Fillet: return "no inside corner between two plates";
    case JointType::Corner: return "no outside corner between two plates";
    case JointType::Lap: return "no step between two parallel plates";
    case JointType::Butt: return "no gap or step between two parallel plates";
    case JointType::VGroove: return "no groove between two bevels";
    case JointType::Bevel: return "no groove between a square wall and a bevel";
    case JointType::UGroove: return "no U groove between two plate tops";
    case JointType::JGroove: return "no J groove between two plate tops";
  }
  return "";
}

// Columns of the profile's interior (between its first and last kept
// point) that show no surface (invalid, or their points removed as
// outliers), in runs of at least min_cols columns that span more than
// min_width_mm between the kept points around them, the runs touching the
// joint's own columns [ca, cb] left out: where a joint may lie unseen.
int hiding_columns(const Segmentation& s, int ca, int cb, int min_cols, double min_width_mm) {
  int u = 0;
  const int n = static_cast<int>(s.cols.size());
  for (int i = 0; i + 1 < n; ++i) {
    const int run = s.cols[i + 1] - s.cols[i] - 1;
    if (run < std::max(1, min_cols) || (s.cols[i] < cb && s.cols[i + 1] > ca)) continue;
    if ((s.points[i + 1] - s.points[i]).norm() > min_width_mm) u += run;
  }
  return u;
}

}  // namespace

std::string_view to_string(JointType type) {
  for (const auto& j : kJointNames)
    if (j.type == type) return j.name;
  return "unknown";
}

std::optional<JointType> joint_type_from_string(std::string_view name) {
  for (const auto& j : kJointNames)
    if (j.name == name) return j.type;
  return std::nullopt;
}

std::string_view to_string(TrackStatus status) {
  switch (status) {
    case TrackStatus::Ok: return "ok";
    case TrackStatus::Rejected: return "rejected";
    case TrackStatus::NoData: return "no_data";
  }
  return "unknown";
}

std::string_view break_point_name(JointType joint, int index) {
  if (index < 0 || index >= kMaxBreakPoints) return {};
  return kBreakNames[static_cast<int>(joint)][index];
}

Tracker::Tracker(const TrackerParams& params) : params_(params) {}

const TrackResult& Tracker::track(const ProfileView& profile, const TrackPrior* prior) {
  track(profile, result_, prior);
  return result_;
}

void Tracker::track(const ProfileView& profile, TrackResult& out, const TrackPrior* prior) {
  out.status = TrackStatus::NoData;
  out.reason.clear();
  out.joint = params_.joint;
  out.break_points.fill(std::nullopt);
  out.track_point.reset();
  out.gap_mm = out.gap_paper_mm = out.angle_deg = out.mismatch_mm = kNaN;
  out.step_mm = out.depth_mm = out.area_mm2 = kNaN;
  out.wall_angle_a_deg = out.wall_angle_b_deg = out.top_width_mm = kNaN;
  out.fill_lowest.reset();
  out.edge_uncertainty_mm = 0.0;
  out.track_uncertainty_mm = 0.0;
  out.track_sigma_mm = out.track_off_probability = kNaN;
  out.noise_mm = 0.0;
  out.confidence = 0.0;
  out.strength = 0.0;
  out.rival_track_point.reset();
  out.rival_strength = 0.0;
  out.readings.clear();
  out.segments.clear();

  // The tolerances follow the profile's noise (tracker/noise.h).
  const SegmentationParams& sp = params_.segmentation;
  out.noise_mm = params_.noise.sigma_mm > 0.0 ? params_.noise.sigma_mm
                                              : estimate_noise_mm(profile, sp.roi_first, sp.roi_last);
  TrackerParams p = scaled_for_noise(params_, out.noise_mm);
  segment_profile(profile, p.segmentation, seg_, p.noise_aware_detach ? p.surface_tol_mm : 0.0,
                  p.split_rough_segments ? p.surface_tol_mm : 0.0, p.noise_aware_islands ? p.surface_tol_mm : 0.0);
  out.valid_points = seg_.valid_points;
  out.outliers = seg_.outliers;
  if (!seg_.error.empty()) {
    out.reason = seg_.error;
    return;
  }
  const int s_min = std::max(2, p.segmentation.segments.min_segment_points);
  long_.clear();
  for (std::size_t i = 0; i < seg_.segments.size(); ++i) {
    const Segment& sg = seg_.segments[i];
    out.segments.push_back({sg.first_col, sg.last_col, sg.count(), sg.line, sg.rms_mm});
    if (sg.fitted && sg.count() >= s_min) long_.push_back(static_cast<int>(i));
  }
  // The plates' own deviation from lines (waviness, mill scale, noise that
  // is correlated over neighbouring columns) is noise to the templates too:
  // the point-weighted median rms of the long segments.
  // The noise of single points (Matcher::set_point_sigma), at least the
  // surface tolerance's floor.
  const double point_sigma =
      std::max(out.noise_mm, params_.surface_tol_mm / std::max(1.0, params_.noise.surface_k));
  if (params_.noise.adapt && params_.noise.sigma_mm <= 0.0 && !long_.empty()) {
    rms_.clear();
    for (int i : long_) {
      const Segment& sg = seg_.segments[i];
      double rms = sg.rms_mm;
      // A fillet's plate may be a gentle arc (FilletParams::curved_plates):
      // its deviation from a line is then its curvature, not noise, and
      // what counts is its rms about the arc (only a segment its line does
      // not explain to the noise can be one: fit_quadratic).
      if (rms > p.fillet.curve_rms_sigma * point_sigma && p.joint == JointType::Fillet && p.fillet.curved_plates) {
        const QuadFit f = fit_quadratic(std::span<const Vec2>(seg_.points).subspan(sg.first, sg.count()), sg.line,
                                        sg.centroid, std::numeric_limits<double>::infinity(), point_sigma, p.fillet,
                                        s_min, std::max(1, sg.count() / 128));
        if (f.curved) rms = f.rms;
      }
      rms_.emplace_back(rms, sg.count());
    }
    std::sort(rms_.begin(), rms_.end());
    int total = 0, acc = 0;
    for (const auto& [rms, count] : rms_) total += count;
    double median = 0.0;
    for (const auto& [rms, count] : rms_)
      if ((acc += count) * 2 >= total) {
        median = rms;
        break;
      }
    if (median > out.noise_mm) {
      out.noise_mm = median;
      p.surface_tol_mm = std::max(p.surface_tol_mm, p.noise.surface_k * median);
    }
  }
  char buf[160];
  if (static_cast<int>(seg_.points.size()) < s_min) {
    std::snprintf(buf, sizeof buf, "%d usable points, at least %d needed", static_cast<int>(seg_.points.size()),
                  s_min);
    out.reason = buf;
    return;
  }
  out.status = TrackStatus::Rejected;
  const int needed = p.joint == JointType::Butt ? 1 : 2;
  if (static_cast<int>(long_.size()) < needed) {
    std::snprintf(buf, sizeof buf, "too few segments: %d with at least %d points, the %s needs %d",
                  static_cast<int>(long_.size()), s_min, to_string(params_.joint).data(), needed);
    out.reason = buf;
    return;
  }
  Candidate best;
  Matcher m(seg_, p, long_, scratch_, bevels_, off_plates_, next_long_, closed_);
  m.set_point_sigma(point_sigma);
  if (!m.run(params_.joint, best, prior)) {
    if (prior && std::isfinite(m.outside_mm())) {
      std::snprintf(buf, sizeof buf, "no joint within %.3g mm of the predicted point (nearest reading %.3g mm away)",
                    prior->radius_mm, m.outside_mm());
      out.reason = buf;
    } else {
      out.reason = shape_of(params_.joint);
    }
    return;
  }
  out.status = best.accepted ? TrackStatus::Ok : TrackStatus::Rejected;
  if (!best.accepted) out.reason = best.reason_text();
  if (best.accepted) {
    // How sure the reading is (ConfidenceParams, docs/JOINTS.md "Confidence").
    const ConfidenceParams& cp = p.confidence;
    const double e = best.evidence.strength;
    out.strength = e;
    const double hidden = std::clamp(cp.hidden_prior, 1e-12, 1.0 - 1e-12);
    // "Not in view": the prior hidden_prior, and for a butt the columns
    // that show nothing where its joint may lie unread (hiding_columns: a
    // shadow or dropout run wider than its widest gap), the joint's place
    // taken as even over the columns.
    int hiding = 0;
    if (cp.hidden_in_unseen && params_.joint == JointType::Butt && best.pa.count() > 0 && best.pb.count() > 0) {
      hiding = hiding_columns(seg_, seg_.cols[best.pa.last], seg_.cols[best.pb.first], p.butt.min_hole_columns,
                              p.butt.gap_mm.max);
    }
    const double unseen =
        std::log(std::max(1, seg_.valid_points) * hidden / (1.0 - hidden) + hiding / (1.0 - hidden));
    // Readings compared with each other (a rival, a step beyond the joint)
    // at the calibration's temperature; against "not in view" as they are
    // (at the temperature too with ConfidenceParams::temper_unseen).
    const double tau = cp.temperature > 0.0 ? cp.temperature : 1.0;
    double against = std::exp(std::min((unseen - e) / (cp.temper_unseen ? tau : 1.0), 700.0)), rivals = 0.0;
    // A rival of that strength against the reading, at the temperature.
    auto odds = [&](double strength) { return std::exp(std::min((strength - e) / tau, 700.0)); };
    m.for_each_rival(best, [&](const Vec2& track, double strength) {
      rivals += odds(strength);
      if (!out.rival_track_point || strength > out.rival_strength) {
        out.rival_track_point = track;
        out.rival_strength = strength;
      }
    });
    m.for_each_reading([&](const Vec2& track, double strength) { out.readings.push_back({track, strength}); });
    // A step beyond the plates that the reading does not explain is a rival
    // as strong as its points' cost.
    int u_first = 0, u_last = 0;
    const double beyond = m.unexplained_beyond(best, u_first, u_last);
    const double step_rival = beyond > 0.0 ? odds(beyond) : 0.0;
    // So is a bump beyond it (a tack weld or a bead on the surface).
    int b_first = 0, b_last = 0;
    double b_height = 0.0;
    const double bump = cp.bump_rival ? m.bump_beyond(best, b_first, b_last, b_height) : 0.0;
    const double bump_rival = bump > 0.0 ? odds(bump) : 0.0;
    const double found = 1.0 / (1.0 + against + rivals + step_rival + bump_rival);
    // ...and that it is where it is read (docs/JOINTS.md "Localization").
    double off = 0.0;
    if (best.located) {
      // The fits' covariance, and the readings within distinct_mm of it
      // (no rivals: the same joint read another way, a corner's apex and
      // its notch's edges), each as likely against it as their strengths
      // say at the temperature: the track point lies among them (their
      // spread about it, weighted).
      Eigen::Matrix2d cov = best.track_cov;
      {
        double wsum = 1.0;
        Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
        for (const auto& r : out.readings) {
          const Vec2 d = r.track_point - *best.track;
          const double dist = d.norm();
          if (dist <= 1e-9 || dist > cp.distinct_mm) continue;
          const double w = std::exp(std::min(r.strength - e, 0.0) / tau);
          wsum += w;
          spread += w * d * d.transpose();
        }
        cov += spread / wsum;
      }
      out.track_sigma_mm = std::sqrt(std::max(cov.trace(), 0.0));
      out.track_off_probability = off = cp.track_interval_mm > 0.0
                                            ? prob_outside_circle(cov, cp.track_interval_mm)
                                            : 0.0;
    }
    out.confidence = found * (1.0 - off);
    // The reading must explain the points near the joint: a bead, a tack
    // weld or a body there that fits none of its lines is no part of this
    // joint, and the joint may lie under it.
    const Evidence& ev = best.evidence;
    if (ev.unexplained > cp.unexplained_points + cp.unexplained_share * ev.points) {
      out.status = TrackStatus::Rejected;
      std::snprintf(buf, sizeof buf,
                    "unexplained: %d of the %d points within %g mm of the joint fit none of its lines "
                    "(a bead, a tack weld or an obstacle?)",
                    ev.unexplained, ev.points, cp.window_mm);
      out.reason = buf;
      out.confidence = 0.0;
    } else if (ev.fit > cp.max_plate_rms_sigma) {
      // A "plate" that is no line there (a bead's or tack weld's surface, a
      // rounded part): the template's lines do not describe what is seen.
      out.status = TrackStatus::Rejected;
      std::snprintf(buf, sizeof buf, "curved: a plate's points lie %.2g noise sigmas (rms) about its line (a bead or a tack weld?)",
                    ev.fit);
      out.reason = buf;
      out.confidence = 0.0;
    } else if (out.confidence < cp.min_confidence) {
      out.status = TrackStatus::Rejected;
      if (off > 1.0 - found)
        std::snprintf(buf, sizeof buf,
                      "uncertain: confidence %.2f, the track point is located to %.2g mm (rms; %.0f %% chance of "
                      "more than %g mm off)",
                      out.confidence, out.track_sigma_mm, 100.0 * off, cp.track_interval_mm);
      else if (bump_rival > std::max({rivals, against, step_rival}))
        std::snprintf(buf, sizeof buf,
                      "ambiguous: confidence %.2f, a bump %.2g mm high over columns %d-%d (a tack weld or a "
                      "bead?): the joint may be under it",
                      out.confidence, b_height, b_first, b_last);
      else if (step_rival > std::max(rivals, against))
        std::snprintf(buf, sizeof buf,
                      "ambiguous: confidence %.2f, the points of columns %d-%d are a step off the reading's "
                      "lines (evidence %.3g vs %.3g): the joint may be there",
                      out.confidence, u_first, u_last, beyond, e);
      else if (rivals > against)
        std::snprintf(buf, sizeof buf, "ambiguous: confidence %.2f, another reading %.3g mm away is as strong (%.3g vs %.3g)",
                      out.confidence, (*out.rival_track_point - *best.track).norm(), out.rival_strength, e);
      else
        std::snprintf(buf, sizeof buf, "weak: confidence %.2f, evidence %.3g where noise reaches %.3g", out.confidence,
                      e, unseen);
      out.reason = buf;
    }
  }
  out.break_points = best.bp;
  out.track_point = best.track;
  out.gap_mm = best.gap;
  out.gap_paper_mm = best.gap_paper;
  out.angle_deg = best.angle;
  out.mismatch_mm = best.mismatch;
  out.step_mm = best.step;
  out.depth_mm = best.depth;
  out.area_mm2 = best.area;
  out.wall_angle_a_deg = best.wall_a;
  out.wall_angle_b_deg = best.wall_b;
  out.top_width_mm = best.top_width;
  out.fill_lowest = best.fill_lowest;
  out.edge_uncertainty_mm = best.edge_unc;
  out.track_uncertainty_mm = best.track_unc;
}

}  // namespace vts::tracker
