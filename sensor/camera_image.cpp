#include "sensor/camera_image.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sensor/error_model.h"
#include "sensor/ray_scene.h"
#include "sensor/rays.h"
#include "sensor/simd_clones.h"

namespace vts {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kPlanck = 6.62607015e-34;   // J s
constexpr double kLight = 2.99792458e8;      // m/s

// Counter-based draws: a splitmix64 hash of (seed, index, stream, i), so a
// pixel's noise does not depend on the order pixels are visited.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Acklam's rational approximation of the standard normal quantile (relative
// error below 1.2e-9), used once to fill the table below.
double normal_quantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double lo = 0.02425;
  if (p < lo) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - lo) return -normal_quantile(1.0 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

// Standard normal draws from a table of 65,536 quantiles at equal
// probability steps (tails cut at 4.3 sigma): one hash and one load per draw.
// Enough for sensor noise; the error model's own draws are not affected.
constexpr int kNormalBits = 16;
const std::array<float, 1 << kNormalBits>& normal_table() {
  static const auto table = [] {
    std::array<float, 1 << kNormalBits> t{};
    for (std::size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<float>(normal_quantile((static_cast<double>(i) + 0.5) / t.size()));
    return t;
  }();
  return table;
}

struct Draws {
  std::uint64_t key;
  const float* table = normal_table().data();
  Draws(std::uint64_t seed, std::int64_t index, std::uint64_t stream)
      : key(mix(mix(seed ^ 0x5ca1ab1eull) ^ static_cast<std::uint64_t>(index)) ^ mix(stream)) {}
  // out[k] = draw number first + k (the table's entry at the hash's low 16
  // bits) for k < n: the entries prefetched as their indices are hashed,
  // then read (the table is 256 KiB and read at random: one load after the
  // other waited for each).
  void normals(std::uint64_t first, std::size_t n, float* out) const {
    thread_local std::vector<std::uint16_t> index;
    index.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      index[k] = static_cast<std::uint16_t>(mix(key ^ (first + k)) & 0xffff);
      __builtin_prefetch(table + index[k]);
    }
    for (std::size_t k = 0; k < n; ++k) out[k] = table[index[k]];
  }
};

// Normal draws per column correlated over `grain` columns: white draws
// smoothed with a Gaussian of std dev grain / 2, scaled back to unit variance.
void correlated_normals(const Draws& draws, std::uint64_t stream, int n, double grain, std::vector<float>& out,
                        std::vector<float>& white) {
  const double sigma = std::max(0.0, 0.5 * grain);
  const int radius = sigma < 0.3 ? 0 : static_cast<int>(std::ceil(3.0 * sigma));
  white.resize(static_cast<std::size_t>(n + 2 * radius));
  draws.normals(stream * 0x100000000ull, white.size(), white.data());
  out.assign(static_cast<std::size_t>(n), 0.0f);
  if (radius == 0) {
    std::copy(white.begin(), white.begin() + n, out.begin());
    return;
  }
  std::vector<float> kernel(static_cast<std::size_t>(2 * radius + 1));
  double norm = 0.0;
  for (int k = -radius; k <= radius; ++k) {
    const double w = std::exp(-0.5 * k * k / (sigma * sigma));
    kernel[static_cast<std::size_t>(k + radius)] = static_cast<float>(w);
    norm += w * w;
  }
  const float scale = static_cast<float>(1.0 / std::sqrt(norm));
  for (int i = 0; i < n; ++i) {
    float s = 0.0f;
    for (int k = 0; k <= 2 * radius; ++k) s += kernel[static_cast<std::size_t>(k)] * white[static_cast<std::size_t>(i + k)];
    out[static_cast<std::size_t>(i)] = s * scale;
  }
}

// erf from a table of values and derivatives with cubic Hermite
// interpolation between them: the error of such an interpolant is at most
// h^4 / 384 max |f| over a step h (step 1/256, |erf| < 7: below
// 5e-12), at a few nanoseconds a call (the bands' splats).
template <int PerUnit, int Units>
struct HermiteTable {
  std::array<double, PerUnit * Units + 2> value{}, slope{};  // slope: derivative times the step
  template <class F, class D>
  HermiteTable(F f, D df) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      const double x = static_cast<double>(i) / PerUnit;
      value[i] = f(x);
      slope[i] = df(x) / PerUnit;
    }
  }
  double operator()(double x) const {  // 0 <= x < Units
    const double t = x * PerUnit;
    const auto i = static_cast<std::size_t>(t);
    const double u = t - static_cast<double>(i), u2 = u * u, u3 = u2 * u;
    return (2.0 * u3 - 3.0 * u2 + 1.0) * value[i] + (u3 - 2.0 * u2 + u) * slope[i] + (3.0 * u2 - 2.0 * u3) * value[i + 1] +
           (u3 - u2) * slope[i + 1];
  }
};

double table_erf(double x) {
  static const HermiteTable<256, 6> table([](double t) { return std::erf(t); },
                                          [](double t) { return 2.0 / std::sqrt(std::numbers::pi) * std::exp(-t * t); });
  const double a = std::abs(x);
  const double y = a < 6.0 ? table(a) : 1.0;
  return x < 0.0 ? -y : y;
}

// Adds area times the share of a unit-area Gaussian (centre mu, std dev
// sigma) over each pixel [r - 0.5, r + 0.5] of rows lo .. hi to
// out[r - lo]; neighbouring pixels share their edge's erf.
void add_pixel_shares(int lo, int hi, double mu, double sigma, double area, float* out) {
  const double k = 1.0 / (std::numbers::sqrt2 * sigma);
  double below = table_erf((lo - 0.5 - mu) * k);
  for (int r = lo; r <= hi; ++r) {
    const double above = table_erf((r + 0.5 - mu) * k);
    out[r - lo] += static_cast<float>(area * (0.5 * (above - below)));
    below = above;
  }
}

// Per-thread scratch of form_image (no allocation per image once grown).
std::vector<float>& scratch_column() { thread_local std::vector<float> v; return v; }

}  // namespace

CameraGeometry camera_geometry(const ScannerDesc& d) {
  // The error model's pinhole (centre, axis, F), with the image axes beside it.
  const CameraModel model = camera_model(d);
  CameraGeometry cam;
  cam.centre = model.centre_mm;
  cam.camera_from_sensor.row(0) = Eigen::Vector3d(model.cos_theta, 0.0, -model.axis.x());
  cam.camera_from_sensor.row(1) = Eigen::Vector3d(0.0, 1.0, 0.0);
  cam.camera_from_sensor.row(2) = model.axis.transpose();
  cam.f_px = model.f_px;
  cam.cos_tilt = std::cos(d.scheimpflug_deg * kDeg);
  cam.sin_tilt = std::sin(d.scheimpflug_deg * kDeg);
  cam.width = d.image_width_px;
  cam.height = d.image_height_px;
  cam.cx = 0.5 * (d.image_width_px - 1);
  cam.cy = 0.5 * (d.image_height_px - 1);
  return cam;
}

bool project(const CameraGeometry& cam, const Eigen::Vector3d& p, Eigen::Vector2d& col_row) {
  const Eigen::Vector3d x = cam.camera_from_sensor * (p - cam.centre);
  const double den = x.z() * cam.cos_tilt - x.x() * cam.sin_tilt;
  if (!(x.z() > 0.0) || !(den > 0.0)) return false;
  col_row = {cam.cx + cam.f_px * cam.cos_tilt * x.y() / den, cam.cy + cam.f_px * x.x() / den};
  return true;
}

bool triangulate(const CameraGeometry& cam, double column, double row, Eigen::Vector2d& yz) {
  // Invert the projection for the ray direction in camera coordinates
  // (x/z, y/z), then meet the laser plane x_sensor = 0.
  const double u = row - cam.cy, v = column - cam.cx;
  const double den = cam.f_px + u * cam.sin_tilt;
  if (!(den > 0.0)) return false;
  const double xz = u * cam.cos_tilt / den;
  const double yz_ratio = v * (cam.cos_tilt - xz * cam.sin_tilt) / (cam.f_px * cam.cos_tilt);
  const Eigen::Vector3d dir = cam.camera_from_sensor.transpose() * Eigen::Vector3d(xz, yz_ratio, 1.0);
  // centre + s dir with x = 0.
  if (!(std::abs(dir.x()) > 1e-12)) return false;
  const double s = -cam.centre.x() / dir.x();
  if (!(s > 0.0)) return false;
  const Eigen::Vector3d p = cam.centre + s * dir;
  yz = {p.y(), p.z()};
  return true;
}

double ambient_radiance(const ScannerDesc& d, const CameraGeometry& cam, double column, double row) {
  // The pixel's ray in camera coordinates (triangulate's, not normalized):
  // (u cos(tau), v, f + u sin(tau)); its angle off the axis has cosine z / |X|.
  const double u = row - cam.cy, v = column - cam.cx;
  const double x = u * cam.cos_tilt, z = cam.f_px + u * cam.sin_tilt;
  if (!(z > 0.0)) return 0.0;
  const double c2 = z * z / (x * x + v * v + z * z);
  return d.ambient_w_m2 * 1e-6 * d.reflectivity / std::numbers::pi * c2 * c2;
}

double sheet_rayleigh_mm(const ScannerDesc& d) {
  return std::numbers::pi * d.sheet_waist_mm * d.sheet_waist_mm / (d.sheet_m2 * d.wavelength_nm * 1e-6);
}

double sheet_half_thickness_mm(const ScannerDesc& d, double range_mm) {
  const double t = (range_mm - d.sheet_focus_mm) / sheet_rayleigh_mm(d);
  return d.sheet_waist_mm * std::sqrt(1.0 + t * t);
}

