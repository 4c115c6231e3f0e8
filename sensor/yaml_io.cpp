#include "sensor/yaml_io.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <limits>
#include <system_error>

namespace vts::yaml_io {

std::string error_text(const std::string& file, int line, const std::string& field, const std::string& message) {
  std::string s = file + ":" + std::to_string(line) + ": ";
  if (!field.empty()) s += field + ": ";
  return s + message;
}

std::string num(double v) {
  std::array<char, 64> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char hex[8];
          std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned>(c));
          out += hex;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s;
}

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null: return "nothing";
    case YAML::NodeType::Sequence: return "a list of " + std::to_string(n.size());
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Scalar: return "'" + n.Scalar() + "'";
    default: return "an undefined node";
  }
}

Reader::Map::Map(const Reader& r, const Field& f, std::vector<std::string> allowed)
    : reader_(r), self_(f), allowed_(std::move(allowed)) {
  if (!f.node.IsMap()) r.fail(f, "expected a map, got " + describe(f.node));
  for (const auto& kv : f.node) {
    const YAML::Node key = kv.first;
    const YAML::Node value = kv.second;
    const int key_line = key.Mark().line + 1;
    if (!key.IsScalar()) r.fail(key_line, f.path, "keys must be plain names, got " + describe(key));
    const std::string name = key.Scalar();
    const std::string path = f.path.empty() ? name : f.path + "." + name;
    bool known = false;
    for (const auto& a : allowed_) known = known || a == name;
    if (!known) r.fail(key_line, path, "unknown key (expected one of: " + join(allowed_) + ")");
    for (const auto& e : entries_)
      if (e.first == name)
        r.fail(key_line, path, "duplicate key (first given on line " + std::to_string(e.second.key_line) + ")");
    entries_.emplace_back(name, Field{value, path, key_line});
  }
}

std::optional<Field> Reader::Map::get(std::string_view name) const {
  for (const auto& e : entries_)
    if (e.first == name) return e.second;
  return std::nullopt;
}

Field Reader::Map::require(std::string_view name) const {
  if (auto f = get(name)) return *f;
  const std::string path = self_.path.empty() ? std::string(name) : self_.path + "." + std::string(name);
  reader_.fail(self_.line(), path, "missing (required)");
}

std::string Reader::scalar_text(const Field& f, const char* expected) const {
  // Quoted scalars ('5', "5") are strings in YAML: tag "!".
  if (!f.node.IsScalar() || f.node.Tag() == "!")
    fail(f, std::string("expected ") + expected + ", got " + describe(f.node));
  return f.node.Scalar();
}

std::optional<double> Reader::try_number(const Field& f) const {
  if (!f.node.IsScalar() || f.node.Tag() == "!") return std::nullopt;
  const std::string s = f.node.Scalar();
  // YAML's special floats, which strtod does not know.
  static const std::pair<std::string_view, double> specials[] = {
      {".nan", NAN},       {".NaN", NAN},       {".NAN", NAN},       {".inf", INFINITY},
      {".Inf", INFINITY},  {".INF", INFINITY},  {"+.inf", INFINITY}, {"+.Inf", INFINITY},
      {"+.INF", INFINITY}, {"-.inf", -INFINITY}, {"-.Inf", -INFINITY}, {"-.INF", -INFINITY}};
  for (const auto& [text, value] : specials)
    if (s == text) return value;
  if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

double Reader::number(const Field& f) const {
  const std::string s = scalar_text(f, "a number");
  const auto v = try_number(f);
  if (!v) fail(f, "expected a number, got " + describe(f.node));
  if (!std::isfinite(*v)) fail(f, "must be a finite number, got '" + s + "'");
  return *v;
}

long long Reader::integer(const Field& f) const {
  std::string s = scalar_text(f, "an integer");
  if (!s.empty() && s.front() == '+') s.erase(0, 1);
  long long v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec == std::errc::result_out_of_range) fail(f, "integer out of range: '" + s + "'");
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) fail(f, "expected an integer, got " + describe(f.node));
  return v;
}

int Reader::int_field(const Field& f, std::string_view key) const {
  const long long v = integer(f);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail(f, std::string(key) + " = " + std::to_string(v) + ": out of range");
  return static_cast<int>(v);
}

std::string Reader::string(const Field& f) const {
  if (!f.node.IsScalar()) fail(f, "expected a string, got " + describe(f.node));
  return f.node.Scalar();
}

Vec3 Reader::vec3(const Field& f) const {
  if (!f.node.IsSequence() || f.node.size() != 3)
    fail(f, "expected a list of 3 numbers [x, y, z], got " + describe(f.node));
  Vec3 v;
  for (std::size_t i = 0; i < 3; ++i)
    v[static_cast<int>(i)] = number(Field{f.node[i], f.path + "[" + std::to_string(i) + "]", 0, f.line()});
  return v;
}

bool Reader::boolean(const Field& f) const {
  const std::string s = scalar_text(f, "true or false");
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  fail(f, "expected true or false, got " + describe(f.node));
}

void Reader::fail_validation(const Map& m, const std::string& message) const {
  const std::string name = message.substr(0, message.find_first_of(" =:"));
  if (auto f = m.get(name)) fail(*f, message);
  const std::string& base = m.self().path;
  fail(m.self().line(), base.empty() ? name : base + "." + name, message);
}

YAML::Node Reader::load(const std::string& text) const {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    fail(e.mark.line + 1, "", "YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    fail(e.mark.line + 1, "", std::string("YAML error: ") + e.what());
  }
}

std::string Reader::read_file(const std::filesystem::path& path, std::string_view what) const {
  const std::string w(what);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(0, "", w + " file not found");
  if (std::filesystem::is_directory(path, ec)) fail(0, "", "is a directory, not a " + w + " file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(0, "", "cannot open " + w + " file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail(0, "", "read error");
  return text.str();
}

bool Reader::has_key(const YAML::Node& map, std::string_view name) {
  if (!map.IsMap()) return false;
  for (const auto& kv : map)
    if (kv.first.IsScalar() && kv.first.Scalar() == name) return true;
  return false;
}

}  // namespace vts::yaml_io
