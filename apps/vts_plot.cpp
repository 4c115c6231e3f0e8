#include "apps/vts_plot.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>

#include "plot/plot.h"
#include "sensor/profile_exr.h"

namespace vts::apps {
namespace {

struct PlotOptions {
  std::string input;
  std::string output;
  std::vector<int> rows;
};

int run_plot(const PlotOptions& o) {
  ProfileRecording rec;
  try {
    rec = read_profile_exr(o.input);
  } catch (const std::exception& e) {
    std::cerr << "vts plot: " << e.what() << "\n";
    return 2;
  }
  std::vector<int> rows = o.rows.empty() ? std::vector<int>{0} : o.rows;
  for (int r : rows) {
    if (r < 0 || r >= static_cast<int>(rec.profiles.size())) {
      std::cerr << "vts plot: --row " << r << ": " << o.input << " has rows 0.."
                << rec.profiles.size() - 1 << "\n";
      return 2;
    }
  }
  double y0 = std::numeric_limits<double>::infinity(), y1 = -y0, z0 = y0, z1 = -y0;
  auto extend = [&](const Profile& p) {
    for (int i = 0; i < p.size(); ++i)
      if (p.valid[i]) {
        y0 = std::min<double>(y0, p.y_mm[i]);
        y1 = std::max<double>(y1, p.y_mm[i]);
        z0 = std::min<double>(z0, p.z_mm[i]);
        z1 = std::max<double>(z1, p.z_mm[i]);
      }
  };
  for (int r : rows) {
    extend(rec.profiles[r]);
    if (rec.info.has_reference) extend(rec.reference[r]);
  }
  if (!std::isfinite(y0)) {
    y0 = -10, y1 = 10, z0 = 0, z1 = 20;  // nothing valid: an empty frame still says so
  }
  const double pad = 0.05 * std::max(y1 - y0, z1 - z0) + 0.5;
  plot::Canvas canvas(1000, 800);
  plot::Chart chart(canvas, 90, 60, 970, 740, y0 - pad, y1 + pad, z0 - pad, z1 + pad, true, true);
  std::string title = rec.info.scene_name + ": row";
  for (int r : rows) title += " " + std::to_string(r);
  chart.frame(title, "y [mm] (sensor frame, along the laser line)", "z [mm] (range axis, down)");
  const plot::Rgb raster{30, 90, 200}, reference{240, 140, 20};
  int valid = 0, total = 0;
  for (int r : rows) {
    auto draw = [&](const Profile& p, plot::Rgb c, double radius) {
      std::vector<double> y, z;
      for (int i = 0; i < p.size(); ++i)
        if (p.valid[i]) {
          y.push_back(p.y_mm[i]);
          z.push_back(p.z_mm[i]);
        }
      chart.points(y, z, c, radius);
      return static_cast<int>(y.size());
    };
    if (rec.info.has_reference) draw(rec.reference[r], reference, 3.0);
    valid += draw(rec.profiles[r], raster, 1.5);
    total += rec.profiles[r].size();
  }
  canvas.text(90, 782, "blue: main channels" + std::string(rec.info.has_reference ? ", orange: ref.* (reference)" : "") +
                           "   valid " + std::to_string(valid) + " of " + std::to_string(total) + " points",
              {40, 40, 40});
  const std::string out = o.output.empty()
                              ? std::filesystem::path(o.input).replace_extension(".png").string()
                              : o.output;
  if (const std::string err = canvas.save_png(out); !err.empty()) {
    std::cerr << "vts plot: " << err << "\n";
    return 1;
  }
  std::cout << "wrote " << std::filesystem::absolute(out).string() << "\n";
  return 0;
}

}  // namespace

CLI::App* add_plot_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<PlotOptions>();
  CLI::App* cmd = app.add_subcommand("plot", "Draw profiles of a vts EXR file to a PNG (sensor frame, mm)");
  cmd->add_option("file", opts->input, "vts profile EXR (from vts scan)")->required();
  cmd->add_option("--row", opts->rows, "profile row(s) to draw, 0-based (default: 0)");
  cmd->add_option("--out", opts->output, "PNG to write (default: the input with .png)");
  cmd->callback([opts, &exit_code] { exit_code = run_plot(*opts); });
  return cmd;
}

}  // namespace vts::apps
