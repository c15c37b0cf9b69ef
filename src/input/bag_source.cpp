#include "dynamap/input/bag_source.h"

#include <mrpt/core/Clock.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <nav_msgs/Odometry.h>
#include <ros/header.h>
#include <rosbag/bag.h>
#include <rosbag/buffer.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include <boost/make_shared.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <set>

#include "bag_index_check.h"
#include "bag_messages.h"
#include "bag_salvage.h"
#include "dynamap/base/allocation_limit.h"
#include "dynamap/base/pose_track.h"
#include "dynamap/input/cdr_messages.h"
#include "dynamap/input/ros2_bag.h"
#include "tf_tree.h"

namespace dynamap {
namespace {

using bag::convertScan;
using bag::frameName;
using bag::MessageCursor;
using bag::pose2D;
using bag::TfTree;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::poses::CPose2D;

constexpr double kHistory_s = 10.0;            // transforms kept before the oldest scan waiting
constexpr std::size_t kMaxPending = 10000;     // scans waiting for later transforms
constexpr std::size_t kPeekTfMessages = 2000;  // /tf messages read to learn the frames
const std::vector<std::string> kTfTopics = {"/tf", "tf"};
const std::vector<std::string> kTfStaticTopics = {"/tf_static", "tf_static"};
const char* const kLaserScanType = "sensor_msgs/LaserScan";
const char* const kOdometryType = "nav_msgs/Odometry";

std::string topicList(const std::vector<std::pair<std::string, std::string>>& topics) {
  std::string out;
  for (const auto& [topic, type] : topics) {
    out += (out.empty() ? "" : ", ") + topic + " (" + type + ")";
  }
  return out.empty() ? "none" : out;
}

}  // namespace

// --- the reader --------------------------------------------------------------------------------

struct BagReader::Impl {
  struct Pending {
    std::size_t index;
    double t;
    CObservation2DRangeScan::Ptr scan;
    std::string frame;
    double centre;
  };
  enum class Outcome { kLater, kReady, kSkipped };

  std::string path;
  BagOptions options;
  rosbag::Bag bag;
  bool salvage = false;     // rosbag cannot open it: read what is left in file order
  bool ros2 = false;        // a ROS 2 bag (ros2_bag.h): its own container, CDR messages
  std::string index_fault;  // why its index, there, cannot be followed ("" when there is none)
  BagContents contents;
  std::unique_ptr<MessageCursor> cursor;  // the scans, /tf and odometry
  TfTree tree;
  PoseTrack odom;
  bool need_odometry = false, need_ground_truth = false;
  SourceStats stats;
  std::deque<Pending> pending;
  std::deque<BagScan> ready;
  double stream_t = -std::numeric_limits<double>::infinity();  // newest stamp read
  bool eof = false;
  std::string fault;

  Impl(const std::string& p, const BagOptions& o) : path(p), options(o) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path + ": " + what); }

  void open();
  void findTopics();
  void readStatic();
  void peekTf();
  void startView();
  void readMessage();
  std::string salvageFault() const;
  /// A ROS 2 stream's fault without the leading "<path>: " fail() adds again.
  std::string withoutPath(const std::string& f) const {
    return f.rfind(path + ": ", 0) == 0 ? f.substr(path.size() + 2) : f;
  }
  std::unique_ptr<MessageCursor> messages(const std::vector<std::string>& topics) {
    if (ros2) return std::make_unique<MessageCursor>(ros2::openRos2Bag(path, topics));
    return salvage ? std::make_unique<MessageCursor>(path, topics)
                   : std::make_unique<MessageCursor>(bag, topics);
  }
  void takeScan(const MessageCursor& m);
  void takeTf(const tf2_msgs::TFMessage& msg, bool is_static);
  Outcome resolve(Pending& p, bool complete);
  void resolvePending(bool final);
  bool topicExists(const std::string& topic, const char* type) const;
};

