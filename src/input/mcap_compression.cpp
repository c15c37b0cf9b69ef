// MCAP chunk compression through Debian's libzstd and liblz4 (LZ4 frame format, as MCAP's
// "lz4"), and zlib's CRC-32.
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <memory>

#include "mcap_format.h"

namespace dynamap::mcap {
namespace {

void unzstd(const std::uint8_t* p, std::size_t n, std::size_t size,
            std::vector<std::uint8_t>& out) {
  // One context per thread, kept: ZSTD_decompress would make (and zero) a new one per chunk.
  static thread_local std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(),
                                                                               &ZSTD_freeDCtx);
  if (!ctx) throw FormatError("no zstd decompression context");
  const std::size_t got = ZSTD_decompressDCtx(ctx.get(), out.data(), out.size(), p, n);
  if (ZSTD_isError(got)) {
    throw FormatError(std::string("zstd data cannot be decompressed: ") + ZSTD_getErrorName(got));
  }
  if (got != size) throw FormatError("zstd data are shorter than the chunk states");
}

void unlz4(const std::uint8_t* p, std::size_t n, std::size_t size, std::vector<std::uint8_t>& out) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) {
    throw FormatError("no LZ4 decompression context");
  }
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in_at = 0, out_at = 0;
  for (;;) {
    std::size_t in_n = n - in_at, out_n = size - out_at;
    const std::size_t hint =
        LZ4F_decompress(ctx.get(), out.data() + out_at, &out_n, p + in_at, &in_n, nullptr);
    if (LZ4F_isError(hint)) {
      throw FormatError(std::string("LZ4 data cannot be decompressed: ") + LZ4F_getErrorName(hint));
    }
    in_at += in_n;
    out_at += out_n;
    if (hint == 0) break;  // the frame is whole
    // Neither input consumed nor output made: the data end before the frame does.
    if (in_n == 0 && out_n == 0) throw FormatError("LZ4 data end inside their frame");
  }
  if (out_at != size) throw FormatError("LZ4 data are shorter than the chunk states");
}

}  // namespace

void decompress(const std::string& compression, const std::uint8_t* p, std::size_t n,
                std::uint64_t size, std::vector<std::uint8_t>& out) {
  if (size > kMaxRecord || size > kMaxRatio * n + (std::uint64_t{1} << 20)) {
    throw FormatError("a chunk states " + std::to_string(size) + " uncompressed bytes for " +
                      std::to_string(n) + " stored");
  }
  if (compression != "zstd" && compression != "lz4") {
    throw FormatError("unknown chunk compression '" + compression + "'");
  }
  // Not zeroed again when the buffer held a chunk as large: only the bytes added are.
  out.resize(static_cast<std::size_t>(size));
  if (compression == "zstd")
    unzstd(p, n, out.size(), out);
  else
    unlz4(p, n, out.size(), out);
}

std::vector<std::uint8_t> compress(const std::string& compression, const std::uint8_t* p,
                                   std::size_t n) {
  std::vector<std::uint8_t> out;
  if (compression == "zstd") {
    out.resize(ZSTD_compressBound(n));
    const std::size_t got = ZSTD_compress(out.data(), out.size(), p, n, 3);
    if (ZSTD_isError(got)) throw FormatError(ZSTD_getErrorName(got));
    out.resize(got);
  } else if (compression == "lz4") {
    out.resize(LZ4F_compressFrameBound(n, nullptr));
    const std::size_t got = LZ4F_compressFrame(out.data(), out.size(), p, n, nullptr);
    if (LZ4F_isError(got)) throw FormatError(LZ4F_getErrorName(got));
    out.resize(got);
  } else {
    throw FormatError("unknown chunk compression '" + compression + "'");
  }
  return out;
}

std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
  uLong c = ::crc32(0L, Z_NULL, 0);
  constexpr std::size_t kStep = 1u << 30;  // zlib takes a uInt length
  for (std::size_t at = 0; at < n; at += kStep) {
    c = ::crc32(c, p + at, static_cast<uInt>(std::min(kStep, n - at)));
  }
  return static_cast<std::uint32_t>(c);
}

}  // namespace dynamap::mcap
