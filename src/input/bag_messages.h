#pragma once
// A bag's messages as the bag reader takes them: a cursor over some topics (rosbag's View, the
// salvage walk of a bag rosbag cannot open, or a ROS 2 bag's CDR stream decoded into the ROS 1
// messages), and a LaserScan as an MRPT scan. Private to the bag reader (bag_source.cpp).

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <ros/message_traits.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <boost/make_shared.hpp>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bag_salvage.h"
#include "dynamap/input/cdr_messages.h"
#include "dynamap/input/ros2_bag.h"

namespace dynamap::bag {

constexpr std::size_t kMaxBeams = 1000000;  // a LaserScan with more beams is refused

/// A LaserScan as an MRPT scan, its beams' middle angle in `centre` (the mount is added once
/// known); null with `bad` saying why when its geometry cannot be mapped.
mrpt::obs::CObservation2DRangeScan::Ptr convertScan(const sensor_msgs::LaserScan& m, double& centre,
                                                    std::string& bad);

/// The messages of some topics, in order: through rosbag's View when the bag has its index, else
/// through BagSalvage in file order (a bag cut off or never closed).
class MessageCursor {
 public:
  MessageCursor(rosbag::Bag& bag, const std::vector<std::string>& topics)
      : view_(std::make_unique<rosbag::View>(bag, rosbag::TopicQuery(topics))),
        size_(view_->size()) {}
  MessageCursor(const std::string& path, const std::vector<std::string>& topics)
      : salvage_(std::make_unique<BagSalvage>(path)), topics_(topics) {}
  /// A ROS 2 bag: the stream hands out CDR bytes, decoded here into the ROS 1 messages.
  explicit MessageCursor(std::unique_ptr<ros2::MessageStream> stream) : ros2_(std::move(stream)) {}

  /// Moves to the next message (the first, on the first call); false at the end.
  bool next() {
    if (ros2_) return ros2_->next();
    if (salvage_) {
      while (salvage_->next()) {
        if (topics_.empty() || std::count(topics_.begin(), topics_.end(), salvage_->topic())) {
          return true;
        }
      }
      return false;
    }
    if (started_)
      ++it_;
    else
      it_ = view_->begin();
    started_ = true;
    done_ += 1;
    return it_ != view_->end();
  }
  const std::string& topic() const {
    return ros2_ ? ros2_->topic() : salvage_ ? salvage_->topic() : it_->getTopic();
  }
  double time() const {
    if (ros2_) return static_cast<double>(ros2_->timeNs()) * 1e-9;
    return salvage_ ? salvage_->time() : it_->getTime().toSec();
  }
  /// The message as T; null when it is of another type. Throws when its bytes are not a T.
  template <class T>
  boost::shared_ptr<T> as() const {
    if (ros2_) return decoded<T>();
    return salvage_ ? salvage_->as<T>() : it_->instantiate<T>();
  }
  /// ROS 2 only (a View reads only the topics asked for): the message's type.
  std::string typeName() const { return ros2_ ? ros2_->type() : std::string(); }
  double fractionRead() const {
    if (ros2_) return ros2_->fractionRead();
    if (salvage_) return salvage_->fractionRead();
    return size_ > 0 ? std::min(1.0, (done_ - 1) / size_) : 1.0;
  }
  /// Salvage and ROS 2: where and why the readable part ended, and the topics seen.
  std::string fault() const { return ros2_ ? ros2_->fault() : salvage_ ? salvage_->fault() : ""; }
  std::vector<std::pair<std::string, std::string>> salvagedTopics() const {
    return salvage_->topics();
  }

 private:
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  double size_ = 0, done_ = 0;
  bool started_ = false;
  template <class T>
  boost::shared_ptr<T> decoded() const {
    if (ros2::ros1TypeName(ros2_->type()) != ros::message_traits::DataType<T>::value()) {
      return nullptr;
    }
    auto out = boost::make_shared<T>();
    try {
      ros2::decode(ros2_->data(), ros2_->size(), *out);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(ros2_->where() + ": " + e.what());
    }
    return out;
  }

  std::unique_ptr<BagSalvage> salvage_;
  std::vector<std::string> topics_;
  std::unique_ptr<ros2::MessageStream> ros2_;
};

}  // namespace dynamap::bag
