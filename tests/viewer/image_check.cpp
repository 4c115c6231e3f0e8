// Assertions on vts-view's output for tests/viewer/screenshot_test.sh.
//
//   viewer_image_check shots A.png B.png VIEW_W  TCP_A(x y) NOZZLE_A(x y)  TCP_B(x y) NOZZLE_B(x y)
//     A: no keys, B: the same frames with keys that moved the torch; VIEW_W:
//     the 3D view is x < VIEW_W, the profile panel the rest. Checks that the
//     laser line's colour (pure red) appears in both 3D views, that the panel's
//     background colour fills the panel, and that the images differ around
//     the torch in A and in B but not in a corner the torch never reaches.
//   viewer_image_check exr FILE MIN_ROWS POINTS
//     A recording made with the P key: readable as a vts profile EXR, at
//     least MIN_ROWS rows of POINTS columns, rows in time order.
//
// Every check prints what it measured; the exit code is the number of failed checks.
#include <stb_image.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "sensor/profile_exr.h"

namespace {

// What viewer/app.h and viewer/panel.h promise.
constexpr int kLaser[3] = {255, 0, 0};
constexpr int kPanelBg[3] = {23, 26, 31};

struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[(static_cast<std::size_t>(y) * w + x) * 3]; }
};

Image load(const char* path) {
  Image im;
  int channels = 0;
  unsigned char* data = stbi_load(path, &im.w, &im.h, &channels, 3);
  if (!data) {
    std::fprintf(stderr, "cannot read %s: %s\n", path, stbi_failure_reason());
    std::exit(100);
  }
  im.rgb.assign(data, data + static_cast<std::size_t>(im.w) * im.h * 3);
  stbi_image_free(data);
  return im;
}

int failures = 0;
void check(bool ok, const std::string& what) {
  std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
  if (!ok) ++failures;
}

bool near(const unsigned char* p, const int c[3], int tol) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(p[k] - c[k]) > tol) return false;
  return true;
}

