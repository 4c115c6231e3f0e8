#pragma once
// vts-view's keys: one table for the help overlay, the GLFW mapping and the
// --keys script parser, so the three cannot disagree.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace vts::viewer {

enum class Key {
  Forward, Back, Left, Right, Up, Down,  // translate (held)
  RollLeft, RollRight, YawLeft, YawRight, PitchUp, PitchDown,  // rotate (held)
  Faster, Slower, Help, Pause, Record, AutoTravel, FollowCamera, ResetTorch, ResetView, LayBead, CameraImage, Quit,
};

struct KeyInfo {
  Key key;
  std::string_view name;   // in --keys scripts, e.g. "w", "plus", "space"
  std::string_view label;  // on the help overlay, e.g. "W", "+", "Space"
  // Help text; empty for the second key of a pair (W / S), whose text is
  // on the first.
  std::string_view action;
  bool held;  // acts every frame while down (motion); else once per press
};

// Every key, in help-overlay order.
std::span<const KeyInfo> key_table();
const KeyInfo& key_info(Key key);

// One frame of a key script: the keys down during that frame (held keys move
// the torch for that frame; the others act once).
using KeyFrame = std::vector<Key>;

// Parses a --keys script: tokens separated by spaces or commas, one frame
// each. A token is a key name (key_table(), case-insensitive), several names
// joined by '+' for one frame ("w+d"), or "_" for a frame with no key;
// "TOKEN*N" repeats it for N frames (1..100000). Example: "w*30 _ d*10 p".
// Throws std::invalid_argument naming the bad token and the valid names.
std::vector<KeyFrame> parse_key_script(std::string_view script);

}  // namespace vts::viewer
