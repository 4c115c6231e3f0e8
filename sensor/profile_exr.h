#pragma once
// vts profile EXR files: one row per profile, one column per point.
// Layout and attributes are documented in docs/EXR_FORMAT.md.
//
// Version 2 (`vts.format` = "vts-profiles 2", written): a two-part file
// without subsampled channels, which OpenImageIO and every other OpenEXR 2+
// reader opens. Part 0 "profiles" (width = points, one row per profile),
// channels FLOAT: range, y, z, valid; with a reference source also ref.range,
// ref.y, ref.z, ref.valid; with the error model on also intensity, true.y,
// true.z, true.valid (the ideal point). Part 1 "rows" (width 1, one row per
// profile): pose.tx, pose.ty, pose.tz (mm, world), pose.qw, pose.qx, pose.qy,
// pose.qz (world_from_sensor rotation, w >= 0), time (s). These per-row values
// are doubles in Profile; the FLOAT channels hold them rounded to float, and
// UINT channels f64hi.<name> and f64lo.<name> hold the high and low 32 bits of
// the IEEE binary64 value, so poses and times round-trip exactly.
//
// Version 1 ("vts-profiles 1", still read): one part holding both, the
// per-row channels x-subsampled (xSampling = width).
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sensor/profile.h"
#include "sensor/scanner.h"

namespace vts {

struct ExrError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ProfileFileInfo {
  ScannerDesc scanner;
  std::string scene_name;  // cell name or scene file path
  std::string scene_text;  // the scene as YAML (docs/SCENE_FORMAT.md)
  int profiles = 0;        // rows
  bool has_reference = false;
  // The main (and ref.*) channels hold measured profiles (sensor/error_model.h),
  // and intensity, true.y, true.z, true.valid are present; attribute
  // vts.error_model. On reading, scanner.ideal = !error_model.
  bool error_model = false;
  std::uint64_t seed = 0;  // seed of the sensor error model's random draws
};

// How the writer compresses both parts: OpenEXR's lossless methods.
// Zip (the default): zlib over blocks of 16 rows, the smallest files of
// these; Zips: zlib row by row; Piz: wavelet and Huffman over blocks of 32
// rows; Rle: run lengths; None: stored as is, the fastest to write and to
// read (docs/EXR_FORMAT.md and docs/PERFORMANCE.md give sizes and speeds).
// Every reader of vts files reads them all.
enum class ExrCompression { Zip, Zips, Piz, Rle, None };
// "zip", "zips", "piz", "rle", "none".
std::string_view to_string(ExrCompression compression);
// The method named `name` (as to_string writes it), or none.
std::optional<ExrCompression> exr_compression_from_string(std::string_view name);
// Every method's name, the default first.
std::vector<std::string> exr_compression_names();

// Streams rows to `path + ".tmp-<pid>"` and renames onto `path` in finish().
// Destroying an unfinished writer removes the temporary file, so `path` never
// holds a half-written file. Memory stays constant in the number of rows.
// Every failure throws ExrError naming `path`.
class ProfileExrWriter {
 public:
  // info.profiles (>= 1) rows will be written; info.scanner.points columns.
  // Creates the parent directory if needed; throws if info.scanner is not
  // valid (vts::validate) or the file cannot be created.
  ProfileExrWriter(const std::filesystem::path& path, const ProfileFileInfo& info,
                   ExrCompression compression = ExrCompression::Zip);
  ~ProfileExrWriter();
  ProfileExrWriter(const ProfileExrWriter&) = delete;
  ProfileExrWriter& operator=(const ProfileExrWriter&) = delete;

  // Row `profile.index` is written; rows must come in order 0, 1, 2, ...
  // `reference` is required iff info.has_reference; only its samples are
  // stored (it shares the row's pose and time). Throws, writing nothing, on a
  // row out of order, a row beyond info.profiles or a profile whose size is
  // not info.scanner.points (or, with info.error_model, that lacks intensity
  // and true.*).
  void write(const Profile& profile, const Profile* reference = nullptr);
  // Throws ExrError if fewer rows than announced were written, and then
  // removes the temporary file at once. A second call does nothing.
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct ProfileRecording {
  ProfileFileInfo info;
  std::vector<Profile> profiles;   // index = row
  std::vector<Profile> reference;  // empty unless info.has_reference; pose,
                                   // time and index copied from `profiles`
  // Per row, the doubles the file stores (profile_row_values' order);
  // profiles[r].world_from_sensor and time_s are made from them. Filled by
  // read_profile_exr; empty in a recording made otherwise.
  std::vector<std::array<double, 8>> row_values;
};

// A row's per-row values in the file's terms: pose.tx, pose.ty, pose.tz (mm),
// pose.qw, pose.qx, pose.qy, pose.qz (rotation_quat of world_from_sensor,
// w >= 0), time (s).
std::array<double, 8> profile_row_values(const Profile& p);
// The row values of `rec`'s row r: rec.row_values[r] when read from a file,
// else profile_row_values(rec.profiles[r]).
std::array<double, 8> recording_row_values(const ProfileRecording& rec, std::size_t r);

// The string attributes that describe a recording (vts.units, vts.frame,
// vts.columns, vts.scanner.*, vts.error_model, vts.scene.*, vts.reference,
// vts.seed), name and value, as the writer stores them in part "profiles";
// the writer adds vts.format and comments. For exports (sensor/profile_export.h).
std::vector<std::pair<std::string, std::string>> profile_attributes(const ProfileFileInfo& info);

// A profile EXR read a block of rows at a time, in order: memory is one
// block (and OpenEXR's buffers) whatever the number of rows. Failures throw
// the ExrError read_profile_exr gives for them; a file whose pixels are bad
// further on reads well up to the block that holds them.
class ProfileExrReader {
 public:
  // Opens the file and reads and checks its header (everything
  // read_profile_exr checks before the pixels).
  explicit ProfileExrReader(const std::filesystem::path& path);
  ~ProfileExrReader();
  ProfileExrReader(const ProfileExrReader&) = delete;
  ProfileExrReader& operator=(const ProfileExrReader&) = delete;

  const ProfileFileInfo& info() const;
  // Rows read so far: the next row's index.
  int rows_read() const;
  // Reads the next min(max_rows, rows left) rows into `profiles`, resized to
  // that count (their storage is reused from call to call) and, when given,
  // their reference profiles (empty unless info().has_reference) and row
  // values (as ProfileRecording's). Returns the count, 0 at the end.
  int read(int max_rows, std::vector<Profile>& profiles, std::vector<Profile>* reference = nullptr,
           std::vector<std::array<double, 8>>* row_values = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Reads the whole file (a ProfileExrReader read at once). Throws ExrError with a message naming the file and
// what is wrong with it (missing file, not an EXR, truncated, missing channel,
// wrong width, bad attribute value).
ProfileRecording read_profile_exr(const std::filesystem::path& path);

}  // namespace vts
