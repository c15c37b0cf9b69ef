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
/// A ROS bag read by openScanSource to its end, with the poses it offers and with a fixed pose,
/// every scan through the mapper (rosbag's index, or the salvage of a bag without one).
void bagInput(const std::uint8_t* data, std::size_t size);

}  // namespace dynamap::fuzz
