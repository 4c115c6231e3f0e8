// TrackResult <-> JSON (trackio/result_json.h): the keys and rounding of
// docs/CLI.md, and the way back.
#include <catch2/catch.hpp>

#include <cmath>

#include "../tracker/synthetic.h"
#include "tracker/tracker.h"
#include "trackio/result_json.h"

namespace {

namespace tk = vts::tracker;
using vts::trackio::Json;

}  // namespace

TEST_CASE("trackio json: a result written by hand", "[trackio]") {
  tk::TrackResult r;
  r.joint = tk::JointType::Butt;
  r.status = tk::TrackStatus::Rejected;
  r.reason = "gap 6 mm outside [0, 5]";
  r.break_points[1] = tk::Vec2(-1.0000004, 100.25);
  r.track_point = tk::Vec2(-0.0000001, 100.5);  // rounds to -0: written as 0
  r.gap_mm = 6.0;
  r.noise_mm = 0.0512345678;
  r.confidence = 0.25;
  r.strength = 3.5;
  r.rival_track_point = tk::Vec2(30.0, 101.0);
  r.rival_strength = 4.0;
  r.valid_points = 500;
  r.outliers = 2;
  tk::TrackResult::SegmentInfo single;
  single.first_col = single.last_col = 7;
  single.points = 1;
  r.segments.push_back(single);
  CHECK(vts::trackio::result_to_json_line(12, r) ==
        R"({"profile":12,"joint":"butt","status":"rejected","reason":"gap 6 mm outside [0, 5]",)"
        R"("break_points":[{"name":"B1","meaning":")" +
            std::string(tk::break_point_name(tk::JointType::Butt, 1)) +
            R"(","y":-1.0,"z":100.25}],"track_point":{"y":0.0,"z":100.5},"rival_track_point":{"y":30.0,"z":101.0},)"
            R"("gap_mm":6.0,"gap_paper_mm":null,)"
            R"("angle_deg":null,"mismatch_mm":null,"step_mm":null,"depth_mm":null,"area_mm2":null,)"
            R"("edge_uncertainty_mm":0.0,"track_uncertainty_mm":0.0,"noise_mm":0.051235,"confidence":0.25,)"
            R"("strength":3.5,"rival_strength":4.0,"wall_angle_a_deg":null,"wall_angle_b_deg":null,)"
            R"("top_width_mm":null,"track_sigma_mm":null,"track_off_probability":null,"fill_lowest":null,)"
            R"("valid_points":500,"outliers":2,)"
            R"("segments":[{"first":7,"last":7,"points":1,"line":null,"rms_mm":0.0}]})"
            "\n");
}

TEST_CASE("trackio json: written, read back and written again gives the same text", "[trackio]") {
  // A 90-degree fillet seen from 100 mm on its bisector.
  const synth::Profile p = synth::sample(synth::valley(tk::Vec2(0.0, 100.0), 90.0));
  tk::Tracker tracker;
  const tk::TrackResult& r = tracker.track(p.view());
  REQUIRE(r.status == tk::TrackStatus::Ok);
  const Json j = vts::trackio::result_to_json(3, r);
  std::int64_t index = -1;
  const tk::TrackResult back = vts::trackio::result_from_json(j, &index);
  CHECK(index == 3);
  CHECK(back.joint == r.joint);
  CHECK(back.status == r.status);
  CHECK(back.segments.size() == r.segments.size());
  REQUIRE(back.track_point);
  CHECK(std::abs(back.track_point->y() - 100.0) < 1e-5);
  CHECK(std::isnan(back.step_mm));
  CHECK(vts::trackio::result_to_json(3, back) == j);
}

TEST_CASE("trackio json: reading names the key that is missing or wrong", "[trackio]") {
  tk::TrackResult r;
  Json j = vts::trackio::result_to_json(0, r);
  j.erase("gap_mm");
  CHECK_THROWS_WITH(vts::trackio::result_from_json(j), "missing key 'gap_mm'");
  j = vts::trackio::result_to_json(0, r);
  j["joint"] = "tee";
  CHECK_THROWS_WITH(vts::trackio::result_from_json(j), "'joint': 'tee' is not a joint");
  j = vts::trackio::result_to_json(0, r);
  j["valid_points"] = "many";
  CHECK_THROWS_WITH(vts::trackio::result_from_json(j), "'valid_points': expected an integer");
}

TEST_CASE("trackio json: a groove's values round-trip, and lines without them still read", "[trackio]") {
  tk::TrackResult r;
  r.joint = tk::JointType::UGroove;
  r.status = tk::TrackStatus::Ok;
  r.track_point = tk::Vec2(1.5, 310.25);
  r.wall_angle_a_deg = 82.0, r.wall_angle_b_deg = 81.5, r.top_width_mm = 23.25;
  r.fill_lowest = tk::Vec2(1.0, 310.5);
  Json j = vts::trackio::result_to_json(0, r);
  const tk::TrackResult back = vts::trackio::result_from_json(j);
  CHECK(back.wall_angle_a_deg == 82.0);
  CHECK(back.wall_angle_b_deg == 81.5);
  CHECK(back.top_width_mm == 23.25);
  REQUIRE(back.fill_lowest);
  CHECK(*back.fill_lowest == tk::Vec2(1.0, 310.5));
  for (const char* key : {"wall_angle_a_deg", "wall_angle_b_deg", "top_width_mm", "fill_lowest"}) j.erase(key);
  const tk::TrackResult old = vts::trackio::result_from_json(j);
  CHECK(std::isnan(old.wall_angle_a_deg));
  CHECK(std::isnan(old.top_width_mm));
  CHECK_FALSE(old.fill_lowest);
}

TEST_CASE("trackio json: the track point's localization round-trips, and lines without it still read", "[trackio]") {
  tk::TrackResult r;
  r.joint = tk::JointType::VGroove;
  r.status = tk::TrackStatus::Ok;
  r.track_point = tk::Vec2(1.5, 110.25);
  r.track_sigma_mm = 0.125, r.track_off_probability = 0.0625;
  Json j = vts::trackio::result_to_json(0, r);
  const tk::TrackResult back = vts::trackio::result_from_json(j);
  CHECK(back.track_sigma_mm == 0.125);
  CHECK(back.track_off_probability == 0.0625);
  for (const char* key : {"track_sigma_mm", "track_off_probability"}) j.erase(key);
  const tk::TrackResult old = vts::trackio::result_from_json(j);
  CHECK(std::isnan(old.track_sigma_mm));
  CHECK(std::isnan(old.track_off_probability));
}
