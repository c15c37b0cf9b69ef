#include "dynamap/input/mrpt_records.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

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

mrpt::serialization::CSerializable::Ptr readBoundedObject(mrpt::io::CStream& in) {
  const AllocationLimit limit;
  return mrpt::serialization::archiveFrom(in).ReadObject();
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