double electrons_per_radiance(const ScannerDesc& d) {
  const double pitch_mm = d.pixel_pitch_um * 1e-3;
  const double photon_j = kPlanck * kLight / (d.wavelength_nm * 1e-9);
  return std::numbers::pi / (4.0 * d.f_number * d.f_number) * pitch_mm * pitch_mm * d.exposure_us * 1e-6 *
         d.quantum_efficiency / photon_j;
}

double dn_per_electron(const ScannerDesc& d) {
  return d.gain * (std::ldexp(1.0, d.image_bits) - 1.0) / d.full_well_e;
}

void RadianceImage::resize(int w, int r, int first) {
  width = w;
  rows = r;
  first_row = first;
  laser.assign(static_cast<std::size_t>(w) * r, 0.0f);
  ambient.assign(static_cast<std::size_t>(w) * r, 0.0f);
}

std::pair<int, int> image_roi(const ScannerDesc& d) {
  if (d.image_roi_rows <= 0) return {0, d.image_height_px};
  return {d.image_roi_first_row, d.image_roi_rows};
}

namespace {

// One secondary band of laser light in the image (the bounce, a mirror
// image): where its centre images, its std dev across the stripe (px) and
// its peak radiance.
struct BandSample {
  double col = 0.0, row = 0.0, sigma = 0.0, radiance = 0.0;
  bool valid = false;
};

// Resamples per-ray bands to the integer image columns between neighbouring
// samples that continue each other (at most `join` px apart); where two
// pieces cross a column, the brighter is kept.
void resample_bands(const std::vector<BandSample>& samples, double join, std::vector<float>& row,
                    std::vector<float>& sigma, std::vector<float>& radiance) {
  const int w = static_cast<int>(row.size());
  for (std::size_t i = 0; i + 1 < samples.size(); ++i) {
    const BandSample& a = samples[i];
    const BandSample& b = samples[i + 1];
    if (!a.valid || !b.valid || std::abs(a.col - b.col) > join || std::abs(a.row - b.row) > join) continue;
    const double lo = std::min(a.col, b.col), hi = std::max(a.col, b.col);
    for (int k = static_cast<int>(std::ceil(lo)); k <= static_cast<int>(std::floor(hi)); ++k) {
      if (k < 0 || k >= w) continue;
      const double f = hi > lo ? (k - a.col) / (b.col - a.col) : 0.0;
      const double rad = a.radiance + f * (b.radiance - a.radiance);
      if (rad <= radiance[static_cast<std::size_t>(k)]) continue;
      row[static_cast<std::size_t>(k)] = static_cast<float>(a.row + f * (b.row - a.row));
      sigma[static_cast<std::size_t>(k)] = static_cast<float>(a.sigma + f * (b.sigma - a.sigma));
      radiance[static_cast<std::size_t>(k)] = static_cast<float>(rad);
    }
  }
}

// A plane of the part the laser lights (a run of primary hits on one
// plane): a candidate mirror for the camera-side path.
struct MirrorPlane {
  Eigen::Vector3d point, normal;  // world; normal towards the laser
  int hits = 0;
};

// Clusters consecutive primary hits into planes: normals within 1 degree
// and points within 0.05 mm of the run's first plane. Keeps runs of at
// least 3 hits, the 16 largest.
std::vector<MirrorPlane> lit_planes(const std::vector<Eigen::Vector3d>& p, const std::vector<Eigen::Vector3d>& n,
                                    const std::vector<char>& hit) {
  std::vector<MirrorPlane> planes;
  const double cos_tol = std::cos(1.0 * kDeg);
  MirrorPlane run;
  const auto close = [&] {
    if (run.hits >= 3) planes.push_back(run);
    run.hits = 0;
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!hit[i]) {
      close();
      continue;
    }
    if (run.hits > 0 && (run.normal.dot(n[i]) < cos_tol || std::abs(run.normal.dot(p[i] - run.point)) > 0.05)) close();
    if (run.hits == 0) run = {p[i], n[i], 0};
    ++run.hits;
  }
  close();
  std::stable_sort(planes.begin(), planes.end(), [](const MirrorPlane& a, const MirrorPlane& b) { return a.hits > b.hits; });
  if (planes.size() > 16) planes.resize(16);
  return planes;
}

// The stripe's per-pixel loop, written to vectorize (float, as the GPU
// shader it replaces computed it; no library calls, no branches, no
// float-to-int conversion, which keeps GCC 12 from vectorizing it for AVX2).
// exp(x) for x <= 0: 2^(x log2 e) split into a whole power n (the exponent
// bits) and e^f, |f| <= ln 2 / 2, by its Taylor series to f^6 (relative
// error below 1.2e-7).
inline float exp_nonpositive(float x) {
  x = std::max(x, -87.0f);
  const float t = x * 1.44269504f;
  // n = t rounded to the nearest whole number: adding 1.5 * 2^23 (|t| <
  // 2^22) leaves it in the sum's low mantissa bits.
  const float shifted = t + 12582912.0f;
  const std::int32_t n = std::bit_cast<std::int32_t>(shifted) - 0x4B400000;
  const float f = (t - (shifted - 12582912.0f)) * 0.693147181f;
  const float poly =
      1.0f + f * (1.0f + f * (0.5f + f * (1.0f / 6.0f + f * (1.0f / 24.0f + f * (1.0f / 120.0f + f * (1.0f / 720.0f))))));
  return poly * std::bit_cast<float>((n + 127) << 23);
}
// Abramowitz and Stegun 7.1.26 (|error| < 1.5e-7 with an exact exp).
inline float erf_as(float x) {
  const float a = std::abs(x);
  const float t = 1.0f / (1.0f + 0.3275911f * a);
  const float y = 1.0f - (((((1.061405429f * t - 1.453152027f) * t) + 1.421413741f) * t - 0.284496736f) * t +
                          0.254829592f) * t * exp_nonpositive(-a * a);
  return std::copysign(y, x);
}

// One image column's pixels seeing one plane, sensor frame, float.
struct StripeColumn {
  float centre[3];    // camera centre
  float dir0[3];      // the pixel ray (scaled, sensor frame) at row 0
  float dir_row[3];   // its change per row
  float n[3];         // the plane's normal, facing the camera
  float k;            // n . (q - centre) (negative)
  float dir_col_x;    // the ray's x change per column
  float den_col;      // n . (the ray's change per column)
  float axis[3];      // the camera's axis
  float power_over_fan, waist, focus, inv_rayleigh, footprint, tan_half_fan, psf2, diffuse, spec_share, inv_2lobe2,
      spec_norm;
};

// The laser radiance of rows first .. first + count - 1 of the column
// (docs/SENSOR_MODEL.md, "The camera image": Sheet, Surface, Pixel), each
// pixel's footprint (the surface point's change along the image's columns
// and rows) taken on the plane. With `kBoxOnly` the pixel's share of the
// sheet is the box (erf) form everywhere, one exp fewer a pixel, and the
// result is true when some pixel needs the Gaussian instead (a footprint
// below 1e-3 of the sheet's width): the caller then runs the full form,
// which gives the same bits in every other pixel.
template <bool kBoxOnly>
[[gnu::always_inline]] inline bool stripe_pixels(const StripeColumn& s, int first, int count, float* __restrict out) {
  int narrow = 0;  // an int: GCC 12 vectorizes an int's |= reduction
  const float dden_row = s.n[0] * s.dir_row[0] + s.n[1] * s.dir_row[1] + s.n[2] * s.dir_row[2];
  const float kPi = 3.14159265358979f;
  for (int i = 0; i < count; ++i) {
    const float row = static_cast<float>(first + i);
    const float dx = s.dir0[0] + row * s.dir_row[0], dy = s.dir0[1] + row * s.dir_row[1],
                dz = s.dir0[2] + row * s.dir_row[2];
    const float den = s.n[0] * dx + s.n[1] * dy + s.n[2] * dz;
    const float t = s.k / den;
    const float px = s.centre[0] + t * dx, py = s.centre[1] + t * dy, pz = s.centre[2] + t * dz;
    const float r = std::sqrt(px * px + py * py + pz * pz);
    const float q = (r - s.focus) * s.inv_rayleigh;
    const float w = s.waist * std::sqrt(1.0f + q * q);
    const float cos_i = -(px * s.n[0] + py * s.n[1] + pz * s.n[2]) / r;
    // x half a pixel either way along the row and the column: for
    // x = c.x + k A / B with A, B affine, x(+1/2) - x(-1/2) = k (a B - A b) / (B^2 - b^2 / 4).
    const float bc = s.den_col, br = dden_row;
    const float dx_col = s.k * (s.dir_col_x * den - dx * bc) / (den * den - 0.25f * bc * bc);
    const float dx_row = s.k * (s.dir_row[0] * den - dx * br) / (den * den - 0.25f * br * br);
    // (& rather than &&: no branch in the loop.)
    const bool ok = (t > 0.0f) & (std::abs(px) <= 3.0f * w + r * s.footprint) & (pz > 0.0f) &
                    (std::abs(py) <= s.tan_half_fan * pz) & (cos_i > 0.0f) & (den * den > 0.25f * bc * bc) &
                    (den * den > 0.25f * br * br);
    const float h = 0.5f * (std::abs(dx_col) + std::abs(dx_row));  // the pixel's half footprint across the sheet
    const float sigma = std::sqrt(0.25f * w * w + s.psf2 * (dx_col * dx_col + dx_row * dx_row));
    const float kk = 0.70710678f / sigma;
    const float box = 0.25f * (erf_as((px + h) * kk) - erf_as((px - h) * kk)) / h;
    float g = box;
    if constexpr (kBoxOnly) {
      narrow |= static_cast<int>(ok & !(h * kk > 1e-3f));  // (rows not ok are 0 either way)
    } else {
      const float gauss = 0.39894228f / sigma * exp_nonpositive(-0.5f * px * px / (sigma * sigma));
      g = h * kk > 1e-3f ? box : gauss;
    }
    const float e = s.power_over_fan / r * g * cos_i;
    // Towards the camera, and the mirror direction of the laser's.
    const float inv_len = 1.0f / std::sqrt(dx * dx + dy * dy + dz * dz);
    const float vx = -dx * inv_len, vy = -dy * inv_len, vz = -dz * inv_len;
    const float cos_v = s.n[0] * vx + s.n[1] * vy + s.n[2] * vz;
    const float mx = px / r + 2.0f * cos_i * s.n[0], my = py / r + 2.0f * cos_i * s.n[1],
                mz = pz / r + 2.0f * cos_i * s.n[2];
    const float a2 = 2.0f * (1.0f - (mx * vx + my * vy + mz * vz));
    const float spec = s.spec_share * exp_nonpositive(-std::max(a2, 0.0f) * s.inv_2lobe2) /
                       (s.spec_norm * std::max(cos_v, 0.05f));
    const float cos_off0 = -(s.axis[0] * vx + s.axis[1] * vy + s.axis[2] * vz);
    const float cos_off = std::max(cos_off0, 0.0f);
    const float value = e * (s.diffuse / kPi + spec) * (cos_off * cos_off) * (cos_off * cos_off);
    out[i] = ok ? value : 0.0f;
  }
  return narrow != 0;
}
// In whole runs of 8 rows (AVX2's width; a multiple of SSE2's): the
// vectorized loop's scalar tail had taken a third of its time. The last
// rows go through a run of 8 into scratch; every row's value is computed
// alone, so the rows past `count` change nothing.
VTS_SIMD_CLONES void stripe_column(const StripeColumn& s, int first, int count, float* __restrict out) {
  const int whole = count & ~7;
  if (whole > 0 && stripe_pixels<true>(s, first, whole, out)) stripe_pixels<false>(s, first, whole, out);
  if (whole == count) return;
  float tail[8];
  if (stripe_pixels<true>(s, first + whole, 8, tail)) stripe_pixels<false>(s, first + whole, 8, tail);
  std::copy_n(tail, count - whole, out + whole);
}

