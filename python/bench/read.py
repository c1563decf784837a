"""gloc.read against dbdreader on comet's deployment (data/comet/from-glider: the
.dbd/.ebd pair and the .sbd/.tbd pairs, 6 files), every sensor, every cycle.

dbdreader (its C extension) reads each file with DBD(..., skip_initial_line=False)
.get(*every sensor), as dbd/benches/read_dbdreader.py does; gloc reads the same
files one by one into DataFrames (the like-for-like figure) and, in one call, as the
merged deployment DataFrame. Each timed run returns what it read; the samples (and
non-NaN cells) are counted after the timing, the same way for both. dbdreader's own way to read a deployment, MultiDBD over
the 6 files with every sensor of any of them, is timed too (the figure issue 29 quotes,
1.20 s). Prints the median wall time of RUNS runs (default 5)
of each (wall time, and the process's CPU time beside it) and the ratios. Usage: python python/bench/read.py [RUNS]
"""

import contextlib
import io
import logging
import os
import sys
import time

import dbdreader

import gloc

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FOLDER = os.path.join(ROOT, "data", "comet", "from-glider")
CACHE = os.path.join(ROOT, "data", "cac")
FILES = sorted(os.path.join(FOLDER, name) for name in os.listdir(FOLDER))


def with_dbdreader():
    read = []
    for path in FILES:
        dbd = dbdreader.DBD(path, cacheDir=CACHE, skip_initial_line=False)
        read.append(dbd.get(*dbd.parameterNames, decimalLatLon=False, discardBadLatLon=False))
        dbd.close()
    return read


def dbdreader_samples(read):
    return sum(len(values) for pairs in read for _, values in pairs)


def with_multidbd():
    """dbdreader's deployment reader: every flight and science sensor of any file.
    It logs each sensor a file lacks; those lines are silenced."""
    logging.disable(logging.CRITICAL)
    try:
        multi = dbdreader.MultiDBD(filenames=FILES, cacheDir=CACHE, skip_initial_line=False)
        names = multi.parameterNames["eng"] + multi.parameterNames["sci"]
        pairs = multi.get(*names, decimalLatLon=False, discardBadLatLon=False, return_nans=False)
        multi.close()
    finally:
        logging.disable(logging.NOTSET)
    return sum(len(values) for _, values in pairs)


def with_gloc_per_file():
    return [gloc.read(path, sensor_cache=CACHE) for path in FILES]


def gloc_cells(frames):
    return sum(int(frame.notna().to_numpy().sum()) for frame in frames)


def with_gloc_merged():
    frame = gloc.read(FILES, sensor_cache=CACHE)
    return frame.shape


class Timed(float):
    """A median wall time (s) that also carries the median CPU time of the process
    (``cpu``): on a shared machine the wall time swings with the other load, the
    CPU time much less (both readers run on one thread)."""

    cpu = 0.0

    def __format__(self, spec):
        return f"{self * 1e3:.1f} ms (CPU {self.cpu * 1e3:.1f} ms)"


def median(function, runs):
    walls, cpus = [], []
    for _ in range(runs):
        start, cpu = time.perf_counter(), time.process_time()
        result = function()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    walls.sort()
    cpus.sort()
    timed = Timed(walls[len(walls) // 2])
    timed.cpu = cpus[len(cpus) // 2]
    return timed, result


def ratio(slow, fast):
    return f"{slow / fast:.1f}x faster (CPU {slow.cpu / fast.cpu:.1f}x)"


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    size = sum(os.path.getsize(path) for path in FILES)
    print(f"comet's deployment: {len(FILES)} files, {size / 1e6:.2f} MB; median of {runs} runs")
    # What each read is counted outside the timing (the samples, the non-NaN cells).
    theirs, their_read = median(with_dbdreader, runs)
    their_samples = dbdreader_samples(their_read)
    ours, our_frames = median(with_gloc_per_file, runs)
    our_samples = gloc_cells(our_frames)
    merged, shape = median(with_gloc_merged, runs)
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        multi, multi_samples = median(with_multidbd, runs)
    print(f"dbdreader 0.6.3, every sensor of each file: {theirs} ({their_samples} samples)")
    print(f"gloc.read, each file a DataFrame:          {ours} ({our_samples} non-NaN cells); {ratio(theirs, ours)}")
    print(f"gloc.read, the merged deployment:           {merged} ({shape[0]} rows x {shape[1]} sensors); {ratio(theirs, merged)}")
    print(f"dbdreader 0.6.3 MultiDBD, the deployment:   {multi} ({multi_samples} samples); gloc.read merged {ratio(multi, merged)}")

main()
