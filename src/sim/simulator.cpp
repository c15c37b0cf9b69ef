#include "dynamap/sim/simulator.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "dynamap/base/angles.h"
#include "dynamap/base/csv_schema.h"

namespace dynamap::sim {
namespace {

// Spreads a small seed over 64 bits (SplitMix64), so seeds 1 and 2 start unrelated streams.
std::uint64_t splitMix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

Pose2 compose(const Pose2& a, double dx, double dy, double dphi) {
  const double c = std::cos(a.phi), s = std::sin(a.phi);
  return {a.x + c * dx - s * dy, a.y + s * dx + c * dy, wrapAngle(a.phi + dphi)};
}

}  // namespace

// ---- the route ----------------------------------------------------------------------------

RobotPath::RobotPath(const RobotSpec& spec) : loop_(spec.loop) {
  const auto& w = spec.waypoints;
  const std::size_t n = w.size();
  if (n < 2) {
    end_ = {w.empty() ? 0 : w[0].x, w.empty() ? 0 : w[0].y, 0};
    loop_ = false;
    return;
  }
  const std::size_t drives = loop_ ? n : n - 1;
  auto heading = [&](std::size_t i) {
    const Vec2 a = w[i % n], b = w[(i + 1) % n];
    return std::atan2(b.y - a.y, b.x - a.x);
  };
  Pose2 p{w[0].x, w[0].y, heading(0)};
  double t = 0;
  for (std::size_t i = 0; i < drives; ++i) {
    const Vec2 b = w[(i + 1) % n];
    const double len = distance(w[i], b);
    legs_.push_back({t, t + len / spec.speed_mps, p, b.x - p.x, b.y - p.y, 0});
    t += len / spec.speed_mps;
    p = {b.x, b.y, p.phi};
    if (i + 1 == drives && !loop_) break;
    const double turn = wrapAngle(heading(i + 1) - p.phi);
    if (turn != 0) {
      const double dt = std::abs(turn) / (spec.turn_rate_dps * kDegToRad);
      legs_.push_back({t, t + dt, p, 0, 0, turn});
      t += dt;
      p.phi = heading(i + 1);
    }
  }
  pass_ = t;
  end_ = p;
}

Pose2 RobotPath::at(double t) const {
  if (legs_.empty()) return end_;
  if (loop_) {
    t = std::fmod(t, pass_);
  } else if (t >= pass_) {
    return end_;
  }
  for (const auto& leg : legs_) {
    if (t >= leg.t1) continue;
    const double u = (t - leg.t0) / (leg.t1 - leg.t0);
    return {leg.from.x + u * leg.dx, leg.from.y + u * leg.dy,
            wrapAngle(leg.from.phi + u * leg.dphi)};
  }
  return loop_ ? legs_.front().from : end_;
}

// ---- the time loop ------------------------------------------------------------------------

Simulator::Simulator(const Scenario& scenario)
    : sc_(scenario),
      path_(scenario.robot),
      range_rng_(splitMix(scenario.seed)),
      odo_rng_(splitMix(scenario.seed + 0x5eedULL)) {
  scan_count_ =
      static_cast<std::size_t>(std::floor(sc_.duration_s * sc_.robot.scan_rate_hz + 1e-9)) + 1;
  last_pose_ = path_.at(0);
  odometry_ = last_pose_;
  // The aperture as MRPT stores it (float), so the angles here are the ones readers compute.
  const double aperture = static_cast<float>(sc_.laser.fov_deg * kDegToRad);
  const int n = sc_.laser.beams;
  for (int i = 0; i < n; ++i) angles_.push_back(-aperture / 2 + i * aperture / (n - 1));
}

bool Simulator::next(ScanTruth& out) {
  if (k_ >= scan_count_) return false;
  out.index = k_;
  out.t = static_cast<double>(k_) / sc_.robot.scan_rate_hz;
  out.pose = path_.at(out.t);

  // Odometry: the true motion since the last scan, in the last pose's frame, plus noise.
  const double c = std::cos(last_pose_.phi), s = std::sin(last_pose_.phi);
  const double gx = out.pose.x - last_pose_.x, gy = out.pose.y - last_pose_.y;
  const double dx = c * gx + s * gy, dy = -s * gx + c * gy;
  const double dphi = wrapAngle(out.pose.phi - last_pose_.phi);
  const double d = std::hypot(dx, dy);
  const double nx = odo_rng_.gaussian(sc_.odometry.noise_xy_per_m * d);
  const double ny = odo_rng_.gaussian(sc_.odometry.noise_xy_per_m * d);
  const double nphi = odo_rng_.gaussian(sc_.odometry.noise_yaw_per_rad * std::abs(dphi));
  odometry_ = compose(odometry_, dx + nx, dy + ny, dphi + nphi);
  out.odometry = odometry_;
  last_pose_ = out.pose;

  // The laser: every beam cast exactly, noise drawn for every beam whether it hit or not.
  out.sensor =
      compose(out.pose, sc_.laser.mount.x, sc_.laser.mount.y, sc_.laser.mount_yaw_deg * kDegToRad);
  out.bodies = bodiesAt(sc_, out.t);
  out.hits.assign(out.bodies.size(), 0);
  out.angles = angles_;
  out.ranges.assign(angles_.size(), 0.f);
  out.valid.assign(angles_.size(), 0);
  const double max_range = sc_.laser.max_range_m;
  for (std::size_t i = 0; i < angles_.size(); ++i) {
    const RayHit hit = castRay(sc_.world, out.bodies, {out.sensor.x, out.sensor.y},
                               out.sensor.phi + angles_[i], max_range);
    const double noise = range_rng_.gaussian(sc_.laser.range_noise_std_m);
    if (!hit.hit()) continue;
    out.valid[i] = 1;
    out.ranges[i] = static_cast<float>(std::clamp(hit.range + noise, 0.0, max_range));
    if (hit.body >= 0) ++out.hits[hit.body];
  }
  ++k_;
  return true;
}

// ---- the writers --------------------------------------------------------------------------

namespace {

mrpt::poses::CPose3D pose3(const Pose2& p) {
  return {p.x, p.y, 0, p.phi, 0, 0};
}

mrpt::obs::CObservation2DRangeScan makeScan(const Scenario& sc, const ScanTruth& st,
                                            mrpt::Clock::time_point stamp) {
  mrpt::obs::CObservation2DRangeScan scan;
  scan.sensorLabel = "LASER";
  scan.timestamp = stamp;
  scan.aperture = static_cast<float>(sc.laser.fov_deg * kDegToRad);
  scan.rightToLeft = true;
  scan.maxRange = static_cast<float>(sc.laser.max_range_m);
  scan.stdError = static_cast<float>(sc.laser.range_noise_std_m);
  scan.sensorPose = pose3({sc.laser.mount.x, sc.laser.mount.y, sc.laser.mount_yaw_deg * kDegToRad});
  scan.resizeScan(st.ranges.size());
  for (std::size_t i = 0; i < st.ranges.size(); ++i) {
    scan.setScanRange(i, st.ranges[i]);
    scan.setScanRangeValidity(i, st.valid[i] != 0);
  }
  return scan;
}

void writeRawlogRecord(mrpt::serialization::CArchive& ar, const Scenario& sc, const ScanTruth& st) {
  const auto stamp = mrpt::Clock::fromDouble(kEpochUnixSeconds + sc.clock_offset_s + st.t);
  mrpt::obs::CObservationOdometry odo;
  odo.sensorLabel = "ODOMETRY";
  odo.timestamp = stamp;
  odo.odometry = mrpt::poses::CPose2D(st.odometry.x, st.odometry.y, st.odometry.phi);
  ar << odo;
  ar << makeScan(sc, st, stamp);
  mrpt::obs::CObservationRobotPose gt;
  gt.sensorLabel = "GT";
  gt.timestamp = stamp;
  gt.pose.mean = pose3(st.pose);
  ar << gt;
}

std::ofstream openText(const std::string& path) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  return f;
}

// printf-style formatting into a string; the C locale is never changed, so '.' is the separator.
template <typename... T>
std::string format(const char* f, T... v) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, v...);
  return buf;
}

