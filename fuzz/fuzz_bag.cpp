// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_bag -max_total_time=3600 -max_len=65536 build-fuzz/corpus/bag fuzz/seeds/bag
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::bagInput(data, size);
  return 0;
}
