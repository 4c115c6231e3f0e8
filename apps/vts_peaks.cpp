#include "apps/vts_peaks.h"

#include <cstdio>
#include <cstring>
#include <optional>
#include <sstream>
#include <utility>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "sensor/camera_image.h"
#include "sensor/image_io.h"
#include "sensor/presets.h"
#include "sensor/profile_csv.h"
#include "sensor/stripe_profile.h"
#include "stripe/peaks.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;

struct PeaksOptions {
  std::string input, out, profile, sensor, row_offset;
  std::string threshold, threshold_rel, method, policy, window, min_width, min_separation, saturation, rows,
      max_jump, jump_cost, miss_cost, brightness_weight, bits;
};

// stripe::validate's message "FIELD = VALUE: why" with the option in place of the field.
std::string with_option_name(const std::string& message) {
  static const std::pair<const char*, const char*> names[] = {
      {"threshold_dn", "--threshold"},  {"threshold_rel", "--threshold-rel"}, {"window_px", "--window"},
      {"min_width_px", "--min-width"},  {"saturation_dn", "--saturation"},    {"min_separation_px", "--min-separation"},
      {"row_first", "--rows FIRST"},    {"row_last", "--rows LAST"},          {"max_jump_px", "--max-jump"},
      {"jump_cost", "--jump-cost"},     {"miss_cost", "--miss-cost"},         {"brightness_weight", "--brightness-weight"}};
  for (const auto& [field, option] : names)
    if (message.rfind(std::string(field) + " = ", 0) == 0) return option + message.substr(std::strlen(field));
  return message;
}