// One row per object, then one per person: a person's legs are summed into the person, whose
// centre is between them.
void writeObjectRows(std::ofstream& out, const Scenario& sc, const ScanTruth& st) {
  for (std::size_t b = 0; b < st.bodies.size(); ++b) {
    const Body& body = st.bodies[b];
    if (body.kind != BodyKind::Object) continue;
    out << format("%zu,%.3f,%s,%d,%.4f,%.4f,%.3f,%d\n", st.index, st.t, "object", body.id,
                  body.centre.x, body.centre.y, 2 * body.radius, st.hits[b]);
  }
  for (const PersonSpec& p : sc.people) {
    int hits = 0;
    for (std::size_t b = 0; b < st.bodies.size(); ++b) {
      if (st.bodies[b].kind == BodyKind::Person && st.bodies[b].id == p.id) hits += st.hits[b];
    }
    const Vec2 c = personPositionAt(p, st.t);
    out << format("%zu,%.3f,%s,%d,%.4f,%.4f,%.3f,%d\n", st.index, st.t, "person", p.id, c.x, c.y,
                  p.diameter, hits);
  }
}

void writeMoves(const std::string& path, const Scenario& sc) {
  std::ofstream out = openText(path);
  out << csv::kMoves << "\n";
  std::vector<MoveSpec> moves = sc.moves;
  std::sort(moves.begin(), moves.end(), [](auto& a, auto& b) { return a.id < b.id; });
  for (const auto& m : moves) {
    const Vec2 from = moveOrigin(sc, m);
    out << format("%d,%d,%.3f,%.3f,%.4f,%.4f,%.4f,%.4f\n", m.id, m.object_id, m.t_start, m.tEnd(),
                  from.x, from.y, m.to.x, m.to.y);
  }
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace

SimulationFiles outputPaths(const Scenario& sc, const std::string& out_dir) {
  const auto base = (std::filesystem::path(out_dir) / sc.name).string();
  return {base + ".rawlog", base + ".gt.txt", base + ".objects.csv", base + ".moves.csv",
          base + ".world.png"};
}

std::size_t writeSimulation(const Scenario& sc, const std::string& out_dir) {
  std::filesystem::create_directories(out_dir);
  const SimulationFiles files = outputPaths(sc, out_dir);
  mrpt::io::CFileGZOutputStream rawlog;
  if (!rawlog.open(files.rawlog, 9)) throw std::runtime_error(files.rawlog + ": cannot open");
  auto ar = mrpt::serialization::archiveFrom(rawlog);
  std::ofstream gt = openText(files.gt);
  std::ofstream objects = openText(files.objects);
  objects << csv::kTruthRows << "\n";

  Simulator sim(sc);
  ScanTruth st;
  while (sim.next(st)) {
    writeRawlogRecord(ar, sc, st);
    gt << format("%.6f %.6f %.6f %.6f\n", kEpochUnixSeconds + sc.clock_offset_s + st.t, st.pose.x,
                 st.pose.y, st.pose.phi);
    writeObjectRows(objects, sc, st);
  }
  rawlog.close();
  if (!gt || !objects) throw std::runtime_error(out_dir + ": write failed");
  writeMoves(files.moves, sc);
  renderWorldImage(sc, files.world_png);
  return sim.scanCount();
}

std::vector<std::size_t> writeSessions(const Scenario& sc, const std::string& out_dir) {
  std::vector<std::size_t> scans;
  forEachSession(sc, [&](const Scenario& s) { scans.push_back(writeSimulation(s, out_dir)); });
  if (sc.sessions.empty()) return scans;
  const std::string path = (std::filesystem::path(out_dir) / sc.name).string() + ".changes.csv";
  std::ofstream out = openText(path);
  out << csv::kSessionChanges << "\n";
  for (const SessionChange& c : sessionChanges(sc)) {
    const bool has_from = c.kind != "object_new", has_to = c.kind != "object_gone";
    out << format("%d,%s,%d,%.3f,", c.session, c.kind.c_str(), c.id, c.size)
        << (has_from ? format("%.4f,%.4f,", c.from.x, c.from.y) : std::string(",,"))
        << (has_to ? format("%.4f,%.4f", c.to.x, c.to.y) : std::string(",")) << "\n";
  }
  if (!out) throw std::runtime_error(path + ": write failed");
  return scans;
}

}  // namespace dynamap::sim
