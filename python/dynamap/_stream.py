"""Mapping one scan at a time, for users with a reader of their own."""

import os

from . import _core
from ._tables import parse_table, table_of_rows


class Mapper:
    """The per-scan step of `dynamap map` (people, S and D, the object table), fed one scan at
    a time. config: an .ini file (None: the built-in defaults); its [input] section is unused
    (each scan comes with its pose).

    >>> m = dynamap.Mapper()
    >>> m.add(ranges, angles, pose=(x, y, phi), t=stamp)
    >>> m.static, m.objects
    """

    def __init__(self, config=None):
        self._m = _core.Mapper(None if config is None else os.fspath(config))

    def add(self, ranges, angles, pose, t=None, *, max_range=80.0, mount=(0.0, 0.0, 0.0),
            valid=None):
        """Maps one scan; True when it was inserted (False: skipped, see counts).

        ranges [m] and angles [rad] (the beams' directions in the laser's frame, evenly spaced,
        either way round): one per beam. pose: the robot's (x [m], y [m], phi [rad]) in the map
        frame. t [s]: the scan's time (default: 0.1 s times the scan's number; the people
        tracker's speeds use it). max_range [m]: the laser's; a range at or above it, not
        finite or not positive is no return, unless valid (one bool per beam) says which are.
        mount: the laser's (x, y, phi) on the robot. ValueError for a malformed scan. The GIL
        is released while the scan is mapped.
        """
        return self._m.add(ranges, angles, tuple(pose), t, max_range, tuple(mount), valid)

    @property
    def static(self):
        """S: P(occupied) per cell, rows of increasing y (as MapResult.static)."""
        return self._m.grid(False)["map"]

    @property
    def dynamic(self):
        """D: P(occupied) per cell, S's geometry."""
        return self._m.grid(True)["map"]

    @property
    def origin(self):
        return tuple(self._m.grid(False)["origin"])

    @property
    def resolution(self):
        return self._m.grid(False)["resolution"]

    @property
    def objects(self):
        """The object table so far (objects.csv's columns)."""
        return parse_table(self._m.table("objects"))

    @property
    def events(self):
        """The object events so far (events.csv's columns)."""
        return parse_table(self._m.table("events"))

    @property
    def people(self):
        """The people tracked at the last scan (person_id, x, y, vx, vy)."""
        return table_of_rows(("person_id", "x", "y", "vx", "vy"), self._m.people())

    @property
    def counts(self):
        """Scans used, skipped (by reason) and bad beams so far."""
        return self._m.counts()


def scans(input, poses="auto"):
    """The scans of a log as `dynamap map` reads them (without the pass of poses slam): an
    iterator of dicts with index, t, pose, ranges, angles, valid, max_range and mount, each
    ready for Mapper.add(**...) but index."""
    return _core.ScanReader(os.fspath(input), poses)
