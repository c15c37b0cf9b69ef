// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_db3 -max_total_time=600 -max_len=65536 build-fuzz/corpus/db3 fuzz/seeds/db3
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::db3Input(data, size);
  return 0;
}
