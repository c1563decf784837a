"""gloc from Python: Slocum glider logs as pandas DataFrames, script checks and
compiles, simulated runs and calibration.

Every function calls the gloc library crates through the native module
``gloc._native`` (the same code as the ``gloc`` command line); this file only turns
what it returns into DataFrames, dataclasses and exceptions.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Iterable, Optional, Sequence, Tuple, Union

import numpy
import pandas

from . import _native

__all__ = [
    "Diagnostic",
    "LogError",
    "ProjectError",
    "CompileError",
    "read",
    "to_xarray",
    "check",
    "compile",
    "run",
    "calibrate",
    "forecast",
    "Forecast",
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


def to_xarray(frame: pandas.DataFrame):
    """A DataFrame of :func:`read` (or :func:`run`'s log) as an ``xarray.Dataset``
    along ``time``: each sensor a variable with its ``units`` and ``bytes`` (what
    the value takes in the file) as attributes, the time coordinate in Unix
    seconds (``units = "seconds since 1970-01-01T00:00:00Z"``, CF), and the
    frame's ``time_sensor`` and ``warnings`` as the Dataset's attributes. The
    values are not copied where numpy can share them. Needs xarray."""
    import xarray

    units = frame.attrs.get("units", {})
    sizes = frame.attrs.get("bytes", {})
    variables = {}
    for name in frame.columns:
        attrs = {}
        if units.get(name):
            attrs["units"] = units[name]
        if name in sizes:
            attrs["bytes"] = int(sizes[name])
        variables[name] = xarray.Variable("time", frame[name].to_numpy(), attrs)
    time = xarray.Variable(
        "time",
        numpy.asarray(frame.index, dtype=numpy.float64),
        {"units": "seconds since 1970-01-01T00:00:00Z", "standard_name": "time"},
    )
    attrs = {}
    if frame.attrs.get("time_sensor"):
        attrs["time_sensor"] = frame.attrs["time_sensor"]
    if frame.attrs.get("warnings"):
        attrs["warnings"] = "\n".join(frame.attrs["warnings"])
    return xarray.Dataset(variables, coords={"time": time}, attrs=attrs)


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


_SURFACING_COLUMNS = [
    "time",
    "lat",
    "lon",
    "waypoint_lat",
    "waypoint_lon",
    "distance_to_waypoint",
    "underwater",
    "estimate_u",
    "estimate_v",
]


@dataclass
class Forecast:
    """A forecast from the end of a glider's logs, as ``gloc forecast`` makes it.
    Times are Unix seconds, positions decimal degrees.

    - ``start``: the last fix and the state there (``time``, ``lat``, ``lon``,
      ``believed`` current, ``waypoint``, ``avg_speed``, ``amp_hours``, ``battery``).
    - ``track``: the forecast track (a point a minute), index ``time``; columns
      ``lat``, ``lon``, ``depth``. ``surfacings``: the predicted first fixes after
      each dive (index ``number`` from 1). ``fixes``: the GPS fixes in the logs.
    - With ``members``: ``members`` each member's track (a point an hour), columns
      ``member, time, lat, lon, depth``; ``member_surfacings`` likewise
      (``member, number, time, lat, lon, ...``); ``offsets`` each member's current
      offset (m/s, ``u`` east, ``v`` north); ``regions`` per hour the convex hull of
      the members (``lat``, ``lon`` arrays, counter-clockwise) and how many members;
      ``surfacing_spread`` per surfacing the members' spread (``radius_95``,
      ``radius_max`` in m from the mean); ``left_grid`` ``{member: message}`` for
      members that left the current or bathymetry grid.
    - ``warnings``: what setting the flight up warned of, as ``gloc forecast``
      prints it on stderr (a mission setting the sensor list lacks, …).
    """

    start: dict
    mission: str
    current: str
    hours: float
    track: pandas.DataFrame
    surfacings: pandas.DataFrame
    ended: Optional[str]
    amp_hours_used: float
    fixes: pandas.DataFrame
    spread: Tuple[float, float]
    seed: int
    warnings: list = field(default_factory=list)
    members: Optional[pandas.DataFrame] = None
    member_surfacings: Optional[pandas.DataFrame] = None
    offsets: Optional[pandas.DataFrame] = None
    regions: Optional[pandas.DataFrame] = None
    surfacing_spread: Optional[pandas.DataFrame] = None
    left_grid: dict = field(default_factory=dict)


def _track_frames(track) -> Tuple[pandas.DataFrame, pandas.DataFrame]:
    points, surfacings, _, _, _ = track
    frame = pandas.DataFrame(
        numpy.asarray(points, dtype=numpy.float64).reshape(-1, 4),
        columns=["time", "lat", "lon", "depth"],
    ).set_index("time")
    up = pandas.DataFrame(
        numpy.asarray(surfacings, dtype=numpy.float64).reshape(-1, len(_SURFACING_COLUMNS)),
        columns=_SURFACING_COLUMNS,
    )
    up.index = pandas.RangeIndex(1, len(up) + 1, name="number")
    return frame, up


def _members_frames(tracks: list) -> Tuple[pandas.DataFrame, pandas.DataFrame]:
    """Every member's points and surfacings, long form (a ``member`` column)."""
    points, surfacings, point_of, surfacing_of = [], [], [], []
    for number, (track_points, track_surfacings, _, _, _) in enumerate(tracks):
        points.extend(track_points)
        surfacings.extend(track_surfacings)
        point_of.extend([number] * len(track_points))
        surfacing_of.extend((number, index) for index in range(1, len(track_surfacings) + 1))
    members = pandas.DataFrame(
        numpy.asarray(points, dtype=numpy.float64).reshape(-1, 4),
        columns=["time", "lat", "lon", "depth"],
    )
    members.insert(0, "member", numpy.asarray(point_of, dtype=numpy.int64))
    up = pandas.DataFrame(
        numpy.asarray(surfacings, dtype=numpy.float64).reshape(-1, len(_SURFACING_COLUMNS)),
        columns=_SURFACING_COLUMNS,
    )
    up.insert(0, "member", numpy.asarray([m for m, _ in surfacing_of], dtype=numpy.int64))
    up.insert(1, "number", numpy.asarray([n for _, n in surfacing_of], dtype=numpy.int64))
    return members, up


