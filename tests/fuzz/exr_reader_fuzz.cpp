// libFuzzer target: any bytes given as a profile EXR either read back or raise
// vts::ExrError; anything else (a crash, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "sensor/profile_exr.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("vts-fuzz-exr-" + std::to_string(::getpid()) + ".exr");
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
  try {
    vts::read_profile_exr(path);
  } catch (const vts::ExrError&) {
  }
  return 0;
}