void BagReader::Impl::open() {
  // rosbag follows the index's offsets and the records' lengths without checking them: it opens
  // only a bag whose every offset and length has been checked (bag_index_check.h).
  if (!looksLikeRosBag(path) && ros2::looksLikeRos2Bag(path)) {
    ros2 = true;
    return;
  }
  if (looksLikeRosBag(path)) {
    const bag::IndexCheck check = bag::checkBagIndex(path);
    if (check.verdict != bag::IndexCheck::Verdict::kSound) {
      salvage = true;
      if (check.verdict == bag::IndexCheck::Verdict::kCorrupt) index_fault = check.reason;
      return;
    }
  }
  try {
    const AllocationLimit limit;
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    salvage = true;  // never closed: rosbag needs the index the recorder writes last
  } catch (const rosbag::BagIOException&) {
    salvage = true;  // cut off: the index, at the end, is gone
  } catch (const rosbag::BagFormatException&) {
    salvage = true;  // an index that is corrupt is as good as none
  } catch (const std::bad_alloc&) {
    salvage = true;  // so is one stating a size no real record has
  } catch (const std::exception& e) {
    fail(std::string("not a readable ROS bag: ") + e.what());
  }
}

bool BagReader::Impl::topicExists(const std::string& topic, const char* type) const {
  for (const auto& [name, t] : contents.topics) {
    if (name == topic && ros2::ros1TypeName(t) == type) return true;
  }
  return false;
}

void BagReader::Impl::findTopics() {
  std::set<std::pair<std::string, std::string>> seen;
  if (ros2) {
    auto all = ros2::openRos2Bag(path, {});
    const ros2::TopicList topics = all->topics();
    seen.insert(topics.begin(), topics.end());
    if (seen.empty()) {
      fail("no topic in the ROS 2 bag" +
           (all->fault().empty() ? std::string() : " (" + withoutPath(all->fault()) + ")"));
    }
  } else if (salvage) {
    MessageCursor all(path, {});
    while (all.next()) {
    }
    const auto topics = all.salvagedTopics();
    seen.insert(topics.begin(), topics.end());
    if (seen.empty()) {
      const std::string why = all.fault();
      fail("not a readable ROS bag: no index and no whole message" +
           (why.empty() ? std::string() : " (" + why + ")"));
    }
  } else {
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      seen.insert({c->topic, c->datatype});
    }
  }
  contents.topics.assign(seen.begin(), seen.end());
  std::vector<std::string> scans;
  for (const auto& [topic, type] : contents.topics) {
    if (ros2::ros1TypeName(type) == kLaserScanType) scans.push_back(topic);
  }
  if (!options.scan_topic.empty()) {
    if (!topicExists(options.scan_topic, kLaserScanType)) {
      fail("no " + std::string(kLaserScanType) + " topic " + options.scan_topic +
           " (topics: " + topicList(contents.topics) + ")");
    }
    contents.scan_topic = options.scan_topic;
  } else if (scans.size() == 1) {
    contents.scan_topic = scans[0];
  } else {
    fail(std::string(scans.empty() ? "no " : "more than one ") + kLaserScanType +
         " topic: pick one with --scan-topic (topics: " + topicList(contents.topics) + ")");
  }
  if (!options.odom_topic.empty() && !topicExists(options.odom_topic, kOdometryType)) {
    fail("no " + std::string(kOdometryType) + " topic " + options.odom_topic +
         " (topics: " + topicList(contents.topics) + ")");
  }
}

void BagReader::Impl::takeTf(const tf2_msgs::TFMessage& msg, bool is_static) {
  for (const auto& tr : msg.transforms) {
    const auto& v = tr.transform.translation;
    const auto pose = pose2D(v.x, v.y, tr.transform.rotation);
    const double t = tr.header.stamp.toSec();
    const std::string parent = frameName(tr.header.frame_id), child = frameName(tr.child_frame_id);
    if (!pose || parent.empty() || child.empty() || parent == child) {
      ++stats.skipped["tf transform not finite or without frames"];
    } else if (!tree.add(parent, child, t, *pose, is_static)) {
      ++stats.skipped["tf transform of a frame past the 1000th"];
    } else if (!is_static) {
      stream_t = std::max(stream_t, t);
    }
  }
}

