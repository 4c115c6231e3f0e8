#pragma once
// Greyscale camera images read from files (PNG, TIFF, EXR, anything
// OpenImageIO reads), for the stripe peak detector (stripe/peaks.h,
// `vts peaks`, docs/PEAKS.md).
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace vts {

// Message: "FILE: why", e.g. "a.png: no such file".
struct ImageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One image in DN, row-major (pixel (row, col) at pixels[row * width + col]).
struct GreyImage {
  int width = 0;
  int height = 0;
  int bits = 8;                       // 8, 10, 12 or 16: full scale is 2^bits - 1 DN
  std::vector<std::uint16_t> pixels;  // width * height, each <= 2^bits - 1
  std::string note;                   // how the file's channels or values were read, "" when as they are
};

// Reads the first subimage of `path`:
// - 8-bit integer pixels: bits 8; 16-bit integer pixels: bits 16, or 10 or
//   12 when the file says so (TIFF's BitsPerSample; the values are then
//   taken back from OpenImageIO's 16-bit scaling to 0..2^bits - 1);
// - half or float pixels (EXR, float TIFF) hold DN: rounded to integers, each
//   must be finite and in [0, 65535], and bits is the smallest of 8, 10, 12,
//   16 whose full scale covers the largest value; an image whose values all
//   lie in [0, 1] and are not all 0 or 1 is refused as not in DN;
// - one channel as it is; two channels (grey and alpha): the first, said in
//   `note`; three or more: the first when the first three are equal in every
//   pixel (grey stored as RGB, said in `note`), otherwise refused as colour.
// Throws ImageError naming the file: missing or unreadable file, colour
// image, other pixel types (signed, 32-bit integer), deep or volume images.
//
// The reading is done by a module, libvts_image_oiio.so, loaded on the
// first call (OpenImageIO's 260 libraries would cost every program that
// links vts_sensor 0.2 s at its start). It is looked for in
// $VTS_IMAGE_MODULE (a file) when that is set, else beside the executable
// (where the build puts it), in ../lib/vts from there, and on the library
// search path; not found, the ImageError says where it looked.
GreyImage read_grey_image(const std::filesystem::path& path);

// The module's interface (sensor/image_module/oiio_reader.cpp), checked
// when it is loaded: bump on any change of GreyImage or of the functions
//   int vts_image_module_abi();
//   int vts_image_module_read(const char* path, GreyImage* out, std::string* error);
inline constexpr int kImageModuleAbi = 1;
inline constexpr const char* kImageModuleFile = "libvts_image_oiio.so";

}  // namespace vts
