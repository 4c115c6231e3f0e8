#pragma once
// The raster profile source: emulates the scanner by rasterizing the mesh into
// a one-row float target of desc.points columns seen from the laser origin
// (OSMesa/llvmpipe, headless), and reading each column back as the range along
// that column's ray (sensor/rays.h). Ranges are exact ray/plane intersections
// per covering triangle, so they agree with the ray-cast reference to well
// under a micrometre; hit/miss can differ only where a ray passes within about
// 1/256 pixel of a mesh boundary edge.
#include <memory>

#include "sensor/mesh.h"
#include "sensor/profile_source.h"
#include "sensor/scanner.h"

namespace vts {

// Builds a source over a copy of mesh_world (world frame, mm); the mesh is
// uploaded once, GL objects are created once and reused by every scan().
// Each source owns its own OpenGL context: one source may be used by one
// thread at a time; separate sources may run on separate threads.
// Throws std::invalid_argument if validate(desc) fails or a triangle indexes
// past the vertex list, std::runtime_error if the GL context or a shader fails.
// Zero-area triangles are skipped; back faces are not culled.
std::unique_ptr<ProfileSource> make_raster_source(const ScannerDesc& desc,
                                                  const Mesh& mesh_world);

}  // namespace vts