def _summary_frames(summary: dict) -> dict:
    offsets = pandas.DataFrame(
        numpy.asarray(summary["offsets"], dtype=numpy.float64).reshape(-1, 2), columns=["u", "v"]
    )
    offsets.index.name = "member"
    regions = pandas.DataFrame(
        {
            "time": [time for _, time, _, _ in summary["regions"]],
            "members": [count for _, _, count, _ in summary["regions"]],
            "lat": [numpy.array([p[0] for p in hull]) for _, _, _, hull in summary["regions"]],
            "lon": [numpy.array([p[1] for p in hull]) for _, _, _, hull in summary["regions"]],
        },
        index=pandas.Index([hour for hour, _, _, _ in summary["regions"]], name="hour"),
    )
    names = ["members", "earliest", "latest", "mean_time", "mean_lat", "mean_lon",
             "radius_95", "radius_max"]
    spread = pandas.DataFrame(
        [entry[1:9] for entry in summary["surfacings"]],
        columns=names,
        index=pandas.Index([entry[0] for entry in summary["surfacings"]], name="number"),
    )
    spread["hull_lat"] = [numpy.array([p[0] for p in entry[9]]) for entry in summary["surfacings"]]
    spread["hull_lon"] = [numpy.array([p[1] for p in entry[9]]) for entry in summary["surfacings"]]
    return {
        "offsets": offsets,
        "regions": regions,
        "surfacing_spread": spread,
        "left_grid": dict(summary["left_grid"]),
    }


def _fly_chunk(asked: dict, first: int, last: int) -> list:
    """A Dask task: members ``first..last`` flown by the native code in the worker."""
    return _call(_native.forecast_members, asked, first, last)


