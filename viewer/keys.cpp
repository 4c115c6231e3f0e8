#include "viewer/keys.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <stdexcept>

namespace vts::viewer {
namespace {

constexpr KeyInfo kKeys[] = {
    {Key::Forward, "w", "W", "torch forward / back along travel (tool x)", true},
    {Key::Back, "s", "S", "", true},
    {Key::Left, "a", "A", "torch left / right (tool -y / +y)", true},
    {Key::Right, "d", "D", "", true},
    {Key::Up, "r", "R", "torch up / down along its axis (tool -z / +z)", true},
    {Key::Down, "f", "F", "", true},
    {Key::RollLeft, "q", "Q", "roll about travel (tool x): tilts the fan across the seam", true},
    {Key::RollRight, "e", "E", "", true},
    {Key::YawLeft, "z", "Z", "turn about the torch axis (tool z)", true},
    {Key::YawRight, "c", "C", "", true},
    {Key::PitchUp, "t", "T", "push / drag angle (about tool y)", true},
    {Key::PitchDown, "g", "G", "", true},
    {Key::Faster, "plus", "+", "speed x1.5 / 1.5 (translation and rotation)", false},
    {Key::Slower, "minus", "-", "", false},
    {Key::Help, "h", "H", "show / hide this help", false},
    {Key::Pause, "space", "Space", "pause / resume the simulation", false},
    {Key::Record, "p", "P", "start / stop recording profiles to EXR (as `vts scan`)", false},
    {Key::AutoTravel, "m", "M", "auto travel: forward at the set speed", false},
    {Key::FollowCamera, "v", "V", "camera follows the torch", false},
    {Key::ResetTorch, "backspace", "Backspace", "torch back to the cell's start pose", false},
    {Key::ResetView, "home", "Home", "reset the camera", false},
    {Key::LayBead, "b", "B", "groove cells: lay one more bead where the sensor says (adaptive fill; the sensor sees the new fill)", false},
    {Key::CameraImage, "i", "I", "camera image on/off: profiles read from the rendered stripe image, shown under the view", false},
    {Key::Quit, "escape", "Esc", "quit", false},
};

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string valid_names() {
  std::string s;
  for (const auto& k : kKeys) s += (s.empty() ? "" : ", ") + std::string(k.name);
  return s + ", _ (no key)";
}

[[noreturn]] void bad(std::string_view token, const std::string& why) {
  throw std::invalid_argument("--keys: token '" + std::string(token) + "': " + why);
}

}  // namespace

std::span<const KeyInfo> key_table() { return kKeys; }

const KeyInfo& key_info(Key key) {
  for (const auto& k : kKeys)
    if (k.key == key) return k;
  return kKeys[0];  // unreachable: every Key is in the table
}

std::vector<KeyFrame> parse_key_script(std::string_view script) {
  std::vector<KeyFrame> frames;
  std::size_t i = 0;
  while (i < script.size()) {
    const auto is_sep = [](char c) { return c == ',' || std::isspace(static_cast<unsigned char>(c)); };
    while (i < script.size() && is_sep(script[i])) ++i;
    std::size_t j = i;
    while (j < script.size() && !is_sep(script[j])) ++j;
    if (j == i) break;
    const std::string_view token = script.substr(i, j - i);
    i = j;

    std::string_view body = token;
    long repeat = 1;
    if (const auto star = token.find('*'); star != std::string_view::npos) {
      body = token.substr(0, star);
      const std::string_view count = token.substr(star + 1);
      const auto r = std::from_chars(count.data(), count.data() + count.size(), repeat);
      if (r.ec != std::errc() || r.ptr != count.data() + count.size() || repeat < 1 || repeat > 100000)
        bad(token, "the repeat count after '*' must be an integer from 1 to 100000");
    }
    if (body.empty()) bad(token, "no key name; valid names: " + valid_names());

    KeyFrame frame;
    if (body != "_") {
      std::size_t p = 0;
      while (p <= body.size()) {
        const std::size_t plus = std::min(body.find('+', p), body.size());
        const std::string name = lower(body.substr(p, plus - p));
        const auto it = std::find_if(std::begin(kKeys), std::end(kKeys),
                                     [&](const KeyInfo& k) { return k.name == name; });
        if (it == std::end(kKeys))
          bad(token, "unknown key '" + name + "'; valid names: " + valid_names());
        frame.push_back(it->key);
        p = plus + 1;
      }
    }
    frames.insert(frames.end(), static_cast<std::size_t>(repeat), frame);
  }
  return frames;
}

}  // namespace vts::viewer
