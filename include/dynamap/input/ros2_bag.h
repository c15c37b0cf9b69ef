#pragma once
// ROS 2 bags as streams of serialized messages: MCAP files (.mcap) and rosbag2 SQLite bags (a
// folder with metadata.yaml and *.db3 files, or a bare .db3 file), told apart by content.
//
// The stream only opens the container: each message comes out as its topic, its type (ROS 2's
// "pkg/msg/Type"), its time and its CDR bytes. Decoding the messages, and what a scan, a
// transform or an odometry pose becomes, is the bag reader's (bag_source.h), the same as for a
// ROS 1 bag.
//
// Contract for bad input: a stream never reads past its file, never allocates more than a record
// states and the file can hold (a compressed chunk at most 1 GiB and 255 times its compressed
// size), and never throws from next(): a record it cannot read ends the stream, and fault() then
// names the file and the record's offset (MCAP: byte offset; .db3: the messages table's row id).
// Every message before the fault has been returned.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace dynamap::ros2 {

/// True when `path` is an MCAP file (its magic), an SQLite file, or a folder holding
/// metadata.yaml or a .db3 / .mcap file; never throws. Built with or without bag support.
bool looksLikeRos2Bag(const std::string& path);
enum class Ros2File { kNone, kMcap, kSqlite };
/// What a file's first 16 bytes say it is.
Ros2File ros2FileKind(const std::string& path);
/// A name ending in .db3 or .mcap.
bool isRos2BagFile(const std::string& name);

/// "sensor_msgs/msg/LaserScan" -> "sensor_msgs/LaserScan" (ROS 1's name of the same message).
std::string ros1TypeName(const std::string& ros2_type);

using TopicList = std::vector<std::pair<std::string, std::string>>;  // topic, ROS 2 type

class MessageStream {
 public:
  virtual ~MessageStream() = default;
  /// Moves to the next message of the topics asked for (all when none), in time order; false at
  /// the end or at a fault.
  virtual bool next() = 0;
  virtual const std::string& topic() const = 0;
  virtual const std::string& type() const = 0;
  /// The time the message was recorded [ns] (MCAP log_time; rosbag2's timestamp).
  virtual std::uint64_t timeNs() const = 0;
  /// The message's CDR bytes, valid until the next call of next().
  virtual const std::uint8_t* data() const = 0;
  virtual std::size_t size() const = 0;
  /// Where the message is, for errors: "<file>: record at offset N" (or "messages row N").
  virtual std::string where() const = 0;
  /// Why the stream ended early, naming the file and the offset; "" when it ended cleanly.
  virtual std::string fault() const = 0;
  /// Bytes (or rows) read over the whole, in [0, 1].
  virtual double fractionRead() const = 0;
  /// Every topic of the bag; an MCAP without its summary is read to its end (or fault) for them.
  virtual TopicList topics() = 0;
};

/// Opens a ROS 2 bag for the messages of `topics` (all when empty). Throws InputError naming the
/// file when it is none (not MCAP, no rosbag2 tables, a metadata.yaml naming a missing file).
std::unique_ptr<MessageStream> openRos2Bag(const std::string& path,
                                           const std::vector<std::string>& topics);

/// The MCAP stream of one file (mcap_reader.cpp) and the rosbag2 stream of one .db3 file
/// (db3_reader.cpp); openRos2Bag chains several of a folder.
std::unique_ptr<MessageStream> openMcap(const std::string& path,
                                        const std::vector<std::string>& topics);
std::unique_ptr<MessageStream> openDb3(const std::string& path,
                                       const std::vector<std::string>& topics);

}  // namespace dynamap::ros2
