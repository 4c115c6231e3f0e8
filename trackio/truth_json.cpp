#include "trackio/truth_json.h"

#include <cmath>

namespace vts::trackio {
namespace {

namespace tk = vts::tracker;

const Json& at(const Json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) throw JsonError(std::string("missing key '") + key + "'");
  return j.at(key);
}

// An optional number: NaN when absent or null.
double optional_value(const Json& j, const char* key) {
  if (!j.contains(key) || j.at(key).is_null()) return tk::kNotMeasured;
  if (!j.at(key).is_number()) throw JsonError(std::string("'") + key + "': expected a number or null");
  return j.at(key).get<double>();
}

double value(const Json& j, const char* key) {
  const Json& v = at(j, key);
  if (!v.is_number()) throw JsonError(std::string("'") + key + "': expected a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw JsonError(std::string("'") + key + "': not finite");
  return d;
}

}  // namespace

tk::Truth truth_from_json(const Json& j, std::int64_t* profile) {
  tk::Truth t;
  const Json& index = at(j, "profile");
  if (!index.is_number_integer()) throw JsonError("'profile': expected an integer");
  if (profile) *profile = index.get<std::int64_t>();
  const Json& tp = at(j, "track_point");
  t.track_point = tk::Vec2(value(tp, "y"), value(tp, "z"));
  if (j.contains("joint")) {
    const Json& jt = j.at("joint");
    if (!jt.is_string()) throw JsonError("'joint': expected a string");
    const auto type = tk::joint_type_from_string(jt.get<std::string>());
    if (!type) throw JsonError("'joint': '" + jt.get<std::string>() + "' is not a joint");
    t.joint = *type;
  }
  t.gap_mm = optional_value(j, "gap_mm");
  t.mismatch_mm = optional_value(j, "mismatch_mm");
  t.angle_deg = optional_value(j, "angle_deg");
  t.step_mm = optional_value(j, "step_mm");
  t.depth_mm = optional_value(j, "depth_mm");
  const double noise = optional_value(j, "noise_mm");
  t.noise_mm = std::isnan(noise) ? 0.0 : noise;
  if (j.contains("ideal")) {
    if (!j.at("ideal").is_boolean()) throw JsonError("'ideal': expected true or false");
    if (j.at("ideal").get<bool>()) t.noise_mm = -1.0;
  }
  if (j.contains("tags")) {
    const Json& tags = j.at("tags");
    if (!tags.is_array()) throw JsonError("'tags': expected a list of strings");
    for (const Json& tag : tags) {
      if (!tag.is_string()) throw JsonError("'tags': expected a list of strings");
      const std::string s = tag.get<std::string>();
      t.hidden = t.hidden || s == "joint_hidden" || s == "notch_unseen";
    }
  }
  return t;
}

}  // namespace vts::trackio
