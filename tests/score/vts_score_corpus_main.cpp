// vts-score-corpus: the tracker on the independent corpus (tests/corpus), as
// the table of docs/JOINTS.md "Scores".
//   vts-score-corpus [--profiles N] [--first-seed S] [--joint NAME]... [--camera-in-plane]
//                    [--failures N] [--tag-stats] [--features FILE] [--dump JOINT SEED LEVEL PREFIX]
//                    [--track-interval MM] [--hidden-prior P] [--min-wall N]
// --failures N prints up to N false reads and imprecise readings per joint
// (seed, tags, result) for a look at them; --features FILE writes one CSV
// line per profile (outcome, error, confidence terms, rival, break points,
// groove values, how far the track point and B2-B4 lie from a seen point,
// the track point's stated rms error and chance of lying more than the
// track interval off); --track-interval MM sets the distance the
// confidence asks the track point to be located within (0: not asked);
// --hidden-prior P sets ConfidenceParams::hidden_prior, --min-wall N
// GrooveParams::min_wall_points.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include "corpus_score.h"

namespace {

// Writes PREFIX.csv (y, z, valid per column) and PREFIX.txt (truth and
// reading: track points, break points, segments, reason).
int dump(vts_corpus::Joint joint, std::uint64_t seed, double level, const std::string& prefix, bool camera_in_plane) {
  using namespace vts_score;
  const vc::Profile p = vc::make_profile(joint, seed, options_for(level, camera_in_plane));
  tk::TrackerParams params;
  params.joint = joint_of(joint);
  params.groove.vgroove_fill = joint == vc::Joint::VGrooveThick;
  tk::Tracker tracker(params);
  const tk::TrackResult& r = tracker.track(tk::ProfileView{p.y, p.z, p.valid});
  FILE* f = std::fopen((prefix + ".csv").c_str(), "w");
  if (!f) return 1;
  std::fprintf(f, "col,y,z,valid\n");
  for (std::size_t i = 0; i < p.y.size(); ++i) std::fprintf(f, "%zu,%.6f,%.6f,%d\n", i, p.y[i], p.z[i], p.valid[i]);
  std::fclose(f);
  f = std::fopen((prefix + ".txt").c_str(), "w");
  if (!f) return 1;
  std::fprintf(f, "truth %.6f %.6f\n", p.truth.track_y_mm, p.truth.track_z_mm);
  for (const auto& [name, xy] : p.truth.break_points) std::fprintf(f, "truth_bp %s %.6f %.6f\n", name.c_str(), xy[0], xy[1]);
  std::fprintf(f, "status %s\nreason %s\n", std::string(tk::to_string(r.status)).c_str(), r.reason.c_str());
  if (r.track_point) std::fprintf(f, "track %.6f %.6f\n", r.track_point->x(), r.track_point->y());
  if (r.rival_track_point) std::fprintf(f, "rival %.6f %.6f %.3f\n", r.rival_track_point->x(), r.rival_track_point->y(), r.rival_strength);
  for (int k = 0; k < tk::kMaxBreakPoints; ++k)
    if (r.break_points[k]) std::fprintf(f, "bp B%d %.6f %.6f\n", k, r.break_points[k]->x(), r.break_points[k]->y());
  for (const auto& rd : r.readings) std::fprintf(f, "reading %.6f %.6f %.3f\n", rd.track_point.x(), rd.track_point.y(), rd.strength);
  for (const auto& sg : r.segments) std::fprintf(f, "segment %d %d %d %.6f %.6f %.6f %.5f\n", sg.first_col, sg.last_col, sg.points, sg.line.n.x(), sg.line.n.y(), sg.line.c, sg.rms_mm);
  std::fprintf(f, "noise %.5f confidence %.4f strength %.3f gap %.4f mismatch %.4f angle %.3f\n", r.noise_mm, r.confidence, r.strength, r.gap_mm, r.mismatch_mm, r.angle_deg);
  std::string tags;
  for (const auto& t : p.truth.tags) tags += t + " ";
  std::fprintf(f, "tags %s\n", tags.c_str());
  std::fclose(f);
  std::printf("%s: %s %s; tags %s\n", prefix.c_str(), std::string(tk::to_string(r.status)).c_str(), r.reason.c_str(), tags.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace vts_score;
  RunOptions o;
  int failures = 0;
  bool tag_stats = false;
  std::string features_path;
  std::vector<vc::Joint> joints;
  tk::TrackerParams base;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "vts-score-corpus: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--profiles") o.profiles = std::atoi(value());
    else if (a == "--first-seed") o.first_seed = std::strtoull(value(), nullptr, 10);
    else if (a == "--camera-in-plane") o.camera_in_laser_plane = true;
    else if (a == "--failures") failures = std::atoi(value());
    else if (a == "--tag-stats") tag_stats = true;
    else if (a == "--features") features_path = value();
    // --track-interval MM: ConfidenceParams::track_interval_mm (0: the
    // track point's localization left out of the confidence).
    else if (a == "--track-interval") base.confidence.track_interval_mm = std::atof(value());
    else if (a == "--hidden-prior") base.confidence.hidden_prior = std::atof(value());
    else if (a == "--min-wall") base.groove.min_wall_points = std::atoi(value());
    else if (a == "--dump") {
      // --dump JOINT SEED LEVEL PREFIX: one profile and its reading, for a plot
      // (tests/score/plot_reading.py).
      if (i + 4 >= argc) {
        std::fprintf(stderr, "vts-score-corpus: --dump needs JOINT SEED LEVEL PREFIX\n");
        return 2;
      }
      const auto j = vc::joint_from_name(argv[i + 1]);
      if (!j) return 2;
      return dump(*j, std::strtoull(argv[i + 2], nullptr, 10), std::atof(argv[i + 3]), argv[i + 4],
                  o.camera_in_laser_plane);
    }
    else if (a == "--joint") {
      const char* v = value();
      const auto j = vc::joint_from_name(v);
      if (!j) {
        std::fprintf(stderr, "vts-score-corpus: --joint: unknown joint '%s'\n", v);
        return 2;
      }
      joints.push_back(*j);
    } else {
      std::fprintf(stderr, "vts-score-corpus: unknown argument '%s'\n", a.c_str());
      return 2;
    }
  }
  if (!joints.empty()) o.joints = joints;
  if (o.profiles <= 0) {
    std::fprintf(stderr, "vts-score-corpus: --profiles must be positive\n");
    return 2;
  }
  // --features FILE: one CSV line per profile (outcome, error, the reading's
  // confidence terms), to look for what separates false reads from right ones.
  FILE* features = features_path.empty() ? nullptr : std::fopen(features_path.c_str(), "w");
  if (features) {
    std::fprintf(features, "joint,seed,noise,outcome,error,status,confidence,strength,rival_strength,rival_mm,"
                           "noise_mm,track_unc,edge_unc,readings,hidden,rival_error,reason");
    for (int k = 0; k < tk::kMaxBreakPoints; ++k) std::fprintf(features, ",b%dy,b%dz", k, k);
    std::fprintf(features, ",wall_a,wall_b,depth,near_track,near_b2,near_b3,near_b4,track_sigma,track_off_p,truth_y,truth_z,tags\n");
  }
  std::size_t n_seen = 0;
  std::map<tk::JointType, int> shown;
  // (joint, tag) -> profiles with it, and of them right / imprecise / rejected / false.
  std::map<std::pair<std::string, std::string>, std::array<int, 5>> tags;
  const auto table = run(o, base, [&](const vc::Profile& p, const tk::TrackResult& r, const tk::Scored& s) {
    if (tag_stats) {
      auto count = [&](const std::string& tag) {
        auto& c = tags[{vc::joint_name(p.truth.joint), tag}];
        ++c[0];
        ++c[1 + static_cast<int>(s.outcome)];
      };
      count("(all)");
      for (const auto& t : p.truth.tags) count(t);
    }
    if (features) {
      // run() reads joint by joint, level by level: the row of this profile.
      const double level = o.levels[(n_seen++ / o.profiles) % o.levels.size()];
      const double rival_mm = r.rival_track_point && r.track_point ? (*r.rival_track_point - *r.track_point).norm() : -1.0;
      std::string reason = r.reason.substr(0, r.reason.find_first_of(":,("));
      const double rival_error =
          r.rival_track_point ? (*r.rival_track_point - tk::Vec2(p.truth.track_y_mm, p.truth.track_z_mm)).norm() : -1.0;
      std::fprintf(features, "%s,%llu,%g,%s,%.4f,%s,%.5f,%.4f,%.4f,%.3f,%.5f,%.4f,%.4f,%zu,%d,%.3f,%s",
                   vc::joint_name(p.truth.joint), static_cast<unsigned long long>(p.truth.seed), level,
                   std::string(tk::to_string(s.outcome)).c_str(), s.track_error_mm,
                   std::string(tk::to_string(r.status)).c_str(), r.confidence, r.strength, r.rival_strength, rival_mm,
                   r.noise_mm, r.track_uncertainty_mm, r.edge_uncertainty_mm, r.readings.size(),
                   p.truth.has_tag("joint_hidden") || p.truth.has_tag("notch_unseen") ? 1 : 0, rival_error, reason.c_str());
      // The break points (nan where the reading has none) and the groove
      // values, to test a model check on the readings before writing it.
      for (const auto& bp : r.break_points)
        std::fprintf(features, ",%.4f,%.4f", bp ? bp->x() : tk::kNotMeasured, bp ? bp->y() : tk::kNotMeasured);
      std::fprintf(features, ",%.3f,%.3f,%.4f", r.wall_angle_a_deg, r.wall_angle_b_deg, r.depth_mm);
      // How far the track point and B2-B4 lie from the nearest point seen.
      auto nearest = [&](const std::optional<tk::Vec2>& x) {
        double best = tk::kNotMeasured;
        if (!x) return best;
        for (std::size_t i = 0; i < p.y.size(); ++i)
          if (p.valid[i]) {
            const double d = std::hypot(p.y[i] - x->x(), p.z[i] - x->y());
            if (!(d >= best)) best = d;
          }
        return best;
      };
      std::fprintf(features, ",%.4f,%.4f,%.4f,%.4f", nearest(r.track_point), nearest(r.break_points[2]),
                   nearest(r.break_points[3]), nearest(r.break_points[4]));
      // How precisely the reading's fits locate the track point.
      std::string truth_tags;
      for (const auto& t : p.truth.tags) truth_tags += (truth_tags.empty() ? "" : " ") + t;
      std::fprintf(features, ",%.4f,%.3g,%.4f,%.4f,%s\n", r.track_sigma_mm, r.track_off_probability,
                   p.truth.track_y_mm, p.truth.track_z_mm, truth_tags.c_str());
    }
    if (s.outcome != tk::Outcome::False && s.outcome != tk::Outcome::Imprecise) return;
    const tk::JointType j = joint_of(p.truth.joint);
    if (shown[j]++ >= failures) return;
    std::string tags;
    for (const auto& t : p.truth.tags) tags += t + " ";
    std::printf("%s seed %llu noise %g: %s, error %.3f mm (%s%s), confidence %.3f, uncertainty %.3f; tags: %s\n",
                vc::joint_name(p.truth.joint), static_cast<unsigned long long>(p.truth.seed), p.truth.noise_mm,
                std::string(tk::to_string(s.outcome)).c_str(), s.track_error_mm,
                std::string(tk::to_string(r.status)).c_str(), r.reason.empty() ? "" : (": " + r.reason).c_str(),
                r.confidence, r.track_uncertainty_mm, tags.c_str());
  });
  if (features) std::fclose(features);
  std::printf("%s", table.markdown().c_str());
  if (tag_stats) {
    std::printf("\n| joint | tag | profiles | right | imprecise | rejected | false |\n|---|---|---|---|---|---|---|\n");
    for (const auto& [key, c] : tags)
      std::printf("| %s | %s | %d | %d | %d | %d | %d |\n", key.first.c_str(), key.second.c_str(), c[0], c[1], c[2], c[3],
                  c[4]);
  }
  std::printf("\nrejections:\n");
  for (const vc::Joint j : o.joints) {
    const auto t = table.total(joint_of(j));
    std::printf("  %s:", vc::joint_name(j));
    for (const auto& [k, v] : t.reject_reasons) std::printf(" %s %d;", k.c_str(), v);
    std::printf("\n");
  }
  return 0;
}
