// The rawlog half of structure_mutators.h: the input read record by record with MRPT's own
// deserializer, one record changed as an object and written back with MRPT's serializer (every
// length it states then right), or one stated length made to lie in the bytes written.
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "dynamap/base/allocation_limit.h"
#include "structure_mutators.h"

namespace dynamap::fuzz {
namespace {

using mrpt::obs::CObservation2DRangeScan;
using Bytes = std::vector<std::uint8_t>;

struct Record {
  std::size_t begin, end;
  mrpt::serialization::CSerializable::Ptr object;
};

/// The whole records at the start of the input (none when it is no plain rawlog).
std::vector<Record> readRecords(const std::uint8_t* data, std::size_t size) {
  std::vector<Record> out;
  mrpt::io::CMemoryStream in;
  in.assignMemoryNotOwn(data, size);
  try {
    const AllocationLimit limit(std::size_t{16} << 20);
    while (in.getPosition() < size && out.size() < 256) {
      const std::size_t begin = in.getPosition();
      auto object = mrpt::serialization::archiveFrom(in).ReadObject();
      out.push_back({begin, static_cast<std::size_t>(in.getPosition()), object});
    }
  } catch (const std::exception&) {
  }
  return out;
}

Bytes serialize(const mrpt::serialization::CSerializable& object) {
  mrpt::io::CMemoryStream out;
  mrpt::serialization::archiveFrom(out).WriteObject(&object);
  const auto* p = static_cast<const std::uint8_t*>(out.getRawBufferData());
  return Bytes(p, p + out.getTotalBytesCount());
}

/// The scan a record is or holds (a sensory frame's first); null when none.
CObservation2DRangeScan* scanOf(const Record& r) {
  if (auto* s = dynamic_cast<CObservation2DRangeScan*>(r.object.get())) return s;
  if (auto* sf = dynamic_cast<mrpt::obs::CSensoryFrame*>(r.object.get())) {
    for (const auto& o : *sf) {
      if (auto* s = dynamic_cast<CObservation2DRangeScan*>(o.get())) return s;
    }
  }
  return nullptr;
}

float strange(std::mt19937& rng) {
  const float values[] = {std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(),
                          -1.0f,
                          0.0f,
                          1e30f,
                          -1e30f,
                          1e-30f,
                          6.2832f,
                          7.0f,
                          1e9f};
  return values[rng() % (sizeof(values) / sizeof(values[0]))];
}

/// One change to a scan's content: its beams (count restated), a range, its geometry or pose.
void changeScan(CObservation2DRangeScan& s, std::size_t room, std::mt19937& rng) {
  const std::size_t n = s.getScanSize();
  switch (rng() % 6) {
    case 0: {  // as many beams as room allows (5 bytes each), or fewer, or none
      const std::size_t most = n + room / 5;
      const std::size_t options[] = {0, 1, 2, n / 2, n + 1, most};
      const std::size_t m = std::min(options[rng() % 6], most);
      s.resizeScan(m);
      for (std::size_t i = n; i < m; ++i) {
        s.setScanRange(i, static_cast<float>(rng() % 3000) / 100.0f);
        s.setScanRangeValidity(i, rng() % 4 != 0);
      }
      break;
    }
    case 1:
      if (n > 0) s.setScanRange(rng() % n, strange(rng));
      if (n > 0) s.setScanRangeValidity(rng() % n, rng() % 2 == 0);
      break;
    case 2:
      s.aperture = strange(rng);
      break;
    case 3:
      s.maxRange = strange(rng);
      break;
    case 4:
      s.sensorPose = mrpt::poses::CPose3D(strange(rng), 0, 0, 0, rng() % 2 ? 0.0 : 0.5, 0);
      break;
    default:
      s.rightToLeft = !s.rightToLeft;
      break;
  }
}

/// The record's bytes with one stated length lying: the beam count (found as the 4 bytes of N
/// before the first range) or a string's length (the sensor label's).
bool lieInLength(Bytes& b, const CObservation2DRangeScan& s, std::mt19937& rng) {
  const std::size_t n = s.getScanSize();
  std::vector<std::size_t> at;
  for (std::size_t i = 0; n > 0 && i + 8 <= b.size(); ++i) {
    std::uint32_t v;
    float r;
    std::memcpy(&v, b.data() + i, 4);
    std::memcpy(&r, b.data() + i + 4, 4);
    const float first = s.getScanRange(0);
    if (v == n && std::memcmp(&r, &first, 4) == 0) at.push_back(i);
  }
  const std::string& label = s.sensorLabel;
  for (std::size_t i = 0; !label.empty() && i + 4 + label.size() <= b.size(); ++i) {
    std::uint32_t v;
    std::memcpy(&v, b.data() + i, 4);
    if (v == label.size() && std::memcmp(b.data() + i + 4, label.data(), label.size()) == 0) {
      at.push_back(i);
    }
  }
  if (at.empty()) return false;
  const std::size_t i = at[rng() % at.size()];
  std::uint32_t v;
  std::memcpy(&v, b.data() + i, 4);
  const std::uint32_t lies[] = {v + 1, v - 1, v * 2, 0xFFFFFFFFu, 0x80000000u, 0u};
  std::memcpy(b.data() + i, &lies[rng() % 6], 4);
  return true;
}

/// A pose or odometry record given a pose no robot reaches.
bool changePose(const Record& r, std::mt19937& rng) {
  const double x = strange(rng);
  if (auto* o = dynamic_cast<mrpt::obs::CObservationOdometry*>(r.object.get())) {
    o->odometry = mrpt::poses::CPose2D(x, o->odometry.y(), o->odometry.phi());
    return true;
  }
  if (auto* p = dynamic_cast<mrpt::obs::CObservationRobotPose*>(r.object.get())) {
    p->pose.mean.x(x);
    return true;
  }
  return false;
}

/// The input with [begin, end) replaced by `with`, when it fits in max_size; 0 otherwise.
std::size_t splice(std::uint8_t* data, std::size_t size, std::size_t max_size, std::size_t begin,
                   std::size_t end, const Bytes& with) {
  const std::size_t out = size - (end - begin) + with.size();
  if (out > max_size) return 0;
  std::memmove(data + begin + with.size(), data + end, size - end);
  if (!with.empty()) std::memcpy(data + begin, with.data(), with.size());
  return out;
}

}  // namespace

std::size_t mutateRawlog(std::uint8_t* data, std::size_t size, std::size_t max_size,
                         unsigned seed) {
  const std::vector<Record> records = readRecords(data, size);
  if (records.empty()) return 0;
  std::mt19937 rng(seed);
  const Record& r = records[rng() % records.size()];
  const Bytes original(data + r.begin, data + r.end);
  switch (rng() % 5) {
    case 0:  // dropped
      return splice(data, size, max_size, r.begin, r.end, {});
    case 1:  // repeated
      return splice(data, size, max_size, r.end, r.end, original);
    case 2: {  // swapped with the next
      if (&r == &records.back()) return 0;
      const Record& next = (&r)[1];
      Bytes both(data + next.begin, data + next.end);
      both.insert(both.end(), original.begin(), original.end());
      return splice(data, size, max_size, r.begin, next.end, both);
    }
    default:
      break;
  }
  try {
    const AllocationLimit limit(std::size_t{16} << 20);
    CObservation2DRangeScan* scan = scanOf(r);
    if (scan) changeScan(*scan, max_size > size ? max_size - size : 0, rng);
    if (!scan && !changePose(r, rng)) return 0;
    Bytes written = serialize(*r.object);
    if (scan && rng() % 2 == 0) lieInLength(written, *scan, rng);
    return splice(data, size, max_size, r.begin, r.end, written);
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace dynamap::fuzz
