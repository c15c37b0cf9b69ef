#pragma once
// Writing ROS 2 bags without ROS 2 (dynamap export-bag, and the tests): CDR messages into an
// MCAP file or a rosbag2 SQLite file, chosen by the output's extension.
//
// MCAP: the Header record (profile "ros2"), then chunks of at most ~1 MiB of records (each
// message's Schema and Channel records in the chunk that first uses them), compressed with
// zstd, LZ4 or not at all, each followed by its MessageIndex records; then DataEnd, the summary
// (Schema, Channel and ChunkIndex records) and the Footer. Schemas carry their name only (no
// message definition text): dynamap needs none, and ROS 2 tools look types up by name.
// .db3: rosbag2's tables (schema, topics, messages with its timestamp index), written in one
// transaction. The same messages give the same bytes.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dynamap::ros2 {

class BagWriter {
 public:
  /// `path` ends in .mcap or .db3 (else std::invalid_argument); `compression`: "zstd", "lz4" or
  /// "none" (MCAP only). An existing file is replaced. Throws std::runtime_error naming the file
  /// when it cannot be written.
  BagWriter(const std::string& path, const std::string& compression);
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// One message: its topic, its ROS 2 type ("sensor_msgs/msg/LaserScan"), its time [ns] and
  /// its CDR bytes. A topic keeps the type of its first message.
  void write(const std::string& topic, const std::string& type, std::uint64_t t_ns,
             const std::vector<std::uint8_t>& cdr);
  /// Finishes the file (summary and footer, or the transaction); the destructor does it too.
  void close();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace dynamap::ros2
