#include "fuzz_entries.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>

#include "dynamap/base/ini.h"
#include "dynamap/input/carmen_reader.h"
#include "dynamap/input/open_source.h"
#include "dynamap/input/session_state.h"
#include "dynamap/mapping/plain_grid.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/scenario.h"

#ifdef DYNAMAP_HAVE_ROSBAG
#include "dynamap/input/cdr_messages.h"
#include "dynamap/input/ros2_bag.h"
#endif

namespace dynamap::fuzz {
namespace {

/// The readers open files by name: one scratch file per process, rewritten for every input.
const std::string& scratchPath(const char* suffix) {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string t = std::string(tmp && *tmp ? tmp : "/tmp") + "/dynamap-fuzz-XXXXXX";
    if (!mkdtemp(t.data())) std::abort();
    return t;
  }();
  static std::string path;
  path = dir + "/input" + suffix;
  return path;
}

std::string writeScratch(const std::uint8_t* data, std::size_t size, const char* suffix) {
  const std::string path = scratchPath(suffix);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

void drain(ScanSource& source, Mapper* mapper) {
  ScanRecord rec;
  while (source.next(rec)) {
    if (mapper) mapper->process(rec);
  }
}

}  // namespace

void scenarioInput(const std::uint8_t* data, std::size_t size) {
  try {
    const IniFile ini =
        IniFile::fromText(std::string(reinterpret_cast<const char*>(data), size), "fuzz.ini");
    sim::parseScenario(ini, "/nonexistent-dir");
  } catch (const std::exception&) {
    // a bad scenario is reported, never a crash
  }
}

void carmenInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratch(data, size, ".log");
  for (const bool skip_bad_lines : {false, true}) {
    try {
      CarmenOptions options;
      options.skip_bad_lines = skip_bad_lines;
      auto source = openCarmenSource(path, PoseSource::Auto, options);
      drain(*source, nullptr);
    } catch (const std::exception&) {
    }
  }
}

/// A small map limit keeps every input's memory and time small; objects on, as `map` runs.
MapConfig fuzzMapConfig() {
  MapConfig config;
  config.map.resolution = 0.1;
  config.map.max_map_size_m = 40;
  return config;
}

/// The file written from the input, told by content and mapped to its end (or its fault).
void mapFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  const std::string path = writeScratch(data, size, suffix);
  const MapConfig config = fuzzMapConfig();
  try {
    auto source = openScanSource(path, PoseSource::Auto);
    Mapper mapper(config);
    drain(*source, &mapper);
  } catch (const std::exception&) {
  }
}

void rawlogInput(const std::uint8_t* data, std::size_t size) {
  mapFile(data, size, ".rawlog");
}

void simplemapInput(const std::uint8_t* data, std::size_t size) {
  mapFile(data, size, ".simplemap");
}

namespace {

/// A bag (ROS 1 or 2) mapped with the poses it offers, then with a fixed pose.
void mapBag(const std::string& path) {
  const MapConfig config = fuzzMapConfig();
  for (const PoseSource poses : {PoseSource::Auto, PoseSource::Fixed}) {
    try {
      InputOptions options;
      options.poses = poses;
      auto source = openScanSource(path, options);
      Mapper mapper(config);
      drain(*source, &mapper);
    } catch (const std::exception&) {
    }
  }
}

}  // namespace

void bagInput(const std::uint8_t* data, std::size_t size) {
  mapBag(writeScratch(data, size, ".bag"));
}

namespace {

/// Every message of a ROS 2 bag decoded as each type (most are not: decode says why).
void decodeEvery(const std::string& path) {
#ifdef DYNAMAP_HAVE_ROSBAG
  try {
    auto stream = ros2::openRos2Bag(path, {});
    stream->topics();
    stream = ros2::openRos2Bag(path, {});
    while (stream->next()) {
      sensor_msgs::LaserScan scan;
      tf2_msgs::TFMessage tf;
      nav_msgs::Odometry odom;
      for (int i = 0; i < 3; ++i) {
        try {
          if (i == 0) ros2::decode(stream->data(), stream->size(), scan);
          if (i == 1) ros2::decode(stream->data(), stream->size(), tf);
          if (i == 2) ros2::decode(stream->data(), stream->size(), odom);
        } catch (const std::runtime_error&) {
        }
      }
    }
  } catch (const std::exception&) {
  }
#else
  (void)path;
#endif
}

void ros2Input(const std::uint8_t* data, std::size_t size, const char* suffix) {
  const std::string path = writeScratch(data, size, suffix);
  decodeEvery(path);
  mapBag(path);
}

}  // namespace

void mcapInput(const std::uint8_t* data, std::size_t size) {
  ros2Input(data, size, ".mcap");
}

void db3Input(const std::uint8_t* data, std::size_t size) {
  ros2Input(data, size, ".db3");
}

void baselineInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratch(data, size, ".log");
  const MapConfig config = fuzzMapConfig();
  try {
    auto source = openScanSource(path, PoseSource::Auto);
    Mapper mapper(config);
    PlainGrid plain(config.map, config.insertion);
    runMapping(*source, mapper, [&](const ScanRecord& rec, const ScanResult& result) {
      if (result.inserted) plain.insert(*rec.scan, rec.pose);
    });
    comparePlain(mapper.map(), plain.grid());
  } catch (const std::exception&) {
  }
}

void configInput(const std::uint8_t* data, std::size_t size) {
  try {
    const IniFile ini =
        IniFile::fromText(std::string(reinterpret_cast<const char*>(data), size), "fuzz.ini");
    const MapConfig config = MapConfig::load(ini);
    std::ostringstream again;
    config.writeIni(again);
    // What a run writes as config.ini must load again: an error here is a bug, not bad input.
    MapConfig::load(IniFile::fromText(again.str(), "config.ini"));
  } catch (const ConfigError&) {
  }
}

void sessionInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::uint64_t kMaxCells = std::uint64_t{1} << 22;
  SessionState state;
  try {
    state = parseSessionState(std::string(reinterpret_cast<const char*>(data), size),
                              "fuzz.json", kMaxCells);
  } catch (const InputError&) {
    return;
  }
  Mapper mapper{MapConfig{}};
  try {
    mapper.continueFrom(state);
  } catch (const std::invalid_argument&) {
    return;  // a grid of another resolution: `dynamap map` says so
  }
  // What a run writes for the next session must read back: an error here is a bug.
  std::ostringstream again;
  writeSessionState(mapper.sessionState(), again);
  parseSessionState(again.str(), "session.json", kMaxCells);
}

}  // namespace dynamap::fuzz
