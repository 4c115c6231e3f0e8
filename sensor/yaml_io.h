#pragma once
// Reading and writing vts's YAML files (scene files, sensor/scene_file.h;
// dataset specs, dataset/spec.h) the same strict way: every value is
// type-checked, unknown and duplicate keys are errors, and each message names
// the file, the line and the dotted field path ("workpieces[0].gap_mm").
// Numbers are written in the shortest form that reads back to the same double.
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "sensor/pose.h"

namespace vts::yaml_io {

// "FILE:LINE: FIELD: message" (no "FIELD: " when field is empty): how
// every reader's error reads.
std::string error_text(const std::string& file, int line, const std::string& field, const std::string& message);
// Shortest text that parses back to exactly `v` (std::to_chars).
std::string num(double v);
// A double-quoted YAML string with its escapes.
std::string quoted(std::string_view s);
// "a, b, c"
std::string join(const std::vector<std::string>& names);
// How a node looks, for "expected X, got Y" messages.
std::string describe(const YAML::Node& n);

// A value together with where it sits in the file and its dotted field path.
// Map values are reported at their key's line (a block list or map value
// starts on the next line; a null value carries the mark of the next token);
// list items at their own line, or the list's line if they are null.
struct Field {
  YAML::Node node;
  std::string path;
  int key_line = 0;     // 1-based line of the key; 0 for list items
  int parent_line = 0;  // 1-based line of the enclosing list, for null items

  int line() const {
    if (key_line > 0) return key_line;
    if (node.IsNull() || node.Mark().line < 0) return parent_line;
    return node.Mark().line + 1;
  }
};

// The checks every reader shares; a file format derives from it and throws
// its own error type from fail().
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  virtual ~Reader() = default;

  // Throws the format's error (raise()): "FILE:LINE: FIELD: message".
  [[noreturn]] void fail(int line, const std::string& field, const std::string& msg) const {
    raise(line, field, msg);
    std::abort();  // raise() always throws
  }
  [[noreturn]] void fail(const Field& f, const std::string& msg) const { fail(f.line(), f.path, msg); }

  // A map's entries, checked against the allowed keys (unknown and duplicate
  // keys are errors), looked up by name.
  class Map {
   public:
    Map(const Reader& r, const Field& f, std::vector<std::string> allowed);
    std::optional<Field> get(std::string_view name) const;
    Field require(std::string_view name) const;
    const Field& self() const { return self_; }
    // The entries in file order.
    const std::vector<std::pair<std::string, Field>>& entries() const { return entries_; }

   private:
    const Reader& reader_;
    Field self_;
    std::vector<std::string> allowed_;
    std::vector<std::pair<std::string, Field>> entries_;
  };

  // The scalar's text; quoted scalars ('5', "5") are strings, not numbers.
  std::string scalar_text(const Field& f, const char* expected) const;
  // The scalar as a number (YAML's special floats too); nullopt if it is not one.
  std::optional<double> try_number(const Field& f) const;
  double number(const Field& f) const;  // finite
  long long integer(const Field& f) const;
  // An integer that fits an int; `key` names it in the message.
  int int_field(const Field& f, std::string_view key) const;
  std::string string(const Field& f) const;
  Vec3 vec3(const Field& f) const;  // [x, y, z]
  bool boolean(const Field& f) const;

  // Turns a validate() message ("gap_mm = -1: must be >= 0") into an error at
  // the named field's node, or at the enclosing map if the field was not given.
  [[noreturn]] void fail_validation(const Map& m, const std::string& message) const;

  // Parses `text`; a YAML syntax error is a fail() at its line.
  YAML::Node load(const std::string& text) const;
  // The file's text; fail() at line 0 when it is missing, a directory or
  // unreadable ("WHAT file not found", "is a directory, not a WHAT file").
  std::string read_file(const std::filesystem::path& path, std::string_view what) const;

  static bool has_key(const YAML::Node& map, std::string_view name);
  const std::string& file() const { return file_; }

 protected:
  // Throws the format's error type; never returns.
  virtual void raise(int line, const std::string& field, const std::string& msg) const = 0;
  std::string file_;
};

}  // namespace vts::yaml_io
