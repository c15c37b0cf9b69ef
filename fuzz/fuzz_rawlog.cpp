// libFuzzer target: see fuzz_entries.h. Run with make fuzz, or directly:
//   build-fuzz/fuzz_rawlog -max_total_time=3600 build-fuzz/corpus/rawlog fuzz/seeds/rawlog
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"
#include "structure_mutators.h"

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamap::fuzz::rawlogInput(data, size);
  return 0;
}

// Two mutations in three know the records (structure_mutators.h); the rest, and any the input
// gives no structure for, are libFuzzer's own byte mutations.
extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  if (seed % 3 != 0) {
    if (const std::size_t n = dynamap::fuzz::mutateRawlog(data, size, max_size, seed / 3)) return n;
  }
  return LLVMFuzzerMutate(data, size, max_size);
}
