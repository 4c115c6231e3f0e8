#include "trackio/result_json.h"

#include <cmath>
#include <utility>

namespace vts::trackio {
namespace {

namespace tk = vts::tracker;
using R = tk::TrackResult;

// The scalar fields, in output order (after "track_point", before
// "segments"): a new field of TrackResult is one line in one of these.
constexpr std::pair<const char*, double R::*> kValues[] = {
    {"gap_mm", &R::gap_mm},
    {"gap_paper_mm", &R::gap_paper_mm},
    {"angle_deg", &R::angle_deg},
    {"mismatch_mm", &R::mismatch_mm},
    {"step_mm", &R::step_mm},
    {"depth_mm", &R::depth_mm},
    {"area_mm2", &R::area_mm2},
    {"edge_uncertainty_mm", &R::edge_uncertainty_mm},
    {"track_uncertainty_mm", &R::track_uncertainty_mm},
    {"noise_mm", &R::noise_mm},
    {"confidence", &R::confidence},
    {"strength", &R::strength},
    {"rival_strength", &R::rival_strength},
};
// The grooves' values (issue 18), written after those above; files written
// before them lack them, so a missing one reads as not measured.
constexpr std::pair<const char*, double R::*> kGrooveValues[] = {
    {"wall_angle_a_deg", &R::wall_angle_a_deg},
    {"wall_angle_b_deg", &R::wall_angle_b_deg},
    {"top_width_mm", &R::top_width_mm},
};
constexpr std::pair<const char*, int R::*> kCounts[] = {
    {"valid_points", &R::valid_points},
    {"outliers", &R::outliers},
};

// Micrometre-rounded value, or null when not measured.
Json num(double v) {
  if (!std::isfinite(v)) return nullptr;
  const double r = std::round(v * 1e6) / 1e6;
  return r == 0.0 ? 0.0 : r;  // no "-0.0"
}

Json point(const tk::Vec2& p) { return Json{{"y", num(p.x())}, {"z", num(p.y())}}; }

const Json& at(const Json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) throw JsonError(std::string("missing key '") + key + "'");
  return j.at(key);
}

// A number, or NaN for null.
double value(const Json& j, const char* key) {
  const Json& v = at(j, key);
  if (v.is_null()) return tk::kNotMeasured;
  if (!v.is_number()) throw JsonError(std::string("'") + key + "': expected a number or null");
  return v.get<double>();
}

template <class T>
T integer(const Json& j, const char* key) {
  const Json& v = at(j, key);
  if (!v.is_number_integer()) throw JsonError(std::string("'") + key + "': expected an integer");
  return v.get<T>();
}

std::string text(const Json& j, const char* key) {
  const Json& v = at(j, key);
  if (!v.is_string()) throw JsonError(std::string("'") + key + "': expected a string");
  return v.get<std::string>();
}

std::optional<tk::Vec2> point_from(const Json& j) {
  if (j.is_null()) return std::nullopt;
  return tk::Vec2(value(j, "y"), value(j, "z"));
}

}  // namespace

Json result_to_json(std::int64_t profile, const R& r) {
  Json j;
  j["profile"] = profile;
  j["joint"] = std::string(tk::to_string(r.joint));
  j["status"] = std::string(tk::to_string(r.status));
  if (r.status != tk::TrackStatus::Ok) j["reason"] = r.reason;
  Json bps = Json::array();
  for (int i = 0; i < tk::kMaxBreakPoints; ++i) {
    if (!r.break_points[i]) continue;
    Json bp{{"name", "B" + std::to_string(i)}, {"meaning", std::string(tk::break_point_name(r.joint, i))}};
    bp.update(point(*r.break_points[i]));
    bps.push_back(std::move(bp));
  }
  j["break_points"] = std::move(bps);
  j["track_point"] = r.track_point ? point(*r.track_point) : Json();
  j["rival_track_point"] = r.rival_track_point ? point(*r.rival_track_point) : Json();
  for (const auto& [key, field] : kValues) j[key] = num(r.*field);
  for (const auto& [key, field] : kGrooveValues) j[key] = num(r.*field);
  j["fill_lowest"] = r.fill_lowest ? point(*r.fill_lowest) : Json();
  for (const auto& [key, field] : kCounts) j[key] = r.*field;
  Json segs = Json::array();
  for (const auto& s : r.segments) {
    Json line = s.points >= 2 ? Json{{"ny", num(s.line.n.x())}, {"nz", num(s.line.n.y())}, {"c", num(s.line.c)}}
                              : Json();
    segs.push_back(Json{{"first", s.first_col},
                        {"last", s.last_col},
                        {"points", s.points},
                        {"line", std::move(line)},
                        {"rms_mm", num(s.rms_mm)}});
  }
  j["segments"] = std::move(segs);
  return j;
}

