#include "dynamap/outputs/map_outputs.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace dynamap {
namespace fs = std::filesystem;

std::string tempName(const std::string& dir, const std::string& name) {
  // Keep the extension: image and gz writers choose their format by it.
  return (fs::path(dir) / (".tmp-" + name)).string();
}

void commit(const std::string& tmp, const std::string& dir, const std::string& name) {
  std::error_code ec;
  fs::rename(tmp, fs::path(dir) / name, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error((fs::path(dir) / name).string() + ": cannot write (" + ec.message() +
                             ")");
  }
}

void writeFileAtomically(const std::string& dir, const std::string& name,
                         const std::function<void(std::ostream&)>& write) {
  const std::string tmp = tempName(dir, name);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw std::runtime_error((fs::path(dir) / name).string() + ": cannot write (" +
                               std::strerror(errno) + ")");
    }
    try {
      write(out);
    } catch (...) {  // a writer that fails leaves no temporary behind
      out.close();
      std::error_code ec;
      fs::remove(tmp, ec);
      throw;
    }
    out.flush();
    if (!out) {
      const int err = errno;  // ENOSPC on a full disk
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error((fs::path(dir) / name).string() + ": write failed (" +
                               std::strerror(err) + ")");
    }
  }
  commit(tmp, dir, name);
}

void saveImageAtomically(const mrpt::img::CImage& img, const std::string& dir,
                         const std::string& name) {
  const std::string tmp = tempName(dir, name);
  if (!img.saveToFile(tmp)) {
    throw std::runtime_error((fs::path(dir) / name).string() + ": cannot write image");
  }
  commit(tmp, dir, name);
}

namespace {

void saveGrid(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& dir,
              const std::string& name) {
  const std::string tmp = tempName(dir, name);
  {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(tmp))
      throw std::runtime_error((fs::path(dir) / name).string() + ": cannot write");
    mrpt::serialization::archiveFrom(out) << grid;
  }
  commit(tmp, dir, name);
}

// A plain MRPT grid holding D's cells, so any MRPT tool can load the dynamic map too.
struct DynamicLayerGrid : mrpt::maps::COccupancyGridMap2D {
  explicit DynamicLayerGrid(const DynamicGridMap& map)
      : COccupancyGridMap2D(map.getXMin(), map.getXMax(), map.getYMin(), map.getYMax(),
                            map.getResolution()) {
    m_map = map.dynamicRaw();
    m_is_empty = false;
  }
};

}  // namespace

void writeGridmap(const DynamicGridMap& map, const std::string& dir, const std::string& name) {
  // Serialised as the base class: what MRPT loads back is the static map S.
  saveGrid(map, dir, name);
}

void writeDynamicGridmap(const DynamicGridMap& map, const std::string& dir,
                         const std::string& name) {
  saveGrid(DynamicLayerGrid(map), dir, name);
}

void writeRosMap(const DynamicGridMap& map, const std::string& dir, const std::string& stem) {
  const unsigned sx = map.getSizeX(), sy = map.getSizeY();
  writeFileAtomically(dir, stem + ".pgm", [&](std::ostream& out) {
    out << "P5\n# dynamap static map\n" << sx << " " << sy << "\n255\n";
    std::string row(sx, '\0');
    for (unsigned r = 0; r < sy; ++r) {
      const unsigned cy = sy - 1 - r;  // PGM's first row is the map's top (largest y)
      for (unsigned cx = 0; cx < sx; ++cx) {
        row[cx] = static_cast<char>(
            DynamicGridMap::cellGrey(map.getRawMap()[cx + static_cast<std::size_t>(cy) * sx]));
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
  });
  writeFileAtomically(dir, stem + ".yaml", [&](std::ostream& out) {
    out << std::setprecision(9) << "image: " << stem << ".pgm\n"
        << "mode: trinary\n"
        << "resolution: " << map.getResolution() << "\n"
        << "origin: [" << map.getXMin() << ", " << map.getYMin() << ", 0.0]\n"
        << "negate: 0\n"
        << "occupied_thresh: 0.65\n"
        << "free_thresh: 0.196\n";
  });
}

void prepareOutputDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw std::runtime_error(dir + ": cannot create output directory" +
                             (ec ? " (" + ec.message() + ")" : std::string()));
  }
  const std::string probe = tempName(dir, "probe");
  {
    std::ofstream out(probe);
    if (!out) throw std::runtime_error(dir + ": output directory is not writable");
  }
  fs::remove(probe, ec);
}

}  // namespace dynamap