// The primary ray of one image column: its direction and nearest hit (world).
struct PrimaryHit {
  Eigen::Vector3d dir = Eigen::Vector3d::Zero(), p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  double t = 0.0;
  bool hit = false;
};

// How far from the laser the stripe is drawn (the renderer's far plane).
double stripe_far_mm(const ScannerDesc& d) { return 2.0 * d.max_hit_mm + 2.0 * d.baseline_mm + 10.0; }

// The sheet's radiance toward the camera at a surface point, per pixel, as
// docs/SENSOR_MODEL.md "The camera image" gives it (Sheet, Surface, Pixel):
// sensor frame, a pixel's derivatives of the surface point along the
// image's columns and rows given.
struct StripeModel {
  CameraGeometry cam;
  Eigen::Matrix3d sensor_from_camera;
  Eigen::Vector3d axis;
  double power_w, fan_rad, tan_half_fan, waist, focus, rayleigh, rho_d, rho_s, lobe, psf, footprint;

  explicit StripeModel(const ScannerDesc& d) : cam(camera_geometry(d)) {
    sensor_from_camera = cam.camera_from_sensor.transpose();
    axis = cam.camera_from_sensor.row(2).transpose();
    power_w = d.laser_power_mw * 1e-3;
    fan_rad = d.fan_deg * kDeg;
    tan_half_fan = std::tan(0.5 * fan_rad);
    waist = d.sheet_waist_mm;
    focus = d.sheet_focus_mm;
    rayleigh = sheet_rayleigh_mm(d);
    rho_d = d.reflectivity;
    rho_s = d.specular_reflectance;
    lobe = std::max(1e-3, d.specular_lobe_deg * kDeg);
    psf = d.psf_sigma_px;
    footprint = (2.0 + 3.0 * d.psf_sigma_px) * d.pixel_pitch_um * 1e-3 / d.focal_length_mm;
    init_rays();
  }
  // The ray of pixel (column, row) from the camera centre, the projection
  // inverted, scaled by f + u sin(tau): affine in (column, row),
  // g0 + column gc + row gr (sensor frame).
  Eigen::Vector3d g0, gc, gr;
  void init_rays() {
    g0 = sensor_from_camera * Eigen::Vector3d(-cam.cy * cam.cos_tilt, -cam.cx, cam.f_px - cam.cy * cam.sin_tilt);
    gc = sensor_from_camera.col(1);
    gr = sensor_from_camera * Eigen::Vector3d(cam.cos_tilt, 0.0, cam.sin_tilt);
  }
  Eigen::Vector3d pixel_dir(double col, double row) const { return g0 + col * gc + row * gr; }
  // A plane (sensor frame) as the pixels see it: point c + (k / n.d) d on
  // the ray d of a pixel.
  struct Plane {
    Eigen::Vector3d n;  // facing the camera
    double k = 0.0;     // n . (q - centre)
  };
  Plane plane(const Eigen::Vector3d& q, const Eigen::Vector3d& n) const {
    const double k = n.dot(q - cam.centre);
    return k < 0.0 ? Plane{n, k} : Plane{-n, -k};
  }
  // Where the ray of pixel (col, row) meets the plane.
  bool on_plane(double col, double row, const Plane& pl, Eigen::Vector3d& p) const {
    const Eigen::Vector3d dir = pixel_dir(col, row);
    const double s = pl.k / pl.n.dot(dir);
    if (!(s > 0.0)) return false;
    p = cam.centre + s * dir;
    return true;
  }
  // The rows of lo .. hi of column col whose pixels see the plane within
  // |x| <= bound (x of a ray's point on a plane is a ratio of two affine
  // functions of the row, monotonic between its poles: solved for x =
  // +-bound), with two rows more either way; all of lo .. hi when a pole
  // (the ray parallel to the plane) lies in between or beyond a solution.
  // Empty (first > last) when none.
  std::pair<int, int> band_rows(double col, int lo, int hi, const Plane& pl, double bound) const {
    const Eigen::Vector3d d0 = g0 + col * gc;
    const double a0 = d0.x(), a1 = gr.x(), b0 = pl.n.dot(d0), b1 = pl.n.dot(gr);
    const double den_lo = b0 + b1 * lo, den_hi = b0 + b1 * hi;
    if (!(den_lo * den_hi > 0.0)) return {lo, hi};
    double rows[2];
    for (int k = 0; k < 2; ++k) {
      // centre.x + pl.k (a0 + a1 row) / (b0 + b1 row) = s
      const double s = (k == 0 ? bound : -bound) - cam.centre.x();
      const double num = s * b0 - pl.k * a0, den = pl.k * a1 - s * b1;
      rows[k] = num / den;
      // (a solution past the pole is on the other branch: all rows)
      if (!std::isfinite(rows[k]) || !((b0 + b1 * rows[k]) * den_lo > 0.0)) return {lo, hi};
    }
    const double first = std::floor(std::min(rows[0], rows[1])) - 2.0;
    const double last = std::ceil(std::max(rows[0], rows[1])) + 2.0;
    if (last < lo || first > hi) return {lo, lo - 1};
    return {static_cast<int>(std::max<double>(lo, first)), static_cast<int>(std::min<double>(hi, last))};
  }
  double sheet_w(double r) const {
    const double q = (r - focus) / rayleigh;
    return waist * std::sqrt(1.0 + q * q);
  }
  // The slab around the sheet where it can light anything: three half
  // thicknesses, two pixel footprints and three lens blurs.
  double slab(double r) const { return 3.0 * sheet_w(r) + r * footprint; }
  // The laser radiance of rows first .. first + count - 1 of column col
  // seeing the plane (lit by the laser, seen by the camera: the caller's to
  // know).
  void column(double col, int first, int count, const Plane& pl, float* out) const {
    StripeColumn sc{};
    const Eigen::Vector3d d0 = g0 + col * gc;
    for (int a = 0; a < 3; ++a) {
      sc.centre[a] = static_cast<float>(cam.centre[a]);
      sc.dir0[a] = static_cast<float>(d0[a]);
      sc.dir_row[a] = static_cast<float>(gr[a]);
      sc.n[a] = static_cast<float>(pl.n[a]);
      sc.axis[a] = static_cast<float>(axis[a]);
    }
    sc.k = static_cast<float>(pl.k);
    sc.dir_col_x = static_cast<float>(gc.x());
    sc.den_col = static_cast<float>(pl.n.dot(gc));
    sc.power_over_fan = static_cast<float>(power_w / fan_rad);
    sc.waist = static_cast<float>(waist);
    sc.focus = static_cast<float>(focus);
    sc.inv_rayleigh = static_cast<float>(1.0 / rayleigh);
    sc.footprint = static_cast<float>(footprint);
    sc.tan_half_fan = static_cast<float>(tan_half_fan);
    sc.psf2 = static_cast<float>(psf * psf);
    sc.diffuse = static_cast<float>(rho_d);
    sc.spec_share = static_cast<float>(rho_s);
    sc.inv_2lobe2 = static_cast<float>(0.5 / (lobe * lobe));
    sc.spec_norm = static_cast<float>(2.0 * std::numbers::pi * lobe * lobe);
    stripe_column(sc, first, count, out);
  }
};

