// libFuzzer target: any bytes given as a scene file either parse into a cell
// or raise vts::SceneError; anything else (a crash, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "sensor/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const vts::Cell cell = vts::parse_scene(text, "fuzz.yaml");
    // What parses must also write back and parse again.
    vts::parse_scene(vts::scene_to_yaml(cell), "fuzz-roundtrip.yaml");
  } catch (const vts::SceneError&) {
  }
  return 0;
}
