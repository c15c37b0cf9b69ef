#pragma once
// Whether rosbag may follow a ROS 1 bag's index. rosbag trusts every offset and length its index
// and records state: an index entry pointing outside its chunk, or a message record whose header
// length runs past the chunk, makes it read outside its buffer (a crash, not an exception). So
// before rosbag opens a bag, dynamap reads the bag once itself, record by record, and checks every
// offset and length rosbag will follow against what holds it; rosbag opens only a bag that passes.
// A bag that fails is read in file order by BagSalvage, which checks each length as it goes.
//
// Private to the bag reader (bag_source.cpp).

#include <string>

namespace dynamap::bag {

struct IndexCheck {
  enum class Verdict {
    kSound,    // every offset and length rosbag follows lies inside what holds it
    kNoIndex,  // no index to follow: never closed (index_pos 0), or cut off before its end
    kCorrupt,  // an index or record that lies: `reason` says which, and where
  };
  Verdict verdict = Verdict::kSound;
  std::string reason;  // "" when sound
};

/// Reads the bag at `path` (its version line already known to be "#ROSBAG V2.0") to its end.
/// Sound means:
/// - every record's header and data lie inside the file, and every header's fields inside it;
/// - every chunk is "none" (its size that of its data), "bz2" or "lz4" (of at most
///   kMaxRecordAllocation bytes, decompressing to records that fill exactly its stated size); its
///   records are connection and message records, each inside the chunk;
/// - index records follow a chunk, state as many 12-byte entries as their data hold, and each entry
///   points at the start of a message record of the index record's connection in that chunk;
/// - the file header's index_pos is the start of conn_count connection records followed by
///   chunk_count chunk info records, each naming a chunk followed by as many index records as its
///   connections.
/// Never throws for what the file holds; reads each record once (chunks decompressed once).
IndexCheck checkBagIndex(const std::string& path);

}  // namespace dynamap::bag