// Pixels in [x0, x1) x [y0, y1) within tol of colour c.
long count(const Image& im, int x0, int x1, int y0, int y1, const int c[3], int tol) {
  long n = 0;
  for (int y = std::max(0, y0); y < std::min(im.h, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(im.w, x1); ++x) n += near(im.at(x, y), c, tol);
  return n;
}

// Mean absolute difference per channel (0..255) over a box around (cx, cy).
double box_diff(const Image& a, const Image& b, int cx, int cy, int r) {
  double sum = 0.0;
  long n = 0;
  for (int y = std::max(0, cy - r); y < std::min(a.h, cy + r + 1); ++y)
    for (int x = std::max(0, cx - r); x < std::min(a.w, cx + r + 1); ++x) {
      for (int k = 0; k < 3; ++k) sum += std::abs(a.at(x, y)[k] - b.at(x, y)[k]);
      n += 3;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

int shots(char** v) {
  const Image a = load(v[0]), b = load(v[1]);
  const int view_w = std::atoi(v[2]);
  const int tcp_a[2] = {std::atoi(v[3]), std::atoi(v[4])}, noz_a[2] = {std::atoi(v[5]), std::atoi(v[6])};
  const int tcp_b[2] = {std::atoi(v[7]), std::atoi(v[8])}, noz_b[2] = {std::atoi(v[9]), std::atoi(v[10])};
  char msg[256];

  check(a.w == b.w && a.h == b.h && a.w >= 640 && a.h >= 480, "both screenshots " + std::to_string(a.w) + "x" +
                                                                    std::to_string(a.h) + ", same size, at least 640x480");
  if (failures) return failures;
  check(view_w > a.w / 3 && view_w < a.w, "3D view width " + std::to_string(view_w) + " is a plausible part of the window");

  // 1. The lit laser line: exactly (255, 0, 0), in the 3D view.
  for (const Image* im : {&a, &b}) {
    const long red = count(*im, 0, view_w, 0, im->h, kLaser, 0);
    std::snprintf(msg, sizeof msg, "%s: %ld pixels of the laser colour (255,0,0) in the 3D view (want >= 40)",
                  im == &a ? "A" : "B", red);
    check(red >= 40, msg);
  }

  // 2. The profile panel: its background colour fills much of the panel and
  // little of the 3D view.
  const long panel_px = static_cast<long>(a.w - view_w) * a.h;
  const long view_px = static_cast<long>(view_w) * a.h;
  const double in_panel = static_cast<double>(count(a, view_w, a.w, 0, a.h, kPanelBg, 2)) / panel_px;
  const double in_view = static_cast<double>(count(a, 0, view_w, 0, a.h, kPanelBg, 2)) / view_px;
  std::snprintf(msg, sizeof msg,
                "panel background (23,26,31) covers %.1f%% of the panel (want >= 20%%) and %.2f%% of the 3D view "
                "(want < 5%%)",
                100.0 * in_panel, 100.0 * in_view);
  check(in_panel >= 0.20 && in_view < 0.05, msg);

  // 3. The keys moved the torch: it is drawn somewhere else in B, the pixels
  // where it was and where it is now changed, and a corner of the 3D view far
  // from both did not (the camera stayed put).
  const double moved = std::hypot(noz_b[0] - noz_a[0], noz_b[1] - noz_a[1]);
  std::snprintf(msg, sizeof msg, "nozzle moved %.0f px on screen, (%d,%d) -> (%d,%d) (want >= 15)", moved, noz_a[0],
                noz_a[1], noz_b[0], noz_b[1]);
  check(moved >= 15.0, msg);
  for (const auto& [name, p] : {std::pair{"nozzle in A", noz_a}, std::pair{"nozzle in B", noz_b},
                                std::pair{"TCP in A", tcp_a}, std::pair{"TCP in B", tcp_b}}) {
    const double d = box_diff(a, b, p[0], p[1], 10);
    std::snprintf(msg, sizeof msg, "A and B differ around the %s at (%d,%d): mean |diff| %.1f (want >= 8)", name,
                  p[0], p[1], d);
    check(d >= 8.0, msg);
  }
  const int cx = view_w - 50, cy = a.h - 40;
  const double still = box_diff(a, b, cx, cy, 30);
  std::snprintf(msg, sizeof msg, "A and B agree in the 3D view's bottom-right corner (%d,%d): mean |diff| %.2f (want < 1)",
                cx, cy, still);
  check(still < 1.0, msg);
  return failures;
}

int exr(char** v) {
  const int min_rows = std::atoi(v[1]), points = std::atoi(v[2]);
  try {
    const vts::ProfileRecording rec = vts::read_profile_exr(v[0]);
    const int rows = static_cast<int>(rec.profiles.size());
    check(rows >= min_rows, std::string(v[0]) + ": " + std::to_string(rows) + " rows (want >= " +
                                std::to_string(min_rows) + ")");
    check(rec.info.scanner.points == points, "points " + std::to_string(rec.info.scanner.points) + " (want " +
                                                 std::to_string(points) + ")");
    bool ordered = true;
    for (int i = 1; i < rows; ++i) ordered &= rec.profiles[i].time_s > rec.profiles[i - 1].time_s;
    check(ordered, "row times increase");
    int valid = 0;
    for (const auto& p : rec.profiles) valid += p.valid_count();
    check(valid > 0, std::to_string(valid) + " valid samples in the recording (want > 0)");
  } catch (const std::exception& e) {
    check(false, std::string("read_profile_exr: ") + e.what());
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "shots" && argc == 13) return shots(argv + 2);
  if (mode == "exr" && argc == 5) return exr(argv + 2);
  std::fprintf(stderr,
               "usage: viewer_image_check shots A.png B.png VIEW_W TCPAX TCPAY NOZAX NOZAY TCPBX TCPBY NOZBX NOZBY\n"
               "       viewer_image_check exr FILE MIN_ROWS POINTS\n");
  return 100;
}
