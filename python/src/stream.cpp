// dynamap._core's streaming side: Mapper, the per-scan step of `dynamap map` fed one scan at a
// time by a reader of the user's own, and ScanReader, dynamap's own readers as an iterator of
// the same scans (what `dynamap map` would map, with their poses).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "dynamap/base/ini.h"
#include "dynamap/input/open_source.h"
#include "dynamap/outputs/tables.h"
#include "dynamap/pipeline/mapper.h"
#include "py_grid.h"

namespace py = pybind11;

namespace dynamap::python {
namespace {

using Pose = std::tuple<double, double, double>;  // x [m], y [m], phi [rad]

/// The beams' directions in the sensor frame must be evenly spaced (MRPT spreads a scan's beams
/// evenly over its aperture): the aperture, its direction of sweep and its centre.
struct Fan {
  double aperture = 0, centre = 0;
  bool right_to_left = true;
};

Fan fanOf(const double* a, std::size_t n) {
  if (n == 0) throw py::value_error("a scan needs at least one beam");
  Fan f;
  f.centre = n == 1 ? a[0] : (a[0] + a[n - 1]) / 2;
  if (n == 1) return f;
  const double step = (a[n - 1] - a[0]) / static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double want = a[0] + step * static_cast<double>(i);
    if (!std::isfinite(a[i]) || std::abs(a[i] - want) > 1e-5)
      throw py::value_error("angles: beam " + std::to_string(i) + " is not evenly spaced (" +
                            std::to_string(a[i]) + " rad, expected " + std::to_string(want) + ")");
  }
  f.aperture = std::abs(a[n - 1] - a[0]);
  f.right_to_left = a[n - 1] >= a[0];
  return f;
}

mrpt::obs::CObservation2DRangeScan::Ptr makeScan(const py::array_t<float>& ranges,
                                                 const py::array_t<double>& angles, double t,
                                                 float max_range, const Pose& mount,
                                                 const std::optional<py::array_t<bool>>& valid) {
  const std::size_t n = static_cast<std::size_t>(ranges.size());
  if (static_cast<std::size_t>(angles.size()) != n)
    throw py::value_error("ranges and angles differ in length (" + std::to_string(n) + " and " +
                          std::to_string(angles.size()) + ")");
  if (valid && static_cast<std::size_t>(valid->size()) != n)
    throw py::value_error("valid and ranges differ in length");
  if (!(max_range > 0)) throw py::value_error("max_range must be positive");
  const Fan fan = fanOf(angles.data(), n);
  auto scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  scan->sensorLabel = "LASER";
  scan->timestamp = mrpt::Clock::fromDouble(t);
  scan->aperture = static_cast<float>(fan.aperture);
  scan->rightToLeft = fan.right_to_left;
  scan->maxRange = max_range;
  scan->sensorPose = mrpt::poses::CPose3D(
      mrpt::poses::CPose2D(std::get<0>(mount), std::get<1>(mount), std::get<2>(mount) + fan.centre));
  std::vector<char> ok(n);
  const float* r = ranges.data();
  for (std::size_t i = 0; i < n; ++i) {
    ok[i] = valid ? valid->data()[i] : (std::isfinite(r[i]) && r[i] > 0 && r[i] < max_range);
  }
  scan->loadFromVectors(n, r, ok.data());
  return scan;
}

MapConfig loadConfig(const std::optional<std::string>& path) {
  if (!path) return MapConfig{};
  return MapConfig::load(IniFile::fromFile(*path));  // ConfigError: dynamap.errors.ConfigError
}

class StreamMapper {
 public:
  explicit StreamMapper(const std::optional<std::string>& config) : mapper_(loadConfig(config)) {}

  bool add(const py::array_t<float, py::array::c_style | py::array::forcecast>& ranges,
           const py::array_t<double, py::array::c_style | py::array::forcecast>& angles,
           const Pose& pose, std::optional<double> t, float max_range, const Pose& mount,
           const std::optional<py::array_t<bool, py::array::c_style | py::array::forcecast>>&
               valid) {
    ScanRecord rec;
    rec.index = next_index_++;
    rec.t = t ? *t : 0.1 * static_cast<double>(rec.index);
    rec.pose = mrpt::poses::CPose2D(std::get<0>(pose), std::get<1>(pose), std::get<2>(pose));
    rec.scan = makeScan(ranges, angles, rec.t, max_range, mount, valid);
    py::gil_scoped_release release;
    return mapper_.process(rec).inserted;
  }

