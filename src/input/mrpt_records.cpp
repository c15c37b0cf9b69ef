#include "dynamap/input/mrpt_records.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "dynamap/base/allocation_limit.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {

void normalizeFlags(mrpt::obs::CObservation2DRangeScan& scan) {
  unsigned char raw = 0;
  std::memcpy(&raw, &scan.rightToLeft, 1);
  scan.rightToLeft = raw != 0;
}

std::size_t recordAllocationBound(std::uint64_t remaining) {
  constexpr std::uint64_t kFactor = 16;
  constexpr std::uint64_t kFloor = std::uint64_t{32} << 20;
  if (remaining == 0 || remaining > kMaxRecordAllocation / kFactor) return kMaxRecordAllocation;
  return static_cast<std::size_t>(std::max(kFloor, kFactor * remaining));
}

mrpt::serialization::CSerializable::Ptr readBoundedObject(mrpt::io::CStream& in,
                                                          std::size_t max_bytes) {
  constexpr std::size_t kTotalFactor = 4;
  const AllocationLimit limit(max_bytes, kTotalFactor * max_bytes);
  return mrpt::serialization::archiveFrom(in).ReadObject();
}

namespace {

/// MRPT's exceptions nest reports with call stacks; the innermost "Message:" says what failed.
std::string innermostMessage(const std::string& what) {
  std::string msg;
  for (std::size_t pos = what.find("Message:"); pos != std::string::npos;
       pos = what.find("Message:", pos + 1)) {
    msg = what.substr(pos + 8, what.find('\n', pos) - pos - 8);
  }
  if (msg.empty()) msg = what.substr(0, what.find('\n'));
  const auto first = msg.find_first_not_of(' ');
  return first == std::string::npos ? std::string() : msg.substr(first);
}

}  // namespace

std::string describeRecordFault(const std::exception& e, mrpt::io::CFileGZInputStream& in,
                                const std::string& what, std::uint64_t start) {
  const std::string where = what + " at byte " + std::to_string(start);
  // MRPT reports a record cut short either as CExceptionEOF or as an error reading it.
  const std::string msg = innermostMessage(e.what());
  if (dynamic_cast<const mrpt::serialization::CExceptionEOF*>(&e) ||
      msg.find("(EOF?)") != std::string::npos || in.checkEOF()) {
    return where + " is cut off (truncated file)";
  }
  if (msg.find("bad_alloc") != std::string::npos) {
    return where + " is corrupt: it states a size no real record has";
  }
  return where + " is corrupt: " + msg;
}

std::string fileHead(const std::string& path, std::size_t n) {
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw InputError(path + ": cannot open");
  std::string head(n, '\0');
  const std::size_t got = in.Read(head.data(), n);
  head.resize(got);
  return head;
}

bool fileExists(const std::string& p) {
  return std::ifstream(p).good();
}

double toSeconds(const mrpt::Clock::time_point& t) {
  return mrpt::Clock::toDouble(t);
}

}  // namespace dynamap
