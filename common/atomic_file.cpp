#include "common/atomic_file.h"

#include <unistd.h>

#include <stdexcept>
#include <string>
#include <system_error>

namespace vts {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)), tmp_(path_) {
  tmp_ += ".tmp-" + std::to_string(::getpid());
  file_.open(tmp_, std::ios::binary | std::ios::trunc);
}

AtomicFile::~AtomicFile() {
  if (done_) return;
  file_.close();
  std::error_code ec;
  fs::remove(tmp_, ec);
}

void AtomicFile::commit() {
  done_ = true;
  file_.close();
  std::error_code ec;
  if (!file_) {
    fs::remove(tmp_, ec);
    throw std::runtime_error("cannot write " + path_.string());
  }
  fs::rename(tmp_, path_, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp_, ec);
    throw std::runtime_error("cannot rename onto " + path_.string() + ": " + why);
  }
}

}  // namespace vts
