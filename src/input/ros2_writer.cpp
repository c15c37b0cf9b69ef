// ROS 2 bag writers (ros2_writer.h): MCAP through mcap_format.h, .db3 through SQLite.
#include "dynamap/input/ros2_writer.h"

#include <sqlite3.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include "mcap_format.h"

namespace dynamap::ros2 {

struct BagWriter::Impl {
  virtual ~Impl() = default;
  virtual void write(const std::string& topic, const std::string& type, std::uint64_t t,
                     const std::vector<std::uint8_t>& cdr) = 0;
  virtual void close() = 0;
};

namespace {

using mcap::Out;

constexpr std::size_t kChunkBytes = 1u << 20;

/// An opcode, a length and the content, appended to `out`.
void record(Out& out, std::uint8_t op, const Out& content) {
  out.u8(op);
  out.u64(content.bytes.size());
  out.raw(content.bytes.data(), content.bytes.size());
}

class McapWriter : public BagWriter::Impl {
 public:
  McapWriter(const std::string& path, const std::string& compression)
      : path_(path),
        compression_(compression == "none" ? "" : compression),
        file_(path, std::ios::binary | std::ios::trunc) {
    if (!file_) throw std::runtime_error(path + ": cannot be written");
    Out head, header;
    head.raw(reinterpret_cast<const std::uint8_t*>(mcap::kMagic), mcap::kMagicSize);
    header.str("ros2");
    header.str("dynamap");
    record(head, mcap::kHeader, header);
    put(head);
  }
  ~McapWriter() override {
    try {
      close();
    } catch (const std::exception&) {  // close() says it to a caller who asks
    }
  }

  void write(const std::string& topic, const std::string& type, std::uint64_t t,
             const std::vector<std::uint8_t>& cdr) override {
    const std::uint16_t channel = channelOf(topic, type);
    if (index_.empty()) start_ = end_ = t;  // the chunk's first message
    start_ = std::min(start_, t);
    end_ = std::max(end_, t);
    index_[channel].push_back({t, chunk_.bytes.size()});
    Out m;
    m.u16(channel);
    m.u32(sequence_++);
    m.u64(t);
    m.u64(t);
    m.raw(cdr.data(), cdr.size());
    record(chunk_, mcap::kMessage, m);
    if (chunk_.bytes.size() >= kChunkBytes) flush();
  }

  void close() override {
    if (closed_) return;
    closed_ = true;
    flush();
    Out end, data_end;
    data_end.u32(0);
    record(end, mcap::kDataEnd, data_end);
    put(end);
    const std::uint64_t summary_start = at_;
    put(summary_);
    Out tail, footer;
    footer.u64(summary_start);
    footer.u64(0);
    footer.u32(0);
    record(tail, mcap::kFooter, footer);
    tail.raw(reinterpret_cast<const std::uint8_t*>(mcap::kMagic), mcap::kMagicSize);
    put(tail);
    file_.close();
    if (!file_) throw std::runtime_error(path_ + ": cannot be written");
  }

 private:
  struct Indexed {
    std::uint64_t t, offset;
  };

  void put(const Out& o) {
    file_.write(reinterpret_cast<const char*>(o.bytes.data()),
                static_cast<std::streamsize>(o.bytes.size()));
    at_ += o.bytes.size();
  }

  /// The channel of a topic; its Schema and Channel records go into the chunk being filled and
  /// into the summary.
  std::uint16_t channelOf(const std::string& topic, const std::string& type) {
    const auto it = channels_.find(topic);
    if (it != channels_.end()) return it->second;
    auto schema = schemas_.find(type);
    if (schema == schemas_.end()) {
      schema = schemas_.emplace(type, static_cast<std::uint16_t>(schemas_.size() + 1)).first;
      Out s;
      s.u16(schema->second);
      s.str(type);
      s.str("ros2msg");
      s.u32(0);
      record(chunk_, mcap::kSchema, s);
      record(summary_, mcap::kSchema, s);
    }
    const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
    channels_[topic] = id;
    Out c;
    c.u16(id);
    c.u16(schema->second);
    c.str(topic);
    c.str("cdr");
    c.u32(0);  // no metadata
    record(chunk_, mcap::kChannel, c);
    record(summary_, mcap::kChannel, c);
    return id;
  }

