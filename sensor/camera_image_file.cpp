#include "sensor/camera_image_file.h"

#include <png.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.h"

namespace vts {
namespace {

void write_bytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::ostream*>(png_get_io_ptr(png));
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
}
void flush_bytes(png_structp) {}

void write_png(std::ostream& out, const CameraImage& im, const std::string& name) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("cannot write " + name + ": libpng could not start");
  }
  const bool wide = im.bits > 8;
  std::vector<png_byte> row(static_cast<std::size_t>(im.width) * (wide ? 2 : 1));
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("cannot write " + name + ": libpng failed");
  }
  png_set_write_fn(png, &out, write_bytes, flush_bytes);
  png_set_IHDR(png, info, static_cast<png_uint_32>(im.width), static_cast<png_uint_32>(im.rows), wide ? 16 : 8,
               PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_color_8 sig{};
  sig.gray = static_cast<png_byte>(im.bits);
  png_set_sBIT(png, info, &sig);
  png_write_info(png, info);
  for (int r = 0; r < im.rows; ++r) {
    const std::uint16_t* src = im.pixels.data() + static_cast<std::size_t>(r) * im.width;
    for (int c = 0; c < im.width; ++c) {
      if (wide) {
        row[2 * static_cast<std::size_t>(c)] = static_cast<png_byte>(src[c] >> 8);  // PNG is big-endian
        row[2 * static_cast<std::size_t>(c) + 1] = static_cast<png_byte>(src[c] & 0xff);
      } else {
        row[static_cast<std::size_t>(c)] = static_cast<png_byte>(src[c]);
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}

std::string number(float v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", static_cast<double>(v));
  return buf;
}

}  // namespace

std::filesystem::path camera_image_path(const std::filesystem::path& dir, std::int64_t index) {
  char name[48];
  std::snprintf(name, sizeof name, "image_%06lld.png", static_cast<long long>(index));
  return dir / name;
}

std::filesystem::path camera_labels_path(const std::filesystem::path& dir, std::int64_t index) {
  return std::filesystem::path(camera_image_path(dir, index)).replace_extension(".csv");
}

void write_camera_image(const std::filesystem::path& dir, const CameraImage& im) {
  {
    AtomicFile file(camera_image_path(dir, im.index));
    if (!file.is_open()) throw std::runtime_error("cannot write " + file.path().string());
    write_png(file.stream(), im, file.path().string());
    file.commit();
  }
  AtomicFile file(camera_labels_path(dir, im.index));
  if (!file.is_open()) throw std::runtime_error("cannot write " + file.path().string());
  std::ostream& out = file.stream();
  out << "# vts camera image " << im.index << ": " << im.width << " columns, rows " << im.first_row << ".."
      << im.first_row + im.rows - 1 << " of the image, " << im.bits << " bits\n";
  out << "column,true_row,bounce_row,mirror_row,true_peak,chosen_peak,chosen_row,peaks\n";
  const auto at = [](const auto& v, int c, auto fallback) {
    return c < static_cast<int>(v.size()) ? v[static_cast<std::size_t>(c)] : fallback;
  };
  const float nan = std::nanf("");
  for (int c = 0; c < im.width; ++c) {
    out << c << ',' << number(at(im.true_row, c, nan)) << ',' << number(at(im.bounce_row, c, nan)) << ','
        << number(at(im.mirror_row, c, nan)) << ','
        << at(im.true_peak, c, -1) << ',' << at(im.chosen_peak, c, -1) << ',' << number(at(im.chosen_row, c, nan))
        << ',' << at(im.peak_count, c, 0) << '\n';
  }
  file.commit();
}

}  // namespace vts
