"""invmap.dask on a LocalCluster of 1 and of 2 single-thread worker processes:
does the second worker add a core's worth of speed?

    PYTHONPATH=build/release/python /usr/bin/python3 bench/dask_workers.py [--points N] [--repeats R]

Each configuration inverts the same points (near the bundled wavy surface,
chunks of 250,000) `repeats` times after a warm-up compute that ships the
geometry and builds it on every worker; the best wall time is reported. The
default thread budget of a task (its worker's nthreads) is measured, and
beside it threads=0, every task using all cores (the default before), which
on n single-thread workers runs n times the cores' threads. The machine's
other load shows in the numbers: compare within one run.
"""

import argparse
import logging
import os
import time
import warnings

import dask.array as da
import distributed
import numpy as np

import invmap
import invmap.dask

SURFACE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "data", "wavy_surface.json")
CHUNK = 250_000


def near_points(manifold, count, seed=5):
    """Points in the surface's box squeezed to 30% of its height, around the surface."""
    info = manifold.info()
    lo, hi = np.array(info["bounds_lo"]), np.array(info["bounds_hi"])
    rng = np.random.default_rng(seed)
    points = lo + (hi - lo) * rng.random((count, 3))
    mid = 0.5 * (lo[2] + hi[2])
    points[:, 2] = mid + (points[:, 2] - mid) * 0.3
    return points


def best_time(client, manifold, points, threads, repeats):
    best = float("inf")
    for repeat in range(repeats + 1):
        # A graph of its own each time (the points' name), so no result of
        # an earlier compute is reused; the first ships and builds the
        # geometry on the workers and is not timed.
        array = da.from_array(points, chunks=(CHUNK, 3), name=f"points-{threads}-{repeat}-{time.time_ns()}")
        result = invmap.dask.invert(array, manifold, threads=threads)
        start = time.perf_counter()
        client.compute(result["status"]).result()
        if repeat > 0:
            best = min(best, time.perf_counter() - start)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=int, default=2_000_000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    warnings.filterwarnings("ignore", category=DeprecationWarning)
    manifold = invmap.load(SURFACE)
    points = near_points(manifold, args.points)
    print(f"{args.points} points, chunks of {CHUNK}, {os.cpu_count()} cores, best of {args.repeats}")
    print("workers x threads | task threads        | seconds | points/s")
    times = {}
    for workers in (1, 2):
        with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                      dashboard_address=None, silence_logs=logging.CRITICAL) as cluster, \
                distributed.Client(cluster) as client:
            for threads, label in ((None, "worker's (default)"), (0, "all cores (0)")):
                seconds = best_time(client, manifold, points, threads, args.repeats)
                times[workers, threads] = seconds
                print(f"{workers} x 1             | {label:19} | {seconds:7.2f} | {args.points / seconds:9.0f}")
    for threads, label in ((None, "worker's (default)"), (0, "all cores (0)")):
        print(f"2 workers over 1, task threads {label}: {times[1, threads] / times[2, threads]:.2f}x")


if __name__ == "__main__":
    main()
