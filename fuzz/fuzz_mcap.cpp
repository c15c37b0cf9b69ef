// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_mcap -max_total_time=600 -max_len=65536 build-fuzz/corpus/mcap fuzz/seeds/mcap
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::mcapInput(data, size);
  return 0;
}
