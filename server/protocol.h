#pragma once
// The wire format of docs/PROTOCOL.md: newline-delimited JSON objects. This
// part knows nothing of sockets or cells, so the fuzzer and the tests drive
// it alone: bytes in, lines out (LineBuffer); a line in, a request or an
// error answer out (parse_request); a request's fields read with messages
// naming the field and the value (Field readers).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include <Eigen/Geometry>

#include "trackio/result_json.h"

namespace vts::server {

using Json = trackio::Json;
using Pose3 = Eigen::Isometry3d;

inline constexpr int kProtocolVersion = 1;
inline constexpr std::size_t kMaxLineBytes = 65536;

// Splits a byte stream into lines ('\n'; a trailing '\r' is dropped).
class LineBuffer {
 public:
  explicit LineBuffer(std::size_t max_line = kMaxLineBytes) : max_(max_line) {}
  // Appends `data` and calls on_line for each complete line, in order.
  // Returns false (and drops what it holds) once a line is longer than the
  // limit: the stream has lost its framing.
  bool feed(std::string_view data, const std::function<void(std::string_view)>& on_line);
  std::size_t pending() const { return buf_.size(); }

 private:
  std::size_t max_;
  std::string buf_;
};

// A command request: `cmd`, the echoed `id` (null if none) and the whole object.
struct Request {
  Json id;
  std::string cmd;
  Json body;
};

// An answer carrying error `code` (docs/PROTOCOL.md, "Errors") and a message.
Json error_answer(const Json& id, std::string_view code, const std::string& message);
Json ok_answer(const Json& id);

// One line: a Request, or the error answer to send (bad_json: not JSON, not
// an object, not UTF-8, no string `cmd`, an `id` that is neither a number nor
// a string). Never throws.
std::variant<Request, Json> parse_request(std::string_view line);

// A request field that is missing, of the wrong type or out of range: the
// message names the field and the value ("bad_argument").
struct BadArgument : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Field readers: throw BadArgument "FIELD = VALUE: WHY".
double number_field(const Json& body, const char* name, double lo, double hi);
double number_field(const Json& body, const char* name, double lo, double hi, double fallback);  // when absent
bool bool_field(const Json& body, const char* name, bool fallback);
std::int64_t integer_field(const Json& body, const char* name, std::int64_t lo, std::int64_t hi,
                           std::int64_t fallback);
std::string string_field(const Json& body, const char* name, const std::string& fallback);
Eigen::Vector3d vec3_field(const Json& body, const char* name);
// {"t": [x, y, z], "R": [[...], [...], [...]]}: R orthonormal within 1e-6, det +1.
Pose3 pose_field(const Json& body, const char* name);

// The JSON forms of docs/PROTOCOL.md.
Json to_json(const Pose3& pose);
Json to_json(const Eigen::Vector3d& v);
// One line (with '\n'), invalid UTF-8 in strings replaced: never throws on content.
std::string to_line(const Json& message);

}  // namespace vts::server
