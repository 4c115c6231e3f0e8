// libFuzzer target: the tracker on arbitrary profiles. The bytes decode into a
// joint (any of the eight, the groove model's too), some parameter variation
// (inside the ranges `vts track --params` accepts) and up to 4096 points: raw
// floats, NaN, infinities, huge and tiny values, duplicates, invalid flags and
// plausible plate-like runs. Contract: no crash or undefined behaviour; the
// status is one of the three; an Ok result has a finite track point and finite
// break points and no reason; a Rejected one says why; tracking the same
// profile again (scratch memory reused) gives the same result bit for bit.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>
#include <vector>

#include "tracker/tracker.h"

namespace tk = vts::tracker;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

class Bytes {
 public:
  Bytes(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  bool empty() const { return i_ >= n_; }
  std::uint8_t u8() { return i_ < n_ ? d_[i_++] : 0; }
  std::int16_t i16() { return static_cast<std::int16_t>(u8() | (u8() << 8)); }
  float f32() {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= std::uint32_t(u8()) << (8 * k);
    float f;
    std::memcpy(&f, &v, sizeof f);
    return f;
  }

 private:
  const std::uint8_t* d_;
  std::size_t n_;
  std::size_t i_ = 0;
};

constexpr float kInf = std::numeric_limits<float>::infinity();
const float kSpecial[16] = {0.0f,     -0.0f,   std::numeric_limits<float>::quiet_NaN(), kInf, -kInf, 1e30f, -1e30f,
                            1e-30f,   std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::denorm_min(), 1e-7f, 100.0f, 1e6f, -1e6f, 1.0f};
const double kTol[8] = {0.0, 1e-9, 0.001, 0.02, 0.3, 5.0, 1e6, 1e300};

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const std::optional<tk::Vec2>& a, const std::optional<tk::Vec2>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || (same(a->x(), b->x()) && same(a->y(), b->y()));
}
bool finite(const tk::Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

tk::TrackerParams decode_params(Bytes& b) {
  tk::TrackerParams p;
  p.joint = tk::kAllJointTypes[b.u8() % std::size(tk::kAllJointTypes)];
  const std::uint8_t flags = b.u8();
  if (flags & 0x80) {  // leave the defaults unless asked
    auto& o = p.segmentation.outliers;
    auto& s = p.segmentation.segments;
    o.enabled = flags & 1;
    p.square_edges = flags & 2;
    p.fillet.web = static_cast<tk::WebSide>((flags >> 2) % 3);
    const std::uint8_t a = b.u8(), c = b.u8(), e = b.u8(), f = b.u8();
    o.max_cluster_points = 1 + a % 64;
    o.support_points = 1 + c % 64;
    o.threshold_mm = kTol[a >> 5];
    o.support_tol_mm = kTol[c >> 5];
    s.split_threshold_mm = kTol[e & 7];
    s.split_interval = 1 + (e >> 3) % 8;
    s.min_segment_points = 2 + f % 32;
    s.max_merge_gap_points = (f >> 5) * 3;
    s.max_merge_angle_deg = (a & 0x1f) * 90.0 / 31.0;
    s.max_merge_offset_mm = kTol[(c >> 2) & 7];
    s.break_min_mm = kTol[(e >> 5) & 7];
    s.break_ratio = 1.0 + (f & 0x1f);
    s.fit_tol_mm = kTol[(f >> 2) & 7];
    p.surface_tol_mm = kTol[(a >> 2) & 7];
    p.max_joint_width_mm = kTol[(c >> 5) & 7];
    p.lap.upper_thickness_mm = (flags & 0x40) ? 0.0 : kTol[(e >> 2) & 7];
    p.vgroove.min_bevel_points = 1 + (a >> 3) % 16;
    if (flags & 0x20) {
      p.segmentation.roi_first = (b.u8() | (b.u8() << 8)) % 4096;
      p.segmentation.roi_last = static_cast<int>((b.u8() | (b.u8() << 8)) % 4097) - 1;
    }
    if (flags & 0x10) p.segmentation.ray_origin_yz = tk::Vec2(b.i16() * 0.5, b.i16() * 0.5);
  }
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  const tk::TrackerParams params = decode_params(b);

  std::vector<float> y, z;
  std::vector<std::uint8_t> valid;
  float py = 0.0f, pz = 100.0f;
  while (!b.empty() && y.size() < 4096) {
    const std::uint8_t tag = b.u8();
    float ny = py, nz = pz;
    switch (tag & 7) {
      case 0:  // raw floats
        ny = b.f32();
        nz = b.f32();
        break;
      case 1: {  // special values
        const std::uint8_t s = b.u8();
        ny = kSpecial[s & 15];
        nz = kSpecial[s >> 4];
        break;
      }
      case 2:  // duplicate of the previous point
        break;
      case 3:  // a run of points along a line (plates, bevels)
      {
        const int n = 1 + b.u8();
        const float dy = b.i16() * 0.001f, dz = b.i16() * 0.001f;
        for (int k = 0; k < n && y.size() < 4095; ++k) {
          py += dy;
          pz += dz;
          y.push_back(py);
          z.push_back(pz);
          valid.push_back(1);
        }
        ny = py + dy;
        nz = pz + dz;
        break;
      }
      case 4:  // absolute, 0.01 mm grid around z = 100
        ny = b.i16() * 0.01f;
        nz = 100.0f + b.i16() * 0.01f;
        break;
      default:  // small step from the previous point
        ny = py + static_cast<std::int8_t>(b.u8()) * 0.05f;
        nz = pz + static_cast<std::int8_t>(b.u8()) * 0.05f;
        break;
    }
    y.push_back(ny);
    z.push_back(nz);
    valid.push_back((tag & 0x80) ? 0 : 1);
    if (std::isfinite(ny) && std::isfinite(nz)) {
      py = ny;
      pz = nz;
    }
  }
  // An empty valid span means "all valid"; exercise it too.
  const bool use_valid = !(params.segmentation.segments.split_interval == 1 && (y.size() & 1));
  tk::ProfileView view{y, z, use_valid ? std::span<const std::uint8_t>(valid) : std::span<const std::uint8_t>()};

  tk::Tracker tracker(params);
  tk::TrackResult first;
  tracker.track(view, first);
  check(first.status == tk::TrackStatus::Ok || first.status == tk::TrackStatus::Rejected ||
        first.status == tk::TrackStatus::NoData);
  check(first.joint == params.joint);
  check(first.valid_points >= 0 && first.valid_points <= static_cast<int>(y.size()));
  check(first.outliers >= 0 && first.outliers <= first.valid_points);
  if (first.status == tk::TrackStatus::Ok) {
    check(first.reason.empty());
    check(first.track_point.has_value() && finite(*first.track_point));
    for (const auto& bp : first.break_points) check(!bp || finite(*bp));
  } else if (first.status == tk::TrackStatus::Rejected) {
    check(!first.reason.empty());
  }
  for (const auto& s : first.segments) {
    check(s.first_col >= 0 && s.first_col <= s.last_col && s.last_col < static_cast<int>(y.size()));
    check(s.points >= 0 && s.points <= s.last_col - s.first_col + 1);
  }

  // Again, with the tracker's scratch memory now in use.
  const tk::TrackResult& again = tracker.track(view);
  check(again.status == first.status && again.reason == first.reason);
  check(same(again.track_point, first.track_point));
  for (int i = 0; i < tk::kMaxBreakPoints; ++i) check(same(again.break_points[i], first.break_points[i]));
  check(same(again.gap_mm, first.gap_mm) && same(again.angle_deg, first.angle_deg));
  check(again.segments.size() == first.segments.size());
  return 0;
}
