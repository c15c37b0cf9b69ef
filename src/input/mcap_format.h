#pragma once
// The MCAP file format as dynamap reads and writes it: opcodes, little-endian fields read with
// bounds checks, and chunk (de)compression (zstd and LZ4 frames).

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynamap::mcap {

constexpr char kMagic[] = "\x89MCAP0\r\n";
constexpr std::size_t kMagicSize = 8;
constexpr std::size_t kRecordHead = 9;  // opcode (1) + content length (8)
constexpr std::size_t kFooterContent = 20;
/// No real chunk holds more; a record stating more is corrupt.
constexpr std::uint64_t kMaxRecord = std::uint64_t{1} << 30;
/// Neither zstd nor LZ4 shrinks real data (laser ranges, transforms) by more than this.
constexpr std::uint64_t kMaxRatio = 255;

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// A field that does not fit in its record.
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Reads the fields of one record's content, each checked against its end.
class Fields {
 public:
  Fields(const std::uint8_t* p, std::size_t n) : p_(p), n_(n) {}
  std::uint8_t u8() { return static_cast<std::uint8_t>(le(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(le(4)); }
  std::uint64_t u64() { return le(8); }
  std::string str() {
    const std::uint32_t n = u32();
    const std::uint8_t* s = take(n);
    return std::string(reinterpret_cast<const char*>(s), n);
  }
  /// Skips a field with a 4-byte length (bytes, a map, an array).
  void skip32() { take(u32()); }
  const std::uint8_t* take(std::uint64_t n) {
    if (n > n_ - at_) throw FormatError("a field runs past its record");
    const std::uint8_t* out = p_ + at_;
    at_ += static_cast<std::size_t>(n);
    return out;
  }
  std::size_t at() const { return at_; }
  std::size_t left() const { return n_ - at_; }

 private:
  std::uint64_t le(int bytes) {
    const std::uint8_t* b = take(static_cast<std::uint64_t>(bytes));
    std::uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | b[i];
    return v;
  }
  const std::uint8_t* p_;
  std::size_t n_, at_ = 0;
};

/// Appends little-endian fields (the writer's side of Fields).
struct Out {
  std::vector<std::uint8_t> bytes;
  void u8(std::uint8_t v) { bytes.push_back(v); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void raw(const std::uint8_t* p, std::size_t n) { bytes.insert(bytes.end(), p, p + n); }
  void le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
};

/// The `size` bytes a chunk compressed with "zstd" or "lz4" holds, into `out` (its storage reused
/// from chunk to chunk); throws FormatError when they do not come out exactly (corrupt data,
/// another size, an unknown method).
void decompress(const std::string& compression, const std::uint8_t* p, std::size_t n,
                std::uint64_t size, std::vector<std::uint8_t>& out);
/// `p[0, n)` compressed with "zstd" or "lz4" (level: zstd's; LZ4 frames use their default).
std::vector<std::uint8_t> compress(const std::string& compression, const std::uint8_t* p,
                                   std::size_t n);
/// CRC-32 (zlib's, as MCAP specifies).
std::uint32_t crc32(const std::uint8_t* p, std::size_t n);

}  // namespace dynamap::mcap
