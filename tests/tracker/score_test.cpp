// Scoring against ground truth (tracker/score.h): outcomes by hand-placed
// track points, and the share of readings more than 3 stated rms off.
#include <catch2/catch.hpp>

#include <string>

#include "tracker/score.h"

namespace tk = vts::tracker;
using tk::Vec2;

namespace {

tk::TrackResult reading(const Vec2& track, double sigma_mm) {
  tk::TrackResult r;
  r.status = tk::TrackStatus::Ok;
  r.joint = tk::JointType::Butt;
  r.track_point = track;
  r.track_sigma_mm = sigma_mm;
  return r;
}

}  // namespace

TEST_CASE("score: outcomes and the share of readings more than 3 stated rms off", "[tracker][score]") {
  tk::Truth truth;
  truth.joint = tk::JointType::Butt;
  truth.track_point = Vec2(0.0, 100.0);
  truth.noise_mm = 0.05;
  tk::ScoreTable table;
  // 0.05 mm off at 0.1 stated: right, within 3 sigma.
  table.add(reading(Vec2(0.05, 100.0), 0.1), truth);
  // 0.2 mm off at 0.05 stated: right (noisy tolerance 0.3), beyond 3 sigma.
  table.add(reading(Vec2(0.0, 100.2), 0.05), truth);
  // 0.5 mm off at 0.1 stated: imprecise, beyond 3 sigma (0.3).
  table.add(reading(Vec2(0.3, 100.4), 0.1), truth);
  // 2 mm off at 1 stated: a false read, within 3 sigma.
  table.add(reading(Vec2(2.0, 100.0), 1.0), truth);
  // No stated error: not counted; a rejection: not counted.
  table.add(reading(Vec2(0.0, 100.0), tk::kNotMeasured), truth);
  tk::TrackResult rejected = reading(Vec2(5.0, 100.0), 0.01);
  rejected.status = tk::TrackStatus::Rejected;
  table.add(rejected, truth);
  // A hidden joint's reading: a false read, not counted for the share.
  tk::Truth hidden = truth;
  hidden.hidden = true;
  table.add(reading(Vec2(3.0, 100.0), 0.01), hidden);

  const tk::Tally t = table.total(tk::JointType::Butt);
  CHECK(t.profiles == 7);
  CHECK(t.right == 3);
  CHECK(t.imprecise == 1);
  CHECK(t.rejected == 1);
  CHECK(t.false_reads == 2);
  CHECK(t.located == 4);
  CHECK(t.over_3_sigma == 2);
  const std::string md = table.markdown();
  INFO(md);
  CHECK(md.find("| over 3 stated rms |") != std::string::npos);
  CHECK(md.find("| butt | all | 7 (1) | 50.0 % | 16.7 % | 16.7 % | 2 |") != std::string::npos);
  CHECK(md.find("| 50.0 % |\n") != std::string::npos);
}

TEST_CASE("score: rejection reasons are counted by kind, whatever their numbers", "[tracker][score]") {
  tk::Truth truth;
  truth.joint = tk::JointType::VGroove;
  truth.track_point = Vec2(0.0, 100.0);
  tk::ScoreTable table;
  for (const char* reason : {"inside a wider groove (walls 45.2 and 45 deg, 22.3 mm wide at the top): its tops",
                             "inside a wider groove (walls 61.7 and 58 deg, 14.7 mm wide at the top): its tops",
                             "gap 3.2 mm outside [0, 3]", "gap 4 mm outside [0, 3]", "uncertain: confidence 0.83"}) {
    tk::TrackResult r;
    r.status = tk::TrackStatus::Rejected;
    r.reason = reason;
    table.add(r, truth);
  }
  const auto& kinds = table.total(tk::JointType::VGroove).reject_reasons;
  CHECK(kinds.size() == 3);
  CHECK(kinds.at("inside a wider groove (walls and deg mm wide at the top)") == 2);
  CHECK(kinds.at("gap mm outside") == 2);
  CHECK(kinds.at("uncertain") == 1);
}