/// /tf_static first, whole: a recorder latches it once, often after the first scans.
void BagReader::Impl::readStatic() {
  auto m = messages(kTfStaticTopics);
  while (m->next()) {
    const AllocationLimit limit;
    if (auto msg = m->as<tf2_msgs::TFMessage>()) takeTf(*msg, true);
  }
}

/// Which frames the bag's /tf names, from its first messages (a peek; nothing is kept).
void BagReader::Impl::peekTf() {
  std::set<std::string> frames;
  std::size_t n = 0;
  for (const auto& topics : {kTfStaticTopics, kTfTopics}) {
    for (auto m = messages(topics); n < kPeekTfMessages && m->next(); ++n) {
      const AllocationLimit limit;
      auto msg = m->as<tf2_msgs::TFMessage>();
      if (!msg) continue;
      for (const auto& tr : msg->transforms) {
        frames.insert(frameName(tr.header.frame_id));
        frames.insert(frameName(tr.child_frame_id));
      }
    }
  }
  contents.ground_truth = frames.count(frameName(options.gt_frame)) > 0;
  contents.odometry =
      !options.odom_topic.empty() || frames.count(frameName(options.odom_frame)) > 0;
}

void BagReader::Impl::startView() {
  if (ros2) {  // every topic: the messages not read are counted
    cursor = messages({});
    return;
  }
  std::vector<std::string> topics = kTfTopics;
  topics.push_back(contents.scan_topic);
  if (!options.odom_topic.empty()) topics.push_back(options.odom_topic);
  cursor = messages(topics);
}

void BagReader::Impl::takeScan(const MessageCursor& m) {
  auto msg = m.as<sensor_msgs::LaserScan>();
  if (!msg) return;
  const std::size_t index = stats.scans++;
  double t = msg->header.stamp.toSec();
  if (t == 0) t = m.time();  // no stamp: the time it was recorded
  double centre = 0;
  std::string bad;
  auto scan = convertScan(*msg, centre, bad);
  if (!scan) {
    ++stats.skipped[bad];
    return;
  }
  scan->timestamp = mrpt::Clock::fromDouble(t);
  pending.push_back({index, t, scan, frameName(msg->header.frame_id), centre});
  stream_t = std::max(stream_t, t);
}

void BagReader::Impl::readMessage() {
  try {
    const AllocationLimit limit;
    if (!cursor->next()) {
      eof = true;
      if (salvage) fault = salvageFault();
      if (ros2) fault = withoutPath(cursor->fault());
      return;
    }
    const MessageCursor& m = *cursor;
    ++stats.records;
    if (m.topic() == contents.scan_topic) {
      takeScan(m);
    } else if (m.topic() == options.odom_topic) {
      if (auto o = m.as<nav_msgs::Odometry>()) {
        const auto& p = o->pose.pose;
        const auto pose = pose2D(p.position.x, p.position.y, p.orientation);
        const double t = o->header.stamp.toSec();
        if (pose) odom.add(t, *pose);
        if (pose) stream_t = std::max(stream_t, t);
      }
    } else if (std::count(kTfTopics.begin(), kTfTopics.end(), m.topic())) {
      if (auto tf = m.as<tf2_msgs::TFMessage>()) takeTf(*tf, false);
    } else if (!std::count(kTfStaticTopics.begin(), kTfStaticTopics.end(), m.topic())) {
      ++stats.skipped[m.typeName() + " on " + m.topic() + ", not read"];
    }
  } catch (const std::bad_alloc&) {
    eof = true;
    fault = "message " + std::to_string(stats.records) + " is corrupt: it states a size no " +
            "real message has";
  } catch (const std::exception& e) {
    eof = true;
    fault = "message " + std::to_string(stats.records) + " cannot be read: " + e.what();
  }
}

/// A bag read without its index ends in a fault either way: cut off where the salvage says, never
/// closed (the recording may have gone on), or an index that lies (the file may, too).
std::string BagReader::Impl::salvageFault() const {
  const std::string where = cursor->fault();
  const std::string what =
      index_fault.empty()
          ? "a ROS bag without its index (cut off, or its recorder did not close it)"
          : "a ROS bag whose index cannot be followed (" + index_fault + ")";
  return what + ", read in file order up to its end" +
         (where.empty() ? std::string() : ": " + where);
}

