#include "apps/cli.h"

#include "common/atomic_file.h"
#include "common/parallel.h"
#include "sensor/presets.h"
#include "sensor/scene_file.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace vts::cli {

[[noreturn]] void bad(const std::string& option, const std::string& value, const std::string& why) {
  throw UsageError(option + " = '" + value + "': " + why);
}

double parse_number(const std::string& option, const std::string& text, const char* unit) {
  const std::string expected = std::string("expected a number") + (*unit ? " in " : "") + unit;
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) bad(option, text, expected);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) bad(option, text, expected);
  if (!std::isfinite(v)) bad(option, text, "must be a finite number");
  return v;
}

double parse_positive(const std::string& option, const std::string& text, const char* unit) {
  const double v = parse_number(option, text, unit);
  if (v <= 0.0) bad(option, text, std::string("must be > 0 ") + unit);
  return v;
}

long long parse_integer(const std::string& option, const std::string& text, long long lo,
                        long long hi) {
  const std::string range = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  std::string t = text;
  if (!t.empty() && t.front() == '+') t.erase(0, 1);
  long long v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec == std::errc::result_out_of_range) bad(option, text, "out of range: expected " + range);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) bad(option, text, "expected " + range);
  if (v < lo || v > hi) bad(option, text, "out of range: expected " + range);
  return v;
}

std::uint64_t parse_seed(const std::string& option, const std::string& text) {
  std::uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size())
    bad(option, text, "expected an unsigned 64-bit integer (0 .. 18446744073709551615)");
  return v;
}

Vec3 parse_vec3(const std::string& option, const std::string& text, const char* unit) {
  std::vector<std::string> parts;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = text.find(',', pos);
    parts.push_back(text.substr(pos, comma - pos));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  const std::string expected =
      std::string("expected three comma-separated numbers X,Y,Z") + (*unit ? " in " : "") + unit;
  if (parts.size() != 3) bad(option, text, expected + ", got " + std::to_string(parts.size()));
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    const std::string& p = parts[i];
    const double x = p.empty() ? 0.0 : std::strtod(p.c_str(), &end);
    if (p.empty() || std::isspace(static_cast<unsigned char>(p.front())) ||
        end != p.c_str() + p.size())
      bad(option, text, expected + " ('" + p + "' is not a number)");
    if (!std::isfinite(x)) bad(option, text, "must be finite numbers");
    v[i] = x;
  }
  return v;
}

void apply_thread_limit(const std::string& option_text) {
  if (!option_text.empty()) {
    set_thread_limit(static_cast<int>(parse_integer("--threads", option_text, 1, 1024)));
    return;
  }
  try {
    thread_limit_from_environment();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

SourceKind parse_source(const std::string& option, const std::string& text) {
  if (text == "raster") return SourceKind::Raster;
  if (text == "reference") return SourceKind::Reference;
  bad(option, text, "expected 'raster' or 'reference'");
}

NamedCell load_cell(const std::string& cell, const std::string& scene) {
  if (!scene.empty()) {
    try {
      return {load_scene(scene), scene};
    } catch (const SceneError& e) {
      throw UsageError(std::string("--scene: ") + e.what());
    }
  }
  const std::string name = cell.empty() ? std::string(kDefaultCell) : cell;
  auto builtin = builtin_cell(name);
  if (!builtin)
    bad("--cell", name, "unknown cell; valid names: " + join_names(builtin_cell_names()) + " (see `vts cells`)");
  return {std::move(*builtin), name};
}

void check_output_file(const std::string& option, const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) bad(option, path, "is a directory, expected a file name");
  if (const std::filesystem::path dir = std::filesystem::path(path).parent_path();
      !dir.empty() && !std::filesystem::is_directory(dir, ec))
    bad(option, path, "directory '" + dir.string() + "' does not exist");
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  AtomicFile file(path);
  file.stream() << text;
  file.commit();
}

namespace {
// The signal caught (SIGINT or SIGTERM), 0 while none.
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int sig) { g_signal = sig; }
}  // namespace

SignalCancel::SignalCancel() {
  g_signal = 0;
  old_int_ = std::signal(SIGINT, on_signal);
  old_term_ = std::signal(SIGTERM, on_signal);
}

SignalCancel::~SignalCancel() {
  std::signal(SIGINT, old_int_);
  std::signal(SIGTERM, old_term_);
}

bool SignalCancel::cancelled() { return g_signal != 0; }
int SignalCancel::signal() { return g_signal; }
const char* SignalCancel::signal_name() { return g_signal == SIGTERM ? "SIGTERM" : "SIGINT"; }

}  // namespace vts::cli
