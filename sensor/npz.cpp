#include "sensor/npz.h"

#include <zlib.h>

#include <bit>
#include <stdexcept>

namespace vts {
namespace {

static_assert(std::endian::native == std::endian::little, "the ZIP and .npy fields are written as in memory");

constexpr std::uint32_t kLocalHeader = 0x04034b50, kCentralHeader = 0x02014b50;
constexpr std::uint32_t kZip64End = 0x06064b50, kZip64Locator = 0x07064b50, kEnd = 0x06054b50;
constexpr std::uint16_t kVersion = 45;  // 4.5: ZIP64
constexpr std::uint16_t kDosDate = (0 << 9) | (1 << 5) | 1;  // 1980-01-01, the earliest a ZIP can say
constexpr std::uint32_t kMore32 = 0xFFFFFFFFu;            // "see the ZIP64 extra field"

void le(std::string& b, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) b.push_back(static_cast<char>(v >> (8 * i)));
}

// The .npy 1.0 preamble: magic, version, header length, and the header dict
// padded with spaces to a multiple of 64 bytes, ending in '\n'.
std::string npy_header(const std::string& descr, const std::vector<std::int64_t>& shape) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (shape[i] < 0) throw std::logic_error("npz: negative dimension");
    if (i > 0) dict += ", ";
    dict += std::to_string(shape[i]);
  }
  if (shape.size() == 1) dict += ',';
  dict += "), }";
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string out = "\x93NUMPY\x01";
  out += '\0';
  le(out, dict.size(), 2);
  return out + dict;
}

std::uint32_t crc(std::uint32_t c, const void* data, std::size_t bytes) {
  return static_cast<std::uint32_t>(crc32_z(c, static_cast<const Bytef*>(data), bytes));
}

// UTF-8 to code points; a byte that starts no valid sequence becomes U+FFFD.
std::vector<std::uint32_t> code_points(const std::string& s) {
  std::vector<std::uint32_t> out;
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = p[i];
    const int len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    std::uint32_t cp = len == 1 ? c : len == 2 ? c & 0x1Fu : len == 3 ? c & 0x0Fu : c & 0x07u;
    bool ok = len > 0 && i + len <= n;
    for (int k = 1; ok && k < len; ++k) {
      ok = (p[i + k] & 0xC0) == 0x80;
      cp = (cp << 6) | (p[i + k] & 0x3Fu);
    }
    static constexpr std::uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
    if (ok && (cp < kMin[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))) ok = false;
    out.push_back(ok ? cp : 0xFFFDu);
    i += ok ? len : 1;
  }
  return out;
}

}  // namespace

void NpzWriter::put(const void* data, std::size_t bytes) {
  out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  written_ += bytes;
}

void NpzWriter::add(const std::string& name, const std::string& descr, const std::vector<std::int64_t>& shape,
                    std::size_t item_bytes, const Emit& emit) {
  if (finished_) throw std::logic_error("npz: add() after finish()");
  const std::string header = npy_header(descr, shape);
  std::uint64_t data_bytes = item_bytes;
  for (std::int64_t d : shape) data_bytes *= static_cast<std::uint64_t>(d);

  Entry e{name + ".npy", 0, header.size() + data_bytes, written_};
  std::uint64_t seen = 0;
  e.crc = crc(0, header.data(), header.size());
  emit([&](const void* data, std::size_t bytes) {
    e.crc = crc(e.crc, data, bytes);
    seen += bytes;
  });
  if (seen != data_bytes)
    throw std::logic_error("npz: array '" + name + "' gave " + std::to_string(seen) + " bytes, its shape " +
                           std::to_string(data_bytes));

  std::string local;
  le(local, kLocalHeader, 4);
  le(local, kVersion, 2);
  le(local, 0, 2);  // flags
  le(local, 0, 2);  // method: stored
  le(local, 0, 2);  // time 00:00
  le(local, kDosDate, 2);
  le(local, e.crc, 4);
  le(local, kMore32, 4);  // compressed size: in the ZIP64 field
  le(local, kMore32, 4);  // size: in the ZIP64 field
  le(local, e.name.size(), 2);
  le(local, 20, 2);  // extra field: ZIP64, 16 bytes of data
  local += e.name;
  le(local, 0x0001, 2);
  le(local, 16, 2);
  le(local, e.size, 8);
  le(local, e.size, 8);
  put(local.data(), local.size());
  put(header.data(), header.size());
  seen = 0;
  emit([&](const void* data, std::size_t bytes) {
    put(data, bytes);
    seen += bytes;
  });
  if (seen != data_bytes)
    throw std::logic_error("npz: array '" + name + "' gave other bytes the second time");
  entries_.push_back(std::move(e));
}

void NpzWriter::add_string(const std::string& name, const std::string& text) {
  const std::vector<std::uint32_t> cps = code_points(text);
  // NumPy has no zero-length unicode type: "<U0" reads back as "<U1".
  const std::size_t n = cps.empty() ? 1 : cps.size();
  std::vector<std::uint32_t> data = cps;
  data.resize(n, 0u);
  add(name, "<U" + std::to_string(n), {}, 4 * n,
      [&](const Sink& sink) { sink(data.data(), data.size() * sizeof(std::uint32_t)); });
}

void NpzWriter::finish() {
  if (finished_) return;
  finished_ = true;
  const std::uint64_t directory_offset = written_;
  for (const Entry& e : entries_) {
    std::string c;
    le(c, kCentralHeader, 4);
    le(c, kVersion, 2);  // made by (MS-DOS attributes, none set)
    le(c, kVersion, 2);  // needed to extract
    le(c, 0, 2);         // flags
    le(c, 0, 2);         // stored
    le(c, 0, 2);
    le(c, kDosDate, 2);
    le(c, e.crc, 4);
    le(c, kMore32, 4);
    le(c, kMore32, 4);
    le(c, e.name.size(), 2);
    le(c, 28, 2);  // extra field: ZIP64, 24 bytes of data
    le(c, 0, 2);   // comment
    le(c, 0, 2);   // disk
    le(c, 0, 2);   // internal attributes
    le(c, 0, 4);   // external attributes
    le(c, kMore32, 4);
    c += e.name;
    le(c, 0x0001, 2);
    le(c, 24, 2);
    le(c, e.size, 8);
    le(c, e.size, 8);
    le(c, e.offset, 8);
    put(c.data(), c.size());
  }
  const std::uint64_t directory_bytes = written_ - directory_offset;
  const std::uint64_t zip64_end_offset = written_;
  std::string t;
  le(t, kZip64End, 4);
  le(t, 44, 8);  // bytes after this field
  le(t, kVersion, 2);
  le(t, kVersion, 2);
  le(t, 0, 4);  // this disk
  le(t, 0, 4);  // the directory's disk
  le(t, entries_.size(), 8);
  le(t, entries_.size(), 8);
  le(t, directory_bytes, 8);
  le(t, directory_offset, 8);
  le(t, kZip64Locator, 4);
  le(t, 0, 4);
  le(t, zip64_end_offset, 8);
  le(t, 1, 4);  // disks
  le(t, kEnd, 4);
  le(t, 0, 2);
  le(t, 0, 2);
  const std::uint64_t count16 = entries_.size() < 0xFFFF ? entries_.size() : 0xFFFF;
  le(t, count16, 2);
  le(t, count16, 2);
  le(t, kMore32, 4);  // directory size: in the ZIP64 record
  le(t, kMore32, 4);  // directory offset: in the ZIP64 record
  le(t, 0, 2);        // comment
  put(t.data(), t.size());
}

}  // namespace vts
