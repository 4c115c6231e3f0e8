#pragma once
// A file written whole or not at all: the bytes go to PATH.tmp-<pid> in the
// same directory and are renamed onto PATH by commit(); an AtomicFile
// destroyed before commit() removes its temporary file, so a failed or
// interrupted run leaves nothing under PATH.
#include <filesystem>
#include <fstream>
#include <ostream>

namespace vts {

class AtomicFile {
 public:
  // Opens the temporary file (binary, truncated); is_open() says whether it could.
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  bool is_open() const { return file_.is_open(); }
  std::ostream& stream() { return file_; }
  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temp_path() const { return tmp_; }

  // Closes the temporary file and renames it onto path(). Throws
  // std::runtime_error "cannot write PATH" when a write failed (or it never
  // opened), "cannot rename onto PATH: WHY" when the rename did; the
  // temporary file is removed either way.
  void commit();

 private:
  std::filesystem::path path_, tmp_;
  std::ofstream file_;
  bool done_ = false;
};

}  // namespace vts