  py::dict grid(bool dynamic) const {
    const Grid g = dynamic ? dynamicGrid(mapper_.map()) : staticGrid(mapper_.map());
    py::dict out;
    out["map"] = toArray(g);
    out["origin"] = py::make_tuple(g.x_min, g.y_min);
    out["resolution"] = g.resolution;
    return out;
  }

  std::string table(const std::string& name) const {
    std::ostringstream o;
    if (name == "objects") writeObjectsCsv(o, mapper_.tracker());
    if (name == "events") writeEventsCsv(o, mapper_.tracker());
    return o.str();
  }

  std::vector<std::tuple<int, double, double, double, double>> people() const {
    std::vector<std::tuple<int, double, double, double, double>> rows;
    for (const PersonRow& p : mapper_.people().reported())
      rows.emplace_back(p.person_id, p.x, p.y, p.vx, p.vy);
    return rows;
  }

  const RunCounts& counts() const { return mapper_.counts(); }

 private:
  Mapper mapper_;
  std::size_t next_index_ = 0;
};

/// A log's scans, read as `dynamap map` reads them (no slam pass).
class ScanReader {
 public:
  ScanReader(const std::string& path, const std::string& poses) {
    InputOptions options;
    options.poses = parsePoseSource(poses);
    source_ = openScanSource(path, options);
  }

  py::dict next() {
    ScanRecord rec;
    bool more = false;
    {
      py::gil_scoped_release release;
      more = source_->next(rec);
    }
    if (!more) throw py::stop_iteration();
    const auto& s = *rec.scan;
    const std::size_t n = s.getScanSize();
    py::array_t<float> ranges(n);
    py::array_t<bool> valid(n);
    py::array_t<double> angles(n);
    const double step = n > 1 ? s.aperture / static_cast<double>(n - 1) : 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      ranges.mutable_data()[i] = s.getScanRange(i);
      valid.mutable_data()[i] = s.getScanRangeValidity(i);
      // The last beam exactly at +aperture/2, so that Mapper.add finds the same fan again.
      const double a = n == 1       ? 0.0
                       : i + 1 == n ? s.aperture / 2.0
                                    : -s.aperture / 2.0 + step * static_cast<double>(i);
      angles.mutable_data()[i] = s.rightToLeft ? a : -a;
    }
    py::dict d;
    d["index"] = rec.index;
    d["t"] = rec.t;
    d["pose"] = py::make_tuple(rec.pose.x(), rec.pose.y(), rec.pose.phi());
    d["ranges"] = ranges;
    d["angles"] = angles;  // in the sensor frame; the mount's phi turns them
    d["valid"] = valid;
    d["max_range"] = s.maxRange;
    d["mount"] = py::make_tuple(s.sensorPose.x(), s.sensorPose.y(), s.sensorPose.yaw());
    return d;
  }

 private:
  std::unique_ptr<ScanSource> source_;
};

}  // namespace

void defineStream(py::module_& m) {
  py::class_<StreamMapper>(m, "Mapper")
      .def(py::init<const std::optional<std::string>&>(), py::arg("config") = py::none())
      .def("add", &StreamMapper::add, py::arg("ranges"), py::arg("angles"), py::arg("pose"),
           py::arg("t") = py::none(), py::arg("max_range") = 80.0f,
           py::arg("mount") = Pose{0, 0, 0}, py::arg("valid") = py::none())
      .def("grid", &StreamMapper::grid, py::arg("dynamic"))
      .def("table", &StreamMapper::table, py::arg("name"))
      .def("people", &StreamMapper::people)
      .def("counts", [](const StreamMapper& s) {
        py::dict d;
        d["used"] = s.counts().scans_used;
        d["skipped_by_reason"] = s.counts().scans_skipped;
        d["bad_beams"] = s.counts().beams_bad;
        return d;
      });
  py::class_<ScanReader>(m, "ScanReader")
      .def(py::init<const std::string&, const std::string&>(), py::arg("path"),
           py::arg("poses") = "auto")
      .def("__iter__", [](ScanReader& r) -> ScanReader& { return r; })
      .def("__next__", &ScanReader::next);
}

}  // namespace dynamap::python
