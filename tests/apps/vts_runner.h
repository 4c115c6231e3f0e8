#pragma once
// Shared by the end-to-end tests of tests/apps: run bin/vts in a fresh
// temporary directory and read back what it wrote.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/temp_dir.h"

namespace vts_test {

namespace fs = std::filesystem;

inline const fs::path kVts = fs::path(VTS_BIN_DIR) / "vts";

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A temporary working directory, removed with everything in it.
struct TempDir : vts::test::TempDir {
  TempDir() : vts::test::TempDir("vts_apps_test") {}

  // Files in the directory other than the captured stdout/stderr, sorted.
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path)) {
      const std::string n = e.path().filename().string();
      if (n != "stdout.txt" && n != "stderr.txt") names.push_back(n);
    }
    std::sort(names.begin(), names.end());
    return names;
  }
};

struct Result {
  int code = -1;
  std::string out, err;
};

// Runs `vts ARGS` in dir (args are passed through the shell as written),
// stdin from /dev/null, stdout and stderr captured; `env` ("NAME=value ...")
// goes before the command.
inline Result run_vts(const TempDir& dir, const std::string& args, const std::string& env = "") {
  const std::string cmd = "cd " + shell_quote(dir.path.string()) + " && " + env + (env.empty() ? "" : " ") +
                          shell_quote(kVts.string()) + " " + args +
                          " > stdout.txt 2> stderr.txt < /dev/null";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir.path / "stdout.txt");
  r.err = slurp(dir.path / "stderr.txt");
  return r;
}

}  // namespace vts_test
