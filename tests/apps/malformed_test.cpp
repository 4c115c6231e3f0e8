// The malformed-input corpus (tests/malformed/cases.txt): every case runs
// bin/vts in a copy of tests/malformed and checks the exit code, the exact stderr line
// and, for accepted inputs, stdout.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kVtsBin = fs::path(VTS_BIN_DIR) / "vts";
const fs::path kMalformed = fs::path(VTS_SOURCE_DIR) / "tests" / "malformed";

struct Case {
  std::string name, args, stderr_text, stdout_text;
  int exit = -1;
  int stdout_lines = -1;  // -1: stdout not checked
  int line = 0;           // in cases.txt
};

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::vector<Case> read_cases() {
  std::ifstream in(kMalformed / "cases.txt");
  REQUIRE(in);
  std::vector<Case> cases;
  std::string line;
  int n = 0;
  bool open = false;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line[0] == '#') continue;
    if (line.empty()) {
      open = false;
      continue;
    }
    const auto colon = line.find(':');
    INFO("cases.txt:" << n << ": " << line);
    REQUIRE(colon != std::string::npos);
    const std::string key = line.substr(0, colon);
    std::string value = line.substr(colon + 1);
    if (!value.empty() && value[0] == ' ') value.erase(0, 1);
    if (key == "case") {
      cases.emplace_back();
      cases.back().name = value;
      cases.back().line = n;
      open = true;
      continue;
    }
    REQUIRE(open);
    Case& c = cases.back();
    if (key == "args") c.args = value;
    else if (key == "exit") c.exit = std::stoi(value);
    else if (key == "stderr") c.stderr_text = value;
    else if (key == "stdout") c.stdout_text = value;
    else if (key == "stdout_lines") c.stdout_lines = std::stoi(value);
    else FAIL("unknown key '" << key << "'");
  }
  return cases;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  std::string l;
  while (std::getline(s, l)) out.push_back(l);
  return out;
}

}  // namespace

TEST_CASE("malformed inputs give their exact message and exit code", "[malformed]") {
  const std::vector<Case> cases = read_cases();
  REQUIRE(cases.size() >= 30);
  static std::atomic<int> counter{0};
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      INFO("tests/malformed/cases.txt:" << c.line << ": " << c.name);
      REQUIRE(!c.args.empty());
      REQUIRE(c.exit >= 0);
      const fs::path tmp = fs::temp_directory_path() /
                           ("vts_malformed_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
      fs::remove_all(tmp);
      fs::create_directories(tmp);
      const fs::path out_dir = tmp / "out";
      fs::create_directories(out_dir);
      // The inputs, copied into a working directory; FILE.exr.in becomes FILE.exr
      // (the repository ignores *.exr outside tests/data).
      const fs::path work = tmp / "work";
      fs::create_directories(work);
      for (const auto& e : fs::directory_iterator(kMalformed)) {
        if (!e.is_regular_file()) continue;
        std::string name = e.path().filename().string();
        if (name.size() > 7 && name.compare(name.size() - 7, 7, ".exr.in") == 0) name.resize(name.size() - 3);
        fs::copy_file(e.path(), work / name);
      }
      std::string args = c.args;
      for (std::size_t at; (at = args.find("{tmp}")) != std::string::npos;)
        args.replace(at, 5, out_dir.string());
      const std::string cmd = "cd " + quote(work.string()) + " && " + quote(kVtsBin.string()) + " " + args +
                              " > " + quote((tmp / "stdout.txt").string()) + " 2> " +
                              quote((tmp / "stderr.txt").string()) + " < /dev/null";
      const int status = std::system(cmd.c_str());
      REQUIRE(WIFEXITED(status));
      const int code = WEXITSTATUS(status);
      const std::string out = read_all(tmp / "stdout.txt");
      const std::string err = read_all(tmp / "stderr.txt");
      INFO("stderr: " << err);
      CHECK(code == c.exit);
      CHECK(err == (c.stderr_text.empty() ? std::string() : c.stderr_text + "\n"));
      if (c.stdout_lines >= 0) {
        const std::vector<std::string> ls = lines_of(out);
        CHECK(static_cast<int>(ls.size()) == c.stdout_lines);
        for (const std::string& l : ls) CHECK(l.find(c.stdout_text) != std::string::npos);
      }
      if (c.exit != 0) CHECK(fs::is_empty(out_dir));  // bad input: nothing written
      std::error_code ec;
      fs::remove_all(tmp, ec);
    }
  }
}
