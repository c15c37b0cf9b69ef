#pragma once
// Reading what is left of a ROS 1 bag that rosbag cannot open: one cut off (its index, at the
// end, is gone) or never closed (the recorder was killed). rosbag's C++ API has no reindex, so
// this walks the bag's records in file order itself, and only that: the record files are read
// and decompressed by rosbag's own ChunkedFile, every record header and connection header is
// parsed by ROS's ros::Header, and messages are deserialized by ros::serialization.
//
// Private to the bag reader (bag_source.cpp).

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <rosbag/chunked_file.h>
#include <boost/make_shared.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace dynamap::bag {

/// True when every length-prefixed field of a record header lies inside its `len` bytes, which
/// the caller holds. ros::Header::parse trusts each field's stated length and reads past the
/// header when it lies: every header dynamap hands it is checked with this first, and every one
/// rosbag hands it has been checked by checkBagIndex (bag_index_check.h) before the bag is opened.
bool headerFieldsFit(const std::uint8_t* p, std::uint32_t len);

/// A little-endian 32-bit number at p (the bag format's byte order).
std::uint32_t le32(const std::uint8_t* p);
/// A 4-byte header field as a number; 0 when absent or of another size.
std::uint32_t field32(const std::map<std::string, std::string>& f, const std::string& key);
/// A record header (length-prefixed name=value fields) of `len` bytes at p, which the caller
/// holds: checked with headerFieldsFit, then parsed by ros::Header. False when it is corrupt.
bool parseFields(const std::uint8_t* p, std::uint32_t len, std::map<std::string, std::string>& out);
/// One record <header_len><header><data_len><data> at p, of which the caller holds n bytes; its
/// size in `used`. False when it runs past the n bytes or its header is corrupt.
bool recordAt(const std::uint8_t* p, std::size_t n, std::size_t& used,
              std::map<std::string, std::string>& fields, const std::uint8_t*& data,
              std::uint32_t& data_len);

class BagSalvage {
 public:
  /// Opens the file; throws InputError when it cannot be opened or is no bag 2.0.
  explicit BagSalvage(const std::string& path);

  /// The next message (file order); false at the end of what can be read: fault() then says
  /// where and why the readable part ended ("" when the file ended cleanly).
  bool next();
  const std::string& topic() const { return current_->topic; }
  const std::string& datatype() const { return current_->datatype; }
  double time() const { return time_; }
  /// The message as T; null when its connection is of another type.
  template <class T>
  boost::shared_ptr<T> as() const;

  /// Every topic and type whose connection record has been read so far.
  std::vector<std::pair<std::string, std::string>> topics() const;
  const std::string& fault() const { return fault_; }
  /// Bytes of the file consumed, over its size.
  double fractionRead() const;

 private:
  struct Connection {
    std::string topic, datatype, md5;
  };
  struct Record {
    std::map<std::string, std::string> fields;
    const std::uint8_t* data = nullptr;
    std::uint32_t data_len = 0;
  };
  bool readOuter();
  bool readFileRecord(Record& r, std::vector<std::uint8_t>& head, bool& cut);
  bool startChunk(Record& r, bool cut);
  bool nextInChunk();
  bool takeRecord(const Record& r);
  void addConnection(const Record& r);

  std::string path_;
  rosbag::ChunkedFile file_;
  std::uint64_t size_ = 0;
  std::vector<std::uint8_t> outer_;  // the data of the last record read from the file
  std::vector<std::uint8_t> chunk_;  // a chunk's records, decompressed
  std::size_t chunk_pos_ = 0;
  std::map<std::uint32_t, Connection> connections_;
  const Connection* current_ = nullptr;
  const std::uint8_t* data_ = nullptr;
  std::uint32_t data_len_ = 0;
  double time_ = 0;
  std::string fault_;
  bool done_ = false;
};

template <class T>
boost::shared_ptr<T> BagSalvage::as() const {
  if (current_->datatype != ros::message_traits::datatype<T>()) return nullptr;
  if (current_->md5 != "*" && current_->md5 != ros::message_traits::md5sum<T>()) return nullptr;
  auto msg = boost::make_shared<T>();
  ros::serialization::IStream in(const_cast<std::uint8_t*>(data_), data_len_);
  ros::serialization::deserialize(in, *msg);
  return msg;
}

}  // namespace dynamap::bag
