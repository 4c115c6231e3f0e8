#pragma once
// SHA-256 (FIPS 180-4), for the checksums of dataset shards (dataset/
// dataset.h) and anything else that must tell a file from a damaged copy.
// Small and dependency-free: vts links no crypto library. On x86-64 CPUs
// with the SHA extensions (Intel since Goldmont/Ice Lake, AMD since Zen) the
// blocks are digested by those instructions (about 10x the portable code),
// chosen at run time; elsewhere by portable C++. Both give the same digest.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace vts {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view bytes) { update(bytes.data(), bytes.size()); }
  // The digest; the object is then spent (call reset() to reuse it).
  std::array<std::uint8_t, 32> digest();
  // The digest as 64 lowercase hex digits.
  std::string hex_digest();
  void reset();

 private:
  void blocks(const std::uint8_t* p, std::size_t n);  // n whole 64-byte blocks
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buf_;
  std::size_t used_ = 0;
  std::uint64_t bytes_ = 0;
};

// Whether the CPU's SHA extensions digest (true where it has them), and a
// switch to the portable code and back for tests and comparisons (setting
// true has no effect on a CPU without them). Thread-safe.
bool sha256_cpu_extensions();
void sha256_use_cpu_extensions(bool on);

// Lowercase hex SHA-256 of `bytes`.
std::string sha256_hex(std::string_view bytes);
// Lowercase hex SHA-256 of the file's contents and its size in bytes;
// throws std::runtime_error "cannot read PATH" when it cannot be read.
std::string sha256_file(const std::filesystem::path& path, std::uint64_t* size = nullptr);

}  // namespace vts