// The primary stripe per image column (docs/SENSOR_MODEL.md "The camera
// image", "The stripe"): the pixels of column c near the sheet see the plane
// of the column's primary hit; where that plane holds over the band (the
// neighbouring columns hit the same plane, the laser reaches and the camera
// sees both ends of the band and its centre), every pixel is evaluated on
// it. Elsewhere (edges, shadows) each pixel's ray is cast (Embree): the
// surface it sees, lit where the laser reaches that point.
// `centre_seen` gets, per column, whether the camera sees the primary hit
// where that ray was cast (1 or 0; -1 where not), for the truth to reuse.
void trace_stripe(const ScannerDesc& d, const CameraGeometry& cam, const RayScene& scene, const Pose& world_from_sensor,
                  const std::vector<PrimaryHit>& primary, LaserPaths& out, std::vector<signed char>& centre_seen) {
  const int w = cam.width;
  const auto [roi_first, roi_rows] = image_roi(d);
  const int roi_last = roi_first + roi_rows - 1;
  out.stripe_offset.assign(static_cast<std::size_t>(w) + 1, 0);
  out.stripe_first_row.assign(static_cast<std::size_t>(w), 0);
  out.stripe_radiance.clear();
  centre_seen.assign(static_cast<std::size_t>(w), -1);
  const StripeModel model(d);
  const Pose sensor_from_world = world_from_sensor.inverse();
  const Eigen::Matrix3d rot = world_from_sensor.linear();
  const Eigen::Matrix3d rot_t = rot.transpose();
  const Eigen::Vector3d origin = world_from_sensor.translation();
  const Eigen::Vector3d cam_world = world_from_sensor * cam.centre;
  const double far = stripe_far_mm(d);
  const double cos_same = std::cos(1.0 * kDeg);
  // The ray that tells whether the laser reaches p (world; r its range,
  // cos_i its incidence); none (false) where p is within the bias of the
  // laser, which then reaches it.
  const auto reach_ray = [&](const Eigen::Vector3d& p, double r, double cos_i, RayScene::Segment& ray) {
    const double bias = 0.02 + 1e-4 * r / std::max(cos_i, 0.1);
    if (r <= bias) return false;
    ray = {origin.cast<float>(), ((p - origin) / r).cast<float>(), 0.0f, static_cast<float>(r - bias)};
    return true;
  };
  const auto reached = [&](const Eigen::Vector3d& p, double r, double cos_i) {
    RayScene::Segment ray;
    return !reach_ray(p, r, cos_i, ray) || !scene.occluded(ray.o, ray.d, ray.tnear, ray.tfar);
  };
  // The ray that tells whether the camera sees p (world) on a surface of
  // normal n.
  const auto seen_ray = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    const Eigen::Vector3d to_cam = cam_world - p;
    const double dist = to_cam.norm();
    const Eigen::Vector3d nn = n.dot(to_cam) < 0.0 ? Eigen::Vector3d(-n) : n;
    return RayScene::Segment{(p + 1e-3 * nn).cast<float>(), (to_cam / dist).cast<float>(),
                             static_cast<float>(kShadowEpsilonMm), static_cast<float>(dist)};
  };
  const auto same_plane = [&](const PrimaryHit& a, const PrimaryHit& b) {
    return a.hit && b.hit && a.n.dot(b.n) >= cos_same && std::abs(a.n.dot(b.p - a.p)) <= 0.05;
  };
  // 1. Per column, the band's pixels on the plane of the column's hit.
  struct Band {
    int lo = 0, hi = -1, first_lit = 0, last_lit = -1;
    std::size_t at = 0;  // its values: values[at .. at + hi - lo]
    bool traced = false;  // lo .. hi evaluated (else no stripe in the column)
    bool clear = false;   // the plane holds over the band (so far)
    Eigen::Vector3d end_world[2], end_sensor[2];
    double cos_i = 0.0;
  };
  thread_local std::vector<Band> bands;
  thread_local std::vector<float> values;
  bands.assign(static_cast<std::size_t>(w), Band{});
  values.clear();
  for (int c = 0; c < w; ++c) {
    Band& b = bands[static_cast<std::size_t>(c)];
    const PrimaryHit& ph = primary[static_cast<std::size_t>(c)];
    if (!ph.hit) continue;
    const Eigen::Vector3d q = sensor_from_world * ph.p;  // sensor frame
    const Eigen::Vector3d n = rot_t * ph.n;
    Eigen::Vector2d cr;
    if (!project(cam, q, cr)) continue;
    const StripeModel::Plane pl = model.plane(q, n);
    // The rows of the band on the plane: where |x| <= slab, from the row of
    // the hit outwards (x is monotonic along a column on a plane).
    const double r0 = std::clamp(std::round(cr.y()), static_cast<double>(roi_first), static_cast<double>(roi_last));
    Eigen::Vector3d pa, pb;
    if (!model.on_plane(c, r0, pl, pa) || !model.on_plane(c, r0 + 1.0, pl, pb)) continue;
    const double slope = std::abs(pb.x() - pa.x());  // mm of x per row
    const double reach = 1.5 * model.slab(q.norm()) + std::abs(pa.x());
    const double span = slope > 0.0 ? std::min(reach / slope + 2.0, static_cast<double>(cam.height)) : cam.height;
    const int lo = static_cast<int>(std::max(static_cast<double>(roi_first), std::floor(r0 - span)));
    const int hi = static_cast<int>(std::min(static_cast<double>(roi_last), std::ceil(r0 + span)));
    if (lo > hi) continue;
    b.traced = true;
    b.lo = lo;
    b.hi = hi;
    b.clear = c > 0 && c + 1 < w && same_plane(ph, primary[static_cast<std::size_t>(c) - 1]) &&
              same_plane(ph, primary[static_cast<std::size_t>(c) + 1]);
    b.at = values.size();
    values.resize(values.size() + static_cast<std::size_t>(hi - lo + 1), 0.0f);
    float* v = values.data() + b.at;
    b.first_lit = hi + 1;
    b.last_lit = lo - 1;
    // Only the rows that can be lit are evaluated (the rest stay 0, as the
    // evaluation would leave them): where the plane's x is within 1.05
    // slabs, with two rows more either way (band_rows); if the outer
    // rows evaluated are lit after all, the whole range is.
    const auto [ea, eb] = model.band_rows(c, lo, hi, pl, 1.05 * model.slab(q.norm()));
    int done_lo = ea, done_hi = eb;  // the rows evaluated (the others are 0)
    if (ea <= eb) {
      model.column(c, ea, eb - ea + 1, pl, v + (ea - lo));
      if ((ea > lo && v[ea - lo] > 0.0f) || (eb < hi && v[eb - lo] > 0.0f)) {
        model.column(c, lo, hi - lo + 1, pl, v);
        done_lo = lo;
        done_hi = hi;
      }
    }
    for (int row = done_lo; row <= done_hi; ++row)
      if (v[row - lo] > 0.0f) {
        b.first_lit = std::min(b.first_lit, row);
        b.last_lit = row;
      }
    if (b.clear && b.first_lit <= b.last_lit) {
      // Both ends of the band and its centre must be reached by the laser
      // and seen by the camera (2. below).
      b.clear = model.on_plane(c, b.first_lit, pl, b.end_sensor[0]) && model.on_plane(c, b.last_lit, pl, b.end_sensor[1]);
      b.cos_i = std::abs(ph.dir.dot(ph.n));
      if (b.clear)
        for (int k = 0; k < 2; ++k) b.end_world[k] = world_from_sensor * b.end_sensor[k];
    }
  }

  // 2. The checks of the plane, in the order a column would make them, each
  // over the columns still clear, 8 rays at a time: the laser reaches the
  // band's first end, the camera sees it; the same at the other end; the
  // camera sees the centre (the primary hit).
  thread_local std::vector<int> pending;
  thread_local std::vector<RayScene::Segment> rays;
  thread_local std::vector<unsigned char> blocked;
  for (int step = 0; step < 5; ++step) {
    pending.clear();
    rays.clear();
    for (int c = 0; c < w; ++c) {
      Band& b = bands[static_cast<std::size_t>(c)];
      if (!b.traced || !b.clear || b.first_lit > b.last_lit) continue;
      const PrimaryHit& ph = primary[static_cast<std::size_t>(c)];
      const int e = step / 2;
      RayScene::Segment ray;
      if (step == 4) ray = seen_ray(ph.p, ph.n);
      else if (step % 2 == 1) ray = seen_ray(b.end_world[e], ph.n);
      else if (!reach_ray(b.end_world[e], b.end_sensor[e].norm(), b.cos_i, ray)) continue;  // reached: no ray needed
      pending.push_back(c);
      rays.push_back(ray);
    }
    blocked.resize(rays.size());
    scene.occluded(rays.data(), rays.size(), blocked.data());
    for (std::size_t k = 0; k < pending.size(); ++k) {
      const int c = pending[k];
      bands[static_cast<std::size_t>(c)].clear = !blocked[k];
      if (step == 4) centre_seen[static_cast<std::size_t>(c)] = blocked[k] ? 0 : 1;
    }
  }

  // 3. Per column, pixel by pixel where the plane does not hold; the
  // column's lit rows into `out`.
  std::vector<float> own;
  for (int c = 0; c < w; ++c) {
    out.stripe_offset[static_cast<std::size_t>(c) + 1] = out.stripe_offset[static_cast<std::size_t>(c)];
    const Band& b = bands[static_cast<std::size_t>(c)];
    if (!b.traced) continue;
    int lo = b.lo, hi = b.hi, first_lit = b.first_lit, last_lit = b.last_lit;
    const float* v = values.data() + b.at;
    if (!b.clear) {
      // Pixel by pixel: what each pixel's ray sees, lit where the laser
      // reaches it; a few rows more, for a plane that ends inside the band.
      lo = std::max(roi_first, lo - 4);
      hi = std::min(roi_last, hi + 4);
      own.assign(static_cast<std::size_t>(hi - lo + 1), 0.0f);
      v = own.data();
      first_lit = hi + 1;
      last_lit = lo - 1;
      for (int row = lo; row <= hi; ++row) {
        const Eigen::Vector3d dir = (rot * model.pixel_dir(c, row)).normalized();
        RayScene::Hit hit;
        if (!scene.intersect(cam_world.cast<float>(), dir.cast<float>(), 0.0f, static_cast<float>(far), hit)) continue;
        const Eigen::Vector3d pw = cam_world + static_cast<double>(hit.t) * dir;
        const Eigen::Vector3d nw = hit.normal.cast<double>();
        const Eigen::Vector3d ps = sensor_from_world * pw, ns = rot_t * nw;
        const double r = ps.norm();
        if (!(r > 0.0) || std::abs(ps.x()) > model.slab(r)) continue;
        const double cos_i = std::abs((pw - origin).dot(nw)) / r;
        if (!reached(pw, r, cos_i)) continue;
        float& value = own[static_cast<std::size_t>(row - lo)];
        model.column(c, row, 1, model.plane(ps, ns), &value);
        if (value > 0.0f) {
          first_lit = std::min(first_lit, row);
          last_lit = row;
        }
      }
    }

    if (first_lit > last_lit) continue;
    out.stripe_first_row[static_cast<std::size_t>(c)] = first_lit;
    out.stripe_radiance.insert(out.stripe_radiance.end(), v + (first_lit - lo), v + (last_lit - lo + 1));
    out.stripe_offset[static_cast<std::size_t>(c) + 1] = static_cast<int>(out.stripe_radiance.size());
  }
}

}  // namespace

