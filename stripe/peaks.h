#pragma once
// Laser-stripe peak detection as a triangulation sensor's firmware does it
// (docs/PEAKS.md): per image column, threshold, split into runs of rows above
// the threshold, a sub-pixel position by centre of gravity or a Gaussian or
// parabolic fit over a window around the maximum (a plateau rule for
// saturated runs), the width at half maximum and the strength; then one peak
// per column chosen by a policy, `continuous` by dynamic programming over the
// columns. Pure C++20: no GL, no files, no other vts library.
//
// Image frame: row-major, the laser stripe runs along the rows, so each
// column holds the stripe at some row. Row r's pixel covers rows
// [r - 0.5, r + 0.5): a peak exactly on row r's centre has row == r.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vts::stripe {

// A greyscale image the detector reads; it does not own the pixels.
struct ImageView {
  const std::uint16_t* data = nullptr;  // row-major, pixel (row, col) at data[row * stride + col]
  int width = 0;                        // columns (>= 1)
  int height = 0;                       // rows (>= 1)
  std::ptrdiff_t stride = 0;            // elements per row, >= width
  int bits = 16;                        // 8, 10, 12 or 16; 8-bit images are passed widened to uint16
};

// Full scale of an image of `bits` bits: 2^bits - 1 DN.
constexpr int full_scale_dn(int bits) { return (1 << bits) - 1; }

// Sub-pixel position of an unsaturated peak, over the window of rows
// [m - window_px, m + window_px] around the run's maximum m (clipped to the
// rows searched and short of the neighbouring peaks' lit rows):
enum class SubPixel {
  centre_of_gravity,  // "cog": sum of row * (value - threshold) / sum of (value - threshold)
  gaussian,           // "gaussian": parabola least-squares fitted to ln(value), weights value^2
  parabolic,          // "parabolic": parabola least-squares fitted to value
};

// Which peak a column reports when it has several:
enum class PeakPolicy {
  strongest,   // "strongest": highest peak_dn; ties (e.g. two saturated peaks) by strength
  first,       // "first": lowest row
  last,        // "last": highest row
  widest,      // "widest": largest width_px; ties by strength
  continuous,  // "continuous": the chain across columns of best total (docs/PEAKS.md "continuous")
};

// Names as above ("cog", "gaussian", "parabolic"; "strongest", "first", "last",
// "widest", "continuous"); parse returns nullopt for any other text.
std::string_view to_string(SubPixel m);
std::string_view to_string(PeakPolicy p);
std::optional<SubPixel> parse_sub_pixel(std::string_view name);
std::optional<PeakPolicy> parse_peak_policy(std::string_view name);
// "cog, gaussian, parabolic" and "strongest, first, last, widest, continuous".
std::string sub_pixel_names();
std::string peak_policy_names();

// The detector's settings; every field has the default a sensor would ship
// with. validate() checks them against an image's depth and height.
struct PeakParams {
  // A pixel is lit when its value exceeds the column's threshold
  // max(threshold_dn, threshold_rel * column maximum). threshold_dn 0 selects
  // full scale / 16 (15.9 DN at 8 bits, 4096 DN at 16); otherwise
  // 0 < threshold_dn < full scale. threshold_rel in [0, 1).
  double threshold_dn = 0.0;
  double threshold_rel = 0.0;
  int window_px = 3;  // half width of the sub-pixel window, 1..32 rows
  SubPixel method = SubPixel::gaussian;
  PeakPolicy policy = PeakPolicy::strongest;
  int min_width_px = 1;  // runs spanning fewer rows (first to last lit row, after merging) are dropped; 1..height
  // Values >= saturation_dn are saturated (plateau rule, docs/PEAKS.md).
  // 0 selects full scale; otherwise threshold < saturation_dn <= full scale.
  double saturation_dn = 0.0;
  // Two runs whose maxima are fewer than this many rows apart are one peak;
  // >= 0 (0: never merge).
  double min_separation_px = 3.0;
  // Rows searched: [row_first, row_last]; row_last -1 means the last row.
  int row_first = 0;
  int row_last = -1;
  // `continuous` only (docs/PEAKS.md): continuity first, brightness second.
  // A chosen peak scores 1 + brightness_weight * peak_dn / full scale; a
  // row change of up to max_jump_px from the previous chosen peak (across
  // columns left without one too) is free, each row beyond costs jump_cost;
  // a column left without a chosen peak although it has peaks costs
  // miss_cost. All >= 0.
  double max_jump_px = 4.0;
  double jump_cost = 0.5;
  double miss_cost = 1.0;
  double brightness_weight = 0.1;
};

// Throws std::invalid_argument naming the field and its value, e.g.
// "window_px = 0: must be 1..32", when a field is out of range for an image
// of `bits` bits and `height` rows (or bits is not 8, 10, 12 or 16).
void validate(const PeakParams& params, int bits, int height);

// One peak of one column.
struct Peak {
  float row = 0.0f;       // sub-pixel row, image frame (row r's centre is r)
  float width_px = 0.0f;  // full width at half of peak_dn, rows (linear interpolation between pixels)
  float peak_dn = 0.0f;   // highest value of the run, DN
  float strength = 0.0f;  // integrated intensity: sum over the run's rows of (value - threshold), DN px
  int first_row = 0;      // first and last lit row of the (merged) run
  int last_row = 0;
  bool saturated = false;  // peak_dn >= saturation: position by the plateau rule
};

// Every peak of every column and the one chosen per column. Reused across
// frames: once it has held a frame of this size with as many peaks, detect_peaks
// allocates nothing.
struct PeakResult {
  std::vector<Peak> peaks;          // column by column, by row within a column
  std::vector<int> column_offset;   // width + 1: column c's peaks are [offset[c], offset[c + 1])
  std::vector<int> chosen;          // width: index into peaks, -1 when the column has none chosen
  std::vector<float> threshold_dn;  // width: the threshold applied to each column

  int width() const { return static_cast<int>(chosen.size()); }
  int count(int column) const { return column_offset[column + 1] - column_offset[column]; }
  const Peak* chosen_peak(int column) const { return chosen[column] < 0 ? nullptr : &peaks[chosen[column]]; }

  // Working memory of detect_peaks, not part of the result.
  std::vector<std::uint16_t> strip_;  // a strip of columns, transposed
  std::vector<double> score_, none_score_;
  std::vector<int> back_, none_back_;
  std::vector<float> none_row_;  // the row of the last chosen peak on "none"'s best path (NaN: none yet)
};

// Detects the peaks of every column of `image` into `out` (replacing its
// content). Throws std::invalid_argument for an invalid image view or
// parameters (validate()).
void detect_peaks(const ImageView& image, const PeakParams& params, PeakResult& out);

}  // namespace vts::stripe
