// dynamap._core: the C++ side of the Python module. run_map() runs the very job `dynamap map`
// runs, from the same command line (parseMapJob), with the GIL released; it hands back S and D
// as copied in memory from the mapper the output files are written from. Errors become the
// exceptions of dynamap.errors carrying the line the command prints.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/serialization/CArchive.h>

#include <atomic>
#include <string>
#include <vector>

#include "dynamap/base/ini.h"
#include "dynamap/base/printable.h"
#include "map_command.h"
#include "py_grid.h"

namespace py = pybind11;

namespace dynamap::python {

namespace {

/// A failure of run_map as the command would report it: its kind picks the Python exception.
struct MapFailure {
  std::string kind;  // a class name of dynamap.errors
  std::string message;
  int exit_status;
};

/// The job, run with the GIL released. Python's signal handlers (Ctrl-C) are run every few
/// scans, with the GIL held for just that moment; a pending KeyboardInterrupt ends the run as
/// a signal ends the command: the output directory as it was.
MapJobResult runReleased(MapJob& job, bool& interrupted) {
  std::atomic<unsigned> calls{0};
  job.cancelled = [&] {
    if (interrupted) return true;
    if (++calls % 32 != 0) return false;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();  // raised again, as KeyboardInterrupt, once the run has unwound
      interrupted = true;
    }
    return interrupted;
  };
  py::gil_scoped_release release;
  return runMapJob(job);
}

MapJobResult runOrFail(MapJob& job) {
  bool interrupted = false;
  try {
    return runReleased(job, interrupted);
  } catch (const RunCancelled&) {
    throw MapFailure{"KeyboardInterrupt", job.out_dir + " keeps the outputs it had", 130};
  } catch (const app::UsageError& e) {
    throw MapFailure{"UsageError",
                     "dynamap map: " + printable(e.what()) + " (see dynamap map --help)", 2};
  } catch (const ConfigError& e) {
    throw MapFailure{"ConfigError", "dynamap map: " + printable(e.what()), 3};
  } catch (const InputError& e) {
    throw MapFailure{"InputError", "dynamap map: " + printable(e.what()), 1};
  } catch (const std::exception& e) {
    throw MapFailure{"Error", "dynamap map: " + printable(e.what()), 1};
  }
}

// A job from the command line, with the command's error for a bad one.
bool parseOrFail(const app::Args& args, MapJob& job, bool& verbose) {
  try {
    return app::parseMapJob(args, job, verbose);
  } catch (const app::UsageError& e) {
    throw MapFailure{"UsageError",
                     "dynamap map: " + printable(e.what()) + " (see dynamap map --help)", 2};
  } catch (const ConfigError& e) {
    throw MapFailure{"ConfigError", "dynamap map: " + printable(e.what()), 3};
  } catch (const std::exception& e) {
    throw MapFailure{"Error", "dynamap map: " + printable(e.what()), 1};
  }
}

/// `dynamap map ARGS` (ARGS without the word map): the run's facts and S and D, or None after
/// --help.
py::object runMap(const std::vector<std::string>& args) {
  MapJob job;
  bool verbose = false;
  if (!parseOrFail(args, job, verbose)) return py::none();
  Grid s, d;
  job.on_mapped = [&](const Mapper& mapper) {
    s = staticGrid(mapper.map());
    d = dynamicGrid(mapper.map());
  };
  const MapJobResult r = runOrFail(job);
  py::dict out;
  out["static"] = toArray(s);
  out["dynamic"] = toArray(d);
  out["origin"] = py::make_tuple(s.x_min, s.y_min);
  out["resolution"] = s.resolution;
  out["pose_source"] = r.pose_source;
  out["pose_detail"] = r.pose_detail;
  out["scans_used"] = r.counts.scans_used;
  out["fault"] = r.outcome.fault;
  out["warnings"] = app::mapWarnings(r);
  out["wall_s"] = r.wall_s;
  out["out"] = job.out_dir;
  return std::move(out);
}

/// An MRPT grid file (static.gridmap.gz, dynamic.gridmap.gz) as run_map returns a map.
py::dict loadGridmap(const std::string& path) {
  mrpt::maps::COccupancyGridMap2D grid;
  {
    mrpt::io::CFileGZInputStream in;
    if (!in.open(path)) throw std::runtime_error(path + ": cannot open");
    mrpt::serialization::archiveFrom(in) >> grid;
  }
  const Grid g = gridOf(grid, grid.getRawMap());
  py::dict out;
  out["map"] = toArray(g);
  out["origin"] = py::make_tuple(g.x_min, g.y_min);
  out["resolution"] = g.resolution;
  return out;
}

void translateFailure(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const MapFailure& f) {
    if (f.kind == "KeyboardInterrupt") {
      PyErr_SetString(PyExc_KeyboardInterrupt, f.message.c_str());
      return;
    }
    py::object cls = py::module_::import("dynamap.errors").attr(f.kind.c_str());
    py::object e = cls(f.message);
    e.attr("exit_status") = f.exit_status;
    PyErr_SetObject(cls.ptr(), e.ptr());
  } catch (const ConfigError& e) {  // the streaming side's (Mapper, ScanReader)
    PyErr_SetString(py::module_::import("dynamap.errors").attr("ConfigError").ptr(), e.what());
  } catch (const InputError& e) {
    PyErr_SetString(py::module_::import("dynamap.errors").attr("InputError").ptr(), e.what());
  }
}

}  // namespace

void defineStream(py::module_& m);  // stream.cpp

}  // namespace dynamap::python

PYBIND11_MODULE(_core, m) {
  using namespace dynamap::python;
  m.doc() = "dynamap's C++ core (use the dynamap package, not this module)";
  py::register_exception_translator(&translateFailure);
  m.def("run_map", &runMap, py::arg("args"),
        "dynamap map ARGS: the run's facts and S and D (P(occupied), rows of increasing y)");
  m.def("load_gridmap", &loadGridmap, py::arg("path"),
        "an MRPT .gridmap.gz as P(occupied), its origin and resolution");
  defineStream(m);
}
