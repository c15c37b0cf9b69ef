"""python3 -m dynamap.batch on a local cluster: every log mapped as the command maps it, the
fleet summary, failures with their error, restarts that redo only what is incomplete."""

import os
import subprocess
import sys

import pytest

from batch_util import (assert_same_outputs, make_manifest, map_sequentially, read_csv,
                        read_journal)
from conftest import run_cli


def batch(*args):
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-m", "dynamap.batch", *args], capture_output=True,
                          text=True, env=env, timeout=600)


def test_a_fleet_on_a_local_cluster_and_its_restarts(tmp_path, exe):
    root = str(tmp_path)
    manifest, rows = make_manifest(root, ["tiny"], 3)
    with open(manifest, "a") as f:  # a log that is not there, and one with a bad pose source
        f.write("logs/missing.rawlog,maps/missing,,\n")
        f.write("logs/tiny-0.rawlog,maps/badposes,,nonsense\n")
    p = batch(manifest, "--workers", "2")
    assert p.returncode == 1, p.stderr
    summary = read_csv(os.path.join(root, "fleet.summary.csv"))
    assert [s["status"] for s in summary] == ["mapped"] * 3 + ["failed"] * 2
    _, missing = run_cli("--input", os.path.join(root, "logs/missing.rawlog"), "--out",
                         str(tmp_path / "x"))
    assert summary[3]["error"] == missing.strip()
    assert "--poses" in summary[4]["error"]
    for s in summary[:3]:
        assert int(s["scans"]) > 10 and s["objects"] != "" and float(s["time_s"]) > 0
    map_sequentially(root, rows, str(tmp_path / "sequential"))
    for r in rows:
        assert_same_outputs(str(tmp_path / "sequential" / os.path.basename(r["output"])),
                            os.path.join(root, r["output"]))
    journal = os.path.join(root, "fleet.summary.runs.csv")
    assert sorted(j[0] for j in read_journal(journal)) == sorted(
        os.path.join(root, r["input"]) for r in rows)

    # Again: the complete ones are kept, not mapped; the failures are tried again.
    os.remove(os.path.join(root, rows[1]["output"], "summary.json"))  # as if cut short
    p = batch(manifest, "--workers", "2")
    summary = read_csv(os.path.join(root, "fleet.summary.csv"))
    assert [s["status"] for s in summary] == ["kept", "mapped", "kept", "failed", "failed"]
    assert summary[0]["scans"] == summary[1]["scans"]
    runs = read_journal(journal)
    assert len(runs) == 4 and runs[-1][0] == os.path.join(root, rows[1]["input"])
    assert_same_outputs(str(tmp_path / "sequential" / "tiny-1"), os.path.join(root, "maps/tiny-1"))


def test_a_bad_manifest_is_refused(tmp_path):
    m = tmp_path / "m.csv"
    m.write_text("input,where\nlog.rawlog,out\n")
    p = batch(str(m))
    assert p.returncode == 2 and "no column output" in p.stderr
    m.write_text("input,output\na.rawlog,out\nb.rawlog,out\n")
    p = batch(str(m))
    assert p.returncode == 2 and "more than one log" in p.stderr
    p = batch(str(tmp_path / "none.csv"))
    assert p.returncode == 2 and "none.csv" in p.stderr
