"""`gloc run --log run.dbd` writes what dbdreader reads, with the same values.

The same seeded run is logged twice: as CSV by gloc's text logger (every sensor
every cycle) and as run.dbd + run.ebd (+ their .cac) by the binary writer (only
changed values). dbdreader (PyPI, pinned) reads the binary files; for every
sensor, its samples must be exactly the CSV's changes: each sample's time and
value equal the CSV row at that time, and between samples the CSV value does
not change. Values of 4-byte sensors compare as float32 (the glider's size).

Usage: python roundtrip.py GLOC_BIN REPO_DIR
"""

import csv
import os
import subprocess
import sys
import tempfile

import numpy
import dbdreader


SENSORS = ",".join([
    "m_present_time", "m_cycle_number", "m_depth", "m_pitch", "c_pitch", "m_ballast_pumped",
    "m_battery", "m_coulomb_amphr_total", "sci_m_present_time", "sci_water_temp",
    "sci_water_pressure", "sci_ruhp_behs", "sci_ruhp_dive_depth", "sci_ruhp_climb_depth",
])


def run(gloc, repo, log):
    subprocess.run(
        # The tracker in its own mission: in the default Fig. 2 mission it aborts for
        # overdepth, which gloc run reports with exit 5.
        [gloc, "run", os.path.join(repo, "examples/thermocline.gbas"),
         "--mission", os.path.join(repo, "examples/thermocline.mi"),
         "--duration", "2h", "--seed", "7", "--log", log, "--log-sensors", SENSORS],
        check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )


def main():
    gloc, repo = sys.argv[1], sys.argv[2]
    failed = []
    with tempfile.TemporaryDirectory() as work:
        run(gloc, repo, os.path.join(work, "run.csv"))
        run(gloc, repo, os.path.join(work, "run.dbd"))
        with open(os.path.join(work, "run.csv"), newline="") as f:
            rows = list(csv.reader(f))
        header, rows = rows[0], rows[1:]
        checked = 0
        for name in ("run.dbd", "run.ebd"):
            dbd = dbdreader.DBD(os.path.join(work, name), cacheDir=work, skip_initial_line=False)
            names = list(dbd.parameterNames)
            sizes = dict(zip(names, dbd.byteSizes))
            pairs = dbd.get(*names, decimalLatLon=False, discardBadLatLon=False)
            time_name = dbd.timeVariable
            csv_time = numpy.array([float(row[header.index(time_name)]) for row in rows])
            for sensor, (t, v) in zip(names, pairs):
                column = header.index(sensor)
                kind = numpy.float32 if sizes[sensor] == 4 else numpy.float64
                series = numpy.array([kind(row[column]) for row in rows]).astype(numpy.float64)
                # The cycles where the value changed: the first, and every change.
                changed = numpy.concatenate(([True], series[1:] != series[:-1]))
                expected_t, expected_v = csv_time[changed], series[changed]
                checked += len(v)
                if not (numpy.array_equal(t, expected_t) and numpy.array_equal(v, expected_v, equal_nan=True)):
                    failed.append(f"{name} {sensor}: dbdreader {len(v)} samples, CSV changes {len(expected_v)}")
            dbd.close()
        if failed:
            print("FAILED roundtrip:")
            for line in failed:
                print(" ", line)
            return 1
        print(f"ok roundtrip: {checked} samples from run.dbd/run.ebd read by dbdreader equal the CSV log of the same run")
        return 0


if __name__ == "__main__":
    sys.exit(main())
