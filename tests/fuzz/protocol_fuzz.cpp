// libFuzzer target: vts serve's wire format (server/protocol.h) on arbitrary
// bytes. The first byte picks the line limit (1..256 bytes, or the server's
// 64 KiB) and how the rest is cut into reads; the bytes go through a
// LineBuffer, every line through parse_request, every request's body
// through each field reader under the names the commands use. Contract: no
// crash or UB; a parse gives a request with a string cmd or an answer with
// "ok": false and error "bad_json"; a field reader returns a finite value
// or throws BadArgument (nothing else); every answer and the pose a reader
// returned go through to_line and read back as JSON, the pose bit for bit.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "server/protocol.h"

using namespace vts::server;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

void check_answer(const Json& a) {
  const std::string line = to_line(a);
  check(!line.empty() && line.back() == '\n');
  const Json back = Json::parse(line, nullptr, false);
  check(!back.is_discarded() && back.is_object());
  check(back.contains("ok") && back["ok"] == false && back["error"].is_string());
}

template <class F>
void reader(F&& f) {
  try {
    f();
  } catch (const BadArgument& e) {
    check(e.what()[0] != '\0');
  }
}

void fields(const Json& body) {
  for (const char* name : {"to_s", "dt_s", "speed_mm_s", "protocol", "after_index", "id", "cmd"}) {
    reader([&] { check(std::isfinite(number_field(body, name, -1e300, 1e300))); });
    reader([&] { check(std::isfinite(number_field(body, name, 0.1, 2000.0, 1.0))); });
    reader([&] { (void)integer_field(body, name, -1, INT64_MAX, -1); });
    reader([&] { (void)bool_field(body, name, false); });
    reader([&] { (void)string_field(body, name, ""); });
  }
  for (const char* name : {"offset_mm", "world_from_tool"}) {
    reader([&] {
      const Eigen::Vector3d v = vec3_field(body, name);
      check(v.allFinite());
    });
    reader([&] {
      const Pose3 p = pose_field(body, name);
      check(p.matrix().allFinite());
      Json wrap;
      wrap["p"] = Json::parse(to_line(to_json(p)));
      check(pose_field(wrap, "p").matrix() == p.matrix());
    });
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t max_line = data[0] == 0 ? kMaxLineBytes : data[0];
  const std::size_t chunk = 1 + (data[0] % 7) * 13;
  LineBuffer lines(max_line);
  std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
  bool framed = true;
  while (!rest.empty() && framed) {
    const std::string_view part = rest.substr(0, chunk);
    rest.remove_prefix(part.size());
    framed = lines.feed(part, [&](std::string_view line) {
      check(line.size() <= max_line);
      auto r = parse_request(line);
      if (auto* a = std::get_if<Json>(&r)) {
        check_answer(*a);
        check((*a)["error"] == "bad_json");
        return;
      }
      const Request& q = std::get<Request>(r);
      check(q.body.is_object());
      check(q.id.is_null() || q.id.is_number() || q.id.is_string());
      check_answer(error_answer(q.id, "unknown_command", "unknown command \"" + q.cmd + "\""));
      fields(q.body);
    });
    check(lines.pending() <= max_line);
  }
  return 0;
}
