"""make bench: a fleet of --count logs mapped one after another in one process, then as a batch
on a local Dask cluster of --workers worker processes (one thread each), each log the same task
(dynamap.batch.map_one). Prints both wall times and the speed-up, checks that the batch's
outputs are byte-identical to the sequential ones, and says whether the speed-up reaches
--floor. The cluster's start is timed apart: a fleet pays it once.

usage: PYTHONPATH=build/python python3 bench/bench_batch.py --source-dir . [--count 16]
           [--workers 2] [--logs people,walkers,...] [--out out/bench-batch] [--floor 1.6]
"""

import argparse
import filecmp
import json
import os
import shutil
import sys
import time

from dynamap import batch


def jobs_for(args, run):
    """--count copies of the bundled logs (taken in turn), each mapped into run/<k>."""
    logs = args.logs.split(",")
    jobs = []
    for k in range(args.count):
        name = logs[k % len(logs)]
        src = os.path.join(args.source_dir, "rawlogs", name, name + ".rawlog")
        log = os.path.abspath(os.path.join(args.out, "logs", f"{k:02d}-{name}.rawlog"))
        if not os.path.exists(log):
            os.makedirs(os.path.dirname(log), exist_ok=True)
            shutil.copyfile(src, log)
        out = os.path.abspath(os.path.join(args.out, run, f"{k:02d}-{name}"))
        jobs.append({"input": log, "output": out, "config": "", "poses": ""})
    return jobs


def same_outputs(a, b):
    for n in sorted(os.listdir(a)):
        pa, pb = os.path.join(a, n), os.path.join(b, n)
        if n == "summary.json":
            with open(pa) as x, open(pb) as y:
                sa, sb = json.load(x), json.load(y)
            sa.pop("timing"), sb.pop("timing")
            if sa != sb:
                return False
        elif not filecmp.cmp(pa, pb, shallow=False):
            return False
    return sorted(os.listdir(a)) == sorted(os.listdir(b))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--source-dir", default=".")
    p.add_argument("--count", type=int, default=16)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--logs", default="people,walkers,arena,storeroom")
    p.add_argument("--out", default="out/bench-batch")
    p.add_argument("--floor", type=float, default=1.6)
    a = p.parse_args()
    from distributed import Client

    seq_jobs, par_jobs = jobs_for(a, "sequential"), jobs_for(a, "batch")
    t0 = time.monotonic()
    cluster = batch.local_cluster(a.workers)
    client = Client(cluster)
    client.run(lambda: __import__("dynamap"))  # each worker loads the module before the clock
    started = time.monotonic() - t0

    t0 = time.monotonic()
    seq = [batch.map_one(j, force=True) for j in seq_jobs]
    sequential = time.monotonic() - t0
    t0 = time.monotonic()
    par = batch.run_batch(par_jobs, client, force=True)
    parallel = time.monotonic() - t0
    client.close()
    cluster.close()

    ok = all(r["status"] == "mapped" for r in seq + par)
    identical = ok and all(same_outputs(s["output"], b["output"]) for s, b in zip(seq_jobs, par_jobs))
    scans = sum(int(r["scans"]) for r in seq if r["scans"] != "")
    speedup = sequential / parallel
    print(f"fleet batch: {a.count} logs ({a.logs}), {scans} scans; cores {os.cpu_count()}, "
          f"load average {os.getloadavg()[0]:.2f}")
    print(f"  sequential (one process)      {sequential:7.2f} s")
    print(f"  batch, {a.workers} local workers        {parallel:7.2f} s   speed-up {speedup:.2f}x "
          f"(floor {a.floor}x: {'met' if speedup >= a.floor else 'NOT met'})")
    print(f"  local cluster start           {started:7.2f} s (once per batch)")
    print(f"  all mapped: {'yes' if ok else 'NO'}; batch outputs identical to sequential: "
          f"{'yes' if identical else 'NO'}")
    return 0 if ok and identical else 1


if __name__ == "__main__":
    sys.exit(main())
