#include "sensor/profile_csv.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <string_view>
#include <system_error>

#include "sensor/scanner.h"

namespace vts {
namespace {

constexpr std::string_view kColumns[] = {"profile", "y", "z", "valid"};
constexpr int kProfile = 0, kY = 1, kZ = 2, kValid = 3;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

bool blank(std::string_view s) { return trim(s).empty(); }

// Splits on commas (no quoting: the format has only numbers).
void split(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  while (true) {
    const std::size_t comma = line.find(',');
    fields.push_back(trim(line.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
}

class Reader {
 public:
  explicit Reader(const std::string& name) : name_(name) {}

  [[noreturn]] void fail(long line, std::string_view field, const std::string& message) const {
    throw CsvError(name_ + ":" + std::to_string(line) + ": " + std::string(field) + ": " + message);
  }

  std::vector<Profile> read(std::istream& in) {
    std::string text;
    long line = 0;
    // Header.
    if (!std::getline(in, text)) fail(1, "header", "empty file, expected the header 'profile,y,z' (optionally ',valid')");
    ++line;
    if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // UTF-8 BOM
    if (blank(text)) fail(1, "header", "empty line, expected the header 'profile,y,z' (optionally ',valid')");
    std::vector<std::string_view> fields;
    split(text, fields);
    int at[4] = {-1, -1, -1, -1};
    for (int i = 0; i < static_cast<int>(fields.size()); ++i) {
      int which = -1;
      for (int k = 0; k < 4; ++k)
        if (fields[i] == kColumns[k]) which = k;
      if (which < 0)
        fail(line, "header",
             "unknown column '" + std::string(fields[i]) +
                 "': expected profile, y, z and optionally valid (names are case-sensitive)");
      if (at[which] >= 0) fail(line, "header", "column '" + std::string(fields[i]) + "' appears twice");
      at[which] = i;
    }
    for (int k = 0; k < 3; ++k)
      if (at[k] < 0) fail(line, "header", "missing column '" + std::string(kColumns[k]) + "'");
    const std::size_t width = fields.size();

    std::vector<Profile> out;
    long blank_line = 0;  // first blank line seen, 0 if none yet
    std::int64_t current = -1;
    long current_first_line = 0;
    while (std::getline(in, text)) {
      ++line;
      if (blank(text)) {
        if (!blank_line) blank_line = line;
        continue;
      }
      if (blank_line)
        fail(blank_line, "line", "blank line inside the data (blank lines are allowed only at the end)");
      split(text, fields);
      if (fields.size() != width)
        fail(line, "line",
             std::to_string(fields.size()) + " fields, expected " + std::to_string(width) + " as in the header");
      const std::int64_t index = parse_index(line, fields[at[kProfile]]);
      if (index < current)
        fail(line, "profile",
             std::to_string(index) + " after " + std::to_string(current) +
                 ": profile indices must not decrease (rows grouped by profile)");
      bool valid = true;
      if (at[kValid] >= 0) {
        const std::string_view v = fields[at[kValid]];
        if (v == "1") valid = true;
        else if (v == "0") valid = false;
        else fail(line, "valid", "'" + std::string(v) + "' is not 0 or 1");
      }
      const float y = parse_coordinate(line, "y", fields[at[kY]], valid);
      const float z = parse_coordinate(line, "z", fields[at[kZ]], valid);
      if (index != current || out.empty()) {
        out.emplace_back();
        out.back().index = index;
        current = index;
        current_first_line = line;
      }
      Profile& p = out.back();
      if (static_cast<int>(p.y_mm.size()) >= kMaxPoints)
        fail(line, "profile",
             "profile " + std::to_string(index) + " (from line " + std::to_string(current_first_line) +
                 ") has more than " + std::to_string(kMaxPoints) + " points");
      p.y_mm.push_back(valid ? y : 0.0f);
      p.z_mm.push_back(valid ? z : 0.0f);
      p.valid.push_back(valid ? 1 : 0);
    }
    if (in.bad()) throw CsvError(name_ + ": read error");
    if (out.empty()) fail(line + 1, "line", "no data rows after the header");
    // The remaining per-column vectors, sized like the points.
    for (Profile& p : out) {
      const int n = static_cast<int>(p.y_mm.size());
      std::vector<float> y = std::move(p.y_mm), z = std::move(p.z_mm);
      std::vector<std::uint8_t> v = std::move(p.valid);
      p.resize(n);
      p.y_mm = std::move(y);
      p.z_mm = std::move(z);
      p.valid = std::move(v);
      for (int i = 0; i < n; ++i)
        p.range_mm[i] = p.valid[i] ? static_cast<float>(std::hypot(double(p.y_mm[i]), double(p.z_mm[i]))) : 0.0f;
    }
    return out;
  }

 private:
  std::string name_;

  std::int64_t parse_index(long line, std::string_view s) const {
    std::int64_t v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec == std::errc::result_out_of_range) fail(line, "profile", "'" + std::string(s) + "' is out of range");
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || v < 0)
      fail(line, "profile", "'" + std::string(s) + "' is not an integer >= 0");
    return v;
  }

  float parse_coordinate(long line, std::string_view field, std::string_view s, bool valid) const {
    double v = 0.0;
    std::string_view t = s;
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ptr != t.data() + t.size() || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
      fail(line, field, "'" + std::string(s) + "' is not a number");
    if (!valid) return 0.0f;  // ignored; any number will do
    if (r.ec == std::errc() && !std::isfinite(v))
      fail(line, field, "'" + std::string(s) + "' is not finite (only rows with valid = 0 may hold nan or inf)");
    if (r.ec == std::errc::result_out_of_range || std::abs(v) > std::numeric_limits<float>::max())
      fail(line, field, "'" + std::string(s) + "' is out of range (mm, single precision)");
    return static_cast<float>(v);
  }
};

}  // namespace

std::vector<Profile> read_profile_csv(std::istream& in, const std::string& name) {
  return Reader(name).read(in);
}

std::vector<Profile> read_profile_csv(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw CsvError(path.string() + ": is a directory, expected a CSV file");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const std::string why = std::filesystem::exists(path, ec) ? "cannot open file" : "no such file";
    throw CsvError(path.string() + ": " + why);
  }
  return read_profile_csv(in, path.string());
}

void write_profile_csv(std::ostream& out, const std::vector<Profile>& profiles) {
  out << "profile,y,z,valid\n";
  char buf[96];
  for (const Profile& p : profiles) {
    const std::size_t n = std::min({p.y_mm.size(), p.z_mm.size(), p.valid.size()});
    for (std::size_t i = 0; i < n; ++i) {
      const bool v = p.valid[i] != 0;
      std::snprintf(buf, sizeof buf, "%lld,%.9g,%.9g,%d\n", static_cast<long long>(p.index),
                    v ? double(p.y_mm[i]) : 0.0, v ? double(p.z_mm[i]) : 0.0, v ? 1 : 0);
      out << buf;
    }
  }
}

}  // namespace vts
