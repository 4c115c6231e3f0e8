#pragma once
// Planar regions of a triangle mesh, re-triangulated with as few triangles as
// their outline needs. A flat face that a mesher or CAD export cut into
// thousands of triangles is one convex polygon; the raster profile source
// (render/raster_source.h) slices, joins and shadow-tests per triangle, so it
// merges such regions before building its hierarchy. The surface does not
// move by more than the tolerance: no vertex is moved; vertices on straight
// region borders are dropped, and a fan's centre may be added.
//
// A region is a set of edge-connected triangles (each interior edge shared
// by exactly two triangles, used once in each direction) whose corners all
// lie within the tolerance of its first triangle's plane, facing the same
// way. A region of three or more triangles is replaced by a fan over its
// outline when
//   - its border is one closed loop (a disk: no holes, no pinched vertex),
//   - the loop is convex once every droppable vertex is left out: it turns
//     left at every vertex but those it runs straight through (within the
//     tolerance), and at three or more, once around (not a star),
//   - the area of that polygon equals the region's,
//   - its fan has fewer triangles than the region.
// A border vertex is droppable when at most two regions meet at it, every
// one of them is replaced, and the border runs straight through it (within
// the tolerance) in each: so both sides of a shared border drop the same
// vertices and the mesh stays free of T-junctions (watertight, as the raster
// source's slicing needs). A polygon that keeps a vertex on a straight run
// (one shared with a region left as it was) is fanned from its vertices'
// centroid, a vertex appended to the positions; any other from its first
// corner. Everything else (curved surfaces, non-convex or holed faces) is
// kept triangle for triangle.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vts {

struct PlanarMergeStats {
  std::size_t triangles_in = 0;
  std::size_t triangles_out = 0;
  std::size_t regions = 0;         // planar regions of 3 or more triangles
  std::size_t merged_regions = 0;  // of those, replaced by a fan
};

// The default tolerance for positions stored as float: 16 float epsilons of
// the largest coordinate magnitude (about 6e-4 mm for a part within 300 mm of
// its centre), far above float rounding, far below a sensor's resolution.
double planar_merge_tolerance(std::span<const float> positions);

// positions: x, y, z per vertex (mm), fan centres appended; indices: 3 per
// triangle, every triangle with non-zero area and indices inside positions.
// Returns 3 indices per output triangle, same winding, into positions.
std::vector<std::uint32_t> merge_planar_regions(std::vector<float>& positions,
                                                std::span<const std::uint32_t> indices,
                                                double tolerance_mm,
                                                PlanarMergeStats* stats = nullptr);

}  // namespace vts
