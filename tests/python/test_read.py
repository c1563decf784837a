"""gloc.read against dbdreader (PyPI, its C extension): every sensor's (time, value)
samples of every real log in data/, equal exactly, as tests/e2e/dbd/compare.py
compares `gloc data convert`; and errors as exceptions naming the file and offset."""

import os
import sys

import numpy
import pytest

import dbdreader
import gloc

from conftest import DATA, ROOT

sys.path.insert(0, os.path.join(ROOT, "tests", "e2e", "dbd"))
from compare import dbdreader_cache  # noqa: E402  (the e2e suite's one copy of the rule)

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


def test_every_real_log_is_listed():
    """A log added to data/ must be added here too."""
    extensions = {".dbd", ".ebd", ".sbd", ".tbd", ".mbd", ".nbd", ".dcd", ".ecd", ".scd", ".tcd", ".mcd", ".ncd"}
    found = set()
    for folder, _, names in os.walk(DATA):
        for name in names:
            if os.path.splitext(name)[1].lower() in extensions:
                found.add(os.path.relpath(os.path.join(folder, name), DATA))
    assert found == {relative for relative, _ in FILES}


@pytest.fixture(scope="module")
def reference_caches(tmp_path_factory):
    """dbdreader 0.6.3 reads only `.cac`: each `.ccc` decompressed with its own
    decompressor, each `.cac` copied (compare.py's `dbdreader_cache`, called here)."""
    caches = {}
    for cache_name in {cache for _, cache in FILES}:
        target = tmp_path_factory.mktemp("cache-" + cache_name)
        dbdreader_cache(os.path.join(DATA, cache_name), str(target))
        caches[cache_name] = str(target)
    return caches


@pytest.mark.parametrize("relative,cache_name", FILES)
def test_read_equals_dbdreader(relative, cache_name, reference_caches):
    path = os.path.join(DATA, relative)
    frame = gloc.read(path, sensor_cache=os.path.join(DATA, cache_name))
    dbd = dbdreader.DBD(path, cacheDir=reference_caches[cache_name], skip_initial_line=False)
    try:
        names = list(dbd.parameterNames)
        sizes = dict(zip(names, dbd.byteSizes))
        units = dict(zip(names, dbd.parameterUnits.values())) if isinstance(dbd.parameterUnits, dict) else None
        pairs = dbd.get(*names, decimalLatLon=False, discardBadLatLon=False, return_nans=False)
        time_variable = dbd.timeVariable
    finally:
        dbd.close()
    assert list(frame.columns) == names
    assert frame.attrs["bytes"] == sizes
    assert frame.attrs["time_sensor"] == time_variable
    if units is not None:
        assert frame.attrs["units"] == units
    # dbdreader's time of a sample is the time sensor's value in that cycle, 1e9
    # where the cycle did not update it.
    row_times = numpy.where(numpy.isnan(frame.index.to_numpy()), 1e9, frame.index.to_numpy())
    # The index is the time sensor's column, as the log has it.
    time_column = frame[time_variable].to_numpy()
    assert numpy.array_equal(frame.index.to_numpy(), time_column, equal_nan=True)
    samples = 0
    for name, (times, values) in zip(names, pairs):
        column = frame[name].to_numpy()
        present = ~numpy.isnan(column)
        theirs_v = numpy.asarray(values, dtype=numpy.float64)
        theirs_t = numpy.asarray(times, dtype=numpy.float64)
        # A NaN the glider wrote (compressed/ has some) is a sample to dbdreader; in
        # the DataFrame it is NaN like a cycle that did not update the sensor (the
        # documented cost of one float per cell), so only numbers are compared.
        written = ~numpy.isnan(theirs_v)
        theirs_v, theirs_t = theirs_v[written], theirs_t[written]
        assert present.sum() == len(theirs_v), name
        assert numpy.array_equal(column[present], theirs_v), name
        assert numpy.array_equal(row_times[present], theirs_t), name
        samples += len(theirs_v)
    assert samples > 0


def test_sensor_selection_keeps_the_order_asked_and_the_time_index():
    path = os.path.join(DATA, "comet/from-glider/comet-2019-222-02-154.dbd")
    cache = os.path.join(DATA, "cac")
    every = gloc.read(path, sensor_cache=cache)
    some = gloc.read(path, sensors=["m_pitch", "M_DEPTH"], sensor_cache=cache)
    assert list(some.columns) == ["m_pitch", "m_depth"]
    assert some.attrs["units"] == {"m_pitch": "rad", "m_depth": "m"}
    assert numpy.array_equal(some.index.to_numpy(), every.index.to_numpy(), equal_nan=True)
    assert numpy.array_equal(some["m_depth"].to_numpy(), every["m_depth"].to_numpy(), equal_nan=True)


def test_flight_and_science_merge_as_gloc_data_convert(gloc_bin, tmp_path):
    """The merge is gloc_dbd's: the DataFrame equals `gloc data convert`'s CSV of
    the same two files (an independent surface over the same merge: rows, columns,
    every cell)."""
    import csv
    import subprocess

    folder = os.path.join(DATA, "comet/from-glider")
    paths = [os.path.join(folder, "comet-2019-222-02-154.dbd"), os.path.join(folder, "comet-2019-222-02-154.ebd")]
    out = tmp_path / "merged.csv"
    subprocess.run(
        [gloc_bin, "data", "convert", *paths, "--sensor-cache", os.path.join(DATA, "cac"), "-o", str(out)],
        check=True,
        capture_output=True,
    )
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    frame = gloc.read(paths, sensor_cache=os.path.join(DATA, "cac"))
    assert list(frame.columns) == rows[0]
    assert len(frame) == len(rows) - 1
    assert "sci_water_temp" in frame.columns and "m_depth" in frame.columns
    for position, name in enumerate(rows[0]):
        cells = [row[position] for row in rows[1:]]
        if frame.attrs["bytes"][name] == 4:
            expected = numpy.array([numpy.float32(c) if c else numpy.nan for c in cells], dtype=numpy.float32).astype(numpy.float64)
        else:
            expected = numpy.array([float(c) if c else numpy.nan for c in cells])
        assert numpy.array_equal(frame[name].to_numpy(), expected, equal_nan=True), name


def test_a_corrupt_log_raises_with_file_and_offset(tmp_path):
    source = os.path.join(DATA, "comet/from-glider/comet-2019-222-02-154.dbd")
    with open(source, "rb") as f:
        data = bytearray(f.read())
    # Cut the file inside its sensor-list header lines: the reader names the byte.
    broken = tmp_path / "broken.dbd"
    broken.write_bytes(bytes(data[:200]))
    with pytest.raises(gloc.LogError) as caught:
        gloc.read(str(broken), sensor_cache=os.path.join(DATA, "cac"))
    error = caught.value
    assert error.file.endswith("broken.dbd")
    assert 0 <= error.offset <= 200
    assert str(broken) in str(error) or "broken.dbd" in str(error)


def test_a_missing_file_is_unreadable(tmp_path):
    with pytest.raises(gloc.LogError) as caught:
        gloc.read(str(tmp_path / "absent.dbd"))
    assert caught.value.kind == "unreadable"


def test_an_unknown_sensor_is_a_value_error():
    path = os.path.join(DATA, "comet/from-glider/comet-2019-222-02-154.dbd")
    with pytest.raises(ValueError, match="m_deptj"):
        gloc.read(path, sensors=["m_deptj"], sensor_cache=os.path.join(DATA, "cac"))
