#include "plot/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <unistd.h>

#include <stb_easy_font.h>
#include <stb_image_write.h>

namespace vts::plot {

Canvas::Canvas(int width, int height, Rgb bg) : width_(width), height_(height) {
  rgb_.resize(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t i = 0; i < rgb_.size(); i += 3) {
    rgb_[i] = bg.r;
    rgb_[i + 1] = bg.g;
    rgb_[i + 2] = bg.b;
  }
}

void Canvas::pixel(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  auto* p = &rgb_[(static_cast<std::size_t>(y) * width_ + x) * 3];
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, int thickness) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  const int steps = std::min(100000, std::max(1, static_cast<int>(std::ceil(len))));
  const int h = thickness / 2;
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0)));
    const int y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
    for (int dy = -h; dy <= thickness - 1 - h; ++dy)
      for (int dx = -h; dx <= thickness - 1 - h; ++dx) pixel(x + dx, y + dy, c);
  }
}

void Canvas::disc(double x, double y, double radius, Rgb c) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  const int r = static_cast<int>(std::ceil(radius));
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (dx * dx + dy * dy <= radius * radius + 0.25)
        pixel(static_cast<int>(std::lround(x)) + dx, static_cast<int>(std::lround(y)) + dy, c);
}

void Canvas::text(double x, double y, const std::string& s, Rgb c, int scale) {
  static char buffer[99999];
  std::string copy = s;
  const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer, sizeof(buffer));
  const float* v = reinterpret_cast<const float*>(buffer);
  for (int q = 0; q < quads; ++q) {
    // Each vertex: x, y, z (float) + 4 colour bytes = 16 bytes = 4 floats.
    const float* quad = v + q * 16;
    const float qx0 = quad[0], qy0 = quad[1], qx1 = quad[8], qy1 = quad[9];
    for (int py = static_cast<int>(qy0 * scale); py < static_cast<int>(qy1 * scale); ++py)
      for (int pxl = static_cast<int>(qx0 * scale); pxl < static_cast<int>(qx1 * scale); ++pxl)
        pixel(static_cast<int>(x) + pxl, static_cast<int>(y) + py, c);
  }
}

int Canvas::text_width(const std::string& s, int scale) {
  std::string copy = s;
  return stb_easy_font_width(copy.data()) * scale;
}

std::string Canvas::save_png(const std::filesystem::path& path) const {
  const std::filesystem::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  if (!stbi_write_png(tmp.c_str(), width_, height_, 3, rgb_.data(), width_ * 3)) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return "cannot write PNG " + path.string();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return "cannot rename PNG onto " + path.string() + ": " + ec.message();
  }
  return {};
}

std::vector<double> ticks(double lo, double hi, int count) {
  std::vector<double> out;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return out;
  const double raw = (hi - lo) / std::max(1, count);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step)
    out.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return out;
}

Chart::Chart(Canvas& canvas, int left, int top, int right, int bottom, double x0, double x1, double y0,
             double y1, bool equal_aspect, bool y_down)
    : c_(canvas), l_(left), t_(top), r_(right), b_(bottom), x0_(x0), x1_(x1), y0_(y0), y1_(y1),
      y_down_(y_down) {
  if (!(x1_ > x0_)) x1_ = x0_ + 1.0;
  if (!(y1_ > y0_)) y1_ = y0_ + 1.0;
  if (equal_aspect) {
    const double sx = (x1_ - x0_) / (r_ - l_), sy = (y1_ - y0_) / (b_ - t_);
    const double s = std::max(sx, sy);
    const double cx = 0.5 * (x0_ + x1_), cy = 0.5 * (y0_ + y1_);
    x0_ = cx - 0.5 * s * (r_ - l_);
    x1_ = cx + 0.5 * s * (r_ - l_);
    y0_ = cy - 0.5 * s * (b_ - t_);
    y1_ = cy + 0.5 * s * (b_ - t_);
  }
}

double Chart::px(double x) const { return l_ + (x - x0_) / (x1_ - x0_) * (r_ - l_); }
double Chart::py(double y) const {
  const double f = (y - y0_) / (y1_ - y0_);
  return y_down_ ? t_ + f * (b_ - t_) : b_ - f * (b_ - t_);
}

void Chart::frame(const std::string& title, const std::string& x_label, const std::string& y_label) {
  const Rgb ink{40, 40, 40}, grid{225, 225, 225};
  auto fmt = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  for (double x : ticks(x0_, x1_)) {
    c_.line(px(x), t_, px(x), b_, grid);
    const std::string s = fmt(x);
    c_.text(px(x) - Canvas::text_width(s) / 2.0, b_ + 6, s, ink);
  }
  for (double y : ticks(y0_, y1_)) {
    c_.line(l_, py(y), r_, py(y), grid);
    const std::string s = fmt(y);
    c_.text(l_ - 6 - Canvas::text_width(s), py(y) - 3, s, ink);
  }
  c_.line(l_, t_, r_, t_, ink);
  c_.line(l_, b_, r_, b_, ink);
  c_.line(l_, t_, l_, b_, ink);
  c_.line(r_, t_, r_, b_, ink);
  c_.text(l_, t_ - 22, title, ink, 2);
  c_.text(0.5 * (l_ + r_) - Canvas::text_width(x_label) / 2.0, b_ + 20, x_label, ink);
  c_.text(r_ - Canvas::text_width(y_label), t_ - 12, y_label, ink);
}

void Chart::points(const std::vector<double>& x, const std::vector<double>& y, Rgb c, double radius) {
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    const double a = px(x[i]), b = py(y[i]);
    if (a >= l_ && a <= r_ && b >= t_ && b <= b_) c_.disc(a, b, radius, c);
  }
}

void Chart::polyline(const std::vector<double>& x, const std::vector<double>& y, Rgb c, int thickness) {
  // Each piece is clipped to the chart's data window (Liang-Barsky), so lines
  // running beyond it do not cross the frame, title or legend.
  const double xlo = std::min(x0_, x1_), xhi = std::max(x0_, x1_);
  const double ylo = std::min(y0_, y1_), yhi = std::max(y0_, y1_);
  for (std::size_t i = 1; i < x.size() && i < y.size(); ++i) {
    if (!(std::isfinite(x[i - 1]) && std::isfinite(y[i - 1]) && std::isfinite(x[i]) &&
          std::isfinite(y[i])))
      continue;
    const double dx = x[i] - x[i - 1], dy = y[i] - y[i - 1];
    double t0 = 0.0, t1 = 1.0;
    bool inside = true;
    auto clip = [&](double p, double q) {  // keep where p t <= q
      if (p == 0.0) {
        inside = inside && q >= 0.0;
        return;
      }
      const double t = q / p;
      if (p < 0.0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    };
    clip(-dx, x[i - 1] - xlo);
    clip(dx, xhi - x[i - 1]);
    clip(-dy, y[i - 1] - ylo);
    clip(dy, yhi - y[i - 1]);
    if (!inside || t0 > t1) continue;
    c_.line(px(x[i - 1] + t0 * dx), py(y[i - 1] + t0 * dy), px(x[i - 1] + t1 * dx),
            py(y[i - 1] + t1 * dy), c, thickness);
  }
}

void Chart::marker(double x, double y, Rgb c, const std::string& label, double radius) {
  c_.disc(px(x), py(y), radius, c);
  if (!label.empty()) c_.text(px(x) + radius + 3, py(y) - radius - 8, label, c, 1);
}

}  // namespace vts::plot
