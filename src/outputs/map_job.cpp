#include "dynamap/outputs/map_job.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "dynamap/input/fixed_pose.h"
#include "dynamap/input/open_source.h"
#include "dynamap/input/read_ahead.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/outputs/output_staging.h"
#include "dynamap/outputs/render.h"
#include "dynamap/outputs/run_outputs.h"
#include "dynamap/outputs/tables.h"

namespace dynamap {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The overlay as it is after scan `scan_index`, with the objects present then.
void writeFrame(const std::string& dir, const Mapper& mapper, std::size_t scan_index) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.png", scan_index);
  // The people of this scan, each with the trail that brought them here.
  std::vector<PersonTrail> trails;
  const std::vector<PersonTrail> all = mapper.people().trails();
  for (const PersonRow& p : mapper.people().reported()) {
    trails.push_back(all[static_cast<std::size_t>(p.person_id - 1)]);
  }
  saveImageAtomically(renderOverlay(mapper.map(), mapper.path(), &mapper.tracker().objects(), &trails), dir,
                      name);
}

// Frames into timelapse.mp4 when ffmpeg is on PATH; a note on stderr otherwise.
void writeTimelapse(const std::string& out_dir, const std::string& frames_dir) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
    std::cerr << "dynamap map: ffmpeg not found, timelapse.mp4 skipped (frames are in "
              << frames_dir << "/)\n";
    return;
  }
  // Frames differ in size when the map grew: pad each to the last (largest) one's size.
  const std::string tmp = out_dir + "/.tmp-timelapse.mp4";
  const std::string cmd =
      "ffmpeg -loglevel error -y -framerate 10 -pattern_type glob -i '" + frames_dir +
      "/*.png' -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p '" + tmp +
      "' && mv '" + tmp + "' '" + out_dir + "/timelapse.mp4'";
  if (std::system(cmd.c_str()) != 0) {
    std::cerr << "dynamap map: warning: ffmpeg failed, timelapse.mp4 not written\n";
  }
}

// What runs beside the mapper for each scan: the streamed files, the baseline, the frames.
struct Writers {
  Writers(const MapJob& job, const std::string& dir)
      : tracks(dir), people(dir), poses(dir), frames_dir(dir + "/frames") {
    if (job.baseline) baseline = std::make_unique<PlainGrid>(job.config.map, job.config.insertion);
    if (job.frames_every > 0) prepareOutputDir(frames_dir);
  }
  TrackLog tracks;  // streamed: rows are never kept in memory
  PeopleLog people;
  PoseLog poses;
  std::unique_ptr<PlainGrid> baseline;
  Clock::duration baseline_time{};
  std::string frames_dir;
};

void afterScan(const MapJob& job, const Mapper& mapper, Writers& w, const ScanRecord& rec,
               const ScanResult& result) {
  // The baseline sees exactly the scans the mapper inserted, at the pose it used (rec's, after
  // scan matching): a scan the mapper skipped (a pose past max_map_size_m, no usable beam) is
  // skipped by both, so the two maps compare like with like and a file bounds both alike.
  if (w.baseline && result.inserted) {  // timed on its own, so both speeds can be reported
    const auto t0 = Clock::now();
    w.baseline->insert(*rec.scan, rec.pose);
    w.baseline_time += Clock::now() - t0;
  }
  w.tracks.append(rec.index, rec.t, mapper.tracker());
  w.people.append(rec.index, rec.t, mapper.people());
  w.poses.append(rec.t, rec.pose);
  if (job.frames_every > 0 && rec.index % static_cast<std::size_t>(job.frames_every) == 0) {
    writeFrame(w.frames_dir, mapper, rec.index);
  }
}

void stopIfCancelled(const MapJob& job) {
  if (job.cancelled && job.cancelled()) throw RunCancelled("the run was interrupted");
}

/// How the job's log is read, whatever the pose source: the format options and [input]'s.
InputOptions inputOptions(const MapJob& job) {
  InputOptions input;
  input.carmen = job.carmen;
  input.carmen.odometry = job.config.carmen_odometry;
  input.pose_track.max_gap = job.config.pose_max_gap;
  input.bag = job.bag;
  return input;
}

/// Pose source slam, pass 1: the whole trajectory (tied to `prior`'s frame when given: an
/// earlier session's S, `source` already moved to start where it was found there), then
/// `source` replaced by pass 2's (the log opened again, each scan's pose the optimised one).
std::unique_ptr<SlamRun> slamPass(const MapJob& job, const MapConfig& config,
                                  std::unique_ptr<ScanSource>& source,
                                  const mrpt::maps::COccupancyGridMap2D* prior) {
  if (job.on_pass) job.on_pass(1);
  ScanSource& first = *source;
  auto run = std::make_unique<SlamRun>(estimateTrajectory(
      first, config,
      [&](std::size_t done) {
        stopIfCancelled(job);
        if (job.progress) job.progress(first.fractionRead(), done);
      },
      prior));
  InputOptions input = inputOptions(job);  // the log read again the same way
  input.poses = PoseSource::Slam;
  source = readAhead(
      std::make_unique<OptimisedPoseSource>(openScanSource(job.input, input), run->poses));
  if (job.on_pass) job.on_pass(2);
  return run;
}

/// Poses that start in the log's own frame, not in a map's: a prior's frame must be found.
bool odometryBased(PoseSource p) {
  return p == PoseSource::Odometry || p == PoseSource::ScanMatching || p == PoseSource::Slam;
}

