#include "bag_index_check.h"

#include <rosbag/chunked_file.h>
#include <rosbag/constants.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <unordered_map>
#include <vector>

#include "bag_salvage.h"
#include "dynamap/base/allocation_limit.h"

namespace dynamap::bag {
namespace {

using Fields = std::map<std::string, std::string>;
constexpr std::uint64_t kFirstRecord = 13;  // after "#ROSBAG V2.0\n"

/// What ends the check early: the verdict and why.
struct Stop {
  IndexCheck::Verdict verdict;
  std::string reason;
};

[[noreturn]] void corrupt(const std::string& why) {
  throw Stop{IndexCheck::Verdict::kCorrupt, why};
}

std::string at(std::uint64_t pos) {
  return "record at byte " + std::to_string(pos);
}

/// A header field of exactly `bytes` bytes, little-endian; nullopt when absent or of another size.
std::optional<std::uint64_t> number(const Fields& f, const std::string& key, std::size_t bytes) {
  const auto it = f.find(key);
  if (it == f.end() || it->second.size() != bytes) return std::nullopt;
  std::uint64_t v = 0;
  for (std::size_t i = bytes; i-- > 0;) v = v << 8 | static_cast<std::uint8_t>(it->second[i]);
  return v;
}

std::uint64_t need(const Fields& f, const std::string& key, std::size_t bytes, std::uint64_t pos) {
  const auto v = number(f, key, bytes);
  if (!v) corrupt(at(pos) + " has no " + std::to_string(bytes) + "-byte field '" + key + "'");
  return *v;
}

char opOf(const Fields& f) {
  const auto it = f.find(rosbag::OP_FIELD_NAME);
  return it != f.end() && it->second.size() == 1 ? it->second[0] : 0;
}

class IndexChecker {
 public:
  explicit IndexChecker(const std::string& path)
      : in_(path, std::ios::binary), size_(std::filesystem::file_size(path)) {}

  void run() {
    pos_ = kFirstRecord;
    in_.seekg(static_cast<std::streamoff>(pos_));
    if (!next()) throw Stop{IndexCheck::Verdict::kNoIndex, "no file header record"};
    if (opOf(fields_) != rosbag::OP_FILE_HEADER) corrupt(at(kFirstRecord) + " is no file header");
    index_pos_ = need(fields_, rosbag::INDEX_POS_FIELD_NAME, 8, start_);
    conns_ = need(fields_, rosbag::CONNECTION_COUNT_FIELD_NAME, 4, start_);
    chunks_ = need(fields_, rosbag::CHUNK_COUNT_FIELD_NAME, 4, start_);
    if (index_pos_ == 0) throw Stop{IndexCheck::Verdict::kNoIndex, "index_pos is 0"};
    while (next()) take();
    checkIndexSection();
  }

 private:
  /// Reads the record at pos_ into start_, fields_ and data_; false at the end of the file.
  bool next() {
    start_ = pos_;
    if (pos_ == size_) return false;
    const std::uint64_t left = size_ - pos_;
    const auto cut = [&] {
      throw Stop{IndexCheck::Verdict::kNoIndex, at(start_) + " runs past the end of the file"};
    };
    if (left < 8) cut();
    const std::uint32_t hlen = read32();
    if (hlen > left - 8) cut();
    std::vector<std::uint8_t> head(hlen);
    readBytes(head.data(), hlen);
    fields_.clear();
    if (!parseFields(head.data(), hlen, fields_)) corrupt(at(start_) + " has a corrupt header");
    const std::uint32_t dlen = read32();
    if (dlen > left - 8 - hlen) cut();
    if (dlen > kMaxRecordAllocation)
      corrupt(at(start_) + " states " + std::to_string(dlen) + " bytes");
    data_.resize(dlen);
    readBytes(data_.data(), dlen);
    pos_ += 8 + std::uint64_t{hlen} + dlen;
    return true;
  }

