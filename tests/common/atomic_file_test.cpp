// Files written whole or not at all (common/atomic_file.h).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/atomic_file.h"
#include "temp_dir.h"

namespace {

std::string read(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("atomic file: the bytes appear under the name only on commit", "[common]") {
  const vts::test::TempDir dir;
  const auto path = dir.path / "out.txt";
  dir.write("out.txt", "old");
  vts::AtomicFile file(path);
  REQUIRE(file.is_open());
  CHECK(file.temp_path().parent_path() == path.parent_path());
  file.stream() << "new bytes";
  file.stream().flush();
  CHECK(read(path) == "old");
  file.commit();
  CHECK(read(path) == "new bytes");
  CHECK(dir.entries() == std::vector<std::string>{"out.txt"});
}

TEST_CASE("atomic file: destroyed before commit, nothing is left", "[common]") {
  const vts::test::TempDir dir;
  {
    vts::AtomicFile file(dir.path / "out.txt");
    file.stream() << "partial";
  }
  CHECK(dir.entries().empty());
}

TEST_CASE("atomic file: a file that cannot be created fails on commit, naming it", "[common]") {
  const vts::test::TempDir dir;
  const auto path = dir.path / "missing" / "out.txt";
  vts::AtomicFile file(path);
  CHECK_FALSE(file.is_open());
  file.stream() << "text";
  CHECK_THROWS_WITH(file.commit(), "cannot write " + path.string());
  CHECK(dir.entries().empty());
}
