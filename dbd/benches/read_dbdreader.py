"""dbdreader's side of `cargo bench -p gloc-dbd --bench read`: reads
comet-2019-222-02-154.dbd and .ebd into every sensor's (time, value) arrays with
its C extension (DBD(..., skip_initial_line=False).get(*all sensors), every
cycle as gloc reads it), and prints the median wall
time of RUNS runs in milliseconds: `python read_dbdreader.py DATA_DIR RUNS`."""

import os
import sys
import time

import dbdreader


def read_all(data):
    folder = os.path.join(data, "comet/from-glider")
    cache = os.path.join(data, "cac")
    samples = 0
    for name in ("comet-2019-222-02-154.dbd", "comet-2019-222-02-154.ebd"):
        dbd = dbdreader.DBD(os.path.join(folder, name), cacheDir=cache, skip_initial_line=False)
        pairs = dbd.get(*dbd.parameterNames, decimalLatLon=False, discardBadLatLon=False)
        samples += sum(len(v) for _, v in pairs)
        dbd.close()
    return samples


def main():
    data, runs = sys.argv[1], int(sys.argv[2])
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        samples = read_all(data)
        times.append((time.perf_counter() - start) * 1e3)
    times.sort()
    print(f"{times[len(times) // 2]:.2f} {samples}")


main()