void trace_laser_paths(const ScannerDesc& d, const RayScene& scene, const Pose& world_from_sensor,
                       LaserPaths& out) {
  const CameraGeometry cam = camera_geometry(d);
  const int w = cam.width;
  out.true_row.assign(static_cast<std::size_t>(w), kNaN);
  out.bounce_row.assign(static_cast<std::size_t>(w), kNaN);
  out.bounce_sigma.assign(static_cast<std::size_t>(w), 0.0f);
  out.bounce_radiance.assign(static_cast<std::size_t>(w), 0.0f);
  out.mirror_row.assign(static_cast<std::size_t>(w), kNaN);
  out.mirror_sigma.assign(static_cast<std::size_t>(w), 0.0f);
  out.mirror_radiance.assign(static_cast<std::size_t>(w), 0.0f);

  const Eigen::Matrix3d rot = world_from_sensor.linear();
  const Eigen::Vector3d origin = world_from_sensor.translation();
  const Eigen::Vector3d cam_world = world_from_sensor * cam.centre;
  const double tan_half_fan = std::tan(0.5 * d.fan_deg * kDeg);
  const double fan_rad = d.fan_deg * kDeg;
  const double power_w = d.laser_power_mw * 1e-3;
  const double lobe = d.specular_lobe_deg * kDeg;
  const Eigen::Vector3d axis_world = rot * cam.camera_from_sensor.row(2).transpose();
  const bool bounce = d.specular_reflectance > 0.0;
  const Eigen::Vector3d plane_normal = rot.col(0);  // the laser plane's normal, world
  const Pose sensor_from_world = world_from_sensor.inverse();
  // The off-axis falloff cos^4 for light leaving along `view` (unit,
  // towards the camera).
  const auto vignetting = [&](const Eigen::Vector3d& view) {
    const double cos_off = std::max(0.0, axis_world.dot(-view));
    return std::pow(cos_off, 4);
  };
  // The band the sheet lights on a surface of normal n: the direction
  // across it within the surface, and its std dev there for a sheet std
  // dev `sigma` (mm).
  const auto across_band = [&](const Eigen::Vector3d& sheet_normal, const Eigen::Vector3d& n, double sigma,
                               Eigen::Vector3d& across, double& sigma_surface) {
    across = sheet_normal - sheet_normal.dot(n) * n;
    const double norm = across.norm();
    if (!(norm > 1e-9)) return false;
    across /= norm;
    sigma_surface = std::min(50.0, sigma / std::max(0.05, std::abs(sheet_normal.dot(across))));
    return true;
  };

  struct Sample {
    double col, row;
    bool seen;
  };
  std::vector<Sample> samples(static_cast<std::size_t>(w));
  std::vector<BandSample> bounced(static_cast<std::size_t>(w));
  // The primary hits (world), for the camera-side mirror.
  std::vector<Eigen::Vector3d> hit_p(static_cast<std::size_t>(w)), hit_n(static_cast<std::size_t>(w));
  std::vector<char> lit(static_cast<std::size_t>(w), 0);
  std::vector<double> lit_irradiance(static_cast<std::size_t>(w), 0.0), lit_sigma(static_cast<std::size_t>(w), 0.0);
  // The primary rays, one per image column: the laser-plane direction that
  // images at column c at mid range (exact for every range without tilt),
  // cast as far as the stripe can be drawn.
  // Their directions in the sensor frame do not depend on the pose: kept
  // per thread for the last camera (zero where outside the fan).
  thread_local std::vector<double> dirs_key;
  thread_local std::vector<Eigen::Vector3d> dirs_sensor;
  const std::vector<double> key = {cam.centre.x(), cam.centre.y(), cam.centre.z(), cam.f_px, cam.cos_tilt, cam.sin_tilt,
                                   cam.cx, cam.cy, static_cast<double>(w), tan_half_fan,
                                   cam.camera_from_sensor(0, 0), cam.camera_from_sensor(0, 1), cam.camera_from_sensor(0, 2),
                                   cam.camera_from_sensor(1, 0), cam.camera_from_sensor(1, 1), cam.camera_from_sensor(1, 2),
                                   cam.camera_from_sensor(2, 0), cam.camera_from_sensor(2, 1), cam.camera_from_sensor(2, 2)};
  if (key != dirs_key) {
    dirs_key = key;
    dirs_sensor.assign(static_cast<std::size_t>(w), Eigen::Vector3d::Zero());
    for (int c = 0; c < w; ++c) {
      Eigen::Vector2d yz;
      const double row_mid = cam.cy;
      double tan_a = 0.0;
      if (triangulate(cam, c, row_mid, yz) && yz.y() > 0.0) tan_a = yz.x() / yz.y();
      else tan_a = (c - cam.cx) * cam.camera_from_sensor(2, 2) / cam.f_px;
      if (std::abs(tan_a) > tan_half_fan) continue;
      dirs_sensor[static_cast<std::size_t>(c)] = Eigen::Vector3d(0.0, tan_a, 1.0).normalized();
    }
  }
  // Cast 8 at a time.
  std::vector<PrimaryHit> primary(static_cast<std::size_t>(w));
  thread_local std::vector<int> cast_columns;
  thread_local std::vector<RayScene::Segment> cast_rays;
  thread_local std::vector<RayScene::Hit> cast_hits;
  thread_local std::vector<unsigned char> cast_found;
  cast_columns.clear();
  cast_rays.clear();
  for (int c = 0; c < w; ++c) {
    const Eigen::Vector3d& ds = dirs_sensor[static_cast<std::size_t>(c)];
    if (ds.z() == 0.0) continue;  // outside the fan
    PrimaryHit& ph = primary[static_cast<std::size_t>(c)];
    ph.dir = rot * ds;
    cast_columns.push_back(c);
    cast_rays.push_back({origin.cast<float>(), ph.dir.cast<float>(), 0.0f, static_cast<float>(stripe_far_mm(d))});
  }
  cast_hits.resize(cast_rays.size());
  cast_found.resize(cast_rays.size());
  scene.intersect(cast_rays.data(), cast_rays.size(), cast_hits.data(), cast_found.data());
  for (std::size_t k = 0; k < cast_columns.size(); ++k) {
    if (!cast_found[k]) continue;
    PrimaryHit& ph = primary[static_cast<std::size_t>(cast_columns[k])];
    const RayScene::Hit& hit = cast_hits[k];
    ph.hit = true;
    ph.t = hit.t;
    ph.p = origin + static_cast<double>(hit.t) * ph.dir;
    ph.n = hit.normal.cast<double>();
  }
  std::vector<signed char> centre_seen;
  trace_stripe(d, cam, scene, world_from_sensor, primary, out, centre_seen);

  // The truth's camera rays where trace_stripe cast none, and the bounce's
  // rays, each kind cast 8 at a time.
  thread_local std::vector<int> seen_columns, bounce_columns;
  thread_local std::vector<RayScene::Segment> seen_rays, bounce_rays;
  thread_local std::vector<Eigen::Vector2d> seen_at;
  thread_local std::vector<unsigned char> seen_blocked;
  seen_columns.clear();
  seen_rays.clear();
  seen_at.clear();
  bounce_columns.clear();
  bounce_rays.clear();
  for (int c = 0; c < w; ++c) {
    Sample& s = samples[static_cast<std::size_t>(c)];
    s = {0, 0, false};
    const PrimaryHit& ph = primary[static_cast<std::size_t>(c)];
    if (!ph.hit || ph.t > d.max_hit_mm) continue;
    const Eigen::Vector3d& dir = ph.dir;
    const Eigen::Vector3d& p = ph.p;
    const Eigen::Vector3d& n = ph.n;
    const Eigen::Vector3d p_s = sensor_from_world * p;
    if (p_s.z() < d.min_range_mm || p_s.z() > d.max_range_mm) continue;
    hit_p[static_cast<std::size_t>(c)] = p;
    hit_n[static_cast<std::size_t>(c)] = n;
    lit[static_cast<std::size_t>(c)] = 1;
    lit_sigma[static_cast<std::size_t>(c)] = 0.5 * sheet_half_thickness_mm(d, static_cast<float>(ph.t));
    lit_irradiance[static_cast<std::size_t>(c)] = power_w / (fan_rad * static_cast<float>(ph.t)) /
                                                  (std::sqrt(2.0 * std::numbers::pi) * lit_sigma[static_cast<std::size_t>(c)]) *
                                                  std::max(0.0, -dir.dot(n));
    Eigen::Vector2d cr;
    const Eigen::Vector3d to_cam = cam_world - p;
    const double dist_cam = to_cam.norm();
    // (The same ray as trace_stripe's centre check, where that was cast:
    // n faces the camera, so it starts at the same point.)
    const signed char known = centre_seen[static_cast<std::size_t>(c)];
    if (project(cam, p_s, cr) && n.dot(to_cam) > 0.0) {
      if (known >= 0) {
        if (known == 1) s = {cr.x(), cr.y(), true};
      } else {
        seen_columns.push_back(c);
        seen_at.push_back(cr);
        seen_rays.push_back({(p + 1e-3 * n).cast<float>(), (to_cam / dist_cam).cast<float>(),
                             static_cast<float>(kShadowEpsilonMm), static_cast<float>(dist_cam)});
      }
    }
    if (!bounce) continue;
    // The mirror reflection of the ray off the surface.
    const Eigen::Vector3d m = dir - 2.0 * dir.dot(n) * n;
    bounce_columns.push_back(c);
    bounce_rays.push_back({(p + 1e-3 * n).cast<float>(), m.cast<float>(), 0.01f, 1e5f});
  }
  seen_blocked.resize(seen_rays.size());
  scene.occluded(seen_rays.data(), seen_rays.size(), seen_blocked.data());
  for (std::size_t k = 0; k < seen_columns.size(); ++k)
    if (!seen_blocked[k]) samples[static_cast<std::size_t>(seen_columns[k])] = {seen_at[k].x(), seen_at[k].y(), true};

  // The bounce: where the reflected ray lands (q), if the camera sees q.
  struct Bounce {
    int c = 0;
    Eigen::Vector3d q, nq, q_to_cam;
    float hq_t = 0.0f;  // (float, as Embree gives it)
    double q_dist = 0.0, cos_q = 0.0;
  };
  thread_local std::vector<Bounce> landed;
  thread_local std::vector<RayScene::Hit> bounce_hits;
  thread_local std::vector<unsigned char> bounce_flags;
  landed.clear();
  bounce_hits.resize(bounce_rays.size());
  bounce_flags.resize(bounce_rays.size());
  scene.intersect(bounce_rays.data(), bounce_rays.size(), bounce_hits.data(), bounce_flags.data());
  std::size_t cast = 0;
  for (std::size_t k = 0; k < bounce_columns.size(); ++k) {
    if (!bounce_flags[k]) continue;
    const int c = bounce_columns[k];
    const PrimaryHit& ph = primary[static_cast<std::size_t>(c)];
    const Eigen::Vector3d& dir = ph.dir;
    const Eigen::Vector3d& p = ph.p;
    const Eigen::Vector3d& n = ph.n;
    const Eigen::Vector3d m = dir - 2.0 * dir.dot(n) * n;
    const RayScene::Hit& hq = bounce_hits[k];
    Bounce b;
    b.c = c;
    b.hq_t = hq.t;
    b.q = p + 1e-3 * n + static_cast<double>(hq.t) * m;
    b.nq = hq.normal.cast<double>();
    b.cos_q = -m.dot(b.nq);
    b.q_to_cam = cam_world - b.q;
    b.q_dist = b.q_to_cam.norm();
    if (!(b.cos_q > 0.0) || b.nq.dot(b.q_to_cam) <= 0.0) continue;
    bounce_rays[cast++] = {(b.q + 1e-3 * b.nq).cast<float>(), (b.q_to_cam / b.q_dist).cast<float>(),
                           static_cast<float>(kShadowEpsilonMm), static_cast<float>(b.q_dist)};
    landed.push_back(b);
  }
  bounce_flags.resize(cast);
  scene.occluded(bounce_rays.data(), cast, bounce_flags.data());
  for (std::size_t k = 0; k < landed.size(); ++k) {
    if (bounce_flags[k]) continue;
    const Bounce& b = landed[k];
    const int c = b.c;
    const PrimaryHit& ph = primary[static_cast<std::size_t>(c)];
    const Eigen::Vector3d& n = ph.n;
    const float travelled = static_cast<float>(ph.t) + b.hq_t;
    // The mirrored sheet: thickness of the beam after `travelled` widened by
    // the lobe over the reflected leg; in-line power density of a fan from
    // the mirrored origin.
    const double sigma_sheet = 0.5 * sheet_half_thickness_mm(d, travelled);
    const double sigma_b = std::hypot(sigma_sheet, lobe * b.hq_t);
    const double irradiance = d.specular_reflectance * power_w / (fan_rad * travelled) /
                              (std::sqrt(2.0 * std::numbers::pi) * sigma_b) * b.cos_q;
    const double radiance = irradiance * d.reflectivity / std::numbers::pi * vignetting(b.q_to_cam / b.q_dist);
    // Width in the image: across the mirrored band on the surface at q.
    const Eigen::Vector3d mn = plane_normal - 2.0 * plane_normal.dot(n) * n;
    Eigen::Vector3d across;
    double sigma_surface = 0.0;
    if (!across_band(mn, b.nq, sigma_b, across, sigma_surface)) continue;
    Eigen::Vector2d qa, qb;
    if (!project(cam, sensor_from_world * b.q, qa) ||
        !project(cam, sensor_from_world * (b.q + sigma_surface * across), qb))
      continue;
    bounced[static_cast<std::size_t>(c)] = {qa.x(), qa.y(), std::max(0.3, std::abs(qb.y() - qa.y())), radiance, true};
  }

  // Resample to the integer image columns between neighbouring samples
  // that continue each other (a jump of more than 4 px is an edge).
  constexpr double kJoin = 4.0;
  for (int c = 0; c + 1 < w; ++c) {
    const Sample& a = samples[static_cast<std::size_t>(c)];
    const Sample& b = samples[static_cast<std::size_t>(c + 1)];
    if (a.seen && b.seen && std::abs(a.col - b.col) <= kJoin && std::abs(a.row - b.row) <= kJoin) {
      const double lo = std::min(a.col, b.col), hi = std::max(a.col, b.col);
      for (int k = static_cast<int>(std::ceil(lo)); k <= static_cast<int>(std::floor(hi)); ++k) {
        if (k < 0 || k >= w) continue;
        const double f = hi > lo ? (k - a.col) / (b.col - a.col) : 0.0;
        out.true_row[static_cast<std::size_t>(k)] = static_cast<float>(a.row + f * (b.row - a.row));
      }
    }
  }
  if (!bounce) return;
  resample_bands(bounced, 3 * kJoin, out.bounce_row, out.bounce_sigma, out.bounce_radiance);

  // The camera-side mirror: the camera sees the lit line of one surface
  // mirrored in another (docs/SENSOR_MODEL.md, "The stripe in a mirror").
  // For a mirror plane S, the image of a lit point P is where the camera
  // sees P' (P mirrored by S), if its ray meets S there first and P lights
  // that point unoccluded.
  const std::vector<MirrorPlane> planes = lit_planes(hit_p, hit_n, lit);
  std::vector<BandSample> mirrored(static_cast<std::size_t>(w));
  const double cos_same = std::cos(2.0 * kDeg);
  struct MirrorRay {
    int c = 0;
    Eigen::Vector3d virt, ray;  // P' and the unit ray to it from the camera
    double virt_dist = 0.0, t_plane = 0.0, leg = 0.0;
  };
  thread_local std::vector<MirrorRay> cand;
  thread_local std::vector<RayScene::Segment> segments;
  thread_local std::vector<RayScene::Hit> hits;
  thread_local std::vector<unsigned char> flags;
  for (const MirrorPlane& plane : planes) {
    const Eigen::Vector3d& ns = plane.normal;
    const double cam_side = ns.dot(cam_world - plane.point);
    if (!(cam_side > 0.0)) continue;  // the camera sees the plane's back
    // Per lit column, the camera's ray to P' (cast 8 at a time, then the
    // rays from the mirror to P for those that meet S first).
    cand.clear();
    segments.clear();
    for (int c = 0; c < w; ++c) {
      mirrored[static_cast<std::size_t>(c)].valid = false;
      if (!lit[static_cast<std::size_t>(c)]) continue;
      const Eigen::Vector3d& p = hit_p[static_cast<std::size_t>(c)];
      const double height = ns.dot(p - plane.point);
      if (height < 0.05) continue;  // on the mirror itself, or behind it
      MirrorRay m;
      m.c = c;
      m.virt = p - 2.0 * height * ns;
      m.ray = m.virt - cam_world;
      m.virt_dist = m.ray.norm();
      m.ray /= m.virt_dist;
      const double denom = m.ray.dot(ns);
      if (!(denom < -1e-6)) continue;
      m.t_plane = -cam_side / denom;
      cand.push_back(m);
      segments.push_back({cam_world.cast<float>(), m.ray.cast<float>(), 0.0f, static_cast<float>(m.t_plane + 1.0)});
    }
    hits.resize(segments.size());
    flags.resize(segments.size());
    scene.intersect(segments.data(), segments.size(), hits.data(), flags.data());
    std::size_t kept = 0;
    segments.clear();
    for (std::size_t i = 0; i < cand.size(); ++i) {
      MirrorRay& m = cand[i];
      const RayScene::Hit& hq = hits[i];
      if (!flags[i]) continue;
      if (std::abs(static_cast<double>(hq.t) - m.t_plane) > 0.05 + 1e-4 * m.t_plane ||
          hq.normal.cast<double>().dot(ns) < cos_same)
        continue;  // something else is seen first, or another surface
      const Eigen::Vector3d& p = hit_p[static_cast<std::size_t>(m.c)];
      const Eigen::Vector3d& np = hit_n[static_cast<std::size_t>(m.c)];
      const Eigen::Vector3d q = cam_world + m.t_plane * m.ray;
      Eigen::Vector3d q_to_p = p - q;
      m.leg = q_to_p.norm();
      q_to_p /= m.leg;
      if (np.dot(-q_to_p) <= 0.0) continue;  // P faces away from the mirror
      segments.push_back({(q + 1e-3 * ns).cast<float>(), q_to_p.cast<float>(), static_cast<float>(kShadowEpsilonMm),
                          static_cast<float>(m.leg - 2.0 * kShadowEpsilonMm)});
      cand[kept++] = m;
    }
    flags.resize(segments.size());
    scene.occluded(segments.data(), segments.size(), flags.data());
    for (std::size_t i = 0; i < kept; ++i) {
      if (flags[i]) continue;
      const MirrorRay& m = cand[i];
      const int c = m.c;
      const Eigen::Vector3d& np = hit_n[static_cast<std::size_t>(c)];
      // The band on P's surface seen through the mirror, its width in the
      // image, widened by the lobe: a reflected direction off by delta
      // shows a point delta * leg away at the virtual distance.
      Eigen::Vector3d across;
      double sigma_surface = 0.0;
      if (!across_band(plane_normal, np, lit_sigma[static_cast<std::size_t>(c)], across, sigma_surface)) continue;
      const Eigen::Vector3d across_virt = across - 2.0 * across.dot(ns) * ns;
      Eigen::Vector2d va, vb;
      if (!project(cam, sensor_from_world * m.virt, va) ||
          !project(cam, sensor_from_world * (m.virt + sigma_surface * across_virt), vb))
        continue;
      const double sigma_img = std::max(0.3, std::abs(vb.y() - va.y()));
      const double sigma_lobe = cam.f_px * lobe * m.leg / m.virt_dist;
      const double sigma = std::hypot(sigma_img, sigma_lobe);
      const double radiance = d.specular_reflectance * lit_irradiance[static_cast<std::size_t>(c)] * d.reflectivity /
                              std::numbers::pi * vignetting(-m.ray) * sigma_img / sigma;
      mirrored[static_cast<std::size_t>(c)] = {va.x(), va.y(), sigma, radiance, true};
    }
    resample_bands(mirrored, 3 * kJoin, out.mirror_row, out.mirror_sigma, out.mirror_radiance);
  }
}

