"""gloc from Python: Slocum glider logs as pandas DataFrames, script checks and
compiles, simulated runs and calibration.

Every function calls the gloc library crates through the native module
``gloc._native`` (the same code as the ``gloc`` command line); this file only turns
what it returns into DataFrames, dataclasses and exceptions.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Iterable, Optional, Sequence, Union

import numpy
import pandas

from . import _native

__all__ = [
    "Diagnostic",
    "LogError",
    "ProjectError",
    "CompileError",
    "read",
    "check",
    "compile",
    "run",
    "calibrate",
]

PathLike = Union[str, "os.PathLike[str]"]


class LogError(Exception):
    """A glider log that cannot be read: ``file``, ``offset`` (a byte offset; for a
    compressed file, of the decompressed data) and ``block`` (the file offset of the
    LZ4 block, or None). ``kind`` is ``"content"`` (bad bytes) or ``"unreadable"``
    (a file or sensor list that cannot be opened), the two exit codes of ``gloc``."""

    def __init__(self, message: str, file: str, offset: int, block: Optional[int], kind: str):
        super().__init__(message)
        self.file = file
        self.offset = offset
        self.block = block
        self.kind = kind


class ProjectError(Exception):
    """Settings, a sensor list, a script or a mission that cannot be used."""


@dataclass(frozen=True)
class Diagnostic:
    """One finding of the checker: ``line`` and ``column`` count from 1 (columns in
    characters), as ``gloc check`` prints them."""

    code: str
    severity: str
    message: str
    line: int
    column: int
    end_line: int
    end_column: int
    help: Optional[str] = None


class CompileError(Exception):
    """A GBASIC script with errors; ``diagnostics`` lists them."""

    def __init__(self, message: str, diagnostics: list):
        super().__init__(message)
        self.diagnostics = diagnostics


def _paths(paths: Union[PathLike, Iterable[PathLike]]) -> list:
    if isinstance(paths, (str, os.PathLike)):
        return [os.fspath(paths)]
    return [os.fspath(path) for path in paths]


def _call(function, *args, **kwargs):
    """Calls the native module, its exceptions turned into this module's."""
    try:
        return function(*args, **kwargs)
    except _native.LogError as error:
        raise LogError(*error.args) from None
    except _native.ProjectError as error:
        raise ProjectError(*error.args) from None


def _frame(names: list, rows: int, data: bytes) -> pandas.DataFrame:
    """Column-major f64 bytes as a DataFrame (no copy of the values)."""
    values = numpy.frombuffer(data, dtype=numpy.float64).reshape(len(names), rows)
    return pandas.DataFrame(
        {name: values[column] for column, name in enumerate(names)}, copy=False
    )


def read(
    paths: Union[PathLike, Iterable[PathLike]],
    sensors: Optional[Sequence[str]] = None,
    sensor_cache: Optional[PathLike] = None,
) -> pandas.DataFrame:
    """Reads glider logs (``.dbd .ebd .sbd .tbd .mbd .nbd``, compressed ``.dcd
    .ecd …``, ``.dba``) into one DataFrame, one row per cycle, NaN where a cycle did
    not update a sensor. Several files are merged as ``gloc data convert`` and the
    replay merge them: a flight log with its science log, segments in time order.

    The index is the time sensor (``m_present_time``, else ``sci_m_present_time``,
    Unix seconds), named ``time``; NaN for a cycle that did not update it. Units are
    in ``df.attrs["units"]`` and the bytes each value takes in the file in
    ``df.attrs["bytes"]``; warnings (a truncated last cycle) in
    ``df.attrs["warnings"]``. ``sensor_cache`` is the folder of sensor lists
    (``.cac``/``.ccc``), searched first, as ``gloc data --sensor-cache``.
    Raises :class:`LogError` with the file and byte offset.
    """
    cache = os.fspath(sensor_cache) if sensor_cache is not None else None
    wanted = list(sensors) if sensors is not None else None
    names, units, sizes, rows, data, times, time_name, warnings = _call(
        _native.read, _paths(paths), wanted, cache
    )
    # Row-major values: one 2-D block, which pandas takes without a copy.
    values = data.reshape(rows, len(names))
    frame = pandas.DataFrame(values, columns=names, copy=False)
    frame.index = pandas.Index(times, name="time")
    frame.attrs["time_sensor"] = time_name
    frame.attrs["units"] = dict(zip(names, units))
    frame.attrs["bytes"] = dict(zip(names, sizes))
    frame.attrs["warnings"] = list(warnings)
    return frame