BagReader::Impl::Outcome BagReader::Impl::resolve(Pending& p, bool complete) {
  using L = PoseTrack::Lookup;
  const std::string& base = frameName(options.base_frame);
  const bool need_any = need_odometry || need_ground_truth;
  CPose2D mount;
  if (p.frame != base && !p.frame.empty()) {
    const L r = tree.lookup(base, p.frame, p.t, complete, mount);
    if (r == L::kLater) return Outcome::kLater;
    if (r == L::kMissing && (need_any || (tree.knows(base) && tree.knows(p.frame)))) {
      ++stats.skipped["scan frame '" + p.frame + "' has no transform to '" + base + "'"];
      return Outcome::kSkipped;
    }
    if (r == L::kMissing) mount = CPose2D();  // no tf at all: the scan's frame is the robot's
  }
  BagScan out;
  auto lookup = [&](const std::string& fixed_frame, std::optional<CPose2D>& pose) {
    CPose2D q;
    const L r = fixed_frame.empty() ? odom.at(p.t, q, complete)
                                    : tree.lookup(frameName(fixed_frame), base, p.t, complete, q);
    if (r == L::kFound) pose = q;
    return r;
  };
  const std::string odom_frame = options.odom_topic.empty() ? options.odom_frame : "";
  for (const auto& [need, frame, pose] :
       {std::tuple{need_odometry, odom_frame, &out.odometry},
        std::tuple{need_ground_truth, options.gt_frame, &out.ground_truth}}) {
    if (!need) continue;
    const L r = lookup(frame, *pose);
    if (r == L::kLater) return Outcome::kLater;
    if (r == L::kMissing) {
      ++stats.skipped[frame.empty()
                          ? "no " + options.odom_topic + " odometry at the scan's time"
                          : "no transform " + frame + " -> " + base + " at the scan's time"];
      return Outcome::kSkipped;
    }
  }
  p.scan->sensorPose = mrpt::poses::CPose3D(mount + CPose2D(0, 0, p.centre));
  out.index = p.index;
  out.t = p.t;
  out.scan = std::move(p.scan);
  ready.push_back(std::move(out));
  return Outcome::kReady;
}

void BagReader::Impl::resolvePending(bool final) {
  while (!pending.empty()) {
    Pending& p = pending.front();
    // No transform stamped within kMinAutoGap after a scan is coming once the data are past that.
    const bool complete =
        final || pending.size() > kMaxPending || stream_t > p.t + PoseTrack::kMinAutoGap;
    if (resolve(p, complete) == Outcome::kLater) break;
    pending.pop_front();
  }
  const double horizon = pending.empty() ? stream_t : std::min(stream_t, pending.front().t);
  tree.forgetBefore(horizon - kHistory_s);
  odom.forgetBefore(horizon - kHistory_s);
}

// --- the public face ---------------------------------------------------------------------------

BagReader::BagReader(const std::string& path, const BagOptions& options)
    : impl_(std::make_unique<Impl>(path, options)) {
  impl_->open();
  try {
    impl_->findTopics();
    impl_->readStatic();
    impl_->peekTf();
    impl_->startView();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    impl_->fail(std::string("cannot read the ROS bag: ") + e.what());
  }
}

BagReader::~BagReader() = default;

const BagContents& BagReader::contents() const {
  return impl_->contents;
}

void BagReader::require(bool odometry, bool ground_truth) {
  impl_->need_odometry = odometry;
  impl_->need_ground_truth = ground_truth;
}

bool BagReader::next(BagScan& out) {
  Impl& m = *impl_;
  while (m.ready.empty()) {
    if (m.eof) {
      m.resolvePending(true);
      if (!m.ready.empty()) break;
      if (m.fault.empty()) return false;
      const std::string f = m.fault;
      m.fault.clear();
      m.fail(f);
    }
    m.readMessage();
    m.resolvePending(false);
  }
  out = std::move(m.ready.front());
  m.ready.pop_front();
  return true;
}

