#include "sensor/mesh_file.h"

#include <unistd.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

namespace vts {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

[[noreturn]] void fail(const fs::path& path, const std::string& message) {
  throw MeshFileError(path.string() + ": " + message);
}

// ".stl", ".obj" or ".ply" from the path, else a MeshFileError.
std::string mesh_extension(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".stl" || ext == ".obj" || ext == ".ply") return ext;
  if (ext.empty()) fail(path, "no file extension (expected " + std::string(kMeshFileTypes) + ")");
  fail(path, "unsupported mesh file type '" + path.extension().string() + "' (expected " +
                 std::string(kMeshFileTypes) + ")");
}

// Welds vertices by exact position (-0 and +0 are one position).
struct PositionKey {
  std::array<std::uint32_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
PositionKey key_of(const Eigen::Vector3f& p) {
  return {{std::bit_cast<std::uint32_t>(p.x() + 0.0f), std::bit_cast<std::uint32_t>(p.y() + 0.0f),
           std::bit_cast<std::uint32_t>(p.z() + 0.0f)}};
}

class MeshBuilder {
 public:
  explicit MeshBuilder(MeshLoadStats& stats) : stats_(stats) {}

  void add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
    ++stats_.triangles_read;
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) {
      ++stats_.skipped_degenerate;
      return;
    }
    const Eigen::Vector3d da = a.cast<double>(), db = b.cast<double>(), dc = c.cast<double>();
    const double longest_sq =
        std::max({(db - da).squaredNorm(), (dc - db).squaredNorm(), (da - dc).squaredNorm()});
    // Zero area, including a repeated vertex: twice the area no more than
    // 1e-12 of the longest edge squared (collinear to rounding).
    if ((db - da).cross(dc - da).norm() <= 1e-12 * longest_sq) {
      ++stats_.skipped_degenerate;
      return;
    }
    mesh_.triangles.push_back({index(a), index(b), index(c)});
  }

  Mesh take() { return std::move(mesh_); }

 private:
  std::uint32_t index(const Eigen::Vector3f& p) {
    const auto [it, inserted] = ids_.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p + Eigen::Vector3f::Zero());
    return it->second;
  }

  MeshLoadStats& stats_;
  Mesh mesh_;
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> ids_;
};

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return e;
}

// Every mesh of `node` and its children, each vertex through the product of
// the transforms from the root down, then scaled to mm.
void collect(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent, double scale,
             MeshBuilder& out, MeshLoadStats& stats, std::vector<Eigen::Vector3f>& positions) {
  const Eigen::Matrix4d transform = parent * to_eigen(node.mTransformation);
  const Eigen::Matrix4d to_mm = Eigen::Vector4d(scale, scale, scale, 1.0).asDiagonal() * transform;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    if (node.mMeshes[k] >= scene.mNumMeshes) continue;
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[k]];
    positions.resize(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      const Eigen::Vector4d q = to_mm * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
      positions[v] = (q.head<3>() / q.w()).cast<float>();
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices < 3) {
        ++stats.ignored_primitives;
        continue;
      }
      bool in_range = true;
      for (unsigned i = 0; i < face.mNumIndices; ++i) in_range = in_range && face.mIndices[i] < mesh.mNumVertices;
      if (!in_range) {  // assimp validates this; counted as degenerate if it ever happens
        stats.triangles_read += face.mNumIndices - 2;
        stats.skipped_degenerate += face.mNumIndices - 2;
        continue;
      }
      // Triangulate leaves only triangles; a polygon is fanned just in case.
      for (unsigned i = 1; i + 1 < face.mNumIndices; ++i)
        out.add_triangle(positions[face.mIndices[0]], positions[face.mIndices[i]],
                         positions[face.mIndices[i + 1]]);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    if (node.mChildren[c]) collect(scene, *node.mChildren[c], transform, scale, out, stats, positions);
}

// ---- writing ----

class LittleEndianBuffer {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) { for (int i = 0; i < 2; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i))); }
  void u32(std::uint32_t v) { for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i))); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void text(std::string_view s) { bytes_.append(s); }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