  void flush() {
    if (chunk_.bytes.empty()) return;
    const auto& raw = chunk_.bytes;
    const std::vector<std::uint8_t> stored =
        compression_.empty() ? raw : mcap::compress(compression_, raw.data(), raw.size());
    Out c, out;
    c.u64(start_);
    c.u64(end_);
    c.u64(raw.size());
    c.u32(mcap::crc32(raw.data(), raw.size()));
    c.str(compression_);
    c.u64(stored.size());
    c.raw(stored.data(), stored.size());
    const std::uint64_t chunk_at = at_;
    record(out, mcap::kChunk, c);
    put(out);
    const std::uint64_t index_at = at_;
    Out offsets, indexes;
    for (const auto& [channel, entries] : index_) {
      offsets.u16(channel);
      offsets.u64(at_ + indexes.bytes.size());
      Out mi;
      mi.u16(channel);
      mi.u32(static_cast<std::uint32_t>(entries.size() * 16));
      for (const Indexed& e : entries) {
        mi.u64(e.t);
        mi.u64(e.offset);
      }
      record(indexes, mcap::kMessageIndex, mi);
    }
    put(indexes);
    Out ci;
    ci.u64(start_);
    ci.u64(end_);
    ci.u64(chunk_at);
    ci.u64(index_at - chunk_at);
    ci.u32(static_cast<std::uint32_t>(offsets.bytes.size()));
    ci.raw(offsets.bytes.data(), offsets.bytes.size());
    ci.u64(indexes.bytes.size());
    ci.str(compression_);
    ci.u64(stored.size());
    ci.u64(raw.size());
    record(summary_, mcap::kChunkIndex, ci);
    chunk_.bytes.clear();
    index_.clear();
    end_ = 0;
  }

  std::string path_, compression_;
  std::ofstream file_;
  std::uint64_t at_ = 0, start_ = 0, end_ = 0;
  std::uint32_t sequence_ = 0;
  std::map<std::string, std::uint16_t> schemas_, channels_;
  std::map<std::uint16_t, std::vector<Indexed>> index_;
  Out chunk_, summary_;
  bool closed_ = false;
};

class Db3Writer : public BagWriter::Impl {
 public:
  explicit Db3Writer(const std::string& path) : path_(path) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
        SQLITE_OK) {
      fail("cannot be created");
    }
    exec(
        "PRAGMA journal_mode=MEMORY; BEGIN;"
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "INSERT INTO schema VALUES(3, 'humble');"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
        " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
        " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
        "CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
    prepare(&topic_, "INSERT INTO topics VALUES(?, ?, ?, 'cdr', '')");
    prepare(&message_, "INSERT INTO messages(topic_id, timestamp, data) VALUES(?, ?, ?)");
  }
  ~Db3Writer() override {
    try {
      close();
    } catch (const std::exception&) {  // close() says it to a caller who asks
    }
  }

  void write(const std::string& topic, const std::string& type, std::uint64_t t,
             const std::vector<std::uint8_t>& cdr) override {
    auto it = ids_.find(topic);
    if (it == ids_.end()) {
      it = ids_.emplace(topic, static_cast<std::int64_t>(ids_.size() + 1)).first;
      sqlite3_bind_int64(topic_, 1, it->second);
      sqlite3_bind_text(topic_, 2, topic.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(topic_, 3, type.c_str(), -1, SQLITE_TRANSIENT);
      step(topic_);
    }
    sqlite3_bind_int64(message_, 1, it->second);
    sqlite3_bind_int64(message_, 2, static_cast<std::int64_t>(t));
    sqlite3_bind_blob(message_, 3, cdr.data(), static_cast<int>(cdr.size()), SQLITE_STATIC);
    step(message_);
  }

  void close() override {
    if (!db_) return;
    sqlite3_finalize(topic_);
    sqlite3_finalize(message_);
    const bool ok = sqlite3_exec(db_, "COMMIT;", nullptr, nullptr, nullptr) == SQLITE_OK;
    sqlite3_close(db_);
    db_ = nullptr;
    if (!ok) throw std::runtime_error(path_ + ": cannot be written");
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    throw std::runtime_error(path_ + ": " + what + " (" + sqlite3_errmsg(db_) + ")");
  }
  void exec(const char* sql) {
    if (sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) != SQLITE_OK) fail("cannot be written");
  }
  void prepare(sqlite3_stmt** st, const char* sql) {
    if (sqlite3_prepare_v2(db_, sql, -1, st, nullptr) != SQLITE_OK) fail("cannot be written");
  }
  void step(sqlite3_stmt* st) {
    if (sqlite3_step(st) != SQLITE_DONE) fail("cannot be written");
    sqlite3_reset(st);
    sqlite3_clear_bindings(st);
  }

  std::string path_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt *topic_ = nullptr, *message_ = nullptr;
  std::map<std::string, std::int64_t> ids_;
};

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

BagWriter::BagWriter(const std::string& path, const std::string& compression) {
  if (compression != "zstd" && compression != "lz4" && compression != "none") {
    throw std::invalid_argument("compression '" + compression + "': zstd, lz4 or none");
  }
  if (endsWith(path, ".mcap")) {
    impl_ = std::make_unique<McapWriter>(path, compression);
  } else if (endsWith(path, ".db3")) {
    impl_ = std::make_unique<Db3Writer>(path);
  } else {
    throw std::invalid_argument(path + ": a ROS 2 bag is written as .mcap or .db3");
  }
}

BagWriter::~BagWriter() = default;

void BagWriter::write(const std::string& topic, const std::string& type, std::uint64_t t_ns,
                      const std::vector<std::uint8_t>& cdr) {
  impl_->write(topic, type, t_ns, cdr);
}

void BagWriter::close() {
  impl_->close();
}

}  // namespace dynamap::ros2
