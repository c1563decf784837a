"""gloc.forecast against `gloc forecast` on comet's logs, and an ensemble on a Dask
LocalCluster of two worker processes against the same ensemble on one process."""

import csv
import os
import re
import subprocess

import numpy
import pandas
import pandas.testing
import pytest

import gloc

from conftest import DATA

FOLDER = os.path.join(DATA, "comet", "from-glider")
LOGS = [
    os.path.join(FOLDER, name)
    for name in (
        "comet-2019-222-02-152.sbd",
        "comet-2019-222-02-153.sbd",
        "comet-2019-222-02-154.dbd",
    )
]
MISSION = os.path.join(DATA, "comet", "missions", "nsb3.mi")
CACHE = os.path.join(DATA, "cac")


def cli_forecast(gloc_bin, tmp_path, *flags):
    """`gloc forecast` on comet's logs: its printed lines and its CSV track."""
    out = tmp_path / "track.csv"
    done = subprocess.run(
        [gloc_bin, "forecast", *LOGS, "--sensor-cache", CACHE, "--mission", MISSION,
         "-o", str(out), *flags],
        capture_output=True, text=True, check=True,
    )
    with open(out, newline="") as handle:
        rows = list(csv.DictReader(handle))
    return done.stdout, rows


def test_the_track_and_surfacings_are_the_command_lines(gloc_bin, tmp_path):
    printed, rows = cli_forecast(gloc_bin, tmp_path, "--hours", "4")
    made = gloc.forecast(LOGS, MISSION, hours=4, sensor_cache=CACHE)
    # The CSV's rounding: time 0.1 s, positions 1e-6 degrees, depth 0.01 m.
    assert len(made.track) == len(rows)
    numpy.testing.assert_allclose(made.track.index, [float(r["unix_time"]) for r in rows], atol=0.051)
    numpy.testing.assert_allclose(made.track["lat"], [float(r["lat"]) for r in rows], atol=5.1e-7)
    numpy.testing.assert_allclose(made.track["lon"], [float(r["lon"]) for r in rows], atol=5.1e-7)
    numpy.testing.assert_allclose(made.track["depth"], [float(r["depth_m"]) for r in rows], atol=0.0051)
    # The printed surfacings: `  1  2019-08-21T19:39:43Z  5421.9272 720.9861  (54.36545, 7.34977) ...`.
    found = re.findall(r"^\s+\d+\s+\S+Z\s+\S+ \S+\s+\((\S+), (\S+)\)", printed, re.M)
    assert len(found) == len(made.surfacings) >= 1
    for (lat, lon), (_, row) in zip(found, made.surfacings.iterrows()):
        assert abs(row["lat"] - float(lat)) <= 5.1e-6 and abs(row["lon"] - float(lon)) <= 5.1e-6
    # The start is the logs' last fix, 2019-08-21T16:42:48Z (`date -u -d @1566405768`).
    assert int(made.start["time"]) == 1566405768
    assert made.start["lat"] == pytest.approx(54 + 19.6355 / 60, abs=1e-6)
    assert made.ended is None and made.members is None
    # Set up as `gloc forecast` sets it up, it warns alike: nsb3.mi's line 12 names
    # `u_sci_dbd_sensor_list_xmit_control`, which the embedded list lacks (S0106, on
    # the command line's stderr too).
    done = subprocess.run(
        [gloc_bin, "forecast", *LOGS, "--sensor-cache", CACHE, "--mission", MISSION, "--hours", "1"],
        capture_output=True, text=True, check=True,
    )
    assert "warning[S0106]: sensor `u_sci_dbd_sensor_list_xmit_control`" in done.stderr
    assert [w for w in made.warnings if w.startswith("S0106 ")] == [
        w for w in made.warnings if "u_sci_dbd_sensor_list_xmit_control" in w
    ] != []


