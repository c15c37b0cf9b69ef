"""The fleet batch on a real cluster: a `dask scheduler` and two `dask worker` processes on
127.0.0.1, one worker killed while it maps. Every log is mapped once, every output is
byte-identical to the command's sequential runs, and a second batch maps nothing."""

import os
import signal
import socket
import subprocess
import sys
import time

import pytest

from batch_util import (assert_same_outputs, make_manifest, map_sequentially, read_csv,
                        read_journal)

DASK = os.path.join(os.path.dirname(sys.executable), "dask")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(args, log):
    # A session of its own: the worker's nanny and its process are killed together.
    return subprocess.Popen([DASK, *args], stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)


def stop(p):
    if p.poll() is None:
        os.killpg(p.pid, signal.SIGKILL)
    p.wait(timeout=30)


def running_maps(root, rows):
    """Output folders with a run in progress in them (its staging folder)."""
    busy = []
    for r in rows:
        out = os.path.join(root, r["output"])
        if os.path.isdir(out) and any(n.startswith(".dynamap-run-") for n in os.listdir(out)):
            busy.append(out)
    return busy


@pytest.fixture
def cluster(tmp_path):
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    log = open(tmp_path / "cluster.log", "w")
    procs = {"scheduler": start(["scheduler", "--host", "127.0.0.1", "--port", str(port),
                                 "--no-dashboard"], log)}
    for name in ("w1", "w2"):
        procs[name] = start(["worker", address, "--name", name, "--nthreads", "1",
                             "--host", "127.0.0.1", "--no-dashboard"], log)
    yield address, procs
    for p in procs.values():
        stop(p)
    log.close()


def just_finished(journal, worker):
    """The journal's last run is `worker`'s and ended a moment ago."""
    runs = read_journal(journal)
    return bool(runs) and runs[-1][2] == worker and time.time() - float(runs[-1][5]) < 0.15


def wait_for_workers(address, n):
    from distributed import Client
    with Client(address, timeout=60) as c:
        c.wait_for_workers(n, timeout=120)


def test_a_killed_worker_loses_nothing(tmp_path, cluster, exe):
    address, procs = cluster
    root = str(tmp_path / "fleet")
    manifest, rows = make_manifest(root, ["people", "walkers"], 4)
    wait_for_workers(address, 2)
    batch = subprocess.Popen([sys.executable, "-m", "dynamap.batch", manifest, "--scheduler",
                              address], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True)
    journal = os.path.join(root, "fleet.summary.runs.csv")
    # Kill w1 just after it finished a log, while both workers map one each: w1's run then
    # has just begun (far from its end, where a kill would come after its outputs).
    deadline = time.monotonic() + 300
    while not (just_finished(journal, "w1") and len(running_maps(root, rows)) == 2):
        assert batch.poll() is None and time.monotonic() < deadline, "no moment to kill at"
        time.sleep(0.01)
    killed_in = running_maps(root, rows)
    stop(procs["w1"])
    out, _ = batch.communicate(timeout=600)
    assert batch.returncode == 0, out

    summary = read_csv(os.path.join(root, "fleet.summary.csv"))
    assert [s["input"] for s in summary] == [os.path.join(root, r["input"]) for r in rows]
    # kept: a log w1 had mapped whose result died with it; the task ran again on w2 and found
    # the outputs complete.
    assert all(s["status"] in ("mapped", "kept") for s in summary), summary
    runs = read_journal(journal)
    # Each log mapped to the end exactly once; the run w1 was killed in was redone by w2.
    assert sorted(r[0] for r in runs) == sorted(s["input"] for s in summary)
    for out in killed_in:  # w2's own run and the one w1 died in, both mapped by w2
        assert [r[2] for r in runs if r[1] == out] == ["w2"], (out, runs)
    assert {r[2] for r in runs} <= {"w1", "w2"}
    assert len(killed_in) == 2 and not running_maps(root, rows)

    map_sequentially(root, rows, str(tmp_path / "sequential"))
    for r in rows:
        assert_same_outputs(str(tmp_path / "sequential" / os.path.basename(r["output"])),
                            os.path.join(root, r["output"]))

    # Restarted: every log's outputs are complete, nothing is mapped again.
    p = subprocess.run([sys.executable, "-m", "dynamap.batch", manifest, "--scheduler", address],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    assert all(s["status"] == "kept" for s in read_csv(os.path.join(root, "fleet.summary.csv")))
    assert len(read_journal(journal)) == len(rows)
