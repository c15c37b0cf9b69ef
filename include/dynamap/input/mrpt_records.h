#pragma once
// Reading MRPT's serialized records safely: shared by the rawlog and simplemap readers.

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/serialization/CSerializable.h>
#include <mrpt/system/datetime.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

namespace dynamap {

/// MRPT copies a scan's rightToLeft byte from the file as it is: any byte but 0 or 1 is no valid
/// bool (reading it is undefined behaviour). Makes it one.
void normalizeFlags(mrpt::obs::CObservation2DRangeScan& scan);

/// The largest single allocation a record may make when `remaining` bytes of the stream are
/// left (0: unknown). A record's buffers hold what the file holds, at most a few times over (a
/// scan's ranges, flags and intensities come from 4 + 1 bytes a beam): 16 times the bytes left,
/// but never under 32 MiB (a small image decoded from a JPEG) nor over kMaxRecordAllocation. So a
/// 500 kB log stating 60 million beams allocates nothing for them.
std::size_t recordAllocationBound(std::uint64_t remaining);

/// recordAllocationBound for a record starting at `position` of a stream of at most `size_bound`
/// bytes (uncompressedSizeBound; 0: unknown, and a position past it makes it unknown too).
inline std::size_t recordAllocationBound(std::uint64_t size_bound, std::uint64_t position) {
  return recordAllocationBound(position < size_bound ? size_bound - position : 0);
}

/// Reads one top-level object under an AllocationLimit of `max_bytes` for any single allocation
/// and 4 times that in all (a real record's buffers are a few copies of its largest): a size or a
/// count in it beyond that throws std::bad_alloc instead of being allocated.
mrpt::serialization::CSerializable::Ptr readBoundedObject(mrpt::io::CStream& in,
                                                          std::size_t max_bytes);

/// Why the record `what` (e.g. "record 12", "keyframe 3"), which began at byte `start` of `in`,
/// could not be read, as "<what> at byte <start> is cut off (truncated file)" when the stream
/// ended inside it, "... is corrupt: it states a size no real record has" when it asked for more
/// than AllocationLimit allows, and "... is corrupt: <MRPT's innermost message>" otherwise.
std::string describeRecordFault(const std::exception& e, mrpt::io::CFileGZInputStream& in,
                                const std::string& what, std::uint64_t start);

/// The first `n` decompressed bytes of a file (gz or plain); throws InputError if unreadable.
std::string fileHead(const std::string& path, std::size_t n);

bool fileExists(const std::string& path);

/// Seconds since the UNIX epoch.
double toSeconds(const mrpt::Clock::time_point& t);

}  // namespace dynamap
