#pragma once
// What the `vts` subcommands share: exit codes, the usage error, option value
// parsers whose messages name the option and the value, and the mapping of
// SIGINT/SIGTERM to a job's cancellation.
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "pipeline/scan_session.h"
#include "sensor/cell.h"
#include "sensor/pose.h"

namespace vts::cli {

// Exit codes: 0 success, 1 runtime failure (GL, EXR write), 2 bad input
// (option value, scene file). 128 + the signal when interrupted: 130 SIGINT,
// 143 SIGTERM.
inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntime = 1;
inline constexpr int kExitUsage = 2;

// A bad option value or input file, found before any output is created.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws UsageError "OPTION = 'VALUE': WHY".
[[noreturn]] void bad(const std::string& option, const std::string& value, const std::string& why);

// Option values, each checked with a message naming the option and the value
// (docs/CLI.md). `unit` goes into the message ("mm"; "" for none).
double parse_number(const std::string& option, const std::string& text, const char* unit);
double parse_positive(const std::string& option, const std::string& text, const char* unit);
long long parse_integer(const std::string& option, const std::string& text, long long lo, long long hi);
std::uint64_t parse_seed(const std::string& option, const std::string& text);
Vec3 parse_vec3(const std::string& option, const std::string& text, const char* unit);
// --threads (docs/CLI.md): the thread limit (common/parallel.h) from the
// option's text, or, when empty, checks VTS_THREADS; UsageError naming the
// option or the variable and the value. Call before any work.
void apply_thread_limit(const std::string& option_text);
// The --threads option's help text.
inline constexpr const char* kThreadsHelp =
    "Most threads to work with, >= 1 (default: $VTS_THREADS, else every hardware thread; never more than the "
    "hardware has). The output does not depend on it";

// "raster" or "reference".
SourceKind parse_source(const std::string& option, const std::string& text);

// The cell of --scene FILE (when given) or --cell NAME (empty: kDefaultCell),
// and its label (the file or the name). UsageError "--scene: WHY" or
// "--cell = 'NAME': unknown cell; valid names: ...".
struct NamedCell {
  Cell cell;
  std::string label;
};
NamedCell load_cell(const std::string& cell, const std::string& scene);

// An output file option: UsageError "OPTION = 'PATH': ..." when PATH is a
// directory or its directory does not exist.
void check_output_file(const std::string& option, const std::string& path);

// Writes `text` to `path` through a temporary file in the same directory,
// renamed when complete; throws std::runtime_error naming the file.
void write_text_file(const std::filesystem::path& path, const std::string& text);

// A job's progress on stderr, "WHAT: done/total profiles (%), rate": every second on a terminal (one line, rewritten); in a
// log only for long runs, every 5 s, one line each. Nothing in between.
class ProgressLine {
 public:
  ProgressLine(std::string what, std::int64_t total)
      : what_(std::move(what)), total_(total), tty_(isatty(STDERR_FILENO) == 1) {
    start_ = last_ = std::chrono::steady_clock::now();
  }
  void update(std::int64_t done) {
    const auto now = std::chrono::steady_clock::now();
    const double interval = tty_ ? 1.0 : 5.0;
    if (std::chrono::duration<double>(now - last_).count() < interval) return;
    last_ = now;
    print(done, now);
  }
  // Completes a line already on the terminal with the final count.
  void done(std::int64_t done) {
    if (!printed_ || !tty_) return;
    print(done, std::chrono::steady_clock::now());
    std::cerr << '\n';
  }

 private:
  void print(std::int64_t done, std::chrono::steady_clock::time_point now) {
    const double t = std::chrono::duration<double>(now - start_).count();
    char line[160];
    std::snprintf(line, sizeof line, "%s: %lld/%lld profiles (%.1f%%), %.0f profiles/s", what_.c_str(),
                  static_cast<long long>(done), static_cast<long long>(total_), 100.0 * done / total_,
                  t > 0 ? done / t : 0.0);
    if (tty_)
      std::cerr << '\r' << line << "\x1b[K" << std::flush;
    else
      std::cerr << line << std::endl;
    printed_ = true;
  }

  std::string what_;
  std::int64_t total_;
  bool tty_;
  bool printed_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

// While it lives, SIGINT and SIGTERM are caught and recorded instead of
// ending the process (the previous handlers come back after); a job polls
// cancelled() and stops between batches.
class SignalCancel {
 public:
  SignalCancel();
  ~SignalCancel();
  SignalCancel(const SignalCancel&) = delete;
  SignalCancel& operator=(const SignalCancel&) = delete;
  static bool cancelled();
  static int signal();  // the signal caught, 0 if none
  // "SIGINT" or "SIGTERM"
  static const char* signal_name();

 private:
  using Handler = void (*)(int);
  Handler old_int_, old_term_;
};

}  // namespace vts::cli