namespace {

// The columns form_image lights at a time: their pixels, row-major, are 16
// floats a row (4 KiB for 64 rows), so a column's rows are one cache line
// apart and the strip stays in L1 from the stripe to the speckle.
constexpr int kStrip = 16;

// form_image's last step per pixel (see there), in memory order. Its own
// function so that it gets the AVX2 and AVX-512 clones (32-bit multiplies,
// packs).
struct SensorConstants {
  std::uint32_t key;
  float k_e, dn_e, read2, offset, noise_scale, max_dn;
};
VTS_SIMD_CLONES void sensor_counts(const SensorConstants& k, std::uint32_t count, const float* __restrict laser,
                                   const float* __restrict ambient, std::uint16_t* __restrict pixels) {
  const std::uint32_t key = k.key;
  const float k_e = k.k_e, dn_e = k.dn_e, read2 = k.read2, offset = k.offset, noise_scale = k.noise_scale,
              max_dn = k.max_dn;
  for (std::uint32_t i = 0; i < count; ++i) {
    std::uint32_t x = key ^ (i * 0x9e3779b9u);  // lowbias32 (Wellons): a full-avalanche 32-bit hash
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    const float z = (static_cast<float>((x & 0xffu) + ((x >> 8) & 0xffu) + ((x >> 16) & 0xffu) + (x >> 24)) - 510.0f) *
                    noise_scale;
    const float e = std::max(0.0f, (laser[i] + ambient[i]) * k_e);
    const float noisy = e + std::sqrt(e + read2) * z;
    pixels[i] = static_cast<std::uint16_t>(std::clamp(noisy * dn_e + offset, 0.0f, max_dn + 0.5f));
  }
}

// The image columns of `paths` that carry a stripe (at most `width`; none
// when its offsets are short).
int stripe_columns(const LaserPaths& paths, int width) {
  const int w = std::min(width, static_cast<int>(paths.stripe_first_row.size()));
  return paths.stripe_offset.size() < static_cast<std::size_t>(w) + 1 ? 0 : w;
}
// Adds column c's stripe to that column's pixels of image rows first_row ..
// first_row + rows - 1, row k at col[k * stride].
void add_stripe_column(const LaserPaths& paths, int c, int first_row, int rows, float* col, std::size_t stride) {
  const int first = paths.stripe_first_row[static_cast<std::size_t>(c)];
  const int begin = paths.stripe_offset[static_cast<std::size_t>(c)];
  for (int k = begin; k < paths.stripe_offset[static_cast<std::size_t>(c) + 1]; ++k) {
    const int row = first + (k - begin) - first_row;
    if (row < 0 || row >= rows) continue;
    col[static_cast<std::size_t>(row) * stride] += paths.stripe_radiance[static_cast<std::size_t>(k)];
  }
}

}  // namespace

