"""gloc.to_xarray: comet's merged flight and science logs as an xarray Dataset,
each sensor's units (as dbdreader reads them from the same files) an attribute."""

import os

import numpy
import pytest

import dbdreader
import gloc

from conftest import DATA

import xarray  # pinned in requirements.txt: missing is a failure, not a skip

FOLDER = os.path.join(DATA, "comet", "from-glider")
PAIR = [os.path.join(FOLDER, "comet-2019-222-02-154." + kind) for kind in ("dbd", "ebd")]
CACHE = os.path.join(DATA, "cac")


def dbdreader_units(path):
    dbd = dbdreader.DBD(path, cacheDir=CACHE, skip_initial_line=False)
    try:
        return dict(zip(dbd.parameterNames, dbd.parameterUnits.values()))
    finally:
        dbd.close()


def test_a_dataset_along_time_with_units_as_attributes():
    frame = gloc.read(PAIR, sensor_cache=CACHE)
    dataset = gloc.to_xarray(frame)
    assert list(dataset.data_vars) == list(frame.columns)
    assert dataset.sizes == {"time": len(frame)}
    # A sensor in both files keeps the flight log's entry (the .dbd lists every
    # sensor, the .ebd 91; sci_dvl_ts_temp is `degC` in one, `degc` in the other).
    units = dbdreader_units(PAIR[1])
    units.update(dbdreader_units(PAIR[0]))
    assert set(units) == set(frame.columns)
    for name, unit in units.items():
        assert dataset[name].attrs["units"] == unit, name
        assert dataset[name].attrs["bytes"] == frame.attrs["bytes"][name], name
    # By hand: m_depth in metres, sci_water_temp in degC (the sensor list's words).
    assert dataset["m_depth"].attrs["units"] == "m"
    assert dataset["sci_water_temp"].attrs["units"] == "degC"
    for name in ("m_depth", "sci_water_temp", "m_gps_lat"):
        assert numpy.array_equal(dataset[name].values, frame[name].to_numpy(), equal_nan=True)
    assert numpy.array_equal(dataset["time"].values, frame.index.to_numpy(), equal_nan=True)
    assert dataset.attrs["time_sensor"] == "m_present_time"
    # CF time: the first cycle, 1566395646.2 s, is 2019-08-21 13:54:06 UTC
    # (`date -u -d @1566395646`).
    decoded = xarray.decode_cf(dataset)
    first = decoded["time"].values[0]
    assert str(first.astype("datetime64[s]")) == "2019-08-21T13:54:06"


def test_a_run_log_becomes_a_dataset_too():
    root = os.path.dirname(DATA)
    log, _ = gloc.run(os.path.join(root, "examples", "fig2.gloc"), cycles=50, seed=1)
    dataset = gloc.to_xarray(log)
    assert dataset.sizes["time"] == 50
    assert dataset["m_present_time"].attrs["bytes"] == 8
    assert numpy.array_equal(dataset["m_depth"].values, log["m_depth"].to_numpy(), equal_nan=True)
