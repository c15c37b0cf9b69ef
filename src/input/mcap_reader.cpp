// An MCAP file as a MessageStream. With its summary (the Footer's summary_start, Channel and
// ChunkIndex records) the chunks are read in the order of their first message's time, skipping
// those without a message of the topics asked for; without one (a file cut short or never
// closed, or written without a summary) the data section is read record by record from the
// start. Within a chunk the messages come out in log_time order.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <set>

#include "dynamap/input/ros2_bag.h"
#include "dynamap/input/scan_source.h"
#include "mcap_format.h"

namespace dynamap::ros2 {
namespace {

using namespace mcap;

struct Channel {
  std::string topic, type;
  bool wanted = false;
};

class McapStream : public MessageStream {
 public:
  McapStream(const std::string& path, const std::vector<std::string>& topics)
      : path_(path), filter_(topics.begin(), topics.end()) {
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError(path + ": cannot be opened");
    in_.seekg(0, std::ios::end);
    file_size_ = static_cast<std::uint64_t>(in_.tellg());
    char magic[kMagicSize] = {};
    in_.seekg(0);
    if (!in_.read(magic, kMagicSize) || !std::equal(magic, magic + kMagicSize, kMagic)) {
      throw InputError(path + ": not an MCAP file (no magic at offset 0)");
    }
    pos_ = kMagicSize;
    indexed_ = readSummary();
  }

  bool next() override {
    while (++entry_ >= entries_.size()) {
      entries_.clear();
      entry_ = static_cast<std::size_t>(-1);
      if (!fault_.empty() || !(indexed_ ? nextIndexedChunk() : nextLinear())) return false;
    }
    const Entry& e = entries_[entry_];
    const Channel& c = channels_[e.channel];
    topic_ = c.topic;
    type_ = c.type;
    return true;
  }
  const std::string& topic() const override { return topic_; }
  const std::string& type() const override { return type_; }
  std::uint64_t timeNs() const override { return entries_[entry_].t; }
  const std::uint8_t* data() const override { return batch_.data() + entries_[entry_].pos; }
  std::size_t size() const override { return entries_[entry_].len; }
  std::string where() const override {
    const Entry& e = entries_[entry_];
    if (e.record == kTopLevel) return path_ + ": record at offset " + std::to_string(e.chunk);
    return path_ + ": chunk at offset " + std::to_string(e.chunk) + ", its record at " +
           std::to_string(e.record);
  }
  std::string fault() const override { return fault_; }
  double fractionRead() const override {
    if (indexed_) return chunks_.empty() ? 1.0 : double(next_chunk_) / double(chunks_.size());
    return file_size_ > 0 ? std::min(1.0, double(pos_) / double(file_size_)) : 1.0;
  }
  TopicList topics() override {
    if (!summary_channels_) {
      while (next()) {
      }
    }
    std::set<std::pair<std::string, std::string>> seen;
    for (const auto& kv : channels_) seen.insert({kv.second.topic, kv.second.type});
    return TopicList(seen.begin(), seen.end());
  }

 private:
  struct Entry {
    std::uint64_t t;
    std::size_t pos, len;
    std::uint16_t channel;
    std::uint64_t chunk, record;  // the chunk's file offset, the record's in its records
  };
  static constexpr std::uint64_t kTopLevel = ~std::uint64_t{0};  // a record outside any chunk
  struct ChunkRef {
    std::uint64_t t, offset, length;
    std::vector<std::uint16_t> channels;  // those it has messages of (none listed: unknown)
    bool wanted;
  };

  void setFault(std::uint64_t offset, const std::string& what) {
    fault_ = path_ + ": record at offset " + std::to_string(offset) + ": " + what;
  }

