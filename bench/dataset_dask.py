#!/usr/bin/env python3
"""Dataset generation throughput on Dask: profiles/s with 1 and 2 worker
processes (1 thread each) on this machine, the same spec, fresh output
directories; and what a 100-million-profile dataset would cost.

    PYTHONPATH=build/python /usr/bin/python3 bench/dataset_dask.py [--shards 32] [--scenes 4] [--profiles 128]
"""
import argparse
import os
import shutil
import tempfile
import time

import distributed

import vts.dataset as ds


def spec(shards, scenes, profiles):
    return {
        "seed": 5, "shards": shards, "scenes_per_shard": scenes, "profiles_per_scene": profiles,
        "joints": {j: {} for j in ("fillet", "corner", "lap", "butt", "vgroove", "bevel", "ugroove", "jgroove")},
        "sensors": {"mspot": {"standoff_mm": [90, 130]}},
    }


def run(s, workers, root):
    out = os.path.join(root, f"w{workers}")
    with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                  dashboard_address=None, silence_logs=40) as cluster, \
            distributed.Client(cluster) as client:
        # Workers up and vts imported before the clock starts (steady state is
        # what a long run sees; each worker's first OSMesa context is still timed).
        client.run(lambda: __import__("vts.dataset"))
        t0 = time.perf_counter()
        m = ds.generate(s, out, client=client)
        t = time.perf_counter() - t0
    profiles = sum(sh["profiles"] for sh in m["shards"])
    size = sum(f["bytes"] for sh in m["shards"] for f in sh["files"])
    return profiles, t, size


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shards", type=int, default=32)
    ap.add_argument("--scenes", type=int, default=4)
    ap.add_argument("--profiles", type=int, default=128)
    a = ap.parse_args()
    s = spec(a.shards, a.scenes, a.profiles)
    root = tempfile.mkdtemp(prefix="vts-dask-bench-")
    try:
        rates = {}
        for w in (1, 2):
            p, t, size = run(s, w, root)
            rates[w] = p / t
            print(f"{w} worker(s): {p} profiles in {t:.2f} s = {p / t:.0f} profiles/s, {size / p / 1024:.1f} KiB/profile")
        print(f"2 workers / 1 worker: {rates[2] / rates[1]:.2f}x")
        n = 100e6
        print(f"100M profiles at the 2-worker rate: {n / rates[2] / 3600:.1f} h on this machine "
              f"({n / rates[2] * 2 / 3600:.0f} core-hours), {n * size / p / 1e12:.2f} TB")
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
