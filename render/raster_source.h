#pragma once
// The raster profile source: emulates the scanner by rasterizing the optical
// plane's slice of the mesh into a one-row depth buffer per profile (OSMesa,
// llvmpipe, headless). The mesh's flat regions are first re-triangulated
// with the few triangles their outlines need (sensor/planar_merge.h: a plate
// meshed into half a million triangles is 12 again; curved surfaces stay as
// they are). For each profile, a bounding-volume hierarchy over the mesh
// (sensor/mesh_bvh.h) finds the triangles its laser plane cuts between the
// fan's sides; each cut is a segment in the plane (collinear runs joined),
// sent as one triangle in its profile's row, already projected (column
// coordinate y/z, reversed depth near/z) and cut to the row's columns. One
// draw covers up to 256 profiles, one row each; the depth test keeps the
// nearest segment per column and the target holds its triangle's number.
// The range along the column's ray is then the exact ray/plane intersection
// with that triangle, in double, so it agrees with the ray-cast reference to
// well under a micrometre;
// hit/miss can differ only where a ray passes within about 1/256 pixel of a
// mesh boundary edge. For a closed mesh with consistent winding, faces turned
// away from the laser are not drawn (they are always behind a front face).
//
// The camera shadow (sensor/error_model.h) is tested on the CPU against the
// same hierarchy: per group of lit columns, the triangles near the sight lines
// to the camera, each intersected exactly with each sight line
// (docs/SENSOR_MODEL.md).
//
// A batch is split into parts that run on the thread limit's threads
// (common/parallel.h), each part on the worker of its thread's slot: an
// OSMesa context of its own with its pipeline and scratch, made current for
// that part only (oneTBB moves work between threads; a context current
// nowhere between uses can follow it, and be destroyed on any thread). No
// allocation per profile once the scratch has grown to the largest pass.
#include <memory>

#include "sensor/mesh.h"
#include "sensor/profile_source.h"
#include "sensor/scanner.h"

namespace vts {

struct RasterOptions {
  // Most parts scan_batch splits a batch into, each on its own thread with
  // its own OpenGL context (built on first use). 0: the thread limit
  // (common/parallel.h); never more than it.
  int threads = 0;
  // Profiles per draw (at most 256).
  int rows_per_pass = 256;
  // Re-triangulate flat regions of the mesh first (sensor/planar_merge.h):
  // a finely meshed flat face is sliced as the few triangles its outline
  // needs. The surface moves by at most about 16 float epsilons of the
  // part's size; off, every triangle is drawn as given.
  bool merge_planar = true;
};

// Builds a source over a copy of mesh_world (world frame, mm); the mesh is
// uploaded once, GL objects are created once and reused by every scan().
// One source may be used by one thread at a time; separate sources may run on
// separate threads; a source may be destroyed on any thread. scan() runs on
// the calling thread; scan_batch() splits batches of 64 profiles or more over
// the thread limit's threads, and a part's failure comes back as its
// exception.
// Throws std::invalid_argument if validate(desc) fails or a triangle indexes
// past the vertex list, std::runtime_error if the GL context or a shader fails.
// Zero-area triangles are skipped; back faces are not culled.
std::unique_ptr<ProfileSource> make_raster_source(const ScannerDesc& desc,
                                                  const Mesh& mesh_world,
                                                  const RasterOptions& options = {});

}  // namespace vts