const SourceStats& BagReader::stats() const {
  return impl_->stats;
}
const std::string& BagReader::path() const {
  return impl_->path;
}
double BagReader::fractionRead() const {
  return impl_->cursor->fractionRead();
}

std::size_t BagReader::samplesKept() const {
  return impl_->tree.samples() + impl_->odom.size();
}

// --- the ScanSource ----------------------------------------------------------------------------

namespace {

class BagSource : public ScanSource {
 public:
  BagSource(const std::string& path, PoseSource source, const BagOptions& options)
      : reader_(path, options), source_(source) {
    const BagContents& c = reader_.contents();
    if (source_ == PoseSource::Simplemap) fail("a ROS bag has no simplemap poses");
    if (source_ == PoseSource::Auto) {
      if (c.ground_truth)
        source_ = PoseSource::GroundTruth;
      else if (c.odometry)
        source_ = PoseSource::Odometry;
      else
        fail(noPoses(options));
    }
    if (source_ == PoseSource::GroundTruth && !c.ground_truth) {
      fail("no ground truth: no frame '" + options.gt_frame + "' in /tf (--gt-frame)");
    }
    if (source_ == PoseSource::Odometry && !c.odometry) {
      fail("no odometry: no frame '" + options.odom_frame + "' in /tf and no --odom-topic");
    }
    reader_.require(source_ == PoseSource::Odometry, source_ == PoseSource::GroundTruth);
  }

  bool next(ScanRecord& out) override {
    BagScan s;
    if (!reader_.next(s)) return false;
    out.index = s.index;
    out.t = s.t;
    out.scan = s.scan;
    out.pose = source_ == PoseSource::Odometry      ? *s.odometry
               : source_ == PoseSource::GroundTruth ? *s.ground_truth
                                                    : CPose2D();
    return true;
  }
  PoseSource poseSource() const override { return source_; }
  const SourceStats& stats() const override { return reader_.stats(); }
  const std::string& path() const override { return reader_.path(); }
  double fractionRead() const override { return reader_.fractionRead(); }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(reader_.path() + ": " + what);
  }
  static std::string noPoses(const BagOptions& o) {
    return "no poses found (no frame '" + o.gt_frame + "' or '" + o.odom_frame +
           "' in /tf, no --odom-topic); --poses fixed maps a robot that stands still";
  }

  BagReader reader_;
  PoseSource source_;
};

}  // namespace

std::unique_ptr<ScanSource> openBagSource(const std::string& path, PoseSource source,
                                          const BagOptions& options) {
  return std::make_unique<BagSource>(path, source, options);
}

}  // namespace dynamap

// --- rosbag's Buffer, bounded ------------------------------------------------------------------
//
// rosbag's Buffer (record headers, chunks, messages) grows with realloc to whatever size a bag
// states, doubling a 32-bit capacity until it is large enough: a corrupt bag makes it allocate
// gigabytes, loop for ever once the doubling overflows, or write through the null pointer a
// failed realloc returns (its check is an assert, compiled out). Like mrpt::aligned_malloc in
// base/allocation_limit.cpp, this definition takes the place of librosbag_storage's own (which
// calls it through the PLT) with the same behaviour for every real bag, and applies the record
// AllocationLimit in force: a refusal, or a failed realloc, throws std::bad_alloc, which the
// bag reader reports as a corrupt bag naming the file.

namespace rosbag {

void Buffer::ensureCapacity(uint32_t capacity) {
  if (capacity <= capacity_) return;
  const std::size_t limit = dynamap::currentAllocationLimit();
  if (limit != 0 && capacity > limit) throw std::bad_alloc();
  std::uint64_t grown = capacity_ == 0 ? capacity : capacity_;
  while (grown < capacity) grown *= 2;  // 64 bits: no overflow
  if (grown > UINT32_MAX || (limit != 0 && grown > limit)) grown = capacity;
  void* p = std::realloc(buffer_, grown);
  if (!p) throw std::bad_alloc();
  buffer_ = static_cast<uint8_t*>(p);
  capacity_ = static_cast<uint32_t>(grown);
}

}  // namespace rosbag
