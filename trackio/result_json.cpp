#include "trackio/result_json.h"

#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>
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
// How precisely the track point is located, written after the grooves'
// values; files written before lack them (read as not measured).
constexpr std::pair<const char*, double R::*> kLocationValues[] = {
    {"track_sigma_mm", &R::track_sigma_mm},
    {"track_off_probability", &R::track_off_probability},
};
constexpr std::pair<const char*, int R::*> kCounts[] = {
    {"valid_points", &R::valid_points},
    {"outliers", &R::outliers},
};

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

// One line of JSON, written as nlohmann's dump(-1) of the same object would
// be (keys in insertion order, no spaces, its number format), without
// building the object: the line is most of `vts track`'s time otherwise.
class LineWriter {
 public:
  std::string out;

  // `"key":`, after a comma unless first in its object.
  LineWriter& key(const char* k) {
    comma();
    out += '"';
    out += k;
    out += "\":";
    first_ = true;  // the value is not preceded by a comma
    return *this;
  }
  void open(char c) {
    comma();
    out += c;
    first_ = true;
  }
  void close(char c) {
    out += c;
    first_ = false;
  }
  void null() { value("null"); }
  void boolean(bool b) { value(b ? "true" : "false"); }
  void integer(std::int64_t v) {
    char buf[24];
    const auto res = std::to_chars(buf, buf + sizeof buf, v);
    value(std::string_view(buf, static_cast<std::size_t>(res.ptr - buf)));
  }
  // num(v): micrometre-rounded, or null when not measured.
  void number(double v) {
    if (!std::isfinite(v)) return null();
    double r = std::round(v * 1e6) / 1e6;
    if (r == 0.0) r = 0.0;  // no "-0.0"
    std::array<char, 64> buf;
    char* end = nlohmann::detail::to_chars(buf.data(), buf.data() + buf.size(), r);
    value(std::string_view(buf.data(), static_cast<std::size_t>(end - buf.data())));
  }
  void string(std::string_view t) {
    // Printable ASCII without quote or backslash is written as is; anything
    // else is escaped by nlohmann (invalid UTF-8 replaced).
    for (const char c : t)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F || c == '"' || c == '\\')
        return value(Json(std::string(t)).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    comma();
    out += '"';
    out += t;
    out += '"';
    first_ = false;
  }
  void point(const tk::Vec2& p) {
    open('{');
    key("y").number(p.x());
    key("z").number(p.y());
    close('}');
  }
  void point(const std::optional<tk::Vec2>& p) { p ? point(*p) : null(); }

 private:
  bool first_ = true;
  void comma() {
    if (!first_) out += ',';
  }
  void value(std::string_view v) {
    comma();
    out += v;
    first_ = false;
  }
};

// The result's members, the object left open (for "sequence").
void write_result(LineWriter& w, std::int64_t profile, const R& r) {
  w.open('{');
  w.key("profile").integer(profile);
  w.key("joint").string(tk::to_string(r.joint));
  w.key("status").string(tk::to_string(r.status));
  if (r.status != tk::TrackStatus::Ok) w.key("reason").string(r.reason);
  w.key("break_points").open('[');
  for (int i = 0; i < tk::kMaxBreakPoints; ++i) {
    if (!r.break_points[i]) continue;
    w.open('{');
    char name[16] = "B";
    const auto end = std::to_chars(name + 1, name + sizeof name, i).ptr;
    w.key("name").string(std::string_view(name, static_cast<std::size_t>(end - name)));
    w.key("meaning").string(tk::break_point_name(r.joint, i));
    w.key("y").number(r.break_points[i]->x());
    w.key("z").number(r.break_points[i]->y());
    w.close('}');
  }
  w.close(']');
  w.key("track_point").point(r.track_point);
  w.key("rival_track_point").point(r.rival_track_point);
  for (const auto& [key, field] : kValues) w.key(key).number(r.*field);
  for (const auto& [key, field] : kGrooveValues) w.key(key).number(r.*field);
  for (const auto& [key, field] : kLocationValues) w.key(key).number(r.*field);
  w.key("fill_lowest").point(r.fill_lowest);
  for (const auto& [key, field] : kCounts) w.key(key).integer(r.*field);
  w.key("segments").open('[');
  for (const auto& seg : r.segments) {
    w.open('{');
    w.key("first").integer(seg.first_col);
    w.key("last").integer(seg.last_col);
    w.key("points").integer(seg.points);
    w.key("line");
    if (seg.points >= 2) {
      w.open('{');
      w.key("ny").number(seg.line.n.x());
      w.key("nz").number(seg.line.n.y());
      w.key("c").number(seg.line.c);
      w.close('}');
    } else {
      w.null();
    }
    w.key("rms_mm").number(seg.rms_mm);
    w.close('}');
  }
  w.close(']');
}

}  // namespace

Json result_to_json(std::int64_t profile, const R& r) { return Json::parse(result_to_json_line(profile, r)); }

std::string result_to_json_line(std::int64_t profile, const R& r) {
  LineWriter w;
  write_result(w, profile, r);
  w.close('}');
  w.out += '\n';
  return std::move(w.out);
}

std::string sequence_to_json_line(std::int64_t profile, const R& r, const tk::Follower& follower) {
  LineWriter w;
  write_result(w, profile, r);
  w.key("sequence").open('{');
  w.key("locked").boolean(follower.locked());
  w.key("region");
  if (const auto& reg = follower.region()) {
    w.open('{');
    w.key("y").number(reg->track_point.x());
    w.key("z").number(reg->track_point.y());
    w.key("radius_mm").number(reg->radius_mm);
    w.close('}');
  } else {
    w.null();
  }
  w.key("filtered").point(follower.filtered());
  w.close('}');
  w.close('}');
  w.out += '\n';
  return std::move(w.out);
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
  for (const auto& [key, field] : kLocationValues)
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
