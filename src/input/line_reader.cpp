#include "dynamap/input/line_reader.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "dynamap/input/scan_source.h"

namespace dynamap {
namespace {

constexpr std::size_t kBlock = 64 * 1024;

// read(2) with EINTR retried; -1 with errno on an error.
ssize_t readSome(int fd, unsigned char* to, std::size_t n) {
  while (true) {
    const ssize_t r = ::read(fd, to, n);
    if (r >= 0 || errno != EINTR) return r;
  }
}

}  // namespace

/// The bytes of the file: as they are, or inflated when it starts with gzip's magic. inflate()
/// is driven here rather than through gzread(), which drops a whole block when a stream turns
/// out damaged at its end (a bad CRC): every byte inflated before the error is given out.
struct LineReader::Stream {
  int fd = -1;
  bool gz = false;
  bool member_ended = false;  // the last gzip member's trailer was read and checked
  bool input_ended = false;
  z_stream z{};
  std::vector<unsigned char> in = std::vector<unsigned char>(kBlock);
  std::string error;  // set once the stream failed: given after the bytes before it

  ~Stream() {
    if (gz) inflateEnd(&z);
    if (fd >= 0) ::close(fd);
  }
  /// Fills z's input; false at the end of the file.
  bool fillInput() {
    const ssize_t n = readSome(fd, in.data(), in.size());
    if (n < 0) {
      error = std::strerror(errno);
      return false;
    }
    z.next_in = in.data();
    z.avail_in = static_cast<uInt>(n);
    input_ended = n == 0;
    return n > 0;
  }
  /// Up to `cap` bytes into `out`; 0 at the end or at an error (`error` then says which).
  std::size_t read(char* out, std::size_t cap);
  std::size_t inflateSome(char* out, std::size_t cap);
};

std::size_t LineReader::Stream::read(char* out, std::size_t cap) {
  if (!error.empty()) return 0;
  if (!gz) {
    if (z.avail_in > 0) {  // the bytes looked at to tell the format
      const std::size_t n = std::min<std::size_t>(cap, z.avail_in);
      std::memcpy(out, z.next_in, n);
      z.next_in += n;
      z.avail_in -= static_cast<uInt>(n);
      return n;
    }
    const ssize_t n = readSome(fd, reinterpret_cast<unsigned char*>(out), cap);
    if (n < 0) error = std::strerror(errno);
    return n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  return inflateSome(out, cap);
}

std::size_t LineReader::Stream::inflateSome(char* out, std::size_t cap) {
  z.next_out = reinterpret_cast<Bytef*>(out);
  z.avail_out = static_cast<uInt>(cap);
  while (z.avail_out == cap && error.empty()) {
    if (z.avail_in == 0 && !fillInput()) {
      if (error.empty() && !member_ended) error = "unexpected end of file";
      break;
    }
    if (member_ended) {
      // gzip allows members one after another; anything else after the last one is ignored.
      if (z.avail_in >= 1 && z.next_in[0] != 0x1f) {
        z.avail_in = 0;
        input_ended = true;
        break;
      }
      inflateReset(&z);
      member_ended = false;
    }
    const int r = inflate(&z, Z_NO_FLUSH);
    if (r == Z_STREAM_END) {
      member_ended = true;
    } else if (r != Z_OK && r != Z_BUF_ERROR) {
      error = z.msg ? z.msg : "decompression error";
    }
  }
  return cap - z.avail_out;
}

LineReader::LineReader(const std::string& path, std::size_t max_line_bytes)
    : path_(path), max_line_(max_line_bytes), stream_(std::make_unique<Stream>()), buf_(kBlock) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
  // A fifo is read as the stream it is (blocking until a writer comes), /dev/null as empty.
  stream_->fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (stream_->fd < 0) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  Stream& s = *stream_;
  if (!s.fillInput() && !s.error.empty())
    throw InputError(path + ": cannot read (" + s.error + ")");
  if (s.z.avail_in >= 2 && s.in[0] == 0x1f && s.in[1] == 0x8b) {
    // 15 + 16: a gzip wrapper, its CRC and length checked at the end of each member.
    if (inflateInit2(&s.z, 15 + 16) != Z_OK) throw InputError(path + ": cannot inflate");
    s.gz = true;
  }
}

LineReader::~LineReader() = default;

bool LineReader::refill() {
  len_ = stream_->read(buf_.data(), buf_.size());
  pos_ = 0;
  if (len_ == 0 && !stream_->error.empty()) {
    // A damaged or cut stream: the partial line before it is dropped, nothing is read again.
    throw InputError(path_ + ": read error after line " + std::to_string(line_no_) + ": " +
                     stream_->error);
  }
  return len_ > 0;
}

std::size_t LineReader::skipEmptyLines() {
  std::size_t skipped = 0;
  while (pos_ < len_ || refill()) {
    const char* start = buf_.data() + pos_;
    const char* end = buf_.data() + len_;
    const char* p = start;
    while (p < end && *p == '\n') ++p;
    const auto n = static_cast<std::size_t>(p - start);
    skipped += n;
    pos_ += n;
    consumed_ += n;
    line_no_ += n;  // before a refill, whose error names the last line read
    if (p < end) break;
  }
  return skipped;
}

bool LineReader::next(std::string& line) {
  line.clear();
  bool got_any = false;
  while (true) {
    if (pos_ == len_ && !refill()) {
      if (got_any) ++line_no_;
      return got_any;
    }
    got_any = true;
    const char* start = buf_.data() + pos_;
    const void* nl = std::memchr(start, '\n', len_ - pos_);
    const std::size_t take =
        nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - start) : len_ - pos_;
    if (line.size() + take > max_line_) {
      throw InputError(path_ + ":" + std::to_string(line_no_ + 1) + ": line longer than " +
                       std::to_string(max_line_) + " bytes");
    }
    line.append(start, take);
    pos_ += take;
    consumed_ += take;
    if (nl) {
      ++pos_;
      ++consumed_;
      ++line_no_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      return true;
    }
  }
}

}  // namespace dynamap
