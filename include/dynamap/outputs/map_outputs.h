#pragma once
// Writers of `dynamap map`'s output files. Every file is written under a temporary name in the
// same directory and renamed when complete, so an interrupted run never leaves a half-written
// file under a final name.

#include <functional>
#include <iosfwd>
#include <string>

#include "dynamap/mapping/dynamic_grid_map.h"

namespace mrpt::img {
class CImage;
}

namespace dynamap {

/// The temporary path `dir/name` is written under before commit() gives it its final name
/// (same directory, same extension).
std::string tempName(const std::string& dir, const std::string& name);
/// Renames `tmp` to `dir/name`; on failure removes `tmp` and throws naming the final file.
void commit(const std::string& tmp, const std::string& dir, const std::string& name);

/// Writes `dir/name` through `write` (text or binary stream), atomically. Throws on I/O errors.
void writeFileAtomically(const std::string& dir, const std::string& name,
                         const std::function<void(std::ostream&)>& write);
/// Saves an image as `dir/name` (PNG by extension), atomically.
void saveImageAtomically(const mrpt::img::CImage& img, const std::string& dir,
                         const std::string& name);
/// S as an MRPT gridmap (gz-compressed COccupancyGridMap2D, loadable by any MRPT tool).
void writeGridmap(const DynamicGridMap& map, const std::string& dir, const std::string& name);
/// D as an MRPT gridmap of the same geometry: its getCell() is D's P(free), so an object cell
/// reads below 1 - object_threshold.
void writeDynamicGridmap(const DynamicGridMap& map, const std::string& dir,
                         const std::string& name);
/// S as a ROS map_server map: `<stem>.pgm` (P(free) in grey levels) and `<stem>.yaml`.
void writeRosMap(const DynamicGridMap& map, const std::string& dir, const std::string& stem);

/// Creates `dir` (and parents) if needed and checks that a file can be written in it.
/// Throws std::runtime_error naming the directory otherwise.
void prepareOutputDir(const std::string& dir);

}  // namespace dynamap
