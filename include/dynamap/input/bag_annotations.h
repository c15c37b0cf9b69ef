#pragma once
// Annotated ROS 1 bags of real laser data: the leg training bags (LaserScans, each with the
// positions of its leg clusters as a geometry_msgs/PoseArray recorded just before it) and bags
// with people's ground truth (leg_tracker/Person messages: a geometry_msgs/Pose and a uint32 id,
// no header; the position is in the laser frame of the scan recorded just before the message).
// Both pair messages with scans by the order they were recorded in, never by their stamps: the
// annotations of these bags carry no stamp, or one from another clock.

#include <cstddef>
#include <string>
#include <vector>

namespace dynamap {

/// A LaserScan as recorded: beam i looks along angle_min + i * angle_increment in the laser's
/// frame; a range outside [range_min, range_max] (or not finite) is no echo.
struct PolarScan {
  std::size_t index = 0;  ///< 0-based among the LaserScans of its topic
  double t = 0;           ///< when it was recorded [s]
  double angle_min = 0, angle_increment = 0, range_min = 0, range_max = 0;
  std::vector<float> ranges;
};

/// A position in a scan's laser frame [m].
struct LaserPoint {
  double x = 0, y = 0;
};

/// One scan of a leg training bag and the leg positions recorded with it.
struct LegTrainingScan {
  PolarScan scan;
  std::vector<LaserPoint> legs;
};

/// The LaserScans of `scan_topic` in recording order, each with the positions of the last
/// PoseArray of `positions_topic` recorded before it ("" = none: every scan has no legs, as in
/// a bag of rooms without people). At most max_scans scans are read (0 = all). Throws
/// std::runtime_error naming the file and topic when the bag cannot be read or lacks the topic.
std::vector<LegTrainingScan> readLegTrainingBag(const std::string& path,
                                                const std::string& scan_topic,
                                                const std::string& positions_topic,
                                                std::size_t max_scans = 0);

/// A person of a ground-truth bag at one scan.
struct PersonTruth {
  std::size_t scan_index = 0;  ///< the LaserScan of scan_topic recorded just before the message
  double t = 0;                ///< when the message was recorded [s]
  int id = 0;
  LaserPoint position;  ///< in that scan's laser frame
};

/// Every leg_tracker/Person message of `person_topic` paired with the scan of `scan_topic`
/// recorded just before it (messages before the first scan are dropped). Throws
/// std::runtime_error naming the file, the topic and the message when one cannot be decoded.
std::vector<PersonTruth> readPersonTruthBag(const std::string& path, const std::string& scan_topic,
                                            const std::string& person_topic);

}  // namespace dynamap
