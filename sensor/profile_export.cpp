#include "sensor/profile_export.h"

#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#include "common/atomic_file.h"
#include "sensor/npz.h"
#include "sensor/profile_csv.h"

namespace vts {
namespace {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little, "PLY and .npy data are written as in memory");

std::string where(const fs::path& path) { return "export '" + path.string() + "'"; }

// Throws unless every per-column vector the export reads has the scanner's
// number of points.
void check_sizes(const ProfileRecording& rec, const std::string& where) {
  const std::size_t n = static_cast<std::size_t>(rec.info.scanner.points);
  auto need = [&](const char* channel, std::size_t r, std::size_t size) {
    if (size != n)
      throw ExportError(where + ": channel " + channel + " of profile " + std::to_string(r) + " has " +
                        std::to_string(size) + " points, expected vts.scanner.points = " + std::to_string(n));
  };
  if (rec.info.has_reference && rec.reference.size() != rec.profiles.size())
    throw ExportError(where + ": the recording has " + std::to_string(rec.reference.size()) +
                      " reference profiles for " + std::to_string(rec.profiles.size()) + " profiles");
  for (std::size_t r = 0; r < rec.profiles.size(); ++r) {
    const Profile& p = rec.profiles[r];
    need("y", r, p.y_mm.size());
    need("z", r, p.z_mm.size());
    need("range", r, p.range_mm.size());
    need("valid", r, p.valid.size());
    if (rec.info.error_model) {
      need("intensity", r, p.intensity.size());
      need("true.y", r, p.true_y_mm.size());
      need("true.z", r, p.true_z_mm.size());
      need("true.valid", r, p.true_valid.size());
    }
    if (rec.info.has_reference) {
      const Profile& q = rec.reference[r];
      need("ref.y", r, q.y_mm.size());
      need("ref.z", r, q.z_mm.size());
      need("ref.range", r, q.range_mm.size());
      need("ref.valid", r, q.valid.size());
    }
  }
}

// One line of a PLY header comment: no line breaks.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

template <class T>
void append(std::string& b, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  b.append(bytes, sizeof(T));
}

}  // namespace

const char* export_format_name(ExportFormat format) {
  switch (format) {
    case ExportFormat::Csv: return "csv";
    case ExportFormat::Ply: return "ply";
    case ExportFormat::Npz: return "npz";
  }
  return "?";
}

std::optional<ExportFormat> export_format_named(std::string_view name) {
  for (ExportFormat f : {ExportFormat::Csv, ExportFormat::Ply, ExportFormat::Npz})
    if (name == export_format_name(f)) return f;
  return std::nullopt;
}

std::optional<ExportFormat> export_format_of(const fs::path& file) {
  std::string ext = file.extension().string();
  if (ext.empty()) return std::nullopt;
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return export_format_named(std::string_view(ext).substr(1));
}

void write_recording_csv(std::ostream& out, const ProfileRecording& rec) {
  check_sizes(rec, "export");
  write_profile_csv(out, rec.profiles);
}

void write_recording_ply(std::ostream& out, const ProfileRecording& rec) {
  check_sizes(rec, "export");
  const bool intensity = rec.info.error_model;
  std::size_t vertices = 0;
  for (const Profile& p : rec.profiles) vertices += static_cast<std::size_t>(p.valid_count());
  out << "ply\n"
      << "format binary_little_endian 1.0\n"
      << "comment vts point cloud: the valid points of a profile recording, world frame, mm (docs/CLI.md)\n"
      << "comment scanner: " << one_line(rec.info.scanner.name) << "\n"
      << "comment scene: " << one_line(rec.info.scene_name) << "\n"
      << "comment error_model: " << (rec.info.error_model ? "triangulation" : "ideal (no intensity)") << "\n"
      << "element vertex " << vertices << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property int profile\nproperty int column\n";
  if (intensity) out << "property float intensity\n";
  out << "end_header\n";
  std::string b;
  for (std::size_t r = 0; r < rec.profiles.size(); ++r) {
    const Profile& p = rec.profiles[r];
    b.clear();
    for (int i = 0; i < p.size(); ++i) {
      if (!p.valid[i]) continue;
      const Vec3 w = p.world_from_sensor * Vec3(0.0, p.y_mm[i], p.z_mm[i]);
      append(b, static_cast<float>(w.x()));
      append(b, static_cast<float>(w.y()));
      append(b, static_cast<float>(w.z()));
      append(b, static_cast<std::int32_t>(r));
      append(b, static_cast<std::int32_t>(i));
      if (intensity) append(b, p.intensity[i]);
    }
    out.write(b.data(), static_cast<std::streamsize>(b.size()));
  }
}