  std::uint32_t read32() {
    std::uint8_t b[4];
    readBytes(b, 4);
    return le32(b);
  }

  void readBytes(std::uint8_t* p, std::size_t n) {
    if (!in_.read(reinterpret_cast<char*>(p), static_cast<std::streamsize>(n))) {
      throw Stop{IndexCheck::Verdict::kNoIndex, at(start_) + " cannot be read"};
    }
  }

  void take() {
    const char op = opOf(fields_);
    starts_[start_] = op;
    if (op != rosbag::OP_INDEX_DATA) chunk_ = std::nullopt;  // index records follow their chunk
    if (op == rosbag::OP_CHUNK) return takeChunk();
    if (op == rosbag::OP_INDEX_DATA) return takeIndex();
    if (op == rosbag::OP_CHUNK_INFO) return takeChunkInfo();
    if (op == rosbag::OP_CONNECTION) return takeConnection(start_, data_.data(), data_.size());
    if (op != rosbag::OP_MSG_DATA) corrupt(at(start_) + " is of no known kind");
  }

  void takeConnection(std::uint64_t pos, const std::uint8_t* data, std::size_t n) {
    Fields connection;
    if (!number(fields_, rosbag::CONNECTION_FIELD_NAME, 4) ||
        !parseFields(data, static_cast<std::uint32_t>(n), connection)) {
      corrupt(at(pos) + ": a corrupt connection record");
    }
  }

  /// The chunk's records, decompressed: each message record's offset and connection kept for the
  /// index records that follow.
  void takeChunk() {
    const std::string& compression = fields_[rosbag::COMPRESSION_FIELD_NAME];
    const std::uint64_t size = need(fields_, rosbag::SIZE_FIELD_NAME, 4, start_);
    const std::string where = "the chunk at byte " + std::to_string(start_);
    std::vector<std::uint8_t> inflated;
    if (compression == rosbag::COMPRESSION_NONE) {
      if (size != data_.size()) corrupt(where + " states a size other than its data's");
    } else if (compression == rosbag::COMPRESSION_BZ2 || compression == rosbag::COMPRESSION_LZ4) {
      if (size > kMaxRecordAllocation)
        corrupt(where + " states " + std::to_string(size) + " bytes");
      inflated.assign(size, 0);  // a short decompression leaves zeros: no record, refused below
      try {
        rosbag::ChunkedFile().decompress(compression == rosbag::COMPRESSION_BZ2
                                             ? rosbag::compression::BZ2
                                             : rosbag::compression::LZ4,
                                         inflated.data(), size, data_.data(), data_.size());
      } catch (const std::exception& e) {
        corrupt(where + " cannot be decompressed (" + e.what() + ")");
      }
    } else {
      corrupt(where + " is compressed as '" + compression + "'");
    }
    walkChunk(inflated.empty() ? data_ : inflated, where);
    chunk_ = start_;
    index_records_[start_] = 0;
  }

  void walkChunk(const std::vector<std::uint8_t>& chunk, const std::string& where) {
    messages_.clear();
    for (std::size_t off = 0; off < chunk.size();) {
      Fields f;
      const std::uint8_t* data = nullptr;
      std::uint32_t n = 0;
      std::size_t used = 0;
      const std::string rec = "record at byte " + std::to_string(off) + " of " + where;
      if (!recordAt(chunk.data() + off, chunk.size() - off, used, f, data, n)) {
        corrupt(rec + " runs past the chunk or has a corrupt header");
      }
      const char op = opOf(f);
      const auto conn = number(f, rosbag::CONNECTION_FIELD_NAME, 4);
      if ((op != rosbag::OP_MSG_DATA && op != rosbag::OP_CONNECTION) || !conn) {
        corrupt(rec + " is no message or connection record");
      }
      Fields connection;
      if (op == rosbag::OP_CONNECTION && !parseFields(data, n, connection)) {
        corrupt(rec + ": a corrupt connection header");
      }
      if (op == rosbag::OP_MSG_DATA) messages_[static_cast<std::uint32_t>(off)] = *conn;
      off += used;
    }
  }

