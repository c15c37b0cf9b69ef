"""Maps every log of a manifest on a Dask cluster, one task per log.

    python3 -m dynamap.batch MANIFEST [--scheduler ADDRESS] [--workers N] [--summary FILE]
                                      [--force]

MANIFEST is a CSV file with a header line and the columns input (the log), output (its output
folder) and, optional, config (an .ini file) and poses (as `dynamap map --poses`); relative
paths are taken from the manifest's folder. Each log is mapped as `dynamap map` maps it, on
whichever worker the scheduler picks (every worker must see the same paths: a shared file
system). Without --scheduler a local cluster of --workers processes runs the tasks.

A log whose output folder holds a complete set of outputs for it (its summary.json, which a run
writes last, names the same input) is not mapped again: a batch that stopped, or lost a worker,
is finished by running it again (--force maps every log anew). The fleet summary (--summary,
default MANIFEST's name with .summary.csv) has one row per log: status (mapped, partial: the
input ended in a fault and the outputs cover the part before it, kept: complete outputs found,
failed), scans, objects, people, time [s], the worker and the error of a failure. Every run
that completes is also appended to the journal beside it (.runs.csv). Exit status 0 when no
log failed, 1 otherwise, 2 for a bad manifest.
"""

import argparse
import csv
import json
import os
import socket
import sys
import time

from ._map import map_args

SUMMARY_COLUMNS = ["input", "output", "status", "scans", "objects", "people", "time_s", "worker",
                   "error"]
JOURNAL_COLUMNS = ["input", "output", "worker", "pid", "start", "end", "status"]


class ManifestError(ValueError):
    pass


def read_manifest(path):
    """The manifest's jobs (dicts of input, output, config, poses), paths made absolute."""
    base = os.path.dirname(os.path.abspath(path))
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"input", "output"} - set(reader.fieldnames or [])
        if missing:
            raise ManifestError(f"{path}: no column {', '.join(sorted(missing))} in the header "
                                "(input,output[,config,poses])")
        jobs = []
        for line, row in enumerate(reader, start=2):
            job = {k: (row.get(k) or "").strip() for k in ("input", "output", "config", "poses")}
            if not job["input"] or not job["output"]:
                raise ManifestError(f"{path}: line {line}: input and output are required")
            for k in ("input", "output", "config"):
                if job[k]:
                    job[k] = os.path.normpath(os.path.join(base, job[k]))
            jobs.append(job)
    outputs = [j["output"] for j in jobs]
    dup = sorted({o for o in outputs if outputs.count(o) > 1})
    if dup:
        raise ManifestError(f"{path}: output folder {dup[0]} is given to more than one log")
    return jobs


def complete_summary(job):
    """The summary.json of a complete set of outputs of this job's log, else None."""
    try:
        with open(os.path.join(job["output"], "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        return None
    return summary if summary.get("input") == job["input"] else None


def _worker_name():
    try:
        from distributed import get_worker
        return str(get_worker().name)
    except (ImportError, ValueError):
        return socket.gethostname()


def _record(job, status, summary, seconds, error=""):
    row = {"input": job["input"], "output": job["output"], "status": status, "scans": "",
           "objects": "", "people": "", "time_s": f"{seconds:.3f}", "worker": _worker_name(),
           "error": error}
    if summary is not None:
        row["scans"] = summary["scans"]["used"]
        row["objects"] = summary["objects"]["total"]
        row["people"] = summary["people"]["tracks"]
    return row


def _journal(path, job, start, end, status):
    line = [job["input"], job["output"], _worker_name(), os.getpid(), f"{start:.3f}",
            f"{end:.3f}", status]
    # One short append per run: whole lines, whichever worker writes.
    with open(path, "a", newline="") as f:
        csv.writer(f).writerow(line)


def map_one(job, journal=None, force=False):
    """One task: maps one log unless its outputs are complete; its fleet-summary row."""
    from . import _core
    from .errors import Error
    start = time.time()
    if not force:
        summary = complete_summary(job)
        if summary is not None:
            return _record(job, "kept", summary, 0.0)
    args = map_args(job["input"], job["config"] or None, job["poses"] or "auto", job["output"])
    try:
        raw = _core.run_map(args)
    except Error as e:
        return _record(job, "failed", None, time.time() - start, str(e))
    end = time.time()
    status = "partial" if raw["fault"] else "mapped"
    if journal:
        _journal(journal, job, start, end, status)
    with open(os.path.join(job["output"], "summary.json")) as f:
        return _record(job, status, json.load(f), end - start, raw["fault"])


def write_summary(path, rows):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=SUMMARY_COLUMNS)
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def run_batch(jobs, client, journal=None, force=False, progress=None):
    """Every job as one task of `client`; the fleet-summary rows in the jobs' order."""
    from distributed import as_completed
    keys = [f"dynamap-map-{i:05d}" for i in range(len(jobs))]
    futures = client.map(map_one, jobs, journal=journal, force=force, key=keys, pure=False)
    index = {f.key: i for i, f in enumerate(futures)}
    rows = [None] * len(jobs)
    for future in as_completed(futures):
        i = index[future.key]
        try:
            rows[i] = future.result()
        except Exception as e:  # the task itself failed: its worker died too often, ...
            rows[i] = _record(jobs[i], "failed", None, 0.0, f"{type(e).__name__}: {e}")
        if progress:
            progress(rows[i])
    return rows


def local_cluster(workers):
    """A cluster of `workers` processes on this machine, one thread each (a task holds a core).

    The workers' sampling profiler (every 10 ms, for the dashboard, which is off) is switched
    off: on a machine with as many workers as cores its samples are taken from the mapping."""
    import dask
    from distributed import LocalCluster
    with dask.config.set({"distributed.worker.profile.enabled": False}):
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                            dashboard_address=None)


def _client(scheduler, workers):
    from distributed import Client
    if scheduler:
        return Client(scheduler)
    return Client(local_cluster(workers))


def _parse(argv):
    p = argparse.ArgumentParser(prog="python3 -m dynamap.batch",
                                description="Map every log of a manifest on a Dask cluster.")
    p.add_argument("manifest", help="CSV: input,output[,config,poses]")
    p.add_argument("--scheduler", help="the Dask scheduler's address (default: a local cluster)")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--summary", help="the fleet summary (default: MANIFEST.summary.csv)")
    p.add_argument("--force", action="store_true", help="map every log, complete or not")
    return p.parse_args(argv)


def main(argv=None):
    a = _parse(argv)
    try:
        jobs = read_manifest(a.manifest)
    except (OSError, ManifestError) as e:
        print(f"dynamap.batch: {e}", file=sys.stderr)
        return 2
    summary = a.summary or os.path.splitext(a.manifest)[0] + ".summary.csv"
    journal = os.path.splitext(summary)[0] + ".runs.csv"
    start = time.time()

    def progress(row):
        print(f"{row['status']:8} {row['input']} {row['error']}".rstrip(), flush=True)

    with _client(a.scheduler, a.workers) as client:
        rows = run_batch(jobs, client, journal, a.force, progress)
    write_summary(summary, rows)
    counts = {s: sum(r["status"] == s for r in rows) for s in ("mapped", "partial", "kept",
                                                                "failed")}
    print(f"dynamap.batch: {len(rows)} logs in {time.time() - start:.1f} s: "
          + ", ".join(f"{n} {s}" for s, n in counts.items()) + f"; summary in {summary}")
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    from dynamap import batch  # tasks must name dynamap.batch.map_one, not __main__'s

    sys.exit(batch.main())