  /// The record at `at`: its opcode and, when `keep`, its content. False (a fault set) when it
  /// does not fit in the file.
  bool readRecord(std::uint64_t at, std::uint8_t& op, std::uint64_t& len, bool keep,
                  std::vector<std::uint8_t>& content) {
    std::uint8_t head[kRecordHead];
    if (file_size_ - at < kRecordHead) {
      setFault(at, "the file ends inside its header (cut off?)");
      return false;
    }
    in_.seekg(static_cast<std::streamoff>(at));
    in_.read(reinterpret_cast<char*>(head), kRecordHead);
    Fields f(head, kRecordHead);
    op = f.u8();
    len = f.u64();
    const std::uint64_t left = file_size_ - at - kRecordHead;
    if (len > left) {
      setFault(at, "states " + std::to_string(len) + " bytes, " + std::to_string(left) +
                       " are left (cut off?)");
      return false;
    }
    if (len > kMaxRecord) {
      setFault(at, "states " + std::to_string(len) + " bytes, more than any record holds");
      return false;
    }
    if (keep) {
      content.resize(static_cast<std::size_t>(len));
      in_.read(reinterpret_cast<char*>(content.data()), static_cast<std::streamsize>(len));
      if (!in_) {
        setFault(at, "cannot be read");
        return false;
      }
    }
    return true;
  }

  /// A Schema, Channel or Message record of `batch_` at `pos` (inside the chunk at file offset
  /// `chunk`, its `record`th byte; or kTopLevel, a record at offset `chunk`).
  void takeRecord(std::uint8_t op, std::size_t pos, std::size_t len, std::uint64_t chunk,
                  std::uint64_t record) {
    Fields f(batch_.data() + pos, len);
    if (op == kSchema) {
      const std::uint16_t id = f.u16();
      schemas_[id] = f.str();
    } else if (op == kChannel) {
      const std::uint16_t id = f.u16(), schema = f.u16();
      Channel c;
      c.topic = f.str();
      const std::string encoding = f.str();
      const auto s = schemas_.find(schema);
      c.type = s == schemas_.end() ? "" : s->second;
      // Only CDR is ROS 2's: another encoding's messages are of no type the reader decodes.
      if (encoding != "cdr") c.type += " (" + encoding + ")";
      c.wanted = filter_.empty() || filter_.count(c.topic) > 0;
      channels_[id] = c;
    } else if (op == kMessage) {
      const std::uint16_t id = f.u16();
      f.u32();
      const std::uint64_t t = f.u64();
      f.u64();
      const auto c = channels_.find(id);
      if (c == channels_.end() || !c->second.wanted) return;
      entries_.push_back({t, pos + f.at(), f.left(), id, chunk, record});
    }
  }

  /// The records of a chunk's content (at file offset `at`, in content_) into entries_, by time.
  void takeChunk(std::uint64_t at) {
    Fields f(content_.data(), content_.size());
    f.u64();
    f.u64();
    const std::uint64_t size = f.u64();
    const std::uint32_t crc = f.u32();
    const std::string compression = f.str();
    const std::uint64_t n = f.u64();
    const std::uint8_t* records = f.take(n);
    std::size_t base = 0;  // where the records start in batch_
    if (compression.empty()) {
      if (n != size) throw FormatError("an uncompressed chunk's size differs from its records'");
      base = static_cast<std::size_t>(records - content_.data());
      batch_.swap(content_);  // read in place
    } else {
      decompress(compression, records, static_cast<std::size_t>(n), size, batch_);
    }
    const auto end = base + static_cast<std::size_t>(size);
    if (crc != 0 && crc32(batch_.data() + base, end - base) != crc) {
      throw FormatError("its records do not match their CRC");
    }
    takeRecords(base, end, at, false);
  }

  /// The records of batch_[begin, end) (a chunk's): all, or (`cut`) those before the first that
  /// does not fit.
  void takeRecords(std::size_t begin, std::size_t end, std::uint64_t at, bool cut) {
    Fields r(batch_.data() + begin, end - begin);
    try {
      while (r.left() > 0) {
        const std::size_t start = r.at();
        const std::uint8_t op = r.u8();
        const std::uint64_t len = r.u64();
        r.take(len);
        takeRecord(op, begin + start + kRecordHead, static_cast<std::size_t>(len), at, start);
      }
    } catch (const FormatError&) {
      if (!cut) throw;
    }
    sortByTime();
  }