def _chunks(members: int, count: int) -> list:
    """``0..members`` in ``count`` consecutive ranges of nearly equal size."""
    count = max(1, min(count, members))
    edges = [members * index // count for index in range(count + 1)]
    return [(edges[i], edges[i + 1]) for i in range(count) if edges[i] < edges[i + 1]]


def forecast(
    logs: Union[PathLike, Iterable[PathLike]],
    mission: PathLike,
    hours: float = 12.0,
    currents: Optional[PathLike] = None,
    members: int = 0,
    seed: int = 1,
    spread: Optional[Union[float, Tuple[float, float]]] = None,
    client: Any = None,
    chunks: Optional[int] = None,
    threads: Optional[int] = None,
    bathymetry: Optional[PathLike] = None,
    sensor_cache: Optional[PathLike] = None,
    sim: Optional[dict] = None,
) -> Forecast:
    """Where will the glider be? ``gloc forecast``: from the last fix of ``logs``
    (one deployment, as :func:`read` takes it), ``mission`` (``.mi``) flown ahead
    ``hours`` (up to 720) in the simulator, in ``currents`` (an ocean model's
    NetCDF ``.nc`` or a CSV ``time,u,v``; default: the glider's own latest
    estimate). ``members`` > 0 flies a seeded ensemble over the current's
    uncertainty (σ ``spread`` m/s, one value or ``(east, north)``; default: the
    spread of the logs' own estimates, at least 0.02), with the hourly regions.

    Without ``client`` the members fly on this machine's threads (``threads``,
    default every core), in the native code. ``client="local"`` starts a Dask
    ``LocalCluster`` of one worker process per core (``threads``, default every
    core), flies on it and closes it. With ``client`` (a
    ``dask.distributed.Client``) they are split into ``chunks`` consecutive ranges
    (default four per worker thread), each flown by the native code in a worker;
    a member depends only on ``seed`` and its number, so any split (threads,
    workers, chunks) gives the same members. The workers read ``logs``,
    ``mission`` and ``currents`` by their paths: on a cluster, a shared file
    system. ``sim``, ``sensor_cache``, ``bathymetry`` as for ``gloc forecast``.
    Returns a :class:`Forecast`."""
    if isinstance(client, str):
        if client != "local":
            raise ValueError(
                f"client={client!r}: give a dask.distributed.Client, \"local\" (a LocalCluster "
                "on this machine) or None (this machine's threads)"
            )
        import distributed

        workers = threads or os.cpu_count() or 1
        with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster, \
                distributed.Client(cluster) as local:
            return forecast(logs, mission, hours=hours, currents=currents, members=members,
                            seed=seed, spread=spread, client=local, chunks=chunks,
                            threads=threads, bathymetry=bathymetry,
                            sensor_cache=sensor_cache, sim=sim)
    if spread is not None and not isinstance(spread, (tuple, list)):
        spread = (float(spread), float(spread))
    asked = {
        "logs": [os.path.abspath(path) for path in _paths(logs)],
        "mission": os.path.abspath(os.fspath(mission)),
        "hours": float(hours),
        "currents": os.path.abspath(os.fspath(currents)) if currents is not None else None,
        "bathymetry": os.path.abspath(os.fspath(bathymetry)) if bathymetry is not None else None,
        "sensor_cache": os.path.abspath(os.fspath(sensor_cache)) if sensor_cache is not None else None,
        "simulator": [(str(name), float(value)) for name, value in (sim or {}).items()],
        "members": int(members),
        "seed": int(seed),
        "spread": (float(spread[0]), float(spread[1])) if spread is not None else None,
    }
    if asked["members"] < 0:
        raise ValueError(f"members={members}: give 0 (no ensemble) or more")
    here = 0 if client is not None else (threads or os.cpu_count() or 1)
    made = _call(_native.forecast, asked, here)
    tracks = made.get("members")
    summary = made.get("ensemble")
    if client is not None and asked["members"] > 0:
        # The spread the first call settled on, so every chunk flies the same members.
        asked["spread"] = made["spread"]
        if chunks is None:
            chunks = 4 * max(1, sum(client.nthreads().values()))
        futures = [
            client.submit(_fly_chunk, asked, first, last, pure=False)
            for first, last in _chunks(asked["members"], int(chunks))
        ]
        tracks = [track for chunk in client.gather(futures) for track in chunk]
        summary = _call(_native.forecast_summary, asked, tracks)
    track, surfacings = _track_frames(made["track"])
    fixes = pandas.DataFrame(
        numpy.asarray(made["fixes"], dtype=numpy.float64).reshape(-1, 3),
        columns=["time", "lat", "lon"],
    )
    result = Forecast(
        start=made["start"],
        mission=made["mission"],
        current=made["current"],
        hours=made["hours"],
        track=track,
        surfacings=surfacings,
        ended=made["track"][2],
        amp_hours_used=made["track"][3],
        fixes=fixes,
        spread=tuple(made["spread"]),
        seed=asked["seed"],
        warnings=list(made["warnings"]),
    )
    if tracks is not None:
        result.members, result.member_surfacings = _members_frames(tracks)
        frames = _summary_frames(summary)
        result.offsets = frames["offsets"]
        result.regions = frames["regions"]
        result.surfacing_spread = frames["surfacing_spread"]
        result.left_grid = frames["left_grid"]
    return result