std::string result_to_json_line(std::int64_t profile, const R& r) {
  std::string line = result_to_json(profile, r).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  line += '\n';
  return line;
}

std::string sequence_to_json_line(std::int64_t profile, const R& r, const tk::Follower& follower) {
  Json j = result_to_json(profile, r);
  Json region;
  if (const auto& reg = follower.region())
    region = Json{{"y", num(reg->track_point.x())}, {"z", num(reg->track_point.y())}, {"radius_mm", num(reg->radius_mm)}};
  j["sequence"] = Json{{"locked", follower.locked()},
                       {"region", std::move(region)},
                       {"filtered", follower.filtered() ? point(*follower.filtered()) : Json()}};
  std::string line = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  line += '\n';
  return line;
}

R result_from_json(const Json& j, std::int64_t* profile) {
  R r;
  if (profile) *profile = integer<std::int64_t>(j, "profile");
  const std::string joint = text(j, "joint"), status = text(j, "status");
  const auto type = tk::joint_type_from_string(joint);
  if (!type) throw JsonError("'joint': '" + joint + "' is not a joint");
  r.joint = *type;
  if (status == "ok") r.status = tk::TrackStatus::Ok;
  else if (status == "rejected") r.status = tk::TrackStatus::Rejected;
  else if (status == "no_data") r.status = tk::TrackStatus::NoData;
  else throw JsonError("'status': '" + status + "' is not ok, rejected or no_data");
  if (r.status != tk::TrackStatus::Ok) r.reason = text(j, "reason");
  const Json& bps = at(j, "break_points");
  if (!bps.is_array()) throw JsonError("'break_points': expected a list");
  for (const Json& bp : bps) {
    const std::string name = text(bp, "name");
    const int i = name.size() == 2 && name[0] == 'B' ? name[1] - '0' : -1;
    if (i < 0 || i >= tk::kMaxBreakPoints) throw JsonError("'break_points': '" + name + "' is not B0 .. B7");
    r.break_points[i] = point_from(bp);
  }
  r.track_point = point_from(at(j, "track_point"));
  r.rival_track_point = point_from(at(j, "rival_track_point"));
  for (const auto& [key, field] : kValues) r.*field = value(j, key);
  for (const auto& [key, field] : kGrooveValues)
    if (j.contains(key)) r.*field = value(j, key);
  if (j.contains("fill_lowest")) r.fill_lowest = point_from(j.at("fill_lowest"));
  for (const auto& [key, field] : kCounts) r.*field = integer<int>(j, key);
  const Json& segs = at(j, "segments");
  if (!segs.is_array()) throw JsonError("'segments': expected a list");
  for (const Json& s : segs) {
    R::SegmentInfo info;
    info.first_col = integer<int>(s, "first");
    info.last_col = integer<int>(s, "last");
    info.points = integer<int>(s, "points");
    if (const Json& line = at(s, "line"); !line.is_null()) {
      info.line.n = tk::Vec2(value(line, "ny"), value(line, "nz"));
      info.line.c = value(line, "c");
    }
    info.rms_mm = value(s, "rms_mm");
    r.segments.push_back(info);
  }
  return r;
}

}  // namespace vts::trackio
