// read_grey_image on files written here with OpenImageIO: known pixel values
// in every supported depth and layout, and the refusals naming the file.
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "sensor/image_io.h"
#include "tests/common/temp_dir.h"

namespace {

namespace fs = std::filesystem;

// Writes width x height x channels pixels of `type` (data in that type).
void write(const fs::path& path, int width, int height, int channels, OIIO::TypeDesc type, const void* data,
           int bits_per_sample = 0) {
  auto out = OIIO::ImageOutput::create(path.string());
  REQUIRE(out);
  OIIO::ImageSpec spec(width, height, channels, type);
  if (bits_per_sample) spec.attribute("oiio:BitsPerSample", bits_per_sample);
  REQUIRE(out->open(path.string(), spec));
  REQUIRE(out->write_image(type, data));
  REQUIRE(out->close());
}

std::string error_of(const fs::path& path) {
  try {
    vts::read_grey_image(path);
  } catch (const vts::ImageError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("8- and 16-bit greyscale images are read exactly", "[image_io]") {
  vts::test::TempDir dir("vts_image_io");
  const std::vector<std::uint8_t> p8 = {0, 1, 2, 127, 128, 254, 255, 9};
  write(dir.path / "a.png", 4, 2, 1, OIIO::TypeDesc::UINT8, p8.data());
  auto img = vts::read_grey_image(dir.path / "a.png");
  CHECK(img.width == 4);
  CHECK(img.height == 2);
  CHECK(img.bits == 8);
  CHECK(img.note.empty());
  CHECK(img.pixels == std::vector<std::uint16_t>(p8.begin(), p8.end()));

  const std::vector<std::uint16_t> p16 = {0, 1, 255, 256, 4095, 40000, 65534, 65535};
  for (const char* name : {"b.png", "b.tif"}) {
    write(dir.path / name, 2, 4, 1, OIIO::TypeDesc::UINT16, p16.data());
    img = vts::read_grey_image(dir.path / name);
    CHECK(img.bits == 16);
    CHECK(img.pixels == p16);
  }
}

TEST_CASE("a 12-bit TIFF keeps its 12-bit values", "[image_io]") {
  vts::test::TempDir dir("vts_image_io");
  const std::vector<std::uint16_t> dn = {0, 1, 2, 100, 2048, 4094, 4095, 7};
  std::vector<std::uint16_t> scaled;  // OpenImageIO takes 16-bit range data for a 12-bit file
  for (auto v : dn) scaled.push_back(static_cast<std::uint16_t>(std::lround(v * 65535.0 / 4095.0)));
  write(dir.path / "c.tif", 8, 1, 1, OIIO::TypeDesc::UINT16, scaled.data(), 12);
  const auto img = vts::read_grey_image(dir.path / "c.tif");
  CHECK(img.bits == 12);
  CHECK(img.pixels == dn);
}

TEST_CASE("float and half EXR pixels are DN, bits from the largest", "[image_io]") {
  vts::test::TempDir dir("vts_image_io");
  const std::vector<float> f = {0.0f, 3.0f, 1000.0f, 17.4f};
  write(dir.path / "d.exr", 2, 2, 1, OIIO::TypeDesc::FLOAT, f.data());
  auto img = vts::read_grey_image(dir.path / "d.exr");
  CHECK(img.bits == 10);
  CHECK(img.pixels == std::vector<std::uint16_t>{0, 3, 1000, 17});
  CHECK(img.note == "float pixels rounded to whole DN");
  write(dir.path / "e.exr", 2, 1, 1, OIIO::TypeDesc::HALF, std::vector<std::uint16_t>{0, 0x7bff}.data());
  img = vts::read_grey_image(dir.path / "e.exr");  // half 65504
  CHECK(img.bits == 16);
  CHECK(img.pixels[1] == 65504);
  const std::vector<float> unit = {0.0f, 0.25f, 1.0f, 0.5f};
  write(dir.path / "f.exr", 2, 2, 1, OIIO::TypeDesc::FLOAT, unit.data());
  CHECK_THAT(error_of(dir.path / "f.exr"), Catch::Contains("f.exr: float pixels all in [0, 1]"));
  const std::vector<float> negative = {0.0f, -2.0f};
  write(dir.path / "g.exr", 2, 1, 1, OIIO::TypeDesc::FLOAT, negative.data());
  CHECK_THAT(error_of(dir.path / "g.exr"), Catch::Contains("g.exr: pixel (row 0, column 1) = -2"));
}

TEST_CASE("grey stored as RGB is read, colour and other layouts are refused", "[image_io]") {
  vts::test::TempDir dir("vts_image_io");
  const std::vector<std::uint8_t> grey_rgb = {10, 10, 10, 200, 200, 200};
  write(dir.path / "g.png", 2, 1, 3, OIIO::TypeDesc::UINT8, grey_rgb.data());
  auto img = vts::read_grey_image(dir.path / "g.png");
  CHECK(img.pixels == std::vector<std::uint16_t>{10, 200});
  CHECK_THAT(img.note, Catch::Contains("first three equal: read as grey"));
  const std::vector<std::uint8_t> ya = {10, 255, 200, 255};
  write(dir.path / "ya.png", 2, 1, 2, OIIO::TypeDesc::UINT8, ya.data());
  img = vts::read_grey_image(dir.path / "ya.png");
  CHECK(img.pixels == std::vector<std::uint16_t>{10, 200});
  CHECK_THAT(img.note, Catch::Contains("read the first as grey"));
  const std::vector<std::uint8_t> colour = {10, 10, 10, 200, 0, 200};
  write(dir.path / "colour.png", 2, 1, 3, OIIO::TypeDesc::UINT8, colour.data());
  CHECK_THAT(error_of(dir.path / "colour.png"), Catch::Contains("colour.png: a colour image (channels R,G,B)"));
  const std::vector<std::int16_t> signed16 = {1, -1};
  write(dir.path / "s.tif", 2, 1, 1, OIIO::TypeDesc::INT16, signed16.data());
  CHECK_THAT(error_of(dir.path / "s.tif"), Catch::Contains("s.tif: pixel type int16 is not supported"));
  CHECK_THAT(error_of(dir.path / "missing.png"), Catch::EndsWith("missing.png: no such file"));
  std::ofstream(dir.path / "text.png") << "not an image\n";
  CHECK_THAT(error_of(dir.path / "text.png"), Catch::Contains("text.png: cannot read as an image"));
}

TEST_CASE("the image module: found beside the executable, or a clear message naming where it was looked for",
          "[image_io]") {
  vts::test::TempDir dir("vts_image_module");
  const std::vector<std::uint8_t> px = {7, 9};
  write(dir.path / "a.png", 2, 1, 1, OIIO::TypeDesc::UINT8, px.data());
  // The programs do not link OpenImageIO themselves: the module does.
  CHECK(vts::read_grey_image(dir.path / "a.png").pixels == std::vector<std::uint16_t>{7, 9});
  const fs::path missing = dir.path / "no-such-module.so";
  ::setenv("VTS_IMAGE_MODULE", missing.c_str(), 1);
  const std::string e = error_of(dir.path / "a.png");
  CHECK_THAT(e, Catch::StartsWith((dir.path / "a.png").string() + ": reading images needs vts's OpenImageIO module"));
  CHECK_THAT(e, Catch::Contains("no-such-module.so"));
  std::ofstream(dir.path / "fake.so") << "not a library\n";
  ::setenv("VTS_IMAGE_MODULE", (dir.path / "fake.so").c_str(), 1);
  CHECK_THAT(error_of(dir.path / "a.png"), Catch::Contains("fake.so"));
  ::unsetenv("VTS_IMAGE_MODULE");
  CHECK(vts::read_grey_image(dir.path / "a.png").pixels == std::vector<std::uint16_t>{7, 9});
}
