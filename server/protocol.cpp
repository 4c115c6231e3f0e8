#include "server/protocol.h"

#include <cmath>
#include <sstream>

namespace vts::server {

bool LineBuffer::feed(std::string_view data, const std::function<void(std::string_view)>& on_line) {
  while (!data.empty()) {
    const std::size_t nl = data.find('\n');
    const std::string_view part = data.substr(0, nl);
    if (buf_.size() + part.size() > max_) {
      buf_.clear();
      buf_.shrink_to_fit();
      return false;
    }
    if (nl == std::string_view::npos) {
      buf_.append(part);
      return true;
    }
    std::string_view line = part;
    if (!buf_.empty()) {
      buf_.append(part);
      line = buf_;
    }
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    on_line(line);
    buf_.clear();
    data.remove_prefix(nl + 1);
  }
  return true;
}

Json error_answer(const Json& id, std::string_view code, const std::string& message) {
  Json j;
  j["id"] = id;
  j["ok"] = false;
  j["error"] = std::string(code);
  j["message"] = message;
  return j;
}

Json ok_answer(const Json& id) {
  Json j;
  j["id"] = id;
  j["ok"] = true;
  return j;
}

std::variant<Request, Json> parse_request(std::string_view line) {
  Json j = Json::parse(line.begin(), line.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return error_answer(nullptr, "bad_json", "the line is not valid JSON (or not UTF-8)");
  if (!j.is_object()) return error_answer(nullptr, "bad_json", "a message must be a JSON object");
  Request r;
  if (const auto it = j.find("id"); it != j.end()) {
    if (!it->is_number() && !it->is_string())
      return error_answer(nullptr, "bad_json", "\"id\" must be a number or a string");
    r.id = *it;
  }
  const auto cmd = j.find("cmd");
  if (cmd == j.end() || !cmd->is_string())
    return error_answer(r.id, "bad_json", "a request needs a string \"cmd\"");
  r.cmd = cmd->get<std::string>();
  r.body = std::move(j);
  return r;
}

namespace {

[[noreturn]] void bad_field(const char* name, const Json* value, const std::string& why) {
  std::string v = value ? value->dump(-1, ' ', false, Json::error_handler_t::replace) : "missing";
  if (v.size() > 80) v = v.substr(0, 77) + "...";
  throw BadArgument(std::string(name) + " = " + v + ": " + why);
}

const Json* find(const Json& body, const char* name) {
  const auto it = body.find(name);
  return it == body.end() ? nullptr : &*it;
}

double finite(const Json& v, const char* name) {
  if (!v.is_number()) bad_field(name, &v, "expected a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) bad_field(name, &v, "expected a finite number");
  return d;
}

}  // namespace

double number_field(const Json& body, const char* name, double lo, double hi) {
  const Json* v = find(body, name);
  if (!v) bad_field(name, nullptr, "required");
  const double d = finite(*v, name);
  if (d < lo || d > hi) {
    std::ostringstream s;
    s << "out of range " << lo << " to " << hi;
    bad_field(name, v, s.str());
  }
  return d;
}

double number_field(const Json& body, const char* name, double lo, double hi, double fallback) {
  return find(body, name) ? number_field(body, name, lo, hi) : fallback;
}

bool bool_field(const Json& body, const char* name, bool fallback) {
  const Json* v = find(body, name);
  if (!v) return fallback;
  if (!v->is_boolean()) bad_field(name, v, "expected true or false");
  return v->get<bool>();
}

std::int64_t integer_field(const Json& body, const char* name, std::int64_t lo, std::int64_t hi,
                           std::int64_t fallback) {
  const Json* v = find(body, name);
  if (!v) return fallback;
  if (!v->is_number_integer()) bad_field(name, v, "expected an integer");
  if (v->is_number_unsigned() && v->get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))
    bad_field(name, v, "out of range " + std::to_string(lo) + " to " + std::to_string(hi));
  const std::int64_t i = v->get<std::int64_t>();
  if (i < lo || i > hi) bad_field(name, v, "out of range " + std::to_string(lo) + " to " + std::to_string(hi));
  return i;
}

std::string string_field(const Json& body, const char* name, const std::string& fallback) {
  const Json* v = find(body, name);
  if (!v) return fallback;
  if (!v->is_string()) bad_field(name, v, "expected a string");
  return v->get<std::string>();
}

namespace {

Eigen::Vector3d vec3(const Json& v, const char* name) {
  if (!v.is_array() || v.size() != 3) bad_field(name, &v, "expected [x, y, z]");
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) out[i] = finite(v[static_cast<std::size_t>(i)], name);
  return out;
}

}  // namespace

Eigen::Vector3d vec3_field(const Json& body, const char* name) {
  const Json* v = find(body, name);
  if (!v) bad_field(name, nullptr, "required");
  return vec3(*v, name);
}

Pose3 pose_field(const Json& body, const char* name) {
  const Json* v = find(body, name);
  if (!v) bad_field(name, nullptr, "required");
  if (!v->is_object()) bad_field(name, v, "expected {\"t\": [x, y, z], \"R\": [[3], [3], [3]]}");
  const Json* t = find(*v, "t");
  const Json* r = find(*v, "R");
  if (!t || !r) bad_field(name, v, "needs \"t\" and \"R\"");
  Pose3 p = Pose3::Identity();
  p.translation() = vec3(*t, name);
  if (!r->is_array() || r->size() != 3) bad_field(name, r, "\"R\" must be 3 rows of 3 numbers");
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) {
    const Json& row = (*r)[static_cast<std::size_t>(i)];
    if (!row.is_array() || row.size() != 3) bad_field(name, r, "\"R\" must be 3 rows of 3 numbers");
    for (int k = 0; k < 3; ++k) m(i, k) = finite(row[static_cast<std::size_t>(k)], name);
  }
  if ((m.transpose() * m - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || m.determinant() < 0.0)
    bad_field(name, r, "\"R\" is not a rotation (orthonormal within 1e-6, determinant +1)");
  p.linear() = m;
  return p;
}

Json to_json(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json to_json(const Pose3& pose) {
  Json j;
  j["t"] = to_json(Eigen::Vector3d(pose.translation()));
  Json r = Json::array();
  for (int i = 0; i < 3; ++i) r.push_back(Json::array({pose.linear()(i, 0), pose.linear()(i, 1), pose.linear()(i, 2)}));
  j["R"] = r;
  return j;
}

std::string to_line(const Json& message) {
  std::string s = message.dump(-1, ' ', false, Json::error_handler_t::replace);
  s.push_back('\n');
  return s;
}

}  // namespace vts::server