// The temporary file: removed unless committed.
class TempFile {
 public:
  explicit TempFile(const fs::path& path) : path_(path), tmp_(path) {
    tmp_ += ".tmp-" + std::to_string(::getpid());
    file_ = std::fopen(tmp_.c_str(), "wb");
    if (!file_) fail(path_, "cannot create '" + tmp_.string() + "': " + std::strerror(errno));
  }
  ~TempFile() {
    if (file_) std::fclose(file_);
    if (!committed_) {
      std::error_code ec;
      fs::remove(tmp_, ec);
    }
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  // Writes and empties the buffer.
  void flush(std::string& bytes) {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
      fail(path_, "write to '" + tmp_.string() + "' failed: " + std::strerror(errno));
    bytes.clear();
  }
  void commit() {
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (rc != 0) fail(path_, "write to '" + tmp_.string() + "' failed: " + std::strerror(errno));
    std::error_code ec;
    fs::rename(tmp_, path_, ec);
    if (ec) fail(path_, "cannot rename '" + tmp_.string() + "' onto it: " + ec.message());
    committed_ = true;
  }

 private:
  fs::path path_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

constexpr std::size_t kFlushBytes = 1 << 20;

void write_stl(const fs::path& path, const Mesh& mesh) {
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    fail(path, "too many triangles for binary STL (" + std::to_string(mesh.triangles.size()) + ")");
  TempFile file(path);
  LittleEndianBuffer out;
  // The header must not begin with "solid" (ASCII STL's keyword).
  std::string header = "binary STL written by vts, units: mm";
  header.resize(80, ' ');
  out.text(header);
  out.u32(static_cast<std::uint32_t>(mesh.triangles.size()));
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f& a = mesh.vertices[t[0]];
    const Eigen::Vector3f& b = mesh.vertices[t[1]];
    const Eigen::Vector3f& c = mesh.vertices[t[2]];
    Eigen::Vector3d n = (b - a).cast<double>().cross((c - a).cast<double>());
    n = n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) out.f32(static_cast<float>(n[i]));
    for (const Eigen::Vector3f* v : {&a, &b, &c})
      for (int i = 0; i < 3; ++i) out.f32((*v)[i]);
    out.u16(0);
    if (out.bytes().size() >= kFlushBytes) file.flush(out.bytes());
  }
  file.flush(out.bytes());
  file.commit();
}

void write_ply(const fs::path& path, const Mesh& mesh) {
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max() ||
      mesh.vertices.size() > std::numeric_limits<std::uint32_t>::max())
    fail(path, "too many vertices or triangles for PLY");
  TempFile file(path);
  LittleEndianBuffer out;
  out.text("ply\nformat binary_little_endian 1.0\ncomment written by vts, units: mm\n");
  out.text("element vertex " + std::to_string(mesh.vertices.size()) + "\n");
  out.text("property float x\nproperty float y\nproperty float z\n");
  out.text("element face " + std::to_string(mesh.triangles.size()) + "\n");
  out.text("property list uchar uint vertex_indices\nend_header\n");
  for (const auto& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i) out.f32(v[i]);
    if (out.bytes().size() >= kFlushBytes) file.flush(out.bytes());
  }
  for (const auto& t : mesh.triangles) {
    out.u8(3);
    for (const std::uint32_t i : t) out.u32(i);
    if (out.bytes().size() >= kFlushBytes) file.flush(out.bytes());
  }
  file.flush(out.bytes());
  file.commit();
}

void write_obj(const fs::path& path, const Mesh& mesh) {
  TempFile file(path);
  std::string out = "# written by vts, units: mm\n";
  char line[128];
  for (const auto& v : mesh.vertices) {
    // 9 significant digits read back to the same float.
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", v.x(), v.y(), v.z());
    out += line;
    if (out.size() >= kFlushBytes) file.flush(out);
  }
  for (const auto& t : mesh.triangles) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    out += line;
    if (out.size() >= kFlushBytes) file.flush(out);
  }
  file.flush(out);
  file.commit();
}

}  // namespace

