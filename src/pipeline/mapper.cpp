#include "dynamap/pipeline/mapper.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/input/fixed_pose.h"

namespace dynamap {

namespace {

constexpr const char* kInput = "input";
// P(free) an added structure's cells get in the state the next session starts from: as sure as
// a wall seen many times.
constexpr float kAddedStructureFree = 0.05f;

/// A key of [input], declared once: its meaning for the key table, how it is read (every error
/// through IniFile::fail, naming the key), and when and how config.ini writes it.
struct InputKey {
  const char* name;
  const char* unit;
  const char* meaning;
  const char* range;
  std::string (*text)(const MapConfig&);  ///< the value as config.ini writes it
  void (*read)(const IniFile&, const std::string& text, MapConfig&);
  const char* comment;                ///< after the value in config.ini
  bool (*written)(const MapConfig&);  ///< when config.ini holds the key
};

/// Reads `key`'s text through `parse`; a std::invalid_argument becomes the key's error.
template <typename Parse>
void readThrough(const IniFile& ini, const char* key, Parse parse) {
  try {
    parse();
  } catch (const std::invalid_argument& e) {
    ini.fail(kInput, key, e.what());
  }
}

std::string shortest(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// poses is always written; the other keys only when they differ from the default, so the
// other runs' config.ini stay as they were before the key existed.
const std::vector<InputKey>& inputKeys() {
  static const std::vector<InputKey> keys = {
      {"poses", "", "where each scan's robot pose comes from",
       "auto, simplemap, ground_truth, odometry, scan_matching, fixed, slam",
       [](const MapConfig& c) { return toString(c.poses); },
       [](const IniFile& ini, const std::string& t, MapConfig& c) {
         readThrough(ini, "poses", [&] { c.poses = parsePoseSource(t); });
       },
       "auto | simplemap | ground_truth | odometry | scan_matching",
       [](const MapConfig&) { return true; }},
      {"fixed_pose", "", "x y phi [m m rad]: the pose of every scan with poses = fixed",
       "three finite numbers", [](const MapConfig& c) { return formatFixedPose(c.fixed_pose); },
       [](const IniFile& ini, const std::string& t, MapConfig& c) {
         readThrough(ini, "fixed_pose", [&] { c.fixed_pose = parseFixedPose(t); });
       },
       "[m m rad] x y phi", [](const MapConfig& c) { return c.poses == PoseSource::Fixed; }},
      {"pose_max_gap", "s",
       "widest gap between two pose samples (ground truth, odometry, ODOM lines) a scan's pose "
       "is interpolated across; 0: 3 x the samples' median spacing, at least 2 s",
       "[0, 3600]", [](const MapConfig& c) { return shortest(c.pose_max_gap); },
       [](const IniFile& ini, const std::string&, MapConfig& c) {
         c.pose_max_gap = ini.getDouble(kInput, "pose_max_gap", 0);
         requireInRange(ini.name(), kInput, "pose_max_gap", c.pose_max_gap, 0, 3600,
                        "in [0, 3600]");
       },
       "[s]", [](const MapConfig& c) { return c.pose_max_gap != 0; }},
      {"carmen_odometry", "",
       "a CARMEN log's odometry for poses = odometry: laser (each laser line's odometry "
       "fields) or odom (the ODOM lines, interpolated to each scan's time)",
       "laser, odom", [](const MapConfig& c) { return toString(c.carmen_odometry); },
       [](const IniFile& ini, const std::string& t, MapConfig& c) {
         readThrough(ini, "carmen_odometry", [&] { c.carmen_odometry = parseCarmenOdometry(t); });
       },
       "laser | odom",
       [](const MapConfig& c) { return c.carmen_odometry != CarmenOdometrySource::LaserLines; }}};
  return keys;
}

}  // namespace

MapConfig MapConfig::load(const IniFile& ini) {
  ini.requireKnownSections({DynamicMapOptions::kSection, InsertionOptions::kSection,
                            ObjectOptions::kSection, PeopleOptions::kSection,
                            ScanMatchOptions::kSection, SlamOptions::kSection,
                            ChangeOptions::kSection, kInput});
  MapConfig c;
  c.map.load(ini);
  c.insertion.load(ini);
  c.objects.load(ini);
  c.people.load(ini);
  c.scan_matching.load(ini);
  c.slam.load(ini);
  c.changes.load(ini);
  std::vector<std::string> names;
  for (const InputKey& k : inputKeys()) names.push_back(k.name);
  ini.requireKnownKeys(kInput, names);
  const MapConfig defaults;
  for (const InputKey& k : inputKeys())
    k.read(ini, ini.getString(kInput, k.name, k.text(defaults)), c);
  return c;
}

void MapConfig::writeIni(std::ostream& out) const {
  out << "; the effective configuration of this run (reload it with --config)\n\n";
  out << "[input]\n";
  for (const InputKey& k : inputKeys()) {
    if (k.written(*this)) out << k.name << " = " << k.text(*this) << "  ; " << k.comment << "\n";
  }
  out << "\n";
  map.writeIni(out);
  out << "\n";
  insertion.writeIni(out);
  out << "\n";
  objects.writeIni(out);
  out << "\n";
  people.writeIni(out);
  out << "\n";
  scan_matching.writeIni(out);
  if (poses == PoseSource::Slam) {
    out << "\n";
    slam.writeIni(out);
  }
  out << "\n";
  changes.writeIni(out);
}

std::vector<OptionDoc> MapConfig::describe() {
  const MapConfig defaults;
  std::vector<OptionDoc> docs;
  for (const InputKey& k : inputKeys()) {
    docs.push_back({kInput, k.name, k.text(defaults), k.unit, k.meaning, k.range});
  }
  for (auto&& more : {DynamicMapOptions::table().describe(defaults.map),
                      InsertionOptions::table().describe(defaults.insertion),
                      ObjectOptions::table().describe(defaults.objects),
                      PeopleOptions::table().describe(defaults.people),
                      ScanMatchOptions::table().describe(defaults.scan_matching),
                      SlamOptions::table().describe(defaults.slam),
                      ChangeOptions::table().describe(defaults.changes)}) {
    docs.insert(docs.end(), more.begin(), more.end());
  }
  return docs;
}

std::size_t ScanMatchCounts::fallbackTotal() const {
  std::size_t n = 0;
  for (const auto& kv : fallbacks) n += kv.second;
  return n;
}

Mapper::Mapper(const MapConfig& config)
    : config_(config),
      map_(config.map, config.insertion),
      tracker_(config.objects),
      people_(config.people),
      people_objects_(config.people),
      path_(config.map.resolution) {
  if (config.poses == PoseSource::ScanMatching) {
    matcher_ = std::make_unique<ScanMatcher>(config.scan_matching);
  }
  const PeopleOptions& p = config.people;
  if (p.enabled && p.leg_classifier) {
    if (p.leg_model.empty()) {
      legs_ = &LegClassifier::builtin();
    } else {
      try {
        own_legs_ = LegClassifier::load(p.leg_model);
      } catch (const std::exception& e) {
        throw ConfigError(std::string("[people] leg_model: ") + e.what());
      }
      legs_ = &own_legs_;
    }
  }
}

void Mapper::continueFrom(SessionState prior) {
  map_.loadStatic(prior.x_min, prior.y_min, prior.resolution, prior.size_x, prior.size_y,
                  prior.static_cells);
  carried_ = std::make_unique<std::vector<TrackedObject>>();
  for (const SessionObject& o : prior.objects) {
    TrackedObject row;
    row.id = o.id;
    for (const ObjectState st : {ObjectState::Present, ObjectState::Absent, ObjectState::Withdrawn,
                                 ObjectState::Relabeled, ObjectState::Retracted}) {
      if (o.state == toString(st)) row.state = st;
    }
    row.shape.cx = o.cx;
    row.shape.cy = o.cy;
    row.shape.size = o.size;
    row.shape.x_min = o.cx - 0.5 * o.size;
    row.shape.x_max = o.cx + 0.5 * o.size;
    row.shape.y_min = o.cy - 0.5 * o.size;
    row.shape.y_max = o.cy + 0.5 * o.size;
    row.n_moves = o.n_moves;
    row.first_seen_t = o.first_seen_t;
    row.last_seen_t = o.last_seen_t;
    carried_->push_back(row);
  }
  sessions_ = prior.sessions + 1;
  changes_ = std::make_unique<SessionChanges>(std::move(prior), config_.changes, config_.objects);
}

void Mapper::finishSession() {
  if (!changes_ || carried_) return;
  const SessionChanges::GridChanges grid = changes_->gridChanges(map_);
  // What the tracker took for objects on a wall that appeared are parts of it.
  for (const ChangeRow& r : grid.structure) {
    if (r.kind != "structure_added") continue;
    for (const TrackedObject& o : tracker_.objects()) {
      const double reach = 0.5 * o.shape.size + map_.getResolution();
      const bool on = std::any_of(r.region.begin(), r.region.end(), [&](const auto& c) {
        return std::hypot(map_.idx2x(c.first) - o.shape.cx, map_.idx2y(c.second) - o.shape.cy) <=
               reach;
      });
      if (on) tracker_.retire(o.id, last_scan_t_, last_scan_index_);
    }
  }
  tracker_.settleCarried(last_scan_t_, last_scan_index_);
  final_changes_ = changes_->report(grid, tracker_);
}

std::vector<ChangeRow> Mapper::changeReport() const {
  if (final_changes_) return *final_changes_;
  return changes_ ? changes_->report(map_, tracker_) : std::vector<ChangeRow>{};
}

SessionState Mapper::sessionState() const {
  SessionState s;
  s.sessions = sessions_;
  s.x_min = map_.getXMin();
  s.y_min = map_.getYMin();
  s.resolution = map_.getResolution();
  s.size_x = map_.getSizeX();
  s.size_y = map_.getSizeY();
  s.static_cells.assign(map_.getRawMap().begin(), map_.getRawMap().end());
  // Structure this session added and kept (in D, as all that appears where S was free) is the
  // building's now: the next session's S holds it, and can see it removed.
  if (changes_ && !carried_) {
    const auto occupied = DynamicGridMap::p2l(kAddedStructureFree);
    for (const ChangeRow& r : changeReport()) {
      if (r.kind != "structure_added") continue;
      for (const auto& [x, y] : r.region)
        s.static_cells[static_cast<std::size_t>(y) * s.size_x + x] = occupied;
    }
  }
  // Before the first scan inserted, the table is still the prior's, waiting: it is kept.
  for (const TrackedObject& o : carried_ ? *carried_ : tracker_.objects()) {
    s.objects.push_back({o.id, toString(o.state), o.shape.cx, o.shape.cy, o.shape.size, o.n_moves,
                         o.first_seen_t, o.last_seen_t});
  }
  s.last_x = last_scan_pose_.x();
  s.last_y = last_scan_pose_.y();
  s.last_phi = last_scan_pose_.phi();
  s.last_t = last_scan_t_;
  return s;
}

std::string Mapper::poseSourceName(const ScanSource& source) const {
  return toString(matcher_ ? PoseSource::ScanMatching : source.poseSource());
}

mrpt::poses::CPose2D Mapper::correctPose(const ScanRecord& rec, const RangeData& rd) {
  // The odometry increment since the last scan, applied to the last pose used, is the guess.
  const mrpt::poses::CPose2D guess =
      have_pose_ ? last_pose_ + (rec.pose - last_odometry_) : rec.pose;
  // Matched against S only: D's people and moved objects cannot pull the pose.
  const ScanMatchResult r = matcher_->match(map_, rd, guess);
  if (r.matched) {
    ++match_counts_.matched;
    match_counts_.sum_correction_m += r.correction_m;
    match_counts_.max_correction_m = std::max(match_counts_.max_correction_m, r.correction_m);
  } else {
    ++match_counts_.fallbacks[r.fallback_reason];
  }
  have_pose_ = true;
  last_odometry_ = rec.pose;
  last_pose_ = r.pose;
  return r.pose;
}

void Mapper::countTime(const ScanRecord& rec) {
  if (have_t_ && rec.t < counts_.last_t && counts_.time_backwards++ == 0)
    counts_.first_backwards_index = rec.index;
  if (!have_t_) counts_.first_t = rec.t;
  have_t_ = true;
  counts_.last_t = rec.t;
}

std::vector<PersonDetection> Mapper::detectAndCheck(const RangeData& rd,
                                                    const mrpt::poses::CPose2D& pose,
                                                    double& free_share) {
  std::vector<PersonDetection> people;
  free_share = 0;
  const bool check = config_.map.d_hold_share < 1;
  if (!config_.people.enabled && !check) return people;
  scanHits(rd, pose, hits_);
  if (config_.people.enabled) {
    people = detectPeople(map_, hits_, config_.people, legs_, &free_hits_);
  } else {
    free_hits_ = freeSpaceHits(map_, hits_, config_.people.wall_guard_cells);
  }
  free_share = shareOfHits(free_hits_.size(), hits_);
  free_share_.add(free_share);
  if (check) {
    // Free space hit by a surface wider than any object is a wall in the wrong place; a
    // moved object close by, in an open space with few echoes, can make most hits alone.
    surface_share_.add(
        freeSurfaceShare(free_hits_, hits_, config_.people, config_.objects.max_size));
    map_.holdDynamic(free_share_.value() > config_.map.d_hold_share &&
                     surface_share_.value() > kSurfaceShare);
  }
  return people;
}

ScanResult Mapper::process(const ScanRecord& rec) {
  countTime(rec);
  ScanResult result;
  // 0. A scan wider than the grids take (kMaxScanBeams) is skipped before anything looks at it:
  // the people detector's clustering of 2,000,000 hits alone would take hours.
  if (rec.scan->getScanSize() > kMaxScanBeams) {
    result.pose = rec.pose;
    result.skip_reason = kTooManyBeams;
    ++counts_.scans_skipped[result.skip_reason];
    return result;
  }
  // 1. The scan's geometry, once for the matcher, the grid and the tracker.
  config_.insertion.rangeData(*rec.scan, range_);
  const RangeData& rd = range_;
  result.pose = matcher_ ? correctPose(rec, rd) : rec.pose;  // 2. where the scan was taken
  // 3. People, and whether the scans agree with S.
  double free_share = 0;
  const std::vector<PersonDetection> people = detectAndCheck(rd, result.pose, free_share);
  map_.insertRange(rd, result.pose);  // 4. S and D
  const ScanInsertStats& st = map_.lastInsertStats();
  counts_.beams_bad += st.beams_bad;
  if (!st.inserted) {
    result.skip_reason = st.skip_reason ? st.skip_reason : "no usable beam";
    ++counts_.scans_skipped[result.skip_reason];
    return result;
  }
  result.inserted = true;
  ++counts_.scans_used;
  // 5. People tracked; where they are, no object is confirmed (exclusion_radius > 0).
  const std::size_t events_before = tracker_.events().size();
  if (config_.people.enabled) {
    people_.update(people, hits_, rec.t, free_share);
    std::vector<ObjectTracker::KeepOut> keep_out;
    for (const auto& [x, y] : people_.personPositions()) {
      keep_out.push_back({x, y, config_.people.exclusion_radius});
    }
    tracker_.setKeepOut(std::move(keep_out));
  }
  // 6. Objects, from the D cells this scan changed and the scan's view of known places; a
  // prior session's table first joins at this session's first time.
  if (carried_) {
    tracker_.carryOver(std::move(*carried_), rec.t);
    carried_.reset();
  }
  const ScanView view = makeScanView(rd, result.pose);
  tracker_.update(map_, view, rec.t, rec.index);
  if (changes_) changes_->update(map_, view, rec.t);
  // 6b. What was a person standing goes from the table.
  if (config_.people.enabled) {
    people_objects_.update(people_, tracker_, events_before, rec.t, rec.index);
  }
  result.object_events = tracker_.events().size() - events_before;
  path_.add(result.pose.x(), result.pose.y());  // 7. the path the pictures draw
  last_scan_pose_ = result.pose;
  last_scan_t_ = rec.t;
  last_scan_index_ = rec.index;
  return result;
}

InputOutcome runMapping(ScanSource& source, Mapper& mapper, const ScanCallback& on_scan) {
  InputOutcome outcome;
  ScanRecord rec;
  while (true) {
    try {
      if (!source.next(rec)) break;
    } catch (const InputError& e) {
      outcome.fault = e.what();
      break;
    }
    const ScanResult result = mapper.process(rec);
    rec.pose = result.pose;  // scan matching may have corrected it
    if (on_scan) on_scan(rec, result);
  }
  return outcome;
}

}  // namespace dynamap
