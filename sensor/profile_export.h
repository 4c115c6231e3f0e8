#pragma once
// A profile recording (sensor/profile_exr.h) in the formats other tools read
// (docs/CLI.md, `vts export`):
//
//   csv  the columns `vts track` reads: profile,y,z,valid, one line per point,
//        sensor frame (sensor/profile_csv.h); poses, times, the reference and
//        the ground truth are not in it.
//   ply  a point cloud, binary little-endian: one vertex per valid point of
//        the main channels, in the world frame (the row's pose applied to the
//        sensor-frame point (0, y, z)), with its profile (row) and column, and
//        its intensity when the recording has the error model's channels (no
//        intensity property otherwise). Header comments name the scanner, the
//        scene and the error model.
//   npz  NumPy arrays (numpy.load): every per-point channel as a
//        (profiles, points) array, the per-row poses and times as doubles,
//        and the recording's attributes as JSON (write_recording_npz).
#include <filesystem>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sensor/profile_exr.h"

namespace vts {

enum class ExportFormat { Csv, Ply, Npz };

// "csv", "ply", "npz".
const char* export_format_name(ExportFormat format);
// The format of that name (lower case), if any.
std::optional<ExportFormat> export_format_named(std::string_view name);
// The format of the file's extension, any case (.csv, .ply, .npz), if any.
std::optional<ExportFormat> export_format_of(const std::filesystem::path& file);

// Message: "export 'PATH': WHY".
struct ExportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes `rec` to `path` in `format` through a temporary file in the same
// directory (common/atomic_file.h), renamed onto `path` when complete: `path`
// is written whole or not at all. The directory must exist. Throws
// ExportError naming `path` when it cannot be written, or when the
// recording's profiles do not all have info.scanner.points points.
void export_recording(const ProfileRecording& rec, const std::filesystem::path& path, ExportFormat format);

// The writers behind it, to any stream. Each throws ExportError("export: ...")
// for profiles of the wrong size.
void write_recording_csv(std::ostream& out, const ProfileRecording& rec);
void write_recording_ply(std::ostream& out, const ProfileRecording& rec);
// Arrays, (P, N) with P profiles of N points, float32 unless said:
//   y, z, range; valid (bool)                      the main channels
//   intensity, true_y, true_z; true_valid (bool)   with the error model only
//   ref_y, ref_z, ref_range; ref_valid (bool)      with the reference only
//   pose  (P, 7) float64: tx, ty, tz (mm), qw, qx, qy, qz (world_from_sensor)
//   time  (P,) float64, s
//   header  0-d unicode string: a JSON object of the recording's attributes
//           (profile_attributes: vts.scanner.*, vts.scene.name, vts.scene.yaml, ...)
void write_recording_npz(std::ostream& out, const ProfileRecording& rec);

}  // namespace vts
