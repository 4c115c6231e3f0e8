#pragma once
// Reading binary files back in tests: a value of type T stored as in memory
// (little-endian on the machines vts builds for) at a byte offset.
#include <catch2/catch.hpp>

#include <cstddef>
#include <cstring>
#include <string>

namespace vts::test {

template <class T>
T get(const std::string& bytes, std::size_t at) {
  REQUIRE(at + sizeof(T) <= bytes.size());
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  return v;
}

}  // namespace vts::test