/// `source` moved to start where --initial-pose says, or, with a prior (`prior_map`: its S) and
/// poses in the log's own frame, where the search places its first scans in it (returned).
std::optional<GlobalPlacement> startInPrior(const MapJob& job, const InputOptions& input,
                                            const MapConfig& config,
                                            const mrpt::maps::COccupancyGridMap2D* prior_map,
                                            std::unique_ptr<ScanSource>& source) {
  if (job.initial_pose) {
    source = startingAt(std::move(source), *job.initial_pose);
    return std::nullopt;
  }
  if (!prior_map || !odometryBased(source->poseSource())) return std::nullopt;
  auto probe = openScanSource(job.input, input);  // the log's first scans, read again
  const GlobalPlacement placed = locateStart(*probe, *prior_map, config.insertion, job.input);
  source = startingAt(std::move(source), placed.pose);
  return placed;
}

/// The prior session's state, read before any work; an error names the file.
std::optional<SessionState> readPrior(const MapJob& job) {
  if (job.prior.empty()) return std::nullopt;
  const double side = std::ceil(maxGridSide(job.config.map) / job.config.map.resolution) + 1;
  return readSessionState(job.prior, static_cast<std::uint64_t>(side * side));
}

/// `mapper` continuing the prior session; an error names the prior's file.
void continuePrior(const MapJob& job, SessionState prior, Mapper& mapper) {
  try {
    mapper.continueFrom(std::move(prior));
  } catch (const std::invalid_argument& e) {
    throw InputError(job.prior + ": the prior session's map does not fit this run: " + e.what());
  }
}

// The run with every output written into `stage`, committed at the end.
MapJobResult runStaged(const MapJob& job, OutputStaging& stage) {
  const std::string& dir = stage.path();
  std::optional<SessionState> prior = readPrior(job);
  InputOptions input = inputOptions(job);
  input.poses = job.config.poses;
  input.fixed_pose = job.config.fixed_pose;
  // Read beside the mapping, on the second core: the same scans in the same order.
  auto source = readAhead(openScanSource(job.input, input));
  MapConfig config = job.config;
  const bool slam_pass = usesSlam(config.poses, *source);
  if (slam_pass) config.poses = PoseSource::Slam;  // config.ini says what ran
  Mapper mapper(config);
  if (prior) continuePrior(job, std::move(*prior), mapper);
  // Before the first scan the mapper's S is the prior's: the start is searched for there.
  // Slam's pass 1 reads the log from there, and is tied to the prior's frame.
  const std::optional<GlobalPlacement> placed =
      startInPrior(job, input, config, prior ? &mapper.map() : nullptr, source);
  std::unique_ptr<SlamRun> slam;
  if (slam_pass) slam = slamPass(job, config, source, prior ? &mapper.map() : nullptr);
  Writers w(job, dir);
  const auto start = Clock::now();
  MapJobResult r;
  r.start = placed;
  r.outcome = runMapping(*source, mapper, [&](const ScanRecord& rec, const ScanResult& result) {
    stopIfCancelled(job);
    afterScan(job, mapper, w, rec, result);
    if (job.progress) job.progress(source->fractionRead(), mapper.counts().scans_used);
  });
  mapper.finishSession();
  w.tracks.finish();
  w.people.finish();
  w.poses.finish();
  if (slam && r.outcome.fault.empty()) r.outcome.fault = slam->outcome.fault;  // pass 1 ended there
  r.baseline_wall_s = std::chrono::duration<double>(w.baseline_time).count();
  r.wall_s = secondsSince(start) - r.baseline_wall_s;
  if (job.on_mapped) job.on_mapped(mapper);
  if (w.baseline) r.baseline = comparePlain(mapper.map(), w.baseline->grid());
  writeMapOutputs(dir, mapper, *source,
                  {job.input, r.wall_s, r.outcome, w.baseline.get(), r.baseline_wall_s,
                   r.baseline.value_or(PlainComparison{}), slam.get()});
  if (job.frames_every > 0) writeTimelapse(dir, w.frames_dir);
  stopIfCancelled(job);  // a signal while the files were written: keep the previous set
  stage.commit();
  r.pose_source = mapper.poseSourceName(*source);
  r.pose_detail = source->poseDetail();
  r.counts = mapper.counts();
  r.source_stats = source->stats();
  r.scan_matching = mapper.scanMatching();
  r.scan_match_counts = mapper.scanMatchCounts();
  if (slam) {
    r.slam = slam->slam->stats();
    r.slam_wall_s = slam->wall_s;
    if (job.on_pass) job.on_pass(0);
  }
  return r;
}

}  // namespace

MapJobResult runMapJob(const MapJob& job) {
  // Before any work: an unwritable or busy directory fails fast. Every output goes into the
  // staging directory and replaces the previous run's set only once all are written.
  OutputStaging stage(job.out_dir);
  try {
    return runStaged(job, stage);
  } catch (const RunCancelled&) {
    throw;
  } catch (const InputError&) {
    throw;
  } catch (const ConfigError&) {
    throw;
  } catch (const std::runtime_error& e) {
    // A write error names the staging directory, which is gone: name the file as the user
    // knows it.
    std::string m = e.what();
    for (auto at = m.find(stage.path()); at != std::string::npos; at = m.find(stage.path())) {
      m.replace(at, stage.path().size(), job.out_dir);
    }
    throw std::runtime_error(m);
  }
}

}  // namespace dynamap