void write_recording_npz(std::ostream& out, const ProfileRecording& rec) {
  check_sizes(rec, "export");
  const std::int64_t rows = static_cast<std::int64_t>(rec.profiles.size());
  const std::int64_t n = rec.info.scanner.points;
  NpzWriter npz(out);
  // A (rows, n) array of one per-column vector of every profile.
  auto columns = [&](const char* name, const std::vector<Profile>& profiles, auto member, const char* descr) {
    using T = typename std::remove_reference_t<decltype(profiles[0].*member)>::value_type;
    npz.add(name, descr, {rows, n}, sizeof(T), [&](const NpzWriter::Sink& sink) {
      for (const Profile& p : profiles) sink((p.*member).data(), (p.*member).size() * sizeof(T));
    });
  };
  columns("y", rec.profiles, &Profile::y_mm, "<f4");
  columns("z", rec.profiles, &Profile::z_mm, "<f4");
  columns("range", rec.profiles, &Profile::range_mm, "<f4");
  columns("valid", rec.profiles, &Profile::valid, "|b1");  // bytes 0 and 1
  if (rec.info.error_model) {
    columns("intensity", rec.profiles, &Profile::intensity, "<f4");
    columns("true_y", rec.profiles, &Profile::true_y_mm, "<f4");
    columns("true_z", rec.profiles, &Profile::true_z_mm, "<f4");
    columns("true_valid", rec.profiles, &Profile::true_valid, "|b1");
  }
  if (rec.info.has_reference) {
    columns("ref_y", rec.reference, &Profile::y_mm, "<f4");
    columns("ref_z", rec.reference, &Profile::z_mm, "<f4");
    columns("ref_range", rec.reference, &Profile::range_mm, "<f4");
    columns("ref_valid", rec.reference, &Profile::valid, "|b1");
  }
  npz.add("pose", "<f8", {rows, 7}, sizeof(double), [&](const NpzWriter::Sink& sink) {
    for (std::int64_t r = 0; r < rows; ++r) sink(recording_row_values(rec, r).data(), 7 * sizeof(double));
  });
  npz.add("time", "<f8", {rows}, sizeof(double), [&](const NpzWriter::Sink& sink) {
    for (std::int64_t r = 0; r < rows; ++r) {
      const double t = recording_row_values(rec, r)[7];
      sink(&t, sizeof t);
    }
  });
  nlohmann::ordered_json header = nlohmann::ordered_json::object();
  for (const auto& [name, value] : profile_attributes(rec.info)) header[name] = value;
  npz.add_string("header", header.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
  npz.finish();
}

void export_recording(const ProfileRecording& rec, const fs::path& path, ExportFormat format) {
  check_sizes(rec, where(path));
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ExportError(where(path) + ": is a directory, expected a file name");
  AtomicFile file(path);
  if (!file.is_open())
    throw ExportError(where(path) + ": cannot create '" + file.temp_path().string() + "': " + std::strerror(errno));
  switch (format) {
    case ExportFormat::Csv: write_recording_csv(file.stream(), rec); break;
    case ExportFormat::Ply: write_recording_ply(file.stream(), rec); break;
    case ExportFormat::Npz: write_recording_npz(file.stream(), rec); break;
  }
  try {
    file.commit();
  } catch (const std::exception& e) {
    throw ExportError(where(path) + ": " + e.what());
  }
}

}  // namespace vts
