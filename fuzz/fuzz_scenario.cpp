// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_scenario -max_total_time=3600 build-fuzz/corpus/scenario fuzz/seeds/scenario
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::scenarioInput(data, size);
  return 0;
}