  /// Reads records from pos_ until one yields messages; false at the end or a fault.
  bool nextLinear() {
    std::vector<std::uint8_t>& content = content_;
    while (entries_.empty()) {
      if (pos_ >= file_size_) {
        setFault(pos_, "the file ends without its footer (cut off, or never closed)");
        return false;
      }
      const std::uint64_t at = pos_;
      std::uint8_t op = 0;
      std::uint64_t len = 0;
      // Peek the opcode first: only a chunk or a schema, channel or message is read whole.
      if (!readRecord(at, op, len, false, content)) {
        if (op == kChunk) salvageCutChunk(at);
        return !entries_.empty();
      }
      const bool keep = op == kChunk || op == kSchema || op == kChannel || op == kMessage;
      if (keep && !readRecord(at, op, len, true, content)) return false;
      pos_ = at + kRecordHead + len;
      if (op == kDataEnd || op == kFooter) {
        pos_ = file_size_;
        return false;
      }
      if (!keep) continue;
      if (!takeBatch(at, op)) return false;
    }
    return true;
  }

  /// One record read whole: a chunk's messages, or a top-level record, into entries_.
  bool takeBatch(std::uint64_t at, std::uint8_t op) {
    try {
      if (op == kChunk) {
        takeChunk(at);
      } else {
        batch_.swap(content_);
        takeRecord(op, 0, batch_.size(), at, kTopLevel);
      }
      return true;
    } catch (const FormatError& e) {
      entries_.clear();
      setFault(at, e.what());
      return false;
    }
  }

  /// A chunk's messages need not be in time order (MCAP does not ask it): they are put in it.
  void sortByTime() {
    std::stable_sort(entries_.begin(), entries_.end(),
                     [](const Entry& a, const Entry& b) { return a.t < b.t; });
  }

  /// A chunk the file ends inside: when uncompressed, its whole records before the cut.
  void salvageCutChunk(std::uint64_t at) {
    if (file_size_ - at - kRecordHead > kMaxRecord) return;
    std::vector<std::uint8_t> rest(static_cast<std::size_t>(file_size_ - at - kRecordHead));
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at + kRecordHead));
    if (!in_.read(reinterpret_cast<char*>(rest.data()), static_cast<std::streamsize>(rest.size())))
      return;
    try {
      Fields f(rest.data(), rest.size());
      f.take(28);                    // start and end times, uncompressed size, CRC
      if (!f.str().empty()) return;  // a compressed chunk cut short is lost
      f.u64();
      batch_.assign(rest.begin() + static_cast<std::ptrdiff_t>(f.at()), rest.end());
    } catch (const FormatError&) {  // not even the chunk's header
      return;
    }
    takeRecords(0, batch_.size(), at, true);
  }

  bool nextIndexedChunk() {
    std::vector<std::uint8_t>& content = content_;
    while (entries_.empty()) {
      if (next_chunk_ >= chunks_.size()) return false;
      const ChunkRef& c = chunks_[next_chunk_++];
      if (!c.wanted) continue;
      std::uint8_t op = 0;
      std::uint64_t len = 0;
      if (!readRecord(c.offset, op, len, true, content)) return false;
      if (op != kChunk || kRecordHead + len != c.length) {
        setFault(c.offset, "the summary's chunk index points at no chunk");
        return false;
      }
      if (!takeBatch(c.offset, op)) return false;
    }
    return true;
  }

  /// Reads the summary named by the footer; false (read the data section instead) when there is
  /// none, it has no chunk index, or any of it is corrupt.
  bool readSummary();
  void takeSummaryRecord(std::uint8_t op, Fields& f, std::uint64_t summary_start);

