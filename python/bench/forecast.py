"""gloc.forecast's ensemble spread over Dask: wall time with 1 and with 2 worker
processes (a LocalCluster, one thread each), side by side, and the native threads
(no Dask) for reference. Comet's logs (data/comet/from-glider: 152.sbd, 153.sbd,
154.dbd), its mission nsb3.mi, 12 h, MEMBERS members (default 1,000), seed 1.
Each figure is the median of RUNS runs (default 3) on a started cluster (its start
is timed apart). Usage: python python/bench/forecast.py [MEMBERS] [RUNS]
"""

import os
import sys
import time

import distributed

import gloc

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FOLDER = os.path.join(ROOT, "data", "comet", "from-glider")
LOGS = [
    os.path.join(FOLDER, f"comet-2019-222-02-{segment}")
    for segment in ("152.sbd", "153.sbd", "154.dbd")
]
MISSION = os.path.join(ROOT, "data", "comet", "missions", "nsb3.mi")
CACHE = os.path.join(ROOT, "data", "cac")


def median(function, runs):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    times.sort()
    return times[len(times) // 2], result


def main():
    members = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    print(f"comet, nsb3.mi, 12 h, {members} members, seed 1; median of {runs} runs; {os.cpu_count()} cores")

    def fly(**how):
        return gloc.forecast(LOGS, MISSION, hours=12, members=members, seed=1,
                             sensor_cache=CACHE, **how)

    figures = {}
    for workers in (1, 2):
        started = time.perf_counter()
        with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            ready = time.perf_counter() - started
            wall, result = median(lambda: fly(client=client), runs)
        figures[f"dask, {workers} worker(s)"] = wall
        print(f"dask LocalCluster, {workers} worker process(es): {wall:6.2f} s "
              f"(cluster start {ready:.1f} s, {len(result.members)} member points)")
    for threads in (1, 2):
        wall, _ = median(lambda: fly(threads=threads), runs)
        figures[f"threads {threads}"] = wall
        print(f"native threads, no Dask, {threads} thread(s):   {wall:6.2f} s")
    one, two = figures["dask, 1 worker(s)"], figures["dask, 2 worker(s)"]
    print(f"2 workers vs 1: {one / two:.2f}x")


if __name__ == "__main__":
    main()
