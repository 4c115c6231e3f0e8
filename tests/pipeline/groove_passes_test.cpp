// A multi-pass weld (pipeline/groove_passes.h, issue 18 point 4): beads laid
// pass after pass in vgroove-thick, the sensor asked between the passes.
// Truth: the hand-worked values of the 60-degree V in 40 mm plate (root face
// 2, gap 2, 4 mm layers, crown 0.8): what is left after k beads is 38 - 4k
// mm deep (the cap's toes are its lowest points), and the top width 2 (1 +
// 38 tan 30) = 45.879 mm whatever is laid.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "pipeline/groove_passes.h"

TEST_CASE("groove passes: the sensor asked between passes of vgroove-thick", "[pipeline][groove]") {
  vts::GroovePassSpec spec;
  spec.cell = *vts::builtin_cell("vgroove-thick");
  spec.cell.scanner.ideal = true;
  spec.source = vts::SourceKind::Reference;
  spec.last_pass = 5;
  spec.profiles = 3;
  spec.fill = vts::FillMode::Model;  // the hand-worked flat layers below
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

// The adaptive fill (docs/SIM.md "Multi-pass"): each bead where the sensor
// said. Truth: with a bias b added to every reported next-bead point along
// the laser line, the beads go b times the laser line's direction across the
// part (worked out here from the cell's pose) off the true B3, within the
// tracker's stated accuracy for B3 on exact sections (0.3 mm,
// docs/JOINTS.md); without a bias, within 0.5 mm (its figure with range
// noise) with the error model on.
namespace {

// The part's y of the sensor's y (the laser line's direction across).
double across_of_laser_line(const vts::Cell& cell) {
  const vts::Pose joint_from_sensor = cell.workpieces.front().world_from_joint.inverse() * cell.path.pose_at(0);
  return joint_from_sensor.linear()(1, 1);
}

}  // namespace

TEST_CASE("groove passes: the adaptive fill lays the beads off by a known bias on the sensor", "[pipeline][groove]") {
  vts::GroovePassSpec spec;
  spec.cell = *vts::builtin_cell("vgroove-thick");
  spec.cell.scanner.ideal = true;
  spec.source = vts::SourceKind::Reference;
  spec.last_pass = 4;
  spec.profiles = 3;
  spec.fill = vts::FillMode::Adaptive;
  spec.bias_mm = 0.6;
  const double expected = 0.6 * across_of_laser_line(spec.cell);
  REQUIRE(std::abs(expected) > 0.55);  // the laser line lies nearly across the seam
  const vts::GroovePassRun run = vts::run_groove_passes(spec);
  INFO(vts::groove_passes_markdown(run));
  REQUIRE(run.stopped.empty());
  REQUIRE(run.passes.size() == 5);
  for (const vts::GroovePass& p : run.passes) {
    INFO("beads laid " << p.laid);
    CHECK(p.ok == 3);
    CHECK(p.bead_laid == (p.laid < 4));
    if (!p.bead_laid) continue;
    CHECK(p.laid_y == p.reported_y);
    CHECK(p.laid_y - p.model_y == Approx(expected).margin(0.3));
  }
  // Four beads laid towards one side: that side's toe is higher.
  const vts::GroovePass& last = run.passes.back();
  CHECK((last.toe_b.y() - last.toe_a.y()) * expected > 0.0);
  CHECK(std::abs(last.toe_b.y() - last.toe_a.y()) > 1.0);
  // The summary shows the offset, in the table and in the JSON.
  char off[32];
  std::snprintf(off, sizeof off, "(%+.3f)", run.passes[0].laid_y - run.passes[0].model_y);
  const std::string md = vts::groove_passes_markdown(run);
  CHECK(md.find("next bead laid / model's centre, across (mm)") != std::string::npos);
  CHECK(md.find(off) != std::string::npos);
  CHECK(md.find("adaptive fill") != std::string::npos);
  const auto j = vts::groove_passes_json(run);
  CHECK(j["fill"].get<std::string>() == "adaptive");
  CHECK(j["passes"][1]["next_bead_offset_mm"].get<double>() == Approx(expected).margin(0.3));
  CHECK(j["passes"][4]["next_bead_laid"].get<bool>() == false);
}

TEST_CASE("groove passes: the adaptive fill lays the beads on centre within the tracker's accuracy", "[pipeline][groove]") {
  vts::GroovePassSpec spec;
  spec.cell = *vts::builtin_cell("vgroove-thick");
  spec.source = vts::SourceKind::Reference;  // error model on, seed 1
  spec.last_pass = 3;
  spec.profiles = 5;
  spec.fill = vts::FillMode::Adaptive;
  const vts::GroovePassRun run = vts::run_groove_passes(spec);
  INFO(vts::groove_passes_markdown(run));
  REQUIRE(run.stopped.empty());
  REQUIRE(run.passes.size() == 4);
  for (const vts::GroovePass& p : run.passes) {
    INFO("beads laid " << p.laid);
    CHECK(p.ok > 0);
    if (p.bead_laid) CHECK(std::abs(p.laid_y - p.model_y) < 0.5);
  }
  // The same run with the model's fill lays the beads on the model's centre.
  spec.fill = vts::FillMode::Model;
  for (const vts::GroovePass& p : vts::run_groove_passes(spec).passes)
    if (p.bead_laid) CHECK(p.laid_y == p.model_y);
}

TEST_CASE("groove passes: the adaptive fill stops where no profile is accepted", "[pipeline][groove]") {
  // The empty thick bevel is read "not sure" (its square wall hides the root).
  vts::GroovePassSpec spec;
  spec.cell = *vts::builtin_cell("bevel-thick");
  spec.source = vts::SourceKind::Reference;
  spec.profiles = 3;
  spec.fill = vts::FillMode::Adaptive;
  const vts::GroovePassRun run = vts::run_groove_passes(spec);
  REQUIRE(run.passes.size() == 1);
  CHECK(run.passes[0].ok == 0);
  CHECK_FALSE(run.passes[0].bead_laid);
  CHECK(run.stopped.find("bead 1 cannot be placed") != std::string::npos);
  CHECK(vts::groove_passes_markdown(run).find("STOPPED: after 0 beads") != std::string::npos);
  CHECK(vts::groove_passes_json(run)["stopped"].get<std::string>() == run.stopped);
  // A bias is only for the adaptive fill; an impossible one is refused.
  spec.fill = vts::FillMode::Model;
  spec.bias_mm = 0.5;
  CHECK(vts::validate(spec).find("adaptive") != std::string::npos);
  spec.fill = vts::FillMode::Adaptive;
  spec.bias_mm = 30.0;
  CHECK(vts::validate(spec).find("bias = 30") != std::string::npos);
}
