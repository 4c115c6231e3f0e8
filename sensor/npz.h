#pragma once
// A NumPy .npz archive written as a stream: an uncompressed ZIP (method
// "stored", CRC-32 from zlib) of .npy arrays (format version 1.0), what
// numpy.savez writes and numpy.load reads (allow_pickle=False suffices: no
// object arrays). Every member carries ZIP64 sizes, as numpy's own do, so
// arrays and archives beyond 4 GiB need no other path. The bytes depend only
// on the arrays (every member is dated 1980-01-01 00:00).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace vts {

class NpzWriter {
 public:
  // Receives the array's raw bytes, in C order, in pieces of any size.
  using Sink = std::function<void(const void* data, std::size_t bytes)>;
  // Calls its sink with every byte of the array; called twice (the CRC, then
  // the bytes), so it must give the same bytes both times.
  using Emit = std::function<void(const Sink&)>;

  explicit NpzWriter(std::ostream& out) : out_(out) {}

  // Appends NAME.npy: `descr` a NumPy type string ("<f4", "<f8", "|b1",
  // "<i8", "<U12"), `shape` its dimensions ({} for a 0-d array), `item_bytes`
  // the size of one element. `emit` must give exactly the product of shape
  // times item_bytes bytes, else std::logic_error.
  void add(const std::string& name, const std::string& descr, const std::vector<std::int64_t>& shape,
           std::size_t item_bytes, const Emit& emit);
  // Appends NAME.npy holding `text` (UTF-8) as a 0-d NumPy unicode string
  // ("<U" + its length in code points; invalid UTF-8 becomes U+FFFD).
  void add_string(const std::string& name, const std::string& text);
  // Writes the central directory. Nothing may be added after.
  void finish();

 private:
  struct Entry {
    std::string name;
    std::uint32_t crc = 0;
    std::uint64_t size = 0, offset = 0;
  };
  void put(const void* data, std::size_t bytes);

  std::ostream& out_;
  std::uint64_t written_ = 0;
  std::vector<Entry> entries_;
  bool finished_ = false;
};

}  // namespace vts