  std::string path_;
  std::set<std::string> filter_;
  std::ifstream in_;
  std::uint64_t file_size_ = 0, pos_ = 0;
  bool indexed_ = false, summary_channels_ = false;
  std::vector<ChunkRef> chunks_;
  std::size_t next_chunk_ = 0;
  std::map<std::uint16_t, std::string> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  std::vector<std::uint8_t> batch_;    // the records of the chunk (or the record) being read
  std::vector<std::uint8_t> content_;  // a record as read from the file
  std::vector<Entry> entries_;
  std::size_t entry_ = static_cast<std::size_t>(-1);
  std::string topic_, type_, fault_;
};

void McapStream::takeSummaryRecord(std::uint8_t op, Fields& f, std::uint64_t summary_start) {
  if (op == kSchema || op == kChannel) {
    const std::size_t n = f.left();
    const std::uint8_t* p = f.take(n);
    batch_.assign(p, p + n);
    takeRecord(op, 0, n, 0, kTopLevel);
    return;
  }
  if (op != kChunkIndex) return;
  ChunkRef c{};
  c.t = f.u64();
  f.u64();
  c.offset = f.u64();
  c.length = f.u64();
  if (c.offset < kMagicSize || c.offset > summary_start || c.length > summary_start - c.offset) {
    throw FormatError("a chunk index points outside the data section");
  }
  // Its message indexes' channels: a chunk with none of the topics asked for is not read.
  const std::uint32_t n = f.u32();
  Fields index(f.take(n), n);
  while (index.left() > 0) {
    c.channels.push_back(index.u16());
    index.u64();
  }
  chunks_.push_back(c);
}

bool McapStream::readSummary() {
  constexpr std::uint64_t kTail = kRecordHead + kFooterContent + kMagicSize;
  if (file_size_ < kMagicSize + kTail) return false;
  std::uint8_t tail[kTail];
  in_.seekg(static_cast<std::streamoff>(file_size_ - kTail));
  if (!in_.read(reinterpret_cast<char*>(tail), kTail)) return false;
  // Byte for byte: kMagic is char (signed here), the tail unsigned, and 0x89 is not -119.
  if (std::memcmp(tail + kTail - kMagicSize, kMagic, kMagicSize) != 0) return false;
  Fields foot(tail, kRecordHead + kFooterContent);
  if (foot.u8() != kFooter || foot.u64() != kFooterContent) return false;
  const std::uint64_t start = foot.u64(), offsets = foot.u64();
  const std::uint64_t end = offsets != 0 ? offsets : file_size_ - kTail;
  if (start < kMagicSize || start > end || end > file_size_ - kTail) return false;
  if (end - start > kMaxRecord) return false;
  std::vector<std::uint8_t> summary(static_cast<std::size_t>(end - start));
  in_.seekg(static_cast<std::streamoff>(start));
  if (!in_.read(reinterpret_cast<char*>(summary.data()),
                static_cast<std::streamsize>(summary.size()))) {
    return false;
  }
  try {
    Fields r(summary.data(), summary.size());
    while (r.left() > 0) {
      const std::uint8_t op = r.u8();
      const std::uint64_t len = r.u64();
      Fields f(r.take(len), static_cast<std::size_t>(len));
      takeSummaryRecord(op, f, start);
    }
  } catch (const FormatError&) {
    chunks_.clear();
    channels_.clear();
    schemas_.clear();
    return false;
  }
  summary_channels_ = !channels_.empty();
  std::stable_sort(chunks_.begin(), chunks_.end(), [](const ChunkRef& a, const ChunkRef& b) {
    return a.t != b.t ? a.t < b.t : a.offset < b.offset;
  });
  for (ChunkRef& c : chunks_) {
    c.wanted = c.channels.empty() ||
               std::any_of(c.channels.begin(), c.channels.end(), [&](std::uint16_t id) {
                 const auto it = channels_.find(id);
                 return it == channels_.end() || it->second.wanted;
               });
  }
  return !chunks_.empty();
}

}  // namespace

std::unique_ptr<MessageStream> openMcap(const std::string& path,
                                        const std::vector<std::string>& topics) {
  return std::make_unique<McapStream>(path, topics);
}

}  // namespace dynamap::ros2
