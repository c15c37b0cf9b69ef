#include "dynamap/evaluation/bag_people_truth.h"

#include <mrpt/poses/CPose3D.h>

#include <map>

#include "dynamap/input/bag_annotations.h"

namespace dynamap {

namespace {

struct ScanPlace {
  double t = 0;
  mrpt::poses::CPose3D mount;
};

// Every scan the mapper reads from the bag, by index: its time and the laser's mount.
std::map<std::size_t, ScanPlace> scanPlaces(BagReader& reader) {
  reader.require(false, false);
  std::map<std::size_t, ScanPlace> out;
  BagScan s;
  while (reader.next(s)) out[s.index] = {s.t, s.scan->sensorPose};
  return out;
}

}  // namespace

BagPeopleTruth bagPeopleTruth(const std::string& bag, const BagOptions& options,
                              const std::string& person_topic,
                              const std::vector<TimedPose>& poses) {
  BagReader reader(bag, options);
  const std::string scan_topic = reader.contents().scan_topic;  // the one the mapper takes
  const auto places = scanPlaces(reader);
  BagPeopleTruth out;
  for (const PersonTruth& p : readPersonTruthBag(bag, scan_topic, person_topic)) {
    ++out.messages;
    const auto it = places.find(p.scan_index);
    const TimedPose* at = it == places.end() ? nullptr : poseAtTime(poses, it->second.t, 1e-3);
    if (at == nullptr) {
      ++out.unplaced;
      continue;
    }
    const mrpt::poses::CPose3D laser =
        mrpt::poses::CPose3D(mrpt::poses::CPose2D(at->x, at->y, at->phi)) + it->second.mount;
    double x = 0, y = 0, z = 0;
    laser.composePoint(p.position.x, p.position.y, 0.0, x, y, z);
    TruthRow r;
    r.scan_index = p.scan_index;
    r.t = it->second.t;
    r.kind = sim::BodyKind::Person;
    r.id = p.id;
    r.x = x;
    r.y = y;
    r.hits = MotOptions{}.min_visible_hits;  // the annotator saw them
    out.rows.push_back(r);
  }
  return out;
}

}  // namespace dynamap
