#pragma once
// Structure-aware mutators for the fuzzers (libFuzzer's LLVMFuzzerCustomMutator). Flipping bytes
// rarely makes an offset or a length lie while the rest of the file stays whole, and the readers'
// worst faults need exactly that: an index entry pointing outside its chunk, a record length past
// the bytes left, a count no record holds. These mutators know the records of a format, and
//  - make one stated number lie against what holds it (near its bound, past it, all ones), or
//  - change a record's content and restate every length, offset and position that depends on it,
//    so that the file stays consistent and the change reaches the parser behind them.
// Each returns the new size (<= max_size); 0 when the input has no structure it knows (the caller
// then mutates bytes). Deterministic for a given seed.

#include <cstddef>
#include <cstdint>

namespace dynamap::fuzz {

/// A ROS 1 bag: index entries' offsets (another message of the chunk, a connection record, the
/// chunk's end, past it), record header and data lengths (top level and inside uncompressed
/// chunks), chunk sizes, connection ids, counts, chunk_pos and index_pos; or a message of an
/// uncompressed chunk grown or shrunk with its data length, its chunk's size, the index offsets
/// after it and every later position restated.
std::size_t mutateBag(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed);

/// An MRPT rawlog, record by record: the beam count of a scan restated with its beams (more,
/// fewer, none) or made to lie against the beams that follow; string and vector lengths made to
/// lie; ranges, aperture, poses and stamps set to what no sensor measures; whole records dropped,
/// repeated or swapped.
std::size_t mutateRawlog(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed);

}  // namespace dynamap::fuzz
