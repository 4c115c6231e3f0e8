#pragma once
// The tracker's parameter file: YAML mirroring tracker::TrackerParams
// (docs/CLI.md "Parameter file"; tracker/params.h documents every field).
// The tracker itself reads no files; `vts track` and the other front-ends
// read parameters through this.
#include <cmath>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "tracker/params.h"
#include "tracker/types.h"

namespace vts::trackio {

// A bad parameter file: "FILE:LINE: key.path: what" (or "FILE: cannot open file").
struct ParamsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Limits of a numeric parameter: [lo, hi], or (lo, hi] when lo_open.
struct Limit {
  double lo = -INFINITY, hi = INFINITY;
  bool lo_open = false;
  bool ok(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
  // "> 0", ">= 0", "from 2 to 4096"
  std::string text() const;
};

// What a parameter file sets: the parameters, and the joint if it names one.
struct ParamsFile {
  tracker::TrackerParams params;
  std::optional<tracker::JointType> joint;
};

// One parameter as the file names it. `path` is its key path
// ("segmentation.segments.split_threshold_mm"); `field` points into a
// ParamsFile, and its type says how the value is written: a number (double),
// an integer (int), true/false (bool), [min, max] (Range), [y, z] (Vec2), a
// joint name, or auto/first/second (WebSide).
using FieldRef = std::variant<double*, int*, bool*, tracker::Range*, tracker::Vec2*,
                              std::optional<tracker::JointType>*, tracker::WebSide*>;
struct ParamField {
  std::string_view path;
  Limit limit;  // numbers and integers only
  FieldRef (*field)(ParamsFile&);
};

// Every parameter a file may set, in the order the messages list them.
std::span<const ParamField> param_fields();
// The field at `path`, or nullptr.
const ParamField* find_param(std::string_view path);
// The unit of a parameter for messages, from its key: "mm" (..._mm),
// "degrees" (..._deg), "" otherwise.
std::string_view unit_of(std::string_view path);

// The number syntax of the file (and of `vts track`'s options): an optional
// '+', then a finite decimal number, or an integer; nothing else around it.
std::optional<double> to_number(std::string_view text);
std::optional<long long> to_integer(std::string_view text);

// Reads the YAML `text` over `into`: the keys present replace their values,
// the others stay; an empty document changes nothing. Unknown and duplicate
// keys, values of the wrong type or out of their limits throw ParamsError
// naming `name`, the line and the key's path.
void read_params(std::string_view text, std::string_view name, ParamsFile& into);
// The same from a file; `file` names it in messages.
void read_params_file(const std::filesystem::path& file, ParamsFile& into);

}  // namespace vts::trackio