void add_stripe(const LaserPaths& paths, RadianceImage& rad) {
  const int w = stripe_columns(paths, rad.width);
  for (int c = 0; c < w; ++c) add_stripe_column(paths, c, rad.first_row, rad.rows, rad.laser.data() + c, rad.width);
}

void form_image(const ScannerDesc& d, RadianceImage& rad, const LaserPaths& paths, std::uint64_t seed,
                std::int64_t index, CameraImage& out) {
  const int w = rad.width, rows = rad.rows, r0 = rad.first_row;
  out.width = w;
  out.rows = rows;
  out.first_row = r0;
  out.bits = d.image_bits;
  out.index = index;
  out.pixels.resize(static_cast<std::size_t>(w) * rows);
  out.true_row = paths.true_row;
  out.bounce_row = paths.bounce_row;
  out.mirror_row = paths.mirror_row;

  // The laser light a strip of kStrip columns at a time (steps 0-2 below,
  // column by column; each pixel gets the same sums in the same order as
  // passes over the whole image would give), then the counts (3).
  // The image's laser light is written, not read, in rad.laser (scratch).
  thread_local std::vector<float> strip;
  strip.resize(static_cast<std::size_t>(kStrip) * rows);
  std::vector<float>& laser = rad.laser;
  laser.resize(static_cast<std::size_t>(w) * rows);
  const int stripe_w = stripe_columns(paths, w);

  // 1. The bounce and the mirror image: a Gaussian band per column,
  // integrated over each pixel. The lens blur widens a band as it widens
  // the stripe (the stripe's blur is in its profile) and keeps its energy.
  int touched_lo = 0, touched_hi = -1;  // the strip column's rows steps 0 and 1 wrote (the rest are 0)
  const auto splat = [&](int c, const std::vector<float>& rows_of, const std::vector<float>& sigma_of,
                         const std::vector<float>& radiance_of, float* col) {
    if (c >= static_cast<int>(rows_of.size())) return;
    const float row = rows_of[static_cast<std::size_t>(c)];
    if (!std::isfinite(row)) return;
    const double band = sigma_of[static_cast<std::size_t>(c)];
    const double sigma = std::hypot(band, d.psf_sigma_px);
    const double area = radiance_of[static_cast<std::size_t>(c)] * band * std::sqrt(2.0 * std::numbers::pi);
    const int lo = std::max(r0, static_cast<int>(std::floor(row - 5.0 * sigma)));
    const int hi = std::min(r0 + rows - 1, static_cast<int>(std::ceil(row + 5.0 * sigma)));
    if (lo > hi) return;
    touched_lo = std::min(touched_lo, lo - r0);
    touched_hi = std::max(touched_hi, hi - r0);
    thread_local std::vector<float> shares;
    shares.assign(static_cast<std::size_t>(hi - lo + 1), 0.0f);
    add_pixel_shares(lo, hi, row, sigma, area, shares.data());
    for (int r = lo; r <= hi; ++r) col[static_cast<std::size_t>(r - r0) * kStrip] += shares[static_cast<std::size_t>(r - lo)];
  };

  // 2. Speckle: per column a brightness factor (log-normal, mean 1, std dev
  // speckle_contrast) and a shift of the stripe (normal, std dev
  // speckle_px), each correlated over the speckle grain 2.44 lambda N / pitch.
  const Draws draws(seed, index, 1);
  thread_local std::vector<float> amp, shift, white;
  amp.clear();
  shift.clear();
  const bool speckle = d.speckle_contrast > 0.0 || d.speckle_px > 0.0;
  if (speckle) {
    const double grain = 2.44 * d.wavelength_nm * 1e-3 * d.f_number / d.pixel_pitch_um;
    correlated_normals(draws, 1, w, grain, amp, white);
    correlated_normals(draws, 2, w, grain, shift, white);
    const double s = std::sqrt(std::log1p(d.speckle_contrast * d.speckle_contrast));
    for (float& a : amp) a = static_cast<float>(std::exp(s * a - 0.5 * s * s));
    for (float& x : shift) x = static_cast<float>(x * d.speckle_px);
  }
  float max_shift = 0.0f;
  for (float x : shift) max_shift = std::max(max_shift, std::abs(x));
  const int pad = static_cast<int>(std::ceil(max_shift)) + 2;
  std::vector<float>& column = scratch_column();

  // 3. Electrons, shot and read noise, gain, black level, saturation.
  // Shot noise (variance e) and read noise (variance read^2) are
  // independent, so their sum is one normal draw of variance e + read^2
  // per pixel: the sum of the four bytes of a 32-bit hash of the pixel's
  // number (Irwin-Hall, mean 510, std dev 147.8; within 0.01 of the
  // normal's distribution function, tails cut at 3.45 sigma). The loop
  // vectorizes (sensor_counts).
  const SensorConstants sensor{
      static_cast<std::uint32_t>(mix(mix(seed ^ 0x5ca1ab1eull) ^ static_cast<std::uint64_t>(index))),
      static_cast<float>(electrons_per_radiance(d)),
      static_cast<float>(dn_per_electron(d)),
      static_cast<float>(d.read_noise_e * d.read_noise_e),
      static_cast<float>(d.dark_offset_dn) + 0.5f,  // + 0.5: rounds when truncated
      d.image_noise ? 1.0f / 147.8f : 0.0f,
      static_cast<float>(std::ldexp(1.0, d.image_bits) - 1.0)};

  for (int c0 = 0; c0 < w; c0 += kStrip) {
    const int nc = std::min(kStrip, w - c0);
    std::fill(strip.begin(), strip.end(), 0.0f);
    for (int j = 0; j < nc; ++j) {
      const int c = c0 + j;
      float* col = strip.data() + j;  // row k at col[k * kStrip]
      touched_lo = rows;
      touched_hi = -1;
      if (c < stripe_w) {  // 0. the stripe (trace_laser_paths)
        add_stripe_column(paths, c, r0, rows, col, kStrip);
        const int first = paths.stripe_first_row[static_cast<std::size_t>(c)] - r0;
        const int count = paths.stripe_offset[static_cast<std::size_t>(c) + 1] - paths.stripe_offset[static_cast<std::size_t>(c)];
        if (count > 0) {
          touched_lo = std::max(0, first);
          touched_hi = std::min(rows - 1, first + count - 1);
        }
      }
      splat(c, paths.bounce_row, paths.bounce_sigma, paths.bounce_radiance, col);
      splat(c, paths.mirror_row, paths.mirror_sigma, paths.mirror_radiance, col);
      if (!speckle) continue;
      // Speckle touches only the rows around the laser light of the column
      // (searched among the rows written).
      int lo = rows, hi = -1;
      for (int k = touched_lo; k <= touched_hi; ++k)
        if (col[static_cast<std::size_t>(k) * kStrip] > 0.0f) {
          lo = std::min(lo, k);
          hi = k;
        }
      if (hi < 0) continue;
      const int first = std::max(0, lo - pad);
      const int last = std::min(rows - 1, hi + pad);
      const int m = last - first + 1;
      // Shift by linear interpolation (keeps the centroid's shift exact);
      // rows from outside first .. last count as 0 (the copy's zero margin
      // of `edge` rows either way).
      const double sh = shift[static_cast<std::size_t>(c)];
      const double a = amp[static_cast<std::size_t>(c)];
      const int whole = static_cast<int>(std::floor(sh));
      const double f = sh - whole;
      const int edge = std::abs(whole) + 1;
      column.assign(static_cast<std::size_t>(m + 2 * edge), 0.0f);
      for (int k = 0; k < m; ++k) column[static_cast<std::size_t>(edge + k)] = col[static_cast<std::size_t>(first + k) * kStrip];
      const float* src = column.data() + edge - whole;
      for (int k = 0; k < m; ++k)
        col[static_cast<std::size_t>(first + k) * kStrip] = static_cast<float>(a * ((1.0 - f) * src[k] + f * src[k - 1]));
    }
    for (int k = 0; k < rows; ++k) {
      const float* from = strip.data() + static_cast<std::size_t>(k) * kStrip;
      float* to = laser.data() + static_cast<std::size_t>(k) * w + c0;
      if (nc == kStrip) std::memcpy(to, from, sizeof(float) * kStrip);  // (a fixed size: inlined)
      else std::copy_n(from, nc, to);
    }
  }
  sensor_counts(sensor, static_cast<std::uint32_t>(static_cast<std::size_t>(w) * rows), laser.data(), rad.ambient.data(),
                out.pixels.data());
}