def _script_arguments(path_or_text: Union[PathLike, str]) -> dict:
    """A path when it names a file, else the script's text."""
    if isinstance(path_or_text, os.PathLike) or (
        isinstance(path_or_text, str) and "\n" not in path_or_text and os.path.isfile(path_or_text)
    ):
        return {"path": os.fspath(path_or_text)}
    return {"text": path_or_text}


def check(path_or_text: Union[PathLike, str], gbasic: Optional[bool] = None) -> list:
    """The diagnostics ``gloc check`` gives a script: a path (``.gloc``, ``.gbas``;
    the gloc.toml above it applies) or the script's text (GLOC unless
    ``gbasic=True``). Returns a list of :class:`Diagnostic`."""
    found = _call(_native.check, gbasic=gbasic, **_script_arguments(path_or_text))
    return [Diagnostic(*entry) for entry in found]


def compile(path_or_text: Union[PathLike, str], optimize: bool = False) -> str:
    """GBASIC to GLOC, as ``gloc compile`` (``-O`` with ``optimize=True``): the GLOC
    text. Raises :class:`CompileError` with the diagnostics when the script has
    errors."""
    text, found = _call(_native.compile, optimize=optimize, **_script_arguments(path_or_text))
    diagnostics = [Diagnostic(*entry) for entry in found]
    if text is None:
        errors = [d for d in diagnostics if d.severity == "error"]
        first = errors[0] if errors else None
        where = f"{first.line}:{first.column}: {first.code} {first.message}" if first else ""
        raise CompileError(f"{len(errors)} error(s); no GLOC: {where}", diagnostics)
    return text


def run(
    script: PathLike,
    mission: Optional[PathLike] = None,
    duration: Optional[float] = None,
    cycles: Optional[int] = None,
    seed: Optional[int] = None,
    sim: Optional[dict] = None,
    profile: Optional[PathLike] = None,
    optimize: bool = True,
):
    """Flies ``script`` on ``mission`` (the embedded Fig. 2 mission, or gloc.toml's,
    when None) as ``gloc run`` does: ``duration`` in seconds (or ``cycles``; default
    24 h), ``seed``, ``sim`` simulator constants (``{"fin_gain": 2.0}``, as
    ``gloc run --sim``), ``profile`` a temperature-profile CSV, ``optimize=False`` as
    ``--no-optimize``.

    Returns ``(log, summary)``: the log a DataFrame of the columns ``gloc run --log``
    writes, one row per cycle, each value as the log holds it (4-byte floats but for
    timestamps and positions; ``log.attrs["bytes"]`` says which), indexed by
    ``m_present_time``; the summary a dict
    (cycles, seconds, end, end_cycle, energy_joules by consumer, warnings,
    printed: the lines the script printed)."""
    constants = [(str(name), float(value)) for name, value in (sim or {}).items()]
    names, sizes, rows, data, summary, printed = _call(
        _native.run,
        os.fspath(script),
        os.fspath(mission) if mission is not None else None,
        float(duration) if duration is not None else None,
        cycles,
        seed,
        constants,
        os.fspath(profile) if profile is not None else None,
        optimize,
    )
    log = _frame(names, rows, data)
    log.attrs["bytes"] = dict(zip(names, sizes))
    if "m_present_time" in names:
        log.index = log["m_present_time"].to_numpy()
        log.index.name = "time"
    summary["printed"] = list(printed)
    return log, summary


def calibrate(
    paths: Union[PathLike, Iterable[PathLike]],
    sensor_cache: Optional[PathLike] = None,
    climb_target: float = 3.0,
) -> dict:
    """The simulator constants ``gloc calibrate`` fits from a glider's logs,
    ``{name: value}`` (the names of ``[simulator]`` in gloc.toml and of ``run``'s
    ``sim``). ``climb_target`` is the yo's ``c_target_depth`` (m). What each value
    was fitted from, and what could not be fitted, are in the attributes ``sources``
    and ``not_fitted`` of the returned dict."""
    cache = os.fspath(sensor_cache) if sensor_cache is not None else None
    fitted, not_fitted = _call(_native.calibrate, _paths(paths), cache, float(climb_target))
    constants = Calibration({name: value for name, value, _ in fitted})
    constants.sources = {name: source for name, _, source in fitted}
    constants.not_fitted = dict(not_fitted)
    return constants


class Calibration(dict):
    """Fitted constants, ``{name: value}``; ``sources``: what each was fitted from;
    ``not_fitted``: ``{name: why}``."""

    sources: dict
    not_fitted: dict