Mesh load_mesh_file(const fs::path& path, double unit_scale_to_mm, MeshLoadStats* stats_out) {
  mesh_extension(path);
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "mesh file not found");
  if (fs::is_directory(path, ec)) fail(path, "is a directory, not a mesh file");
  if (!fs::is_regular_file(path, ec)) fail(path, "not a regular file");
  if (!std::isfinite(unit_scale_to_mm) || unit_scale_to_mm <= 0.0)
    fail(path, "unit scale must be a finite number > 0 (mm per file unit)");

  Assimp::Importer importer;
  // Only triangulation: vertices are welded by exact position in MeshBuilder
  // (across meshes too), which makes aiProcess_JoinIdenticalVertices
  // redundant; it would also need the normals removed first (STL has one per
  // face), and it more than doubles the time and triples the memory of
  // loading a million-triangle STL (3.7 s and 590 MB against 1.6 s and
  // 210 MB). Degenerate triangles are counted here, not removed by assimp.
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate);
  if (!scene) {
    std::string why = importer.GetErrorString();
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    fail(path, "not a mesh file: " + (why.empty() ? std::string("assimp cannot read it") : why));
  }

  // assimp takes some text as an empty mesh (its STL reader any text that
  // begins with "solid", its OBJ reader any text at all): a file without a
  // single vertex is not a mesh file.
  std::int64_t vertices = 0;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) vertices += scene->mMeshes[i] ? scene->mMeshes[i]->mNumVertices : 0;
  if (vertices == 0) fail(path, "not a mesh file: no vertices or faces found");

  MeshLoadStats stats;
  stats.file = path.string();
  MeshBuilder builder(stats);
  std::vector<Eigen::Vector3f> positions;
  if (scene->mRootNode)
    collect(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), unit_scale_to_mm, builder, stats,
            positions);
  Mesh mesh = builder.take();
  importer.FreeScene();

  if (mesh.triangles.empty()) {
    std::string why = "no triangles";
    if (stats.triangles_read > 0)
      why += " (all " + std::to_string(stats.triangles_read) + " degenerate)";
    else if (stats.ignored_primitives > 0)
      why += " (only " + std::to_string(stats.ignored_primitives) + " points and lines)";
    fail(path, why);
  }
  const MeshLoadStats edges = mesh_edge_stats(mesh);
  stats.triangles_kept = edges.triangles_kept;
  stats.open_edges = edges.open_edges;
  stats.nonmanifold_edges = edges.nonmanifold_edges;
  if (stats_out) *stats_out = stats;
  return mesh;
}

MeshLoadStats mesh_edge_stats(const Mesh& mesh) {
  MeshLoadStats s;
  s.triangles_read = s.triangles_kept = static_cast<std::int64_t>(mesh.triangles.size());
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t a = t[i], b = t[(i + 1) % 3];
      edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++s.open_edges;
    if (j - i > 2) ++s.nonmanifold_edges;
    i = j;
  }
  return s;
}

void write_mesh_file(const fs::path& path, const Mesh& mesh) {
  const std::string ext = mesh_extension(path);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (const std::uint32_t v : mesh.triangles[i])
      if (v >= mesh.vertices.size())
        fail(path, "triangle " + std::to_string(i) + " indexes vertex " + std::to_string(v) + " of " +
                       std::to_string(mesh.vertices.size()));
  if (ext == ".stl") write_stl(path, mesh);
  else if (ext == ".ply") write_ply(path, mesh);
  else write_obj(path, mesh);
}

std::optional<double> mesh_unit_mm(std::string_view name) {
  if (name == "mm") return 1.0;
  if (name == "cm") return 10.0;
  if (name == "m") return 1000.0;
  if (name == "in") return 25.4;
  return std::nullopt;
}

std::string mesh_unit_name(double mm_per_unit) {
  for (const char* name : {"mm", "cm", "m", "in"})
    if (*mesh_unit_mm(name) == mm_per_unit) return name;
  return {};
}

}  // namespace vts
