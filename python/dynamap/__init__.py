"""dynamap from Python: map a log as `dynamap map` does and get S, D, the poses and the tables
as numpy arrays and tables (docs/python.md); map scan by scan with Mapper; map a fleet's logs on
a Dask cluster with `python3 -m dynamap.batch`."""

from ._map import MapResult, map
from ._stream import Mapper, scans
from ._tables import read_table
from .errors import ConfigError, DynamapWarning, Error, InputError, UsageError
from ._core import load_gridmap

__all__ = ["map", "MapResult", "Mapper", "scans", "read_table", "load_gridmap", "Error",
           "UsageError", "ConfigError", "InputError", "DynamapWarning"]
