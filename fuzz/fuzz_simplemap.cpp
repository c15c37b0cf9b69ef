// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_simplemap -max_total_time=3600 build-fuzz/corpus/simplemap fuzz/seeds/simplemap
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::simplemapInput(data, size);
  return 0;
}
