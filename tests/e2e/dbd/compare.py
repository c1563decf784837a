"""Every sensor's values and times from `gloc data convert` against dbdreader's.

For each real log in the repository's data/: gloc converts it to CSV (one row per cycle,
an empty cell where the cycle did not update the sensor); dbdreader (PyPI, pinned
in tests/e2e/requirements.txt, its C extension) reads every sensor with
skip_initial_line=False, decimalLatLon=False,
discardBadLatLon=False (raw values, as the file has them). For each sensor the (time, value)
samples must be equal, exactly: a 4-byte sensor is a float32 in the file, which
gloc prints as the shortest text that reads back as that float32, so this script
reads such cells as numpy.float32 (lossless) before comparing; 1-, 2- and 8-byte
values compare as printed. A time is the time sensor's cell in that row, or 1e9
when the row has none (dbdreader's fill value for a time sensor not set).

Usage: python compare.py GLOC_BIN DATA_DIR   (a missing DATA_DIR is a failure)
"""

import csv
import os
import subprocess
import sys
import tempfile

import numpy
import dbdreader
import dbdreader.decompress

FILES = [
    ("comet/from-glider/comet-2019-222-02-154.dbd", "cac"),
    ("comet/from-glider/comet-2019-222-02-154.ebd", "cac"),
    ("comet/from-glider/comet-2019-222-02-152.sbd", "cac"),
    ("comet/from-glider/comet-2019-222-02-152.tbd", "cac"),
    ("comet/from-glider/comet-2019-222-02-153.sbd", "cac"),
    ("comet/from-glider/comet-2019-222-02-153.tbd", "cac"),
    ("compressed/01600000.dcd", "compressed"),
    ("compressed/01600000.ecd", "compressed"),
]


def dbdreader_cache(source, target):
    """dbdreader 0.6.3 reads only `.cac`: decompress each `.ccc` with its own
    decompressor, copy each `.cac`."""
    for name in os.listdir(source):
        base, extension = os.path.splitext(name)
        path = os.path.join(source, name)
        if extension == ".ccc":
            with dbdreader.decompress.Decompressor(path) as d:
                data = d.decompress()
        elif extension == ".cac":
            with open(path, "rb") as f:
                data = f.read()
        else:
            continue
        with open(os.path.join(target, base.lower() + ".cac"), "wb") as f:
            f.write(data)


def gloc_samples(gloc, path, cache, out):
    subprocess.run(
        [gloc, "data", "convert", path, "--sensor-cache", cache, "-o", out],
        check=True,
        stderr=subprocess.PIPE,
    )
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def compare(gloc, data, relative, cache_name, work):
    path = os.path.join(data, relative)
    cache = os.path.join(data, cache_name)
    reference_cache = os.path.join(work, "cache-" + cache_name)
    if not os.path.isdir(reference_cache):
        os.mkdir(reference_cache)
        dbdreader_cache(cache, reference_cache)
    dbd = dbdreader.DBD(path, cacheDir=reference_cache, skip_initial_line=False)
    names = list(dbd.parameterNames)
    sizes = dict(zip(names, dbd.byteSizes))
    pairs = dbd.get(*names, decimalLatLon=False, discardBadLatLon=False, return_nans=False)
    times = [t for t, _ in pairs]
    values = [v for _, v in pairs]
    dbd.close()
    header, rows = gloc_samples(gloc, path, cache, os.path.join(work, "out.csv"))
    problems = []
    if header != names:
        problems.append(f"sensor lists differ: gloc {len(header)}, dbdreader {len(names)}")
        return problems, 0
    time_column = header.index(dbd.timeVariable)
    row_times = numpy.array(
        [float(row[time_column]) if row[time_column] != "" else 1e9 for row in rows]
    )
    samples = 0
    for column, name in enumerate(header):
        present = [i for i, row in enumerate(rows) if row[column] != ""]
        if sizes[name] == 4:
            ours = numpy.array(
                [numpy.float32(rows[i][column]) for i in present], dtype=numpy.float32
            ).astype(numpy.float64)
        else:
            ours = numpy.array([float(rows[i][column]) for i in present])
        our_times = row_times[present]
        theirs_t = numpy.asarray(times[column], dtype=numpy.float64)
        theirs_v = numpy.asarray(values[column], dtype=numpy.float64)
        samples += len(theirs_v)
        if len(ours) != len(theirs_v):
            problems.append(f"{name}: gloc {len(ours)} samples, dbdreader {len(theirs_v)}")
        elif not numpy.array_equal(our_times, theirs_t, equal_nan=True):
            at = int(numpy.argmax(~((our_times == theirs_t) | (numpy.isnan(our_times) & numpy.isnan(theirs_t)))))
            problems.append(f"{name}: time {at} is {our_times[at]!r} in gloc, {theirs_t[at]!r} in dbdreader")
        elif not numpy.array_equal(ours, theirs_v, equal_nan=True):
            at = int(numpy.argmax(~((ours == theirs_v) | (numpy.isnan(ours) & numpy.isnan(theirs_v)))))
            problems.append(f"{name}: value {at} is {ours[at]!r} in gloc, {theirs_v[at]!r} in dbdreader")
    return problems, samples


def main():
    gloc, data = sys.argv[1], sys.argv[2]
    if not os.path.isdir(data):
        print(f"dbd compare: {data} is missing: the real logs belong to the repository (data/README.md)")
        return 1
    failed = False
    total = 0
    with tempfile.TemporaryDirectory() as work:
        for relative, cache in FILES:
            problems, samples = compare(gloc, data, relative, cache, work)
            total += samples
            if problems:
                failed = True
                print(f"FAILED {relative}: {len(problems)} sensors differ")
                for problem in problems[:20]:
                    print(f"  {problem}")
            else:
                print(f"ok {relative}: {samples} samples equal to dbdreader's")
    print(f"dbd compare: {total} samples in all")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
