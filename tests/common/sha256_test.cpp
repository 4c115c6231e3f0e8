// SHA-256 against the FIPS 180-2 examples (and the empty message), fed whole
// and in pieces that straddle the 64-byte blocks, and a file's digest.
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include "common/sha256.h"
#include "tests/common/temp_dir.h"

using vts::sha256_hex;

TEST_CASE("sha256: the standard's examples", "[sha256]") {
  CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  CHECK(sha256_hex(std::string(1000000, 'a')) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("sha256: pieces of any size give the digest of the whole", "[sha256]") {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += static_cast<char>((i * 37 + 11) & 0xff);
  const std::string whole = sha256_hex(text);
  for (std::size_t piece : {1u, 3u, 55u, 56u, 63u, 64u, 65u, 200u}) {
    vts::Sha256 h;
    for (std::size_t at = 0; at < text.size(); at += piece) h.update(std::string_view(text).substr(at, piece));
    CHECK(h.hex_digest() == whole);
  }
  vts::test::TempDir dir;
  std::uint64_t size = 0;
  CHECK(vts::sha256_file(dir.write("t.bin", text), &size) == whole);
  CHECK(size == text.size());
  CHECK_THROWS_WITH(vts::sha256_file(dir.path / "missing"), Catch::Contains("cannot read"));
}

TEST_CASE("sha256: the CPU's SHA extensions and the portable code give the same digests", "[sha256]") {
  // Lengths around the block and padding boundaries and long runs, bytes from
  // a fixed LCG (seeded): each digest made both ways. On a CPU without the
  // extensions both runs are the portable code, and the standard's examples
  // above are the check.
  const bool had = vts::sha256_cpu_extensions();
  std::string text;
  std::uint32_t x = 12345;
  for (int i = 0; i < 70000; ++i) {
    x = x * 1664525u + 1013904223u;
    text += static_cast<char>(x >> 24);
  }
  for (std::size_t n : {0u, 1u, 55u, 56u, 63u, 64u, 65u, 119u, 128u, 1000u, 4096u, 65537u, 70000u}) {
    const std::string_view part = std::string_view(text).substr(0, n);
    vts::sha256_use_cpu_extensions(false);
    CHECK_FALSE(vts::sha256_cpu_extensions());
    const std::string portable = sha256_hex(part);
    vts::sha256_use_cpu_extensions(true);
    CHECK(sha256_hex(part) == portable);
  }
  vts::sha256_use_cpu_extensions(false);
  CHECK(sha256_hex(std::string(1000000, 'a')) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  vts::sha256_use_cpu_extensions(had);
  WARN("SHA extensions " << (had ? "used" : "absent") << " on this CPU");
}
