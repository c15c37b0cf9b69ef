"""dynamap.map(): the run of `dynamap map`, its maps and tables as Python objects."""

import json
import os
import shutil
import tempfile
import warnings

import numpy as np

from . import _core
from ._tables import read_table
from .errors import DynamapWarning

# Keyword arguments of map() and the `dynamap map` options they stand for.
_VALUE_OPTIONS = {
    "fixed_pose": "--fixed-pose",
    "frames_every": "--frames-every",
    "fov": "--fov",
    "carmen_odometry": "--carmen-odometry",
    "scan_topic": "--scan-topic",
    "odom_topic": "--odom-topic",
    "odom_frame": "--odom-frame",
    "base_frame": "--base-frame",
    "gt_frame": "--gt-frame",
    "prior": "--prior",
    "initial_pose": "--initial-pose",
}


class MapResult:
    """What one run made.

    static, dynamic: the static map S and the dynamic map D, P(occupied) per cell (float32),
        shape (rows, columns); row 0 is the cell row at the smallest y, column 0 at the
        smallest x: cell (row i, column j) covers x in origin[0] + [j, j + 1) * resolution and
        y in origin[1] + [i, i + 1) * resolution. Show them with origin="lower".
    origin: (x_min, y_min) [m] of the grid's corner; resolution: a cell's side [m].
    poses: N x 4 array (t [s], x [m], y [m], phi [rad]): the pose each scan was mapped at.
    objects, events, tracks, people: the run's tables (objects.csv, ...).
    changes: with prior=..., what changed since that session (changes.csv); else None.
    summary: summary.json as a dict. pose_source: the pose source used (never auto).
    fault: the fault the input ended in ("" when it was read to its end); warnings: what the
        command prints as warnings. out: the output directory (None when it was temporary).
    """

    def __init__(self, raw, out_dir, keep):
        self.static = raw["static"]
        self.dynamic = raw["dynamic"]
        self.origin = tuple(raw["origin"])
        self.resolution = raw["resolution"]
        self.pose_source = raw["pose_source"]
        self.fault = raw["fault"]
        self.warnings = list(raw["warnings"])
        with open(os.path.join(out_dir, "summary.json")) as f:
            self.summary = json.load(f)
        poses = np.loadtxt(os.path.join(out_dir, "poses.txt"), comments=("%", "#"), ndmin=2)
        self.poses = poses.reshape(-1, 4) if poses.size else np.zeros((0, 4))
        for name in ("objects", "events", "tracks", "people"):
            setattr(self, name, read_table(os.path.join(out_dir, name + ".csv")))
        changes = os.path.join(out_dir, "changes.csv")
        self.changes = read_table(changes) if os.path.exists(changes) else None
        self.out = out_dir if keep else None

    def __repr__(self):
        rows, cols = self.static.shape
        return (f"<dynamap.MapResult {len(self.poses)} scans ({self.pose_source} poses), "
                f"{rows}x{cols} cells of {self.resolution:.6g} m, {len(self.objects)} objects>")


def map_args(input, config=None, poses="auto", out=None, baseline=True, skip_bad_lines=False,
             **options):
    """The `dynamap map` command line (without the word map) of the same arguments as map()."""
    args = ["--input", os.fspath(input), "--out", os.fspath(out)]
    if config is not None:
        args += ["--config", os.fspath(config)]
    # "auto" is what the command does without --poses: the config's [input] poses, auto there.
    if poses is not None and (poses != "auto" or config is None):
        args += ["--poses", poses]
    if not baseline:
        args.append("--no-baseline")
    if skip_bad_lines:
        args.append("--skip-bad-lines")
    for key, value in options.items():
        if key not in _VALUE_OPTIONS:
            raise TypeError(f"map() got an unexpected keyword argument '{key}'")
        if value is None:
            continue
        if key == "prior":
            value = os.fspath(value)
        if key in ("fixed_pose", "initial_pose") and not isinstance(value, str):
            value = " ".join(repr(float(v)) for v in value)
        args += [_VALUE_OPTIONS[key], str(value)]
    return args


def map(input, config=None, poses="auto", out=None, **options):
    """Maps the log `input` exactly as `dynamap map` does and returns its MapResult.

    config: an .ini file (None: the built-in defaults). poses: the pose source, as --poses
    (auto: the config's [input] poses when it names one, else chosen by the log). out: the
    output directory, written as by the command (None: a temporary one, removed afterwards).
    Further keywords stand for the command's options: baseline=False (--no-baseline),
    skip_bad_lines, fixed_pose=(x, y, phi), frames_every, fov, carmen_odometry, scan_topic,
    odom_topic, odom_frame, base_frame, gt_frame, prior (an earlier run's output folder: this
    run continues that session and reports what changed, MapResult.changes), initial_pose=(x, y,
    phi) (where the log starts in the prior's map).
    Raises dynamap.UsageError, ConfigError, InputError or Error with the command's message;
    the command's warnings become DynamapWarning. The GIL is released while the log is mapped.
    """
    keep = out is not None
    out_dir = os.fspath(out) if keep else tempfile.mkdtemp(prefix="dynamap-")
    try:
        raw = _core.run_map(map_args(input, config, poses, out_dir, **options))
        for line in raw["warnings"]:
            warnings.warn(line, DynamapWarning, stacklevel=2)
        return MapResult(raw, out_dir, keep)
    finally:
        if not keep:
            shutil.rmtree(out_dir, ignore_errors=True)
