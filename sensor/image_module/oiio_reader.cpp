// The image reader module (libvts_image_oiio.so): read_grey_image's body,
// built apart from vts_sensor because OpenImageIO brings about 260 shared
// libraries with it, 0.2 s at every start of a program linked to them.
// sensor/image_io.cpp loads this module when the first image is read.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <system_error>

#include "sensor/image_io.h"

namespace vts {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw ImageError(path.string() + ": " + why);
}

std::string channel_list(const OIIO::ImageSpec& spec) {
  std::string s;
  for (int c = 0; c < spec.nchannels; ++c) {
    if (c) s += ",";
    s += c < static_cast<int>(spec.channelnames.size()) ? spec.channelnames[c] : std::to_string(c);
  }
  return s;
}

GreyImage read_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) fail(path, "is a directory, not an image");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    std::string why = OIIO::geterror();
    if (why.empty()) why = "not an image OpenImageIO can read";
    fail(path, "cannot read as an image: " + why);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.deep) fail(path, "a deep image: not a camera image");
  if (spec.depth > 1) fail(path, "a volume image (depth " + std::to_string(spec.depth) + "): not a camera image");
  if (spec.width < 1 || spec.height < 1) fail(path, "an empty image");
  const OIIO::TypeDesc type = spec.format;
  const bool is_float = type.basetype == OIIO::TypeDesc::HALF || type.basetype == OIIO::TypeDesc::FLOAT ||
                        type.basetype == OIIO::TypeDesc::DOUBLE;
  if (type.basetype != OIIO::TypeDesc::UINT8 && type.basetype != OIIO::TypeDesc::UINT16 && !is_float)
    fail(path, std::string("pixel type ") + type.c_str() +
                   " is not supported: expected 8- or 16-bit unsigned integers, or half or float values in DN");

  GreyImage img;
  img.width = spec.width;
  img.height = spec.height;
  const int nch = spec.nchannels;
  const std::size_t npx = static_cast<std::size_t>(img.width) * img.height;
  // Channels read: one, or the first three to compare them.
  const int nread = nch >= 3 ? 3 : 1;
  std::vector<float> f;
  std::vector<std::uint16_t> u;
  bool ok;
  if (is_float) {
    f.resize(npx * nread);
    ok = in->read_image(0, 0, 0, nread, OIIO::TypeDesc::FLOAT, f.data());
  } else {
    u.resize(npx * nread);
    ok = in->read_image(0, 0, 0, nread, OIIO::TypeDesc::UINT16, u.data());
  }
  if (!ok) fail(path, "cannot read its pixels: " + in->geterror());

  if (nch == 2) img.note = "2 channels (" + channel_list(spec) + "): read the first as grey";
  if (nch >= 3) {
    for (std::size_t i = 0; i < npx; ++i) {
      const bool same = is_float ? (f[3 * i] == f[3 * i + 1] && f[3 * i] == f[3 * i + 2])
                                 : (u[3 * i] == u[3 * i + 1] && u[3 * i] == u[3 * i + 2]);
      if (!same)
        fail(path, "a colour image (channels " + channel_list(spec) +
                       "): the peak detector needs one grey channel; extract one with oiiotool " + path.string() +
                       " --ch 0 -o grey.png");
    }
    img.note = std::to_string(nch) + " channels (" + channel_list(spec) + ") with the first three equal: read as grey";
  }

  img.pixels.resize(npx);
  if (!is_float) {
    const int file_bits = spec.get_int_attribute("oiio:BitsPerSample", 0);
    img.bits = type.basetype == OIIO::TypeDesc::UINT8 ? 8 : (file_bits == 10 || file_bits == 12 ? file_bits : 16);
    // OpenImageIO hands out every integer image scaled to the 16-bit range
    // (8-bit v as v * 257, 12-bit v as v * 65535 / 4095): undo it exactly.
    const double scale = ((1 << img.bits) - 1) / 65535.0;
    for (std::size_t i = 0; i < npx; ++i)
      img.pixels[i] = static_cast<std::uint16_t>(std::lround(u[i * nread] * scale));
    return img;
  }

  float top = 0.0f;
  bool fractional = false;
  for (std::size_t i = 0; i < npx; ++i) {
    const float v = f[i * nread];
    if (!std::isfinite(v) || v < 0.0f || v > 65535.5f) {
      const std::size_t row = i / img.width, col = i % img.width;
      fail(path, "pixel (row " + std::to_string(row) + ", column " + std::to_string(col) + ") = " +
                     std::to_string(v) + ": float pixels must hold DN in [0, 65535]");
    }
    top = std::max(top, v);
    fractional |= v != std::round(v);
  }
  if (top <= 1.0f && fractional)
    fail(path, "float pixels all in [0, 1]: they look normalised, not DN; scale them to DN (oiiotool " +
                   path.string() + " --mulc 65535 -d uint16 -o scaled.png)");
  for (std::size_t i = 0; i < npx; ++i) img.pixels[i] = static_cast<std::uint16_t>(std::lround(f[i * nread]));
  const long top_dn = std::lround(top);
  img.bits = top_dn <= 255 ? 8 : top_dn <= 1023 ? 10 : top_dn <= 4095 ? 12 : 16;
  if (fractional) img.note = "float pixels rounded to whole DN";
  return img;
}

}  // namespace
}  // namespace vts

extern "C" int vts_image_module_abi() { return vts::kImageModuleAbi; }

extern "C" int vts_image_module_read(const char* path, vts::GreyImage* out, std::string* error) {
  try {
    *out = vts::read_image(path);
    return 1;
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = std::string(path) + ": cannot read as an image (an unknown error in OpenImageIO)";
  }
  return 0;
}
