// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_session -max_total_time=3600 build-fuzz/corpus/session fuzz/seeds/session
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::sessionInput(data, size);
  return 0;
}
