#pragma once
// A small PNG plotter for profiles and charts written by the vts commands
// (no GL: it must run anywhere the headless tools run).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vts::plot {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

class Canvas {
 public:
  Canvas(int width, int height, Rgb background = {255, 255, 255});
  int width() const { return width_; }
  int height() const { return height_; }
  void pixel(int x, int y, Rgb c);
  void line(double x0, double y0, double x1, double y1, Rgb c, int thickness = 1);
  void disc(double x, double y, double radius, Rgb c);
  // stb_easy_font glyphs, top-left at (x, y), scale 1 = about 7 px tall.
  void text(double x, double y, const std::string& s, Rgb c, int scale = 1);
  static int text_width(const std::string& s, int scale = 1);
  // Writes to a temporary name, then renames. Returns an error message or "".
  std::string save_png(const std::filesystem::path& path) const;
  const std::vector<std::uint8_t>& rgb() const { return rgb_; }

 private:
  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

// A chart area on a canvas mapping data (x, y) to pixels, with a frame, ticks,
// labels and a title. With equal_aspect the ranges grow so 1 unit is the same
// length on both axes. With y_down the y axis grows downwards (sensor z).
class Chart {
 public:
  Chart(Canvas& canvas, int left, int top, int right, int bottom, double x0, double x1, double y0,
        double y1, bool equal_aspect = false, bool y_down = false);
  void frame(const std::string& title, const std::string& x_label, const std::string& y_label);
  void points(const std::vector<double>& x, const std::vector<double>& y, Rgb c, double radius = 1.5);
  void polyline(const std::vector<double>& x, const std::vector<double>& y, Rgb c, int thickness = 1);
  void marker(double x, double y, Rgb c, const std::string& label = "", double radius = 4.0);
  double px(double x) const;
  double py(double y) const;

 private:
  Canvas& c_;
  int l_, t_, r_, b_;
  double x0_, x1_, y0_, y1_;
  bool y_down_;
};

// "Nice" tick positions covering [lo, hi], about `count` of them.
std::vector<double> ticks(double lo, double hi, int count = 6);

}  // namespace vts::plot
