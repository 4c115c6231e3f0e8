// The raster source's batches: many profiles per draw, split over worker
// threads, must give exactly what one scan per profile gives, and must not
// allocate once warmed up.
#include <catch2/catch.hpp>

#include <vector>

#include "render/raster_source.h"
#include "sensor/cell.h"
#include "tests/common/count_allocations.h"

using namespace vts;
using vts::test::g_allocations;

TEST_CASE("raster: a batch over workers and passes equals one scan per profile", "[gl][raster]") {
  for (const char* name : {"static-B", "lap", "vgroove"}) {
    const Cell cell = *builtin_cell(name);
    std::vector<Pose> poses;
    for (int i = 0; i < 600; ++i) poses.push_back(cell.path.pose_at(i % 200));
    // A turned pose in the middle breaks the run of parallel laser planes.
    poses[301].linear() = poses[301].linear() * Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
    auto batch_source = make_raster_source(cell.scanner, cell.mesh(), {.threads = 2, .rows_per_pass = 100});
    auto single_source = make_raster_source(cell.scanner, cell.mesh(), {.threads = 1});
    std::vector<Profile> batch(poses.size());
    batch_source->scan_batch(poses, batch);
    Profile one;
    int lit = 0;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      single_source->scan(poses[k], one);
      INFO(name << " pose " << k);
      REQUIRE(one.valid == batch[k].valid);
      REQUIRE(one.range_mm == batch[k].range_mm);
      REQUIRE(one.cos_incidence == batch[k].cos_incidence);
      REQUIRE(one.camera_visible == batch[k].camera_visible);
      CHECK(batch[k].world_from_sensor.matrix() == poses[k].matrix());
      lit += one.valid_count();
    }
    CHECK(lit > 600 * cell.scanner.points / 2);
  }
}

TEST_CASE("raster: no allocation per profile once warmed up", "[gl][raster]") {
  const Cell cell = *builtin_cell("fillet");
  auto source = make_raster_source(cell.scanner, cell.mesh(), {.threads = 2, .rows_per_pass = 64});
  std::vector<Pose> poses;
  for (int i = 0; i < 512; ++i) poses.push_back(cell.path.pose_at(i % 200));
  std::vector<Profile> out(poses.size());
  source->scan_batch(poses, out);  // warm-up: workers, contexts, scratch
  source->scan_batch(poses, out);
  const long before = g_allocations.load();
  for (int round = 0; round < 3; ++round) source->scan_batch(poses, out);
  const long per_batch = (g_allocations.load() - before) / 3;
  // Handing a batch to the worker thread costs a std::function or two; nothing
  // may grow with the number of profiles.
  CHECK(per_batch <= 4);
  CHECK(out[100].valid_count() > 0);
}
