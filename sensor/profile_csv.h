#pragma once
// Profiles as CSV text: the form a real sensor's recording is easily turned
// into (docs/CLI.md, `vts track`).
//
// Format. The first line is a header naming the columns, comma-separated,
// case-sensitive, in any order: `profile`, `y`, `z` (required) and `valid`
// (optional); any other name is an error. Every further line is one point:
// the profile index (an integer >= 0), y and z in mm (sensor frame: y along
// the laser line, z the range along the optical axis) and, with the `valid`
// column, 1 (measured) or 0 (no return). Rows are grouped by profile, in scan
// order within a profile; profile indices never decrease (they may skip).
// Profiles may have different numbers of points, at most kMaxPoints each.
// Fields may be surrounded by spaces; lines may end in CRLF. y and z must be
// finite, except on rows with valid = 0, where any number (also nan, inf) is
// accepted and stored as 0. Blank lines are allowed only at the end.
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sensor/profile.h"

namespace vts {

// Message: "FILE:LINE: FIELD: message", e.g.
// "rec.csv:17: z: 'abc' is not a number"; or "FILE: message" when the file
// cannot be opened.
struct CsvError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads every profile of the file. Each Profile has y_mm, z_mm, valid and
// range_mm = hypot(y, z) (0 where invalid) filled, every other per-column
// vector zeroed, `index` set to the file's profile index, an identity pose and
// time 0. Throws CsvError.
std::vector<Profile> read_profile_csv(const std::filesystem::path& path);
// The same from a stream; `name` is the file name used in messages.
std::vector<Profile> read_profile_csv(std::istream& in, const std::string& name);

// A CSV file read a batch of profiles at a time, in order: memory is one
// batch whatever the file's length. Messages as read_profile_csv's; an error
// further on in the file is thrown by the read() that reaches it.
class ProfileCsvReader {
 public:
  // Opens the file (or takes the stream; `name` is the file name used in
  // messages) and reads its header. Throws CsvError.
  explicit ProfileCsvReader(const std::filesystem::path& path);
  ProfileCsvReader(std::istream& in, const std::string& name);
  ~ProfileCsvReader();
  ProfileCsvReader(const ProfileCsvReader&) = delete;
  ProfileCsvReader& operator=(const ProfileCsvReader&) = delete;

  // The next profiles, at most max_profiles (>= 1), into `profiles`
  // (replacing its content), each as read_profile_csv gives it. Returns false,
  // `profiles` empty, at the end. Throws CsvError.
  bool read(std::vector<Profile>& profiles, int max_profiles);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes profiles in the format above with the `valid` column (header
// `profile,y,z,valid`), floats with 9 significant digits, so reading the text
// back gives the same y, z and valid bit for bit. Invalid points are written
// as 0,0.
void write_profile_csv(std::ostream& out, const std::vector<Profile>& profiles);

}  // namespace vts
