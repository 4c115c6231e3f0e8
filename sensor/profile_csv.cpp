#include "sensor/profile_csv.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <limits>
#include <memory>
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
  Reader(std::istream& in, const std::string& name) : in_(in), name_(name) {}

  [[noreturn]] void fail(long line, std::string_view field, const std::string& message) const {
    throw CsvError(name_ + ":" + std::to_string(line) + ": " + std::string(field) + ": " + message);
  }

  void read_header() {
    // Header.
    if (!std::getline(in_, text_)) fail(1, "header", "empty file, expected the header 'profile,y,z' (optionally ',valid')");
    ++line_;
    if (text_.size() >= 3 && text_.compare(0, 3, "\xEF\xBB\xBF") == 0) text_.erase(0, 3);  // UTF-8 BOM
    if (blank(text_)) fail(1, "header", "empty line, expected the header 'profile,y,z' (optionally ',valid')");
    split(text_, fields_);
    for (int i = 0; i < static_cast<int>(fields_.size()); ++i) {
      int which = -1;
      for (int k = 0; k < 4; ++k)
        if (fields_[i] == kColumns[k]) which = k;
      if (which < 0)
        fail(line_, "header",
             "unknown column '" + std::string(fields_[i]) +
                 "': expected profile, y, z and optionally valid (names are case-sensitive)");
      if (at_[which] >= 0) fail(line_, "header", "column '" + std::string(fields_[i]) + "' appears twice");
      at_[which] = i;
    }
    for (int k = 0; k < 3; ++k)
      if (at_[k] < 0) fail(line_, "header", "missing column '" + std::string(kColumns[k]) + "'");
    width_ = fields_.size();
  }

  // Up to max_profiles (>= 1) further profiles into `out`; false at the end.
  // A profile is complete when a row of the next one, or the end, is read.
  bool read(std::vector<Profile>& out, std::size_t max_profiles) {
    out.clear();
    while (!done_ && out.size() < max_profiles) {
      if (!std::getline(in_, text_)) {
        if (in_.bad()) throw CsvError(name_ + ": read error");
        if (!seen_) fail(line_ + 1, "line", "no data rows after the header");
        done_ = true;
        out.push_back(finished(std::move(pending_)));
        break;
      }
      ++line_;
      if (blank(text_)) {
        if (!blank_line_) blank_line_ = line_;
        continue;
      }
      if (blank_line_)
        fail(blank_line_, "line", "blank line inside the data (blank lines are allowed only at the end)");
      split(text_, fields_);
      if (fields_.size() != width_)
        fail(line_, "line",
             std::to_string(fields_.size()) + " fields, expected " + std::to_string(width_) + " as in the header");
      const std::int64_t index = parse_index(line_, fields_[at_[kProfile]]);
      if (index < current_)
        fail(line_, "profile",
             std::to_string(index) + " after " + std::to_string(current_) +
                 ": profile indices must not decrease (rows grouped by profile)");
      bool valid = true;
      if (at_[kValid] >= 0) {
        const std::string_view v = fields_[at_[kValid]];
        if (v == "1") valid = true;
        else if (v == "0") valid = false;
        else fail(line_, "valid", "'" + std::string(v) + "' is not 0 or 1");
      }
      const float y = parse_coordinate(line_, "y", fields_[at_[kY]], valid);
      const float z = parse_coordinate(line_, "z", fields_[at_[kZ]], valid);
      if (index != current_ || !seen_) {
        if (seen_) out.push_back(finished(std::move(pending_)));
        pending_ = Profile();
        pending_.index = index;
        current_ = index;
        current_first_line_ = line_;
        seen_ = true;
      }
      Profile& p = pending_;
      if (static_cast<int>(p.y_mm.size()) >= kMaxPoints)
        fail(line_, "profile",
             "profile " + std::to_string(index) + " (from line " + std::to_string(current_first_line_) +
                 ") has more than " + std::to_string(kMaxPoints) + " points");
      p.y_mm.push_back(valid ? y : 0.0f);
      p.z_mm.push_back(valid ? z : 0.0f);
      p.valid.push_back(valid ? 1 : 0);
    }
    return !out.empty();
  }

 private:
  std::istream& in_;
  std::string name_;
  std::string text_;
  std::vector<std::string_view> fields_;
  long line_ = 0;
  int at_[4] = {-1, -1, -1, -1};
  std::size_t width_ = 0;
  long blank_line_ = 0;  // first blank line seen, 0 if none yet
  std::int64_t current_ = -1;
  long current_first_line_ = 0;
  bool seen_ = false;  // a data row was read
  bool done_ = false;  // the end was read
  Profile pending_;    // the profile being read

  // The remaining per-column vectors, sized like the points.
  static Profile finished(Profile p) {
    const int n = static_cast<int>(p.y_mm.size());
    std::vector<float> y = std::move(p.y_mm), z = std::move(p.z_mm);
    std::vector<std::uint8_t> v = std::move(p.valid);
    p.resize(n);
    p.y_mm = std::move(y);
    p.z_mm = std::move(z);
    p.valid = std::move(v);
    for (int i = 0; i < n; ++i)
      p.range_mm[i] = p.valid[i] ? static_cast<float>(std::hypot(double(p.y_mm[i]), double(p.z_mm[i]))) : 0.0f;
    return p;
  }

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

struct ProfileCsvReader::Impl {
  std::ifstream file;
  Reader reader;
  Impl(std::istream& in, const std::string& name) : reader(in, name) {}
  explicit Impl(const std::filesystem::path& path) : file(path, std::ios::binary), reader(file, path.string()) {}
};

ProfileCsvReader::ProfileCsvReader(std::istream& in, const std::string& name)
    : impl_(std::make_unique<Impl>(in, name)) {
  impl_->reader.read_header();
}

ProfileCsvReader::ProfileCsvReader(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw CsvError(path.string() + ": is a directory, expected a CSV file");
  impl_ = std::make_unique<Impl>(path);
  if (!impl_->file) {
    const std::string why = std::filesystem::exists(path, ec) ? "cannot open file" : "no such file";
    throw CsvError(path.string() + ": " + why);
  }
  impl_->reader.read_header();
}

ProfileCsvReader::~ProfileCsvReader() = default;

bool ProfileCsvReader::read(std::vector<Profile>& profiles, int max_profiles) {
  return impl_->reader.read(profiles, static_cast<std::size_t>(std::max(max_profiles, 1)));
}

namespace {

std::vector<Profile> read_all(ProfileCsvReader& reader) {
  std::vector<Profile> all, batch;
  while (reader.read(batch, 1 << 16))
    for (Profile& p : batch) all.push_back(std::move(p));
  return all;
}

}  // namespace

std::vector<Profile> read_profile_csv(std::istream& in, const std::string& name) {
  ProfileCsvReader reader(in, name);
  return read_all(reader);
}

std::vector<Profile> read_profile_csv(const std::filesystem::path& path) {
  ProfileCsvReader reader(path);
  return read_all(reader);
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
