// One rosbag2 SQLite file (.db3) as a MessageStream, through Debian's libsqlite3: the `topics`
// table (id, name, type, serialization_format) and the `messages` table (id, topic_id,
// timestamp, data), read in timestamp order (then row id, the order they were written in).
// The file is opened read-only and immutable: reading never writes beside it (no -wal, -shm or
// journal), even for a bag whose recorder left it in WAL mode.
#include <sqlite3.h>

#include <algorithm>
#include <map>
#include <set>

#include "dynamap/input/ros2_bag.h"
#include "dynamap/input/scan_source.h"

namespace dynamap::ros2 {
namespace {

/// sqlite3's URI form of a path: '%', '?' and '#' escaped.
std::string fileUri(const std::string& path) {
  std::string out = "file:";
  for (const char c : path) {
    if (c == '%' || c == '?' || c == '#') {
      static const char kHex[] = "0123456789ABCDEF";
      out += '%';
      out += kHex[(c >> 4) & 15];
      out += kHex[c & 15];
    } else {
      out += c;
    }
  }
  return out + "?immutable=1";
}

struct Statement {
  sqlite3_stmt* s = nullptr;
  ~Statement() { sqlite3_finalize(s); }
};

/// Closed however the stream ends (close_v2: once its statements are finalized too).
struct Database {
  sqlite3* p = nullptr;
  ~Database() { sqlite3_close_v2(p); }
};

class Db3Stream : public MessageStream {
 public:
  Db3Stream(const std::string& path, const std::vector<std::string>& topics) : path_(path) {
    const int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_NOMUTEX;
    const int rc = sqlite3_open_v2(fileUri(path).c_str(), &database_.p, flags, nullptr);
    db_ = database_.p;
    if (rc != SQLITE_OK) {
      fail("cannot be opened as SQLite");
    }
    sqlite3_extended_result_codes(db_, 1);
    readTopics(topics);
    prepareMessages();
  }
  ~Db3Stream() override {
    sqlite3_finalize(messages_.s);
    messages_.s = nullptr;
  }

  bool next() override {
    if (done_) return false;
    const int rc = sqlite3_step(messages_.s);
    if (rc == SQLITE_DONE) {
      done_ = true;
      return false;
    }
    if (rc != SQLITE_ROW) {
      done_ = true;
      fault_ = path_ + ": messages row after id " + std::to_string(row_) +
               " cannot be read: " + sqlite3_errmsg(db_);
      return false;
    }
    row_ = sqlite3_column_int64(messages_.s, 0);
    const auto t = topics_.find(sqlite3_column_int64(messages_.s, 1));
    if (t == topics_.end()) {
      done_ = true;
      fault_ = where() + ": a topic id the topics table does not have";
      return false;
    }
    topic_ = t->second.first;
    type_ = t->second.second;
    time_ = static_cast<std::uint64_t>(sqlite3_column_int64(messages_.s, 2));
    data_ = static_cast<const std::uint8_t*>(sqlite3_column_blob(messages_.s, 3));
    size_ = static_cast<std::size_t>(sqlite3_column_bytes(messages_.s, 3));
    ++read_;
    return true;
  }
  const std::string& topic() const override { return topic_; }
  const std::string& type() const override { return type_; }
  std::uint64_t timeNs() const override { return time_; }
  const std::uint8_t* data() const override { return data_; }
  std::size_t size() const override { return size_; }
  std::string where() const override { return path_ + ": messages row " + std::to_string(row_); }
  std::string fault() const override { return fault_; }
  double fractionRead() const override {
    return total_ > 0 ? std::min(1.0, double(read_) / double(total_)) : 1.0;
  }
  TopicList topics() override {
    std::set<std::pair<std::string, std::string>> seen;
    for (const auto& kv : all_topics_) seen.insert(kv.second);
    return TopicList(seen.begin(), seen.end());
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ": " + what +
                     (db_ ? std::string(" (") + sqlite3_errmsg(db_) + ")" : std::string()));
  }

  void prepare(Statement& st, const std::string& sql) {
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st.s, nullptr) != SQLITE_OK) {
      fail("not a rosbag2 bag: no readable topics and messages tables");
    }
  }

  void readTopics(const std::vector<std::string>& wanted) {
    Statement st;
    prepare(st, "SELECT id, name, type, serialization_format FROM topics");
    int rc;
    while ((rc = sqlite3_step(st.s)) == SQLITE_ROW) {
      const auto text = [&](int col) {
        const auto* p = sqlite3_column_text(st.s, col);
        return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
      };
      std::string type = text(2);
      const std::string format = text(3);
      if (format != "cdr") type += " (" + format + ")";  // no type the reader decodes
      const std::int64_t id = sqlite3_column_int64(st.s, 0);
      all_topics_[id] = {text(1), type};
      if (wanted.empty() || std::count(wanted.begin(), wanted.end(), text(1))) {
        topics_[id] = all_topics_[id];
      }
    }
    if (rc != SQLITE_DONE) fail("its topics table cannot be read");
  }

  void prepareMessages() {
    std::string ids;
    for (const auto& kv : topics_) ids += (ids.empty() ? "" : ",") + std::to_string(kv.first);
    const std::string where = " WHERE topic_id IN (" + ids + ")";
    Statement count;
    prepare(count, "SELECT COUNT(*) FROM messages" + where);
    if (sqlite3_step(count.s) == SQLITE_ROW) total_ = sqlite3_column_int64(count.s, 0);
    prepare(messages_, "SELECT id, topic_id, timestamp, data FROM messages" + where +
                           " ORDER BY timestamp, id");
  }

  std::string path_;
  Database database_;
  sqlite3* db_ = nullptr;
  std::map<std::int64_t, std::pair<std::string, std::string>> all_topics_, topics_;
  Statement messages_;
  bool done_ = false;
  std::int64_t row_ = 0, read_ = 0, total_ = 0;
  std::string topic_, type_, fault_;
  std::uint64_t time_ = 0;
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace

std::unique_ptr<MessageStream> openDb3(const std::string& path,
                                       const std::vector<std::string>& topics) {
  return std::make_unique<Db3Stream>(path, topics);
}

}  // namespace dynamap::ros2