def test_an_ensemble_on_two_dask_workers_is_the_one_on_one_process(gloc_bin, tmp_path):
    import distributed  # pinned in requirements.txt: missing is a failure, not a skip
    members, hours = 8, 4
    here = gloc.forecast(LOGS, MISSION, hours=hours, members=members, seed=5,
                         sensor_cache=CACHE, threads=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        # Three chunks over two workers: a split unlike the threads' one.
        spread = gloc.forecast(LOGS, MISSION, hours=hours, members=members, seed=5,
                               sensor_cache=CACHE, client=client, chunks=3)
        workers = {info["id"] for info in client.scheduler_info()["workers"].values()}
    assert len(workers) == 2
    assert here.members["member"].nunique() == members
    pandas.testing.assert_frame_equal(here.members, spread.members, check_exact=True)
    pandas.testing.assert_frame_equal(here.member_surfacings, spread.member_surfacings, check_exact=True)
    pandas.testing.assert_frame_equal(here.offsets, spread.offsets, check_exact=True)
    for column in ("lat", "lon"):
        for a, b in zip(here.regions[column], spread.regions[column]):
            numpy.testing.assert_array_equal(a, b)
    # Members differ from each other: the offsets are drawn, not repeated.
    assert here.offsets["u"].nunique() == members
    # A different seed, different members.
    other = gloc.forecast(LOGS, MISSION, hours=hours, members=members, seed=6, sensor_cache=CACHE)
    assert not other.offsets.equals(here.offsets)
    # The summary equals what `gloc forecast --members` prints for the same seed:
    # `surfacing 1: 8 members, ..., 95% within 4254 m of (54.36534, 7.34261), all within 5738 m`.
    printed, _ = cli_forecast(gloc_bin, tmp_path, "--hours", str(hours), "--members",
                              str(members), "--seed", "5", "-j", "2")
    lines = re.findall(
        r"surfacing (\d+): (\d+) members, .* 95% within (\d+) m of \((\S+), (\S+)\), all within (\d+) m",
        printed,
    )
    assert len(lines) == len(spread.surfacing_spread) >= 1
    for (number, count, r95, lat, lon, rmax) in lines:
        row = spread.surfacing_spread.loc[int(number)]
        assert row["members"] == int(count)
        assert abs(row["radius_95"] - float(r95)) <= 0.5 and abs(row["radius_max"] - float(rmax)) <= 0.5
        assert abs(row["mean_lat"] - float(lat)) <= 5.1e-6 and abs(row["mean_lon"] - float(lon)) <= 5.1e-6


def test_client_local_starts_a_local_cluster_and_flies_the_same_members():
    members, hours = 4, 2
    here = gloc.forecast(LOGS, MISSION, hours=hours, members=members, seed=3,
                         sensor_cache=CACHE, threads=1)
    local = gloc.forecast(LOGS, MISSION, hours=hours, members=members, seed=3,
                          sensor_cache=CACHE, client="local", threads=2)
    assert here.members["member"].nunique() == members
    pandas.testing.assert_frame_equal(here.members, local.members, check_exact=True)
    pandas.testing.assert_frame_equal(here.offsets, local.offsets, check_exact=True)
    with pytest.raises(ValueError, match="client='cluster'"):
        gloc.forecast(LOGS, MISSION, members=2, sensor_cache=CACHE, client="cluster")


def test_bad_requests_are_clear_errors(tmp_path):
    with pytest.raises(ValueError, match="hours=0"):
        gloc.forecast(LOGS, MISSION, hours=0, sensor_cache=CACHE)
    with pytest.raises(ValueError, match="members=-1"):
        gloc.forecast(LOGS, MISSION, members=-1, sensor_cache=CACHE)
    with pytest.raises(ValueError, match=r"members=100001: give 1 to 100000 members \(or 0"):
        gloc.forecast(LOGS, MISSION, members=100001, sensor_cache=CACHE)
    with pytest.raises(ValueError, match="hours=721: give a horizon above 0 and up to 720 hours"):
        gloc.forecast(LOGS, MISSION, hours=721, sensor_cache=CACHE)
    missing = str(tmp_path / "nothing.dbd")
    with pytest.raises(gloc.LogError) as raised:
        gloc.forecast([missing], MISSION, sensor_cache=CACHE)
    assert raised.value.kind == "unreadable" and "nothing.dbd" in str(raised.value)
    with pytest.raises(ValueError, match="currents"):
        gloc.forecast(LOGS, MISSION, currents=MISSION, sensor_cache=CACHE)
