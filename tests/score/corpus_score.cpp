#include "corpus_score.h"

#include <cmath>

namespace vts_score {

tk::JointType joint_of(vc::Joint j) {
  switch (j) {
    case vc::Joint::Fillet: return tk::JointType::Fillet;
    case vc::Joint::Corner: return tk::JointType::Corner;
    case vc::Joint::Lap: return tk::JointType::Lap;
    case vc::Joint::Butt: return tk::JointType::Butt;
    case vc::Joint::VGroove: return tk::JointType::VGroove;
    case vc::Joint::Bevel: return tk::JointType::Bevel;
    case vc::Joint::UGroove: return tk::JointType::UGroove;
    case vc::Joint::JGroove: return tk::JointType::JGroove;
    case vc::Joint::VGrooveThick: return tk::JointType::VGroove;  // the v-groove template in thick plate
  }
  return tk::JointType::Fillet;
}

tk::Truth truth_of(const vc::Truth& t) {
  tk::Truth out;
  out.joint = joint_of(t.joint);
  out.track_point = tk::Vec2(t.track_y_mm, t.track_z_mm);
  out.gap_mm = t.gap_mm;
  out.mismatch_mm = t.mismatch_mm;
  out.angle_deg = t.angle_deg;
  out.step_mm = t.step_mm;
  out.depth_mm = t.depth_mm;
  out.noise_mm = t.noise_mm;
  // The joint cannot be read where the corpus says a point its track point
  // needs is unseen, and where a corner's gap shows no wall (it then looks
  // like a closed corner, read at the apex: docs/JOINTS.md).
  out.hidden = t.has_tag("joint_hidden") || t.has_tag("notch_unseen");
  return out;
}

vc::Options options_for(double level, bool camera_in_laser_plane) {
  vc::Options opt;
  opt.noise_mm = std::max(0.0, level);
  opt.imperfections = level >= 0.0;
  opt.camera_in_laser_plane = camera_in_laser_plane;
  return opt;
}

ReadOne read_one(vc::Joint joint, std::uint64_t seed, double level, const tk::TrackerParams& base) {
  ReadOne one{vc::make_profile(joint, seed, options_for(level, false)), {}, {}};
  tk::TrackerParams params = base;
  params.joint = joint_of(joint);
  params.groove.vgroove_fill = joint == vc::Joint::VGrooveThick;
  tk::Tracker tracker(params);
  tracker.track(tk::ProfileView{one.profile.y, one.profile.z, one.profile.valid}, one.result);
  tk::Truth t = truth_of(one.profile.truth);
  t.noise_mm = level;
  one.scored = tk::score(one.result, t);
  return one;
}

tk::ScoreTable run(const RunOptions& o, const tk::TrackerParams& base,
                   const std::function<void(const vc::Profile&, const tk::TrackResult&, const tk::Scored&)>& each) {
  tk::ScoreTable table;
  tk::TrackResult r;
  for (const vc::Joint j : o.joints) {
    tk::TrackerParams params = base;
    params.joint = joint_of(j);
    // Thick v-grooves have beads laid in them: the user says so (--fill).
    params.groove.vgroove_fill = params.groove.vgroove_fill || j == vc::Joint::VGrooveThick;
    tk::Tracker tracker(params);
    for (const double level : o.levels) {
      const vc::Options opt = options_for(level, o.camera_in_laser_plane);
      for (int k = 0; k < o.profiles; ++k) {
        const vc::Profile p = vc::make_profile(j, o.first_seed + static_cast<std::uint64_t>(k), opt);
        tracker.track(tk::ProfileView{p.y, p.z, p.valid}, r);
        tk::Truth t = truth_of(p.truth);
        t.noise_mm = level;  // the row: ideal (-1) apart from noise 0 with imperfections
        const tk::Scored s = tk::score(r, t);
        table.rows[{t.joint, level}].add(s, r, t);
        if (each) each(p, r, s);
      }
    }
  }
  return table;
}

}  // namespace vts_score
