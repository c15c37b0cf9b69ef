#pragma once
// The people of a real ROS 1 bag with ground truth (leg_tracker/Person messages, positions in
// the laser frame of the scan recorded just before each message) as truth rows in the map frame
// of a dynamap run, so that CLEAR MOT scores a run on a real bag as it scores a simulated one.
// Built only with ROS bag support (DYNAMAP_HAVE_ROSBAG).

#include <string>
#include <vector>

#include "dynamap/base/pose_track.h"
#include "dynamap/evaluation/evaluation.h"
#include "dynamap/input/bag_source.h"

namespace dynamap {

/// What a bag's people truth came to.
struct BagPeopleTruth {
  std::vector<TruthRow> rows;   ///< kind Person, in the map frame; hits = MotOptions' minimum
  std::size_t messages = 0;     ///< Person messages read
  std::size_t unplaced = 0;     ///< of them, whose scan the run has no pose for (not scored)
};

/// Each Person message of `person_topic` placed in the map: its scan's sensor pose is the pose
/// of `poses` (the run's poses.txt) at the scan's time composed with the laser's mount from the
/// bag's tf (identity when the bag has none). `options` chooses the scan topic as for mapping.
/// Throws InputError / std::runtime_error naming the bag when it cannot be read.
BagPeopleTruth bagPeopleTruth(const std::string& bag, const BagOptions& options,
                              const std::string& person_topic,
                              const std::vector<TimedPose>& poses);

}  // namespace dynamap