  void takeIndex() {
    if (!chunk_) corrupt(at(start_) + ": an index record that follows no chunk");
    const std::uint64_t ver = need(fields_, rosbag::VER_FIELD_NAME, 4, start_);
    const std::uint64_t conn = need(fields_, rosbag::CONNECTION_FIELD_NAME, 4, start_);
    const std::uint64_t count = need(fields_, rosbag::COUNT_FIELD_NAME, 4, start_);
    if (ver != rosbag::INDEX_VERSION || count * 12 != data_.size()) {
      corrupt(at(start_) + ": an index record of version " + std::to_string(ver) + " stating " +
              std::to_string(count) + " entries in " + std::to_string(data_.size()) + " bytes");
    }
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::uint32_t offset = le32(data_.data() + 12 * i + 8);
      const auto m = messages_.find(offset);
      if (m == messages_.end() || m->second != conn) {
        corrupt(at(start_) + ": index entry " + std::to_string(i) + " points at byte " +
                std::to_string(offset) + " of the chunk at byte " + std::to_string(*chunk_) +
                ", where no message of connection " + std::to_string(conn) + " starts");
      }
    }
    ++index_records_[*chunk_];
  }

  void takeChunkInfo() {
    const std::uint64_t ver = need(fields_, rosbag::VER_FIELD_NAME, 4, start_);
    const std::uint64_t chunk = need(fields_, rosbag::CHUNK_POS_FIELD_NAME, 8, start_);
    const std::uint64_t count = need(fields_, rosbag::COUNT_FIELD_NAME, 4, start_);
    const auto it = index_records_.find(chunk);
    if (ver != rosbag::CHUNK_INFO_VERSION || count * 8 != data_.size() ||
        it == index_records_.end() || it->second != count) {
      corrupt(at(start_) + ": chunk info naming byte " + std::to_string(chunk) + " and " +
              std::to_string(count) + " connections, which is no chunk followed by as many " +
              "index records");
    }
  }

  /// rosbag reads conn_count connection records from index_pos, then chunk_count chunk infos.
  void checkIndexSection() const {
    auto it = starts_.find(index_pos_);
    if (it == starts_.end()) corrupt("index_pos " + std::to_string(index_pos_) + " is no record");
    for (std::uint64_t k = 0; k < conns_ + chunks_; ++k, ++it) {
      const char want = k < conns_ ? rosbag::OP_CONNECTION : rosbag::OP_CHUNK_INFO;
      if (it == starts_.end() || it->second != want) {
        corrupt("the index at byte " + std::to_string(index_pos_) + " holds fewer than its " +
                std::to_string(conns_) + " connections and " + std::to_string(chunks_) +
                " chunk infos");
      }
    }
  }

  std::ifstream in_;
  std::uint64_t size_;
  std::uint64_t pos_ = 0, start_ = 0;  // the next record's byte, the current one's
  Fields fields_;
  std::vector<std::uint8_t> data_;
  std::uint64_t index_pos_ = 0, conns_ = 0, chunks_ = 0;  // the file header's
  std::map<std::uint64_t, char> starts_;                  // every record's byte and op
  std::optional<std::uint64_t> chunk_;  // the chunk the next index record belongs to
  std::unordered_map<std::uint32_t, std::uint64_t> messages_;  // its message records: offset, conn
  std::map<std::uint64_t, std::uint64_t> index_records_;  // chunk byte -> index records after it
};

}  // namespace

IndexCheck checkBagIndex(const std::string& path) {
  try {
    const AllocationLimit limit;
    IndexChecker(path).run();
    return {};
  } catch (const Stop& s) {
    return {s.verdict, s.reason};
  } catch (const std::exception& e) {  // an allocation past the limit, a file that went away
    return {IndexCheck::Verdict::kCorrupt, e.what()};
  }
}

}  // namespace dynamap::bag
