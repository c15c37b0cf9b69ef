#pragma once
// Reading MRPT's serialized records safely: shared by the rawlog and simplemap readers.

#include <mrpt/io/CStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/serialization/CSerializable.h>
#include <mrpt/system/datetime.h>

#include <cstddef>
#include <string>

namespace dynamap {

/// MRPT copies a scan's rightToLeft byte from the file as it is: any byte but 0 or 1 is no valid
/// bool (reading it is undefined behaviour). Makes it one.
void normalizeFlags(mrpt::obs::CObservation2DRangeScan& scan);

/// Reads one top-level object under an AllocationLimit: a size in it beyond any real record
/// throws std::bad_alloc instead of being allocated.
mrpt::serialization::CSerializable::Ptr readBoundedObject(mrpt::io::CStream& in);

/// The first `n` decompressed bytes of a file (gz or plain); throws InputError if unreadable.
std::string fileHead(const std::string& path, std::size_t n);

bool fileExists(const std::string& path);

/// Seconds since the UNIX epoch.
double toSeconds(const mrpt::Clock::time_point& t);

}  // namespace dynamap
