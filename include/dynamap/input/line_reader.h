#pragma once
// LineReader: the lines of a text file, plain or gzip-compressed, read in blocks with every line
// capped in length. Every text reader of dynamap (CARMEN logs, pose files, CSV tables) reads
// through it, so that no file — /dev/zero, a 300 MB line, a gz bomb — makes a reader hold more
// than one capped line, and a damaged gz stream is a fault at the last good line, never data
// read twice.
//
// A file starting with gzip's magic is inflated with zlib, any other read as it is. A
// decompression error (a damaged CRC or length, a stream cut short, garbage inside it) ends the
// file there: the lines inflated before it are returned, the partial line at the error is not,
// and next() then throws InputError naming the file, the last complete line and zlib's reason.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dynamap {

class LineReader {
 public:
  /// The longest line any reader accepts [bytes] unless it asks for less.
  static constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

  /// Opens `path` (a regular file, a fifo or a device: what it is opened as is read). Throws
  /// InputError "<path>: cannot open (<errno text>)", or "<path>: is a directory".
  explicit LineReader(const std::string& path, std::size_t max_line_bytes = kMaxLineBytes);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// The next line without its '\n' (a trailing '\r' dropped too); false at the end of the file.
  /// Throws InputError "<path>:<line>: line longer than N bytes" before holding more than N, or
  /// "<path>: read error after line <n>: <why>" for a read or decompression error.
  bool next(std::string& line);
  /// Passes over the empty lines (a '\n' alone) at the reader's position and returns how many,
  /// each counted as a line: a byte compare each, where next() costs a call and a string. A gz of
  /// 14 MB can hold 3 billion of them. Throws as next() does.
  std::size_t skipEmptyLines();
  /// The number of the line next() returned last (1-based; 0 before the first).
  std::size_t lineNumber() const { return line_no_; }
  /// Uncompressed bytes consumed so far.
  std::uint64_t position() const { return consumed_; }
  const std::string& path() const { return path_; }

 private:
  bool refill();
  struct Stream;  // the file descriptor and zlib's state, kept out of this header

  std::string path_;
  std::size_t max_line_;
  std::unique_ptr<Stream> stream_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, len_ = 0;
  std::size_t line_no_ = 0;
  std::uint64_t consumed_ = 0;
};

}  // namespace dynamap
