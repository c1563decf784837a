"""gloc.run against `gloc run --log x.csv`: the same seed gives the same log, cell
for cell, and the summary's end and energy are those the CLI prints."""

import csv
import os
import re
import subprocess

import numpy
import pytest

import gloc

from conftest import ROOT, DATA

RUNS = [
    # (script, mission, duration, seed)
    ("examples/fig2.gloc", None, "30m", 7),
    ("examples/thermocline.gbas", "examples/thermocline.mi", "1h", 3),
    ("examples/fig2.gloc", "examples/goto.mi", "1h", 11),
]


def seconds(text):
    units = {"s": 1, "m": 60, "h": 3600, "d": 86400}
    return sum(float(number) * units[unit] for number, unit in re.findall(r"(\d+(?:\.\d+)?)([smhd])", text))


def cli_log(gloc_bin, tmp_path, script, mission, duration, seed):
    out = tmp_path / "run.csv"
    command = [gloc_bin, "run", os.path.join(ROOT, script), "--duration", duration, "--seed", str(seed), "--log", str(out)]
    if mission:
        command += ["--mission", os.path.join(ROOT, mission)]
    result = subprocess.run(command, capture_output=True, text=True)
    assert result.returncode in (0, 5), result.stderr
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    return rows, result


def cli_dba_sizes(gloc_bin, tmp_path, script, mission, duration, seed):
    out = tmp_path / "run.dba"
    command = [gloc_bin, "run", os.path.join(ROOT, script), "--duration", duration, "--seed", str(seed), "--log", str(out)]
    if mission:
        command += ["--mission", os.path.join(ROOT, mission)]
    subprocess.run(command, capture_output=True, text=True)
    lines = out.read_text().splitlines()
    # 14 tag lines, then names, units, bytes.
    return [int(size) for size in lines[16].split()]


@pytest.mark.parametrize("script,mission,duration,seed", RUNS)
def test_run_log_equals_the_cli_log(gloc_bin, tmp_path, script, mission, duration, seed):
    rows, result = cli_log(gloc_bin, tmp_path, script, mission, duration, seed)
    log, summary = gloc.run(
        os.path.join(ROOT, script),
        mission=os.path.join(ROOT, mission) if mission else None,
        duration=seconds(duration),
        seed=seed,
    )
    assert list(log.columns) == rows[0]
    assert len(log) == len(rows) - 1 == summary["cycles"]
    # Which columns the log holds as 4-byte floats: the `.dba` header's bytes line
    # of the same run on the command line.
    sizes = cli_dba_sizes(gloc_bin, tmp_path, script, mission, duration, seed)
    assert log.attrs["bytes"] == dict(zip(rows[0], sizes))
    for position, name in enumerate(rows[0]):
        # The CSV holds each value as the shortest text that reads back as the
        # value the log holds: read a 4-byte column as float32 (lossless), then
        # widen, as tests/e2e/dbd/compare.py does.
        cells = [row[position] for row in rows[1:]]
        if sizes[position] == 4:
            expected = numpy.array([numpy.float32(c) for c in cells], dtype=numpy.float32).astype(numpy.float64)
        else:
            expected = numpy.array([float(c) for c in cells])
        assert numpy.array_equal(log[name].to_numpy(), expected, equal_nan=True), name
    # The script's output is the CLI's stdout, line for line.
    assert summary["printed"] == result.stdout.splitlines()


def test_run_summary_says_what_the_cli_summary_says(gloc_bin):
    """The end and the energy by consumer, against the lines `gloc run` prints
    (`mission end   completed at cycle N`, `by consumer   hotel 2.1 kJ, …`)."""
    script = os.path.join(ROOT, "examples/fig2.gloc")
    result = subprocess.run([gloc_bin, "run", script, "--seed", "1"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    end = re.search(r"^mission end\s+completed at cycle (\d+)", result.stderr, re.MULTILINE)
    consumers = re.search(
        r"^by consumer\s+hotel ([0-9.]+) kJ, pump ([0-9.]+) kJ, pitch ([0-9.]+) kJ, science ([0-9.]+) kJ",
        result.stderr,
        re.MULTILINE,
    )
    assert end and consumers, result.stderr
    log, summary = gloc.run(script, seed=1)
    assert summary["end"] is not None and "complete" in summary["end"].lower()
    assert summary["end_cycle"] == int(end.group(1))
    energy = summary["energy_joules"]
    for name, printed in zip(("hotel", "pump", "pitch", "science"), consumers.groups()):
        # The CLI prints kJ to one decimal.
        assert round(energy[name] / 1000, 1) == float(printed), name
    assert energy["total"] == pytest.approx(sum(energy[name] for name in ("hotel", "pump", "pitch", "science")))


def test_simulator_constants_change_the_run():
    script = os.path.join(ROOT, "examples/fig2.gloc")
    plain, _ = gloc.run(script, duration=600, seed=1)
    heavy, _ = gloc.run(script, duration=600, seed=1, sim={"drag_cd0": 0.6})
    assert not plain["m_depth"].equals(heavy["m_depth"])


def test_a_script_with_errors_raises(tmp_path):
    bad = tmp_path / "bad.gloc"
    bad.write_text("nregs 1\nnblbs 2\nninstr 5\nlabel 0\nyield\njumpi 0\nlabel 0\njumpi 0\n")
    with pytest.raises(gloc.ProjectError, match="E0103"):
        gloc.run(str(bad))


def test_an_unknown_simulator_constant_raises():
    with pytest.raises(gloc.ProjectError, match="not_a_constant"):
        gloc.run(os.path.join(ROOT, "examples/fig2.gloc"), sim={"not_a_constant": 1.0})


def test_calibrate_gives_the_constants_gloc_calibrate_writes(gloc_bin):
    path = os.path.join(DATA, "comet/from-glider/comet-2019-222-02-154.dbd")
    cache = os.path.join(DATA, "cac")
    result = subprocess.run([gloc_bin, "calibrate", path, "--sensor-cache", cache], capture_output=True, text=True, check=True)
    table = {}
    for line in result.stdout.splitlines():
        match = re.match(r"^(\w+)\s*=\s*([-+0-9.eE]+)", line)
        if match:
            table[match.group(1)] = float(match.group(2))
    fitted = gloc.calibrate(path, sensor_cache=cache)
    assert len(table) > 10
    assert set(fitted) == set(table)
    not_fitted = re.findall(r"^not fitted\s+(\w+):", result.stderr, re.MULTILINE)
    assert set(fitted.not_fitted) == set(not_fitted)
    for name, value in fitted.items():
        # The table prints each value rounded; the dict holds the fit.
        assert value == pytest.approx(table[name], rel=1e-3, abs=1e-6), name
    assert all(fitted.sources[name] for name in fitted)
