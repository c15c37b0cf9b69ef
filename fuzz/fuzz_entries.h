#pragma once
// The fuzzers' entry points: each feeds one input, as bytes, through one of dynamap's real
// parsing paths and returns normally whatever the bytes are. A fault in the input is expected
// (and swallowed as the caller of that path would handle it); a crash, a sanitizer report, a hang
// or an unbounded allocation is a bug. fuzz/fuzz_<name>.cpp wraps each for libFuzzer;
// tests/faults_test.cpp replays tests/fuzz_regressions/<name>/ through the same functions.

#include <cstddef>
#include <cstdint>

namespace dynamap::fuzz {

/// A scenario .ini: IniFile::fromText, then parseScenario.
void scenarioInput(const std::uint8_t* data, std::size_t size);
/// A CARMEN log (plain text) read by openCarmenSource to its end.
void carmenInput(const std::uint8_t* data, std::size_t size);
/// A rawlog read by openScanSource to its end, every scan through the mapper (objects on).
void rawlogInput(const std::uint8_t* data, std::size_t size);
/// A simplemap (either of MRPT's formats) read keyframe by keyframe as rawlogInput reads a rawlog.
void simplemapInput(const std::uint8_t* data, std::size_t size);
/// A ROS bag read by openScanSource to its end, with the poses it offers and with a fixed pose,
/// every scan through the mapper (rosbag's index, or the salvage of a bag without one).
void bagInput(const std::uint8_t* data, std::size_t size);
/// A ROS 2 MCAP file, and a rosbag2 .db3 file: as bagInput, and every message of the raw stream
/// decoded as each of the three message types dynamap reads (ros2_bag.h, cdr_messages.h).
void mcapInput(const std::uint8_t* data, std::size_t size);
void db3Input(const std::uint8_t* data, std::size_t size);

/// A log of any format (told by content, as `dynamap map` does) mapped with the plain MRPT
/// comparison grid beside the mapper: each scan the mapper inserted goes into the baseline at
/// the mapper's pose, as `dynamap map` feeds it, then the two grids are compared.
void baselineInput(const std::uint8_t* data, std::size_t size);
/// A `dynamap map` configuration: IniFile::fromText, MapConfig::load, and the loaded config
/// written back and loaded again (what config.ini of a run must survive).
void configInput(const std::uint8_t* data, std::size_t size);

/// A session.json (what `dynamap map --prior` reads): parseSessionState; a state it accepts
/// is continued by a mapper (Mapper::continueFrom), whose own state must write and read back.
void sessionInput(const std::uint8_t* data, std::size_t size);

}  // namespace dynamap::fuzz
