#pragma once
// The ray-cast reference: casts exactly the column rays of sensor/rays.h
// against the mesh with Embree 3 (robust scene, high build quality) and turns
// each hit distance into a sample with vts::set_column, so it filters exactly
// as the raster emulator does. It is the ground truth the raster emulator is
// held against.
#include <memory>

#include "sensor/mesh.h"
#include "sensor/profile_source.h"
#include "sensor/scanner.h"

namespace vts {

// Builds the Embree scene once from `mesh_world` (world frame, mm); the mesh is
// copied, so it need not outlive the source. An empty mesh is allowed (every
// column invalid). kind() == "reference".
//
// scan() sets out.world_from_sensor to the pose and resizes `out` to
// desc.points (no allocation when it already has that size); it leaves
// out.time_s and out.index to the caller. scan_batch() spreads batches of 64
// profiles or more over at most `threads` of the thread limit's threads
// (0: all of them; common/parallel.h).
//
// Throws std::invalid_argument if validate(desc) fails or a triangle indexes a
// vertex that does not exist, std::runtime_error with Embree's message if
// Embree fails.
//
// `moving`, when given and not empty, is a part that moves against the rest
// (RayScene's moving part): move_part() places it before the scans that
// follow (never during a batch).
std::unique_ptr<ProfileSource> make_reference_source(const ScannerDesc& desc,
                                                     const Mesh& mesh_world, int threads = 0,
                                                     const Mesh* moving = nullptr);

}  // namespace vts
