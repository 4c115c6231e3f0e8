// A multi-pass weld (pipeline/groove_passes.h, issue 18 point 4): beads laid
// pass after pass in vgroove-thick, the sensor asked between the passes.
// Truth: the hand-worked values of the 60-degree V in 40 mm plate (root face
// 2, gap 2, 4 mm layers, crown 0.8): what is left after k beads is 38 - 4k
// mm deep (the cap's toes are its lowest points), and the top width 2 (1 +
// 38 tan 30) = 45.879 mm whatever is laid.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "pipeline/groove_passes.h"

TEST_CASE("groove passes: the sensor asked between passes of vgroove-thick", "[pipeline][groove]") {
  vts::GroovePassSpec spec;
  spec.cell = *vts::builtin_cell("vgroove-thick");
  spec.cell.scanner.ideal = true;
  spec.source = vts::SourceKind::Reference;
  spec.last_pass = 5;
  spec.profiles = 3;
  const vts::GroovePassRun run = vts::run_groove_passes(spec);
  REQUIRE(run.passes.size() == 6);
  double area_before = INFINITY;
  for (const vts::GroovePass& p : run.passes) {
    INFO("beads laid " << p.laid << ": " << p.first_reason);
    CHECK(p.ok == 3);
    CHECK(p.depth_true == Approx(38.0 - 4.0 * p.laid).margin(1e-9));
    CHECK(p.width_true == Approx(45.879).margin(0.001));
    CHECK(p.depth == Approx(p.depth_true).margin(0.1));
    CHECK(p.area == Approx(p.area_true).epsilon(0.02));
    CHECK(p.width == Approx(p.width_true).margin(0.1));
    CHECK(p.wall_a == Approx(60.0).margin(0.5));
    CHECK(p.wall_b == Approx(60.0).margin(0.5));
    CHECK(std::hypot(p.next_dy, p.next_dz) < 0.3);
    CHECK(p.area_true < area_before);  // each bead fills some of it
    area_before = p.area_true;
  }
  // Three beads: the hand-worked 794.081 mm^2 (tests/sensor/groove_test.cpp).
  CHECK(run.passes[3].area_true == Approx(794.081).margin(0.01));
  const auto j = vts::groove_passes_json(run);
  CHECK(j["passes"].size() == 6);
  CHECK(j["passes"][3]["depth_true_mm"].get<double>() == Approx(26.0));
}

TEST_CASE("groove passes: what cannot run is said before anything runs", "[pipeline][groove]") {
  vts::GroovePassSpec spec;
  spec.cell = *vts::builtin_cell("fillet");
  CHECK(vts::validate(spec).find("is no groove") != std::string::npos);
  CHECK_THROWS_AS(vts::run_groove_passes(spec), std::invalid_argument);
  spec.cell = *vts::builtin_cell("vgroove-thick");
  spec.last_pass = 20;  // 80 mm of beads in a 38 mm deep groove
  CHECK(vts::validate(spec).find("passes = 20") != std::string::npos);
  spec.last_pass = 2;
  spec.first_pass = 3;
  CHECK(vts::validate(spec).find("first <= last") != std::string::npos);
}
