#include "apps/vts_sensors.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "plot/plot.h"
#include "sensor/error_model.h"
#include "sensor/presets.h"
#include "sensor/rays.h"

namespace vts::apps {
namespace {

struct SensorsOptions {
  std::string plot;     // PNG to write
  std::string sensor;   // preset to plot
};

void list() {
  std::printf("Sensor presets (vts scan --sensor NAME; scene file scanner.preset):\n\n");
  std::printf("%-15s %6s %8s %13s %21s %21s\n", "name", "points", "rate Hz", "range mm",
              "depth step near/far", "lateral near/far");
  for (const std::string& name : sensor_preset_names()) {
    const ScannerDesc d = *sensor_preset(name);
    char range[32], step[40], lateral[40];
    std::snprintf(range, sizeof range, "%g..%g", d.min_range_mm, d.max_range_mm);
    std::snprintf(step, sizeof step, "%.4f / %.4f mm", depth_step_mm(d, d.min_range_mm),
                  depth_step_mm(d, d.max_range_mm));
    std::snprintf(lateral, sizeof lateral, "%.4f / %.4f mm", lateral_spacing_mm(d, d.min_range_mm),
                  lateral_spacing_mm(d, d.max_range_mm));
    std::printf("%-15s %6d %8g %13s %21s %21s\n", name.c_str(), d.points, d.rate_hz, range, step,
                lateral);
    std::printf("  %s\n", sensor_preset_description(name).c_str());
  }
  const ScannerDesc m = *sensor_preset(kDefaultSensor);
  std::printf("\nmspot at the paper's ranges: depth step %.4f mm at 100 mm, %.4f mm at 300 mm, "
              "%.4f mm at 1000 mm\n",
              depth_step_mm(m, 100.0), depth_step_mm(m, 300.0), depth_step_mm(m, 1000.0));
  std::printf("\nMaterials (vts scan --material NAME; scene file scanner.material):\n\n");
  for (const std::string& name : material_names())
    std::printf("%-12s %s\n", name.c_str(), material_description(name).c_str());
}

// Measured on the model itself: a flat plate square to the axis at range z,
// speckle and quantization only, 20 profiles; returns the standard deviation
// of measured - true depth.
double measured_noise_mm(ScannerDesc d, double z) {
  d.shiny_cluster_prob = d.rough_outlier_prob = 0.0;
  d.dropout_prob_normal = d.dropout_prob_grazing = 0.0;
  d.roi_first_column = 0;
  d.roi_last_column = d.points - 1;
  Profile ideal;
  ideal.resize(d.points);
  for (int i = 0; i < d.points; ++i) {
    const double t = column_tan(d, i);
    ideal.valid[i] = ideal.camera_visible[i] = 1;
    ideal.z_mm[i] = static_cast<float>(z);
    ideal.y_mm[i] = static_cast<float>(t * z);
    ideal.range_mm[i] = static_cast<float>(z * std::sqrt(1.0 + t * t));
    ideal.cos_incidence[i] = static_cast<float>(1.0 / std::sqrt(1.0 + t * t));
  }
  ScanState state;
  state.seed = 1;
  Profile m;
  double s = 0, s2 = 0;
  int n = 0;
  for (int k = 0; k < 20; ++k) {
    ideal.index = k;
    apply_error_model(d, ideal, state, m);
    for (int i = 0; i < m.size(); ++i) {
      if (!m.valid[i]) continue;
      const double e = double(m.z_mm[i]) - z;
      s += e;
      s2 += e * e;
      ++n;
    }
  }
  if (n < 2) return 0.0;
  const double mean = s / n;
  return std::sqrt(std::max(0.0, s2 / n - mean * mean));
}

int plot(const SensorsOptions& o) {
  const std::string name = o.sensor.empty() ? std::string(kDefaultSensor) : o.sensor;
  const auto preset = sensor_preset(name);
  if (!preset) {
    std::cerr << "vts sensors: --sensor '" << name << "': unknown sensor; valid names: "
              << join_names(sensor_preset_names()) << "\n";
    return 2;
  }
  const ScannerDesc& d = *preset;
  const double z0 = d.min_range_mm, z1 = d.max_range_mm;
  std::vector<double> z, step, noise, lateral;
  for (int k = 0; k <= 200; ++k) {
    const double r = z0 + (z1 - z0) * k / 200.0;
    z.push_back(r);
    step.push_back(depth_step_mm(d, r));
    const double sigma_px = std::sqrt(d.speckle_px * d.speckle_px +
                                      d.subpixel_step_px * d.subpixel_step_px / 12.0);
    noise.push_back(depth_step_mm(d, r) * sigma_px / d.subpixel_step_px);
    lateral.push_back(lateral_spacing_mm(d, r));
  }
  const double ymax = std::max({*std::max_element(step.begin(), step.end()),
                                *std::max_element(noise.begin(), noise.end()),
                                *std::max_element(lateral.begin(), lateral.end())});
  plot::Canvas canvas(1000, 720);
  plot::Chart chart(canvas, 90, 60, 970, 610, 0.0, z1 * 1.15, 0.0, ymax * 1.05);
  chart.frame("vts sensors --plot: " + name + " (" + d.material + ") resolution against range",
              "range z [mm]", "depth step, noise, spacing [mm]");
  const plot::Rgb blue{30, 90, 200}, orange{230, 120, 20}, green{40, 150, 60}, black{0, 0, 0};
  chart.polyline(z, step, blue, 2);
  chart.polyline(z, noise, orange, 2);
  chart.polyline(z, lateral, green, 2);
  // Measured: the error model run on a flat plate at ten ranges.
  for (int k = 0; k <= 9; ++k) {
    const double r = z0 + (z1 - z0) * (k + 0.5) / 10.0;
    chart.marker(r, measured_noise_mm(d, r), orange, "", 4.0);
  }
  if (name == "mspot") {
    chart.marker(100.0, 0.015, black, "paper 0.015 @ 100", 5.0);
    chart.marker(1000.0, 1.5, black, "paper 1.5 @ 1000", 5.0);
  }
  canvas.text(90, 670,
              "blue: depth quantization step z^2 s / K    orange: depth noise sd (line: model, "
              "dots: measured on a flat plate)    green: lateral point spacing",
              {40, 40, 40});
  char figures[200];
  std::snprintf(figures, sizeof figures,
                "K = %.0f mm px, sub-pixel step %.4g px, speckle %.3g px, %d points over %.4g deg",
                camera_model(d).k_mm_px, d.subpixel_step_px, d.speckle_px, d.points, d.fan_deg);
  canvas.text(90, 690, figures, {40, 40, 40});
  if (const std::string err = canvas.save_png(o.plot); !err.empty()) {
    std::cerr << "vts sensors: " << err << "\n";
    return 1;
  }
  std::cout << "wrote " << std::filesystem::absolute(o.plot).string() << "\n";
  return 0;
}

}  // namespace

CLI::App* add_sensors_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<SensorsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sensors", "List the sensor presets with their resolution, and the material presets");
  cmd->add_option("--plot", opts->plot,
                  "Write a PNG of one sensor's depth step, depth noise and lateral spacing "
                  "against range")
      ->type_name("FILE.png");
  cmd->add_option("--sensor", opts->sensor, "Sensor preset to plot (default mspot)")
      ->type_name("NAME");
  cmd->callback([opts, &exit_code] {
    if (opts->plot.empty()) {
      if (!opts->sensor.empty()) {
        std::cerr << "vts sensors: --sensor is for --plot\n";
        exit_code = 2;
        return;
      }
      list();
      exit_code = 0;
    } else {
      exit_code = plot(*opts);
    }
  });
  return cmd;
}

}  // namespace vts::apps
