"""Helpers of the batch tests: a manifest of copies of bundled logs, the sequential reference
and the comparison of two output folders."""

import csv
import os
import shutil

from conftest import bundled, run_cli, summary_of


def make_manifest(root, logs, copies):
    """Copies of the bundled `logs` (copies of each, under distinct names) and a manifest
    mapping each into its own folder; the manifest's path and its rows."""
    os.makedirs(os.path.join(root, "logs"), exist_ok=True)
    rows = []
    for k in range(copies):
        for name in logs:
            log = os.path.join("logs", f"{name}-{k}.rawlog")
            shutil.copyfile(bundled(name), os.path.join(root, log))
            rows.append({"input": log, "output": os.path.join("maps", f"{name}-{k}")})
    manifest = os.path.join(root, "fleet.csv")
    with open(manifest, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["input", "output", "config", "poses"])
        w.writeheader()
        w.writerows(rows)
    return manifest, rows


def map_sequentially(root, rows, into):
    """Each log of `rows` mapped by the command, one after another, into `into`/<name>."""
    for r in rows:
        out = os.path.join(into, os.path.basename(r["output"]))
        status, err = run_cli("--input", os.path.join(root, r["input"]), "--out", out)
        assert status == 0, err


def assert_same_outputs(a, b):
    """Every file byte-identical; summary.json but for its timing block."""
    names = sorted(os.listdir(a))
    assert names == sorted(os.listdir(b)), (a, b)
    for n in names:
        if n == "summary.json":
            assert summary_of(a) == summary_of(b), (a, b)
            continue
        with open(os.path.join(a, n), "rb") as x, open(os.path.join(b, n), "rb") as y:
            assert x.read() == y.read(), os.path.join(b, n)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_journal(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.reader(f))
