#include "bag_salvage.h"

#include <ros/header.h>
#include <rosbag/constants.h>
#include <rosbag/exceptions.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "dynamap/base/allocation_limit.h"
#include "dynamap/input/scan_source.h"

namespace dynamap::bag {
namespace {

const std::string kVersionLine = "#ROSBAG V2.0\n";

}  // namespace

std::uint32_t le32(const std::uint8_t* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

std::uint32_t field32(const std::map<std::string, std::string>& f, const std::string& key) {
  const auto it = f.find(key);
  if (it == f.end() || it->second.size() != 4) return 0;
  return le32(reinterpret_cast<const std::uint8_t*>(it->second.data()));
}

bool parseFields(const std::uint8_t* p, std::uint32_t len,
                 std::map<std::string, std::string>& out) {
  if (!headerFieldsFit(p, len)) return false;
  std::vector<std::uint8_t> copy(p, p + len);  // ros::Header wants a mutable buffer
  ros::Header header;
  std::string error;
  if (!header.parse(copy.data(), len, error)) return false;
  out = *header.getValues();
  return true;
}

bool recordAt(const std::uint8_t* p, std::size_t n, std::size_t& used,
              std::map<std::string, std::string>& fields, const std::uint8_t*& data,
              std::uint32_t& data_len) {
  if (n < 4) return false;
  const std::uint32_t hlen = le32(p);
  if (hlen > n - 4 || n - 4 - hlen < 4) return false;
  if (!parseFields(p + 4, hlen, fields)) return false;
  const std::uint32_t dlen = le32(p + 4 + hlen);
  if (dlen > n - 8 - hlen) return false;
  data = p + 8 + hlen;
  data_len = dlen;
  used = 8 + hlen + dlen;
  return true;
}

bool headerFieldsFit(const std::uint8_t* p, std::uint32_t len) {
  std::uint32_t pos = 0;
  while (pos < len) {
    if (len - pos < 4) return false;
    const std::uint32_t n = le32(p + pos);
    if (n > len - pos - 4) return false;
    pos += 4 + n;
  }
  return true;
}

BagSalvage::BagSalvage(const std::string& path) : path_(path) {
  try {
    std::error_code ec;
    size_ = std::filesystem::file_size(path, ec);
    file_.openRead(path);
    std::string version(kVersionLine.size(), '\0');
    file_.read(version.data(), version.size());
    if (version != kVersionLine) throw InputError(path + ": not a ROS bag 2.0");
  } catch (const rosbag::BagException& e) {
    throw InputError(path + ": cannot read: " + e.what());
  }
}

void BagSalvage::addConnection(const Record& r) {
  std::map<std::string, std::string> header;
  if (!parseFields(r.data, r.data_len, header)) return;
  Connection c{r.fields.count("topic") ? r.fields.at("topic") : header["topic"], header["type"],
               header["md5sum"]};
  connections_[field32(r.fields, rosbag::CONNECTION_FIELD_NAME)] = c;
}

/// A connection or message record inside a chunk (or, in bags from old writers, outside one).
/// True for a message of a known connection: it is then the current one.
bool BagSalvage::takeRecord(const Record& r) {
  const auto op = r.fields.find(rosbag::OP_FIELD_NAME);
  if (op == r.fields.end() || op->second.size() != 1) return false;
  if (op->second[0] == rosbag::OP_CONNECTION) {
    addConnection(r);
    return false;
  }
  if (op->second[0] != rosbag::OP_MSG_DATA) return false;
  const auto c = connections_.find(field32(r.fields, rosbag::CONNECTION_FIELD_NAME));
  const auto t = r.fields.find(rosbag::TIME_FIELD_NAME);
  if (c == connections_.end() || t == r.fields.end() || t->second.size() != 8) return false;
  const auto* tb = reinterpret_cast<const std::uint8_t*>(t->second.data());
  time_ = le32(tb) + le32(tb + 4) * 1e-9;
  current_ = &c->second;
  data_ = r.data;
  data_len_ = r.data_len;
  return true;
}

bool BagSalvage::nextInChunk() {
  while (chunk_pos_ < chunk_.size()) {
    Record r;
    std::size_t used = 0;
    if (!recordAt(chunk_.data() + chunk_pos_, chunk_.size() - chunk_pos_, used, r.fields, r.data,
                  r.data_len)) {
      chunk_pos_ = chunk_.size();  // the rest of a chunk cut off is lost
      return false;
    }
    chunk_pos_ += used;
    if (takeRecord(r)) return true;
  }
  return false;
}

/// Reads the next record of the file into `r` (its data in outer_, at most what the file still
/// holds); `cut` when the data run past the end of the file. False, fault_ set, when not even the
/// header can be read.
bool BagSalvage::readFileRecord(Record& r, std::vector<std::uint8_t>& head, bool& cut) {
  const std::uint64_t start = file_.getOffset();
  const std::string where = "record at byte " + std::to_string(start);
  std::uint8_t len[4];
  if (size_ - start < 8) return (fault_ = where + " is cut off (truncated bag)"), false;
  file_.read(len, 4);
  const std::uint32_t hlen = le32(len);
  if (hlen > size_ - start - 8 || hlen > kMaxRecordAllocation) {
    return (fault_ = where + " is cut off or corrupt (truncated bag)"), false;
  }
  head.resize(hlen);
  file_.read(head.data(), hlen);
  if (!parseFields(head.data(), hlen, r.fields)) return (fault_ = where + " is corrupt"), false;
  file_.read(len, 4);
  const std::uint64_t left = size_ - file_.getOffset();
  const std::uint32_t dlen = le32(len);
  cut = dlen > left;
  outer_.resize(std::min<std::uint64_t>({dlen, left, kMaxRecordAllocation}));
  file_.read(outer_.data(), outer_.size());
  r.data = outer_.data();
  r.data_len = static_cast<std::uint32_t>(outer_.size());
  if (cut) {
    fault_ = where + " is cut off after " + std::to_string(left) + " of its " +
             std::to_string(dlen) + " bytes (truncated bag)";
  }
  return true;
}

/// A chunk's records, decompressed by rosbag, become the ones to walk. An uncompressed chunk
/// cut off keeps its whole records; a compressed one cut off cannot be decompressed.
bool BagSalvage::startChunk(Record& r, bool cut) {
  const std::string compression = r.fields[rosbag::COMPRESSION_FIELD_NAME];
  chunk_pos_ = 0;
  if (compression == rosbag::COMPRESSION_NONE) {
    chunk_.assign(outer_.begin(), outer_.end());
    return true;
  }
  if (cut) return false;
  const std::uint32_t size = field32(r.fields, rosbag::SIZE_FIELD_NAME);
  if (size > kMaxRecordAllocation ||
      (compression != rosbag::COMPRESSION_BZ2 && compression != rosbag::COMPRESSION_LZ4)) {
    fault_ = "a chunk of " + std::to_string(size) + " bytes compressed as '" + compression +
             "' is corrupt";
    return false;
  }
  chunk_.resize(size);
  file_.decompress(
      compression == rosbag::COMPRESSION_BZ2 ? rosbag::compression::BZ2 : rosbag::compression::LZ4,
      chunk_.data(), size, outer_.data(), r.data_len);
  return true;
}

/// Reads the next record of the file: a chunk, or a lone connection or message record (walked
/// as a chunk of one); index records are passed over. False at the end of what can be read.
bool BagSalvage::readOuter() {
  if (file_.getOffset() >= size_) return false;  // the end, on a record boundary
  Record r;
  std::vector<std::uint8_t> head;
  bool cut = false;
  if (!readFileRecord(r, head, cut)) return false;
  const auto op = r.fields.find(rosbag::OP_FIELD_NAME);
  const char kind = op != r.fields.end() && op->second.size() == 1 ? op->second[0] : 0;
  if (kind == rosbag::OP_CHUNK) return startChunk(r, cut);
  if (kind == rosbag::OP_CONNECTION || kind == rosbag::OP_MSG_DATA) {
    const auto hlen = static_cast<std::uint32_t>(head.size());
    const auto n = static_cast<std::uint32_t>(outer_.size());
    chunk_.assign(hlen + 8 + n, 0);
    std::memcpy(chunk_.data(), &hlen, 4);  // little-endian, as the format (x86, ARM)
    std::memcpy(chunk_.data() + 4, head.data(), hlen);
    std::memcpy(chunk_.data() + 4 + hlen, &n, 4);
    std::memcpy(chunk_.data() + 8 + hlen, outer_.data(), n);
    chunk_pos_ = 0;
  }
  return !cut;
}

bool BagSalvage::next() {
  while (!done_) {
    if (nextInChunk()) return true;
    chunk_.clear();
    chunk_pos_ = 0;
    if (!fault_.empty()) break;  // the cut chunk, walked, was the last
    try {
      const AllocationLimit limit;
      if (!readOuter()) break;
    } catch (const std::exception& e) {
      fault_ = "record at byte " + std::to_string(file_.getOffset()) + " is cut off or corrupt (" +
               e.what() + ")";
      break;
    }
  }
  done_ = true;
  return false;
}

std::vector<std::pair<std::string, std::string>> BagSalvage::topics() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& kv : connections_) out.emplace_back(kv.second.topic, kv.second.datatype);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

double BagSalvage::fractionRead() const {
  return size_ > 0 ? std::min(1.0, static_cast<double>(file_.getOffset()) / size_) : 1.0;
}

}  // namespace dynamap::bag
