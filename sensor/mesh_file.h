#pragma once
// Triangle mesh files: CAD workpieces read with assimp (STL ASCII and binary,
// OBJ, PLY ASCII and binary) and generated meshes written as binary STL,
// binary little-endian PLY or OBJ (docs/SCENE_FORMAT.md, `vts mesh`).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sensor/mesh.h"

namespace vts {

// What load_mesh_file found in a file. Counts are of triangles after assimp
// has triangulated polygons and after vertices at exactly the same position
// are welded into one (whatever the format, vertices are compared by
// position, so edges are shared across faces, groups and objects).
struct MeshLoadStats {
  std::string file;                     // the path as given
  std::int64_t triangles_read = 0;      // triangles in the file
  std::int64_t triangles_kept = 0;      // in the mesh: read - skipped_degenerate
  std::int64_t skipped_degenerate = 0;  // zero area, a repeated vertex, or a non-finite coordinate
  std::int64_t ignored_primitives = 0;  // points and lines (not surfaces), ignored
  std::int64_t open_edges = 0;          // edges of exactly one kept triangle (holes, borders)
  std::int64_t nonmanifold_edges = 0;   // edges of three or more kept triangles

  // Every edge is shared by exactly two triangles (a watertight surface).
  bool closed() const { return triangles_kept > 0 && open_edges == 0 && nonmanifold_edges == 0; }
};

// what() names the file and the problem, e.g.
// "part.stl: not a mesh file: <assimp's reason>".
struct MeshFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// ".stl, .obj or .ply" (lower or upper case).
inline constexpr std::string_view kMeshFileTypes = ".stl, .obj or .ply";

// Reads the triangles of every mesh in the file, each vertex carried through
// its node's transforms down the file's node tree, then multiplied by
// unit_scale_to_mm (mm per file unit, > 0 and finite). Degenerate triangles are
// skipped; points and lines ignored; open or non-manifold surfaces are kept
// as they are (both sources scan them). The mesh holds only the vertices its
// triangles use. `stats`, if given, receives the counts.
//
// Throws MeshFileError: missing file, a directory or other non-regular file,
// an unsupported extension, a file assimp cannot read ("not a mesh file"), or
// no usable triangle ("no triangles").
Mesh load_mesh_file(const std::filesystem::path& path, double unit_scale_to_mm = 1.0,
                    MeshLoadStats* stats = nullptr);

// Edge counts of a mesh as load_mesh_file reports them (triangles_kept is the
// mesh's triangle count; the other counts are those of the mesh's own vertex
// indices).
MeshLoadStats mesh_edge_stats(const Mesh& mesh);

// Writes `mesh` by the path's extension: .stl binary STL (80-byte header not
// beginning with "solid", face normals from the vertices), .ply binary
// little-endian PLY (float x y z, uchar/uint vertex_indices), .obj OBJ text
// (positions with 9 significant digits: they read back to the same floats).
// Written to PATH.tmp-<pid> in the same directory and renamed onto PATH when
// complete, so PATH is never half written. The directory must exist.
// Throws MeshFileError (unsupported extension, more triangles than the format
// holds, I/O failure; the temporary file is removed).
void write_mesh_file(const std::filesystem::path& path, const Mesh& mesh);

// Scene-file units (`unit:` of a mesh workpiece): mm per file unit for "mm",
// "cm", "m" and "in"; nullopt for anything else.
std::optional<double> mesh_unit_mm(std::string_view name);
// The unit's name when mm_per_unit is exactly one of them, else empty.
std::string mesh_unit_name(double mm_per_unit);

}  // namespace vts