stripe::PeakParams peak_params(const ScannerDesc& d) {
  stripe::PeakParams p;
  p.threshold_dn = d.peak_threshold_dn;
  p.window_px = d.peak_window_px;
  const auto method = stripe::parse_sub_pixel(d.peak_method);
  if (!method)
    throw std::invalid_argument("peak_method = '" + d.peak_method + "': must be one of " + stripe::sub_pixel_names());
  const auto policy = stripe::parse_peak_policy(d.peak_policy);
  if (!policy)
    throw std::invalid_argument("peak_policy = '" + d.peak_policy + "': must be one of " +
                                stripe::peak_policy_names());
  p.method = *method;
  p.policy = *policy;
  return p;
}

void detect_stripe(const ScannerDesc& d, CameraImage& image, stripe::PeakResult& peaks) {
  const stripe::ImageView view{image.pixels.data(), image.width, image.rows, image.width, image.bits};
  stripe::detect_peaks(view, peak_params(d), peaks);
  image.true_peak.assign(static_cast<std::size_t>(image.width), -1);
  image.chosen_peak.assign(static_cast<std::size_t>(image.width), -1);
  image.chosen_row.assign(static_cast<std::size_t>(image.width), kNaN);
  image.peak_count.assign(static_cast<std::size_t>(image.width), 0);
  for (int c = 0; c < image.width; ++c) {
    const int first = peaks.column_offset[static_cast<std::size_t>(c)];
    image.peak_count[static_cast<std::size_t>(c)] = peaks.count(c);
    if (const stripe::Peak* chosen = peaks.chosen_peak(c)) {
      image.chosen_peak[static_cast<std::size_t>(c)] = peaks.chosen[static_cast<std::size_t>(c)] - first;
      image.chosen_row[static_cast<std::size_t>(c)] = chosen->row + static_cast<float>(image.first_row);
    }
    const float truth = c < static_cast<int>(image.true_row.size()) ? image.true_row[static_cast<std::size_t>(c)] : kNaN;
    if (!std::isfinite(truth)) continue;
    double best = std::numeric_limits<double>::infinity();
    for (int k = first; k < peaks.column_offset[static_cast<std::size_t>(c) + 1]; ++k) {
      const stripe::Peak& pk = peaks.peaks[static_cast<std::size_t>(k)];
      const double off = std::abs(pk.row + image.first_row - truth);
      if (off <= std::max(1.5, 0.5 * pk.width_px) && off < best) {
        best = off;
        image.true_peak[static_cast<std::size_t>(c)] = k - first;
      }
    }
  }
}

void profile_from_peaks(const ScannerDesc& d, const CameraImage& image, const stripe::PeakResult& peaks,
                        const Profile& ideal, Profile& out) {
  const int n = d.points;
  if (!out.sized(n)) out.resize(n);
  out.world_from_sensor = ideal.world_from_sensor;
  out.time_s = ideal.time_s;
  out.index = ideal.index;
  const CameraGeometry cam = camera_geometry(d);
  const double full_scale = std::ldexp(1.0, image.bits) - 1.0;
  const double step = d.subpixel_step_px;
  const int roi_first = std::max(0, d.roi_first_column), roi_last = std::min(n - 1, d.roi_last_column);
  // The chosen peak's row of an image column (image frame), or NaN.
  auto row_of = [&](int c) -> double {
    if (c < 0 || c >= image.width) return std::numeric_limits<double>::quiet_NaN();
    const stripe::Peak* p = peaks.chosen_peak(c);
    return p ? p->row + image.first_row : std::numeric_limits<double>::quiet_NaN();
  };
  auto value_of = [&](int c) -> double {
    const stripe::Peak* p = c >= 0 && c < image.width ? peaks.chosen_peak(c) : nullptr;
    return p ? p->peak_dn : 0.0;
  };
  for (int i = 0; i < n; ++i) {
    const bool ideal_ok = ideal.size() == n && ideal.valid[static_cast<std::size_t>(i)];
    out.true_valid[static_cast<std::size_t>(i)] = ideal_ok ? 1 : 0;
    out.true_y_mm[static_cast<std::size_t>(i)] = ideal_ok ? ideal.y_mm[static_cast<std::size_t>(i)] : 0.0f;
    out.true_z_mm[static_cast<std::size_t>(i)] = ideal_ok ? ideal.z_mm[static_cast<std::size_t>(i)] : 0.0f;
    out.cos_incidence[static_cast<std::size_t>(i)] = ideal.size() == n ? ideal.cos_incidence[static_cast<std::size_t>(i)] : 0.0f;
    out.camera_visible[static_cast<std::size_t>(i)] = ideal.size() == n ? ideal.camera_visible[static_cast<std::size_t>(i)] : 0;
    out.valid[static_cast<std::size_t>(i)] = 0;
    out.y_mm[static_cast<std::size_t>(i)] = out.z_mm[static_cast<std::size_t>(i)] = out.range_mm[static_cast<std::size_t>(i)] = 0.0f;
    out.intensity[static_cast<std::size_t>(i)] = 0.0f;
    if (i < roi_first || i > roi_last) continue;
    const double t = column_tan(d, i);
    double z = ideal_ok ? ideal.z_mm[static_cast<std::size_t>(i)] : 0.5 * (d.min_range_mm + d.max_range_mm);
    bool ok = false;
    double col = 0.0, value = 0.0;
    Eigen::Vector2d yz;
    for (int iter = 0; iter < 4; ++iter) {
      Eigen::Vector2d cr;
      if (!project(cam, Eigen::Vector3d(0.0, z * t, z), cr)) break;
      col = cr.x();
      const int c0 = static_cast<int>(std::floor(col));
      const double f = col - c0;
      const double r0 = row_of(c0), r1 = row_of(c0 + 1);
      double row;
      if (std::isfinite(r0) && std::isfinite(r1) && std::abs(r1 - r0) <= 2.0) {
        row = r0 + f * (r1 - r0);
        value = std::max(value_of(c0), value_of(c0 + 1));
      } else {
        const int near = f < 0.5 ? c0 : c0 + 1;
        row = row_of(near);
        value = value_of(near);
      }
      if (!std::isfinite(row)) break;
      if (step > 0.0) row = std::round(row / step) * step;
      if (!triangulate(cam, col, row, yz) || !(yz.y() > 0.0)) break;
      const double dz = std::abs(yz.y() - z);
      z = yz.y();
      ok = true;
      if (dz < 1e-6) break;
    }
    if (!ok) continue;
    if (col < -0.5 || col > image.width - 0.5) continue;
    const double range = yz.norm();
    if (z < d.min_range_mm || z > d.max_range_mm || range > d.max_hit_mm) continue;
    out.valid[static_cast<std::size_t>(i)] = 1;
    out.y_mm[static_cast<std::size_t>(i)] = static_cast<float>(yz.x());
    out.z_mm[static_cast<std::size_t>(i)] = static_cast<float>(z);
    out.range_mm[static_cast<std::size_t>(i)] = static_cast<float>(range);
    out.intensity[static_cast<std::size_t>(i)] = static_cast<float>(std::min(1.0, value / full_scale));
  }
}

}  // namespace vts