int run_peaks(const PeaksOptions& o) {
  // Everything is checked before anything is written.
  std::optional<ScannerDesc> sensor;
  if (!o.sensor.empty()) {
    sensor = sensor_preset(o.sensor);
    if (!sensor)
      cli::bad("--sensor", o.sensor,
               "unknown sensor; valid names: " + join_names(sensor_preset_names()) + " (see `vts sensors`)");
  }
  // The detector: the preset's (its peak_* fields, as `vts scan --camera-image`
  // runs it) with --sensor, else the detector's own defaults; each option
  // below overrides.
  stripe::PeakParams params = sensor ? peak_params(*sensor) : stripe::PeakParams{};
  if (!o.threshold.empty()) params.threshold_dn = cli::parse_positive("--threshold", o.threshold, "DN");
  if (!o.threshold_rel.empty()) params.threshold_rel = cli::parse_number("--threshold-rel", o.threshold_rel, "");
  if (!o.method.empty()) {
    const auto m = stripe::parse_sub_pixel(o.method);
    if (!m) cli::bad("--method", o.method, "expected one of " + stripe::sub_pixel_names());
    params.method = *m;
  }
  if (!o.policy.empty()) {
    const auto p = stripe::parse_peak_policy(o.policy);
    if (!p) cli::bad("--policy", o.policy, "expected one of " + stripe::peak_policy_names());
    params.policy = *p;
  }
  if (!o.window.empty()) params.window_px = static_cast<int>(cli::parse_integer("--window", o.window, 1, 32));
  if (!o.min_width.empty())
    params.min_width_px = static_cast<int>(cli::parse_integer("--min-width", o.min_width, 1, 1 << 20));
  if (!o.min_separation.empty())
    params.min_separation_px = cli::parse_number("--min-separation", o.min_separation, "px");
  if (!o.saturation.empty()) params.saturation_dn = cli::parse_positive("--saturation", o.saturation, "DN");
  if (!o.rows.empty()) {
    const auto colon = o.rows.find(':');
    if (colon == std::string::npos) cli::bad("--rows", o.rows, "expected FIRST:LAST (image rows, 0-based)");
    params.row_first = static_cast<int>(cli::parse_integer("--rows", o.rows.substr(0, colon), 0, 1 << 20));
    params.row_last = static_cast<int>(cli::parse_integer("--rows", o.rows.substr(colon + 1), 0, 1 << 20));
  }
  if (!o.max_jump.empty()) params.max_jump_px = cli::parse_number("--max-jump", o.max_jump, "px");
  if (!o.jump_cost.empty()) params.jump_cost = cli::parse_number("--jump-cost", o.jump_cost, "");
  if (!o.miss_cost.empty()) params.miss_cost = cli::parse_number("--miss-cost", o.miss_cost, "");
  if (!o.brightness_weight.empty())
    params.brightness_weight = cli::parse_number("--brightness-weight", o.brightness_weight, "");
  int bits = 0;
  if (!o.bits.empty()) {
    bits = static_cast<int>(cli::parse_integer("--bits", o.bits, 8, 16));
    if (bits != 8 && bits != 10 && bits != 12 && bits != 16) cli::bad("--bits", o.bits, "expected 8, 10, 12 or 16");
  }
  if (!o.profile.empty() && !sensor) cli::bad("--profile", o.profile, "needs --sensor PRESET (the camera model)");
  if (!o.row_offset.empty() && !sensor) cli::bad("--row-offset", o.row_offset, "needs --sensor PRESET");
  const int row_offset =
      o.row_offset.empty() ? 0 : static_cast<int>(cli::parse_integer("--row-offset", o.row_offset, 0, 1 << 20));
  const std::string out =
      o.out.empty() ? fs::path(o.input).filename().replace_extension(".peaks.csv").string() : o.out;
  cli::check_output_file("--out", out);
  const std::string profile_out =
      o.profile.empty() && sensor ? fs::path(o.input).filename().replace_extension(".profile.csv").string()
                                  : o.profile;
  if (sensor) cli::check_output_file("--profile", profile_out);

  GreyImage img;
  try {
    img = read_grey_image(o.input);
  } catch (const ImageError& e) {
    throw cli::UsageError(e.what());
  }
  if (bits) {
    for (std::uint16_t v : img.pixels)
      if (v > stripe::full_scale_dn(bits))
        cli::bad("--bits", o.bits, o.input + " has values up to " + std::to_string(v) + " DN, above the full scale " +
                                       std::to_string(stripe::full_scale_dn(bits)));
    img.bits = bits;
  }
  try {
    stripe::validate(params, img.bits, img.height);
  } catch (const std::invalid_argument& e) {
    throw cli::UsageError(o.input + " (" + std::to_string(img.width) + "x" + std::to_string(img.height) + ", " +
                          std::to_string(img.bits) + "-bit): " + with_option_name(e.what()));
  }
  Profile profile;
  stripe::PeakResult peaks;
  stripe::detect_peaks({img.pixels.data(), img.width, img.height, img.width, img.bits}, params, peaks);
  if (sensor) {
    try {
      peaks_to_profile(*sensor, peaks, img.height, img.bits, row_offset, profile);
    } catch (const std::invalid_argument& e) {
      cli::bad("--sensor", o.sensor, o.input + ": " + e.what());
    }
  }

  std::ostringstream csv;
  write_peaks_csv(csv, peaks);
  cli::write_text_file(out, csv.str());  // std::runtime_error naming the file: exit 1
  int found = 0;
  for (int c = 0; c < peaks.width(); ++c) found += peaks.chosen[c] >= 0;
  if (!img.note.empty()) std::printf("%s: %s\n", o.input.c_str(), img.note.c_str());
  std::printf("%s (%dx%d, %d-bit): %zu peaks, one chosen (%s) in %d of %d columns; wrote %s\n", o.input.c_str(),
              img.width, img.height, img.bits, peaks.peaks.size(), std::string(stripe::to_string(params.policy)).c_str(),
              found, img.width, out.c_str());
  if (sensor) {
    std::ostringstream profile_csv;
    write_profile_csv(profile_csv, {profile});
    cli::write_text_file(profile_out, profile_csv.str());
    std::printf("profile through %s's camera: %d valid points; wrote %s\n", o.sensor.c_str(), profile.valid_count(),
                profile_out.c_str());
  }
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_peaks_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<PeaksOptions>();
  CLI::App* cmd = app.add_subcommand(
      "peaks",
      "Find the laser stripe's peak in every column of a greyscale camera image (8- or 16-bit PNG, TIFF, EXR; the "
      "stripe along the rows) as sensor firmware does; write the peaks as CSV and, with --sensor, the profile "
      "(docs/PEAKS.md)");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("image", o->input, "Greyscale image, the stripe running along the rows")
      ->required()
      ->type_name("IMAGE");
  cmd->add_option("--out", o->out,
                  "Peaks CSV to write (default: IMAGE's name with .peaks.csv, in the working directory); written "
                  "whole or not at all")
      ->type_name("FILE.csv");
  cmd->add_option("--threshold", o->threshold, "Lit above this many DN (default: the --sensor preset's, else full scale / 16)")->type_name("DN");
  cmd->add_option("--threshold-rel", o->threshold_rel,
                  "Lit above this fraction of the column's maximum too, 0..1 (default 0)")
      ->type_name("F");
  cmd->add_option("--method", o->method, "Sub-pixel position: cog, gaussian or parabolic (default: the --sensor preset's, cog; else gaussian)")
      ->type_name("NAME");
  cmd->add_option("--policy", o->policy,
                  "Peak chosen per column: strongest, first, last, widest or continuous (default: the --sensor preset's, continuous; else strongest)")
      ->type_name("NAME");
  cmd->add_option("--window", o->window, "Half width of the sub-pixel window, rows, 1..32 (default: the --sensor preset's, 4; else 3)")
      ->type_name("N");
  cmd->add_option("--min-width", o->min_width, "Fewest lit rows of a peak (default 1)")->type_name("N");
  cmd->add_option("--min-separation", o->min_separation,
                  "Maxima closer than this are one peak, rows (default 3)")
      ->type_name("PX");
  cmd->add_option("--saturation", o->saturation, "Saturated at or above this (default: full scale)")
      ->type_name("DN");
  cmd->add_option("--rows", o->rows, "Search only image rows FIRST..LAST (default: all)")->type_name("FIRST:LAST");
  cmd->add_option("--max-jump", o->max_jump, "continuous: free row change between columns (default 4)")
      ->type_name("PX");
  cmd->add_option("--jump-cost", o->jump_cost, "continuous: cost per row beyond --max-jump (default 0.5)")
      ->type_name("C");
  cmd->add_option("--miss-cost", o->miss_cost, "continuous: cost of a column left without its peaks (default 1)")
      ->type_name("C");
  cmd->add_option("--brightness-weight", o->brightness_weight,
                  "continuous: a chosen peak scores 1 + this x its value over full scale (default 0.1)")
      ->type_name("W");
  cmd->add_option("--bits", o->bits, "The image's depth, 8, 10, 12 or 16, when the file does not say it")
      ->type_name("N");
  cmd->add_option("--sensor", o->sensor,
                  "Triangulate the chosen peaks through this preset's camera (`vts sensors`) to a profile")
      ->type_name("PRESET");
  cmd->add_option("--profile", o->profile,
                  "Profile CSV to write with --sensor, as vts track reads it (default: IMAGE's name with "
                  ".profile.csv)")
      ->type_name("FILE.csv");
  cmd->add_option("--row-offset", o->row_offset,
                  "With --sensor: the camera row of the image's first row, for a region of interest (default 0)")
      ->type_name("ROW");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_peaks(*o);
    } catch (const cli::UsageError& e) {
      std::cerr << "vts peaks: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const std::runtime_error& e) {
      std::cerr << "vts peaks: " << e.what() << "\n";
      exit_code = cli::kExitRuntime;
    }
  });
  return cmd;
}

}  // namespace vts::apps
