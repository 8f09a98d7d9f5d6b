"""Design sweeps of the linear engine (``rodstab sweep``), serial or on dask.distributed.

The critical load factor of a design while one design value varies. Each value is a *point*:
an independent design (:func:`design_at`: :func:`rodstab.io.vary.set_design_value` validated by
:func:`rodstab.io.design.parse_design`) and one linear stability solve
(:func:`rodstab.linear.solve.linear_stability`). Nothing is carried from one point to the
next, so the points are independent tasks, run where :mod:`rodstab.executor` says: in this
process, or on the workers of a dask.distributed cluster. Both run the same function
(:func:`solve_points`), so the numbers do not depend on where they were computed.

A point that fails is a row like the others, with its ``status`` and the reason in ``error``,
and the sweep goes on: :data:`INVALID` (the design is invalid at that value, or too large for
the limits: :class:`~rodstab.errors.RodstabInputError`) or :data:`NOT_CONVERGED` (the eigen
solve's residual is above its tolerance, or it raised
:class:`~rodstab.errors.NotConverged`). Any other exception is a bug and stops the sweep.

With an output directory (``--out DIR``, :func:`open_table`):

* ``DIR/run.json`` -- what is swept: the design's data, the key, the values, the elements.
  Written first. A rerun into ``DIR`` resumes only the same sweep; another one is refused,
  naming the difference (``restart=True``, ``--restart``: start afresh).
* ``DIR/sweep.csv`` -- one row per completed point (:func:`columns`), appended and flushed as
  each task completes (so in completion order); rewritten in point order once every point is
  done. A killed sweep keeps the rows of every completed task (at most a partial last line,
  which the rerun drops); the rerun solves only the missing points.

CSV, not Parquet, is the streamed table: a CSV grows by appending lines and whatever a kill
leaves is readable up to its last complete line, while a Parquet file is readable only once
its footer is written (streaming it would mean a file per task and a merge). ``parquet=True``
(``--parquet``) also writes ``DIR/sweep.parquet`` from the finished table.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import functools
import io
import json
import math
import os
import sys
import time
import types
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .errors import NotConverged, RodstabInputError, require_finite, require_positive_int
from .executor import check_workers, run_points, task_size
from .io.design import SWEEP_DEFAULT_N, Design, load_design
from .io.vary import design_at, parse_vary, set_design_value
from .limits import DEFAULT as DEFAULT_LIMITS
from .limits import Limits, require_steps
from .linear.solve import converged_stability
from .results import Result

if TYPE_CHECKING:
    import pandas as pd

#: Status of a point: solved; its design invalid (or too large) at its value; not converged.
OK = "ok"
INVALID = "invalid"
NOT_CONVERGED = "not_converged"
STATUSES = (OK, INVALID, NOT_CONVERGED)
#: The solver's outputs in a row, after ``index``, the varied key and ``status``.
COLUMNS = ("load_factor_critical", "load_factor_lower", "multiplicity",
           "paper_load_factor_critical", "residual")
#: The column of a design with units: |natural curvature| (1/m) of the load-factor segment at
#: the critical load factor.
PHYSICAL_COLUMN = "critical_natural_curvature_per_m"
#: Files of a sweep's output directory.
RUN_FILE = "run.json"
CSV_FILE = "sweep.csv"
PARQUET_FILE = "sweep.parquet"
#: Identifies a run.json written by this module (and its layout).
RUN_FORMAT = "rodstab sweep 1"
#: The engine and method of every point, for results and tables.
METHOD = "linear_stability at each value (FE of P2, eq 2.12)"


def columns(key: str, physical: bool = False) -> tuple[str, ...]:
    """Return the columns of a sweep's table of ``key``, in order.

    ``index`` (the point's position in the sweep, from 0), ``key`` (its value), ``status``
    (:data:`STATUSES`), the solver's outputs (:data:`COLUMNS`; empty for an invalid point),
    ``seconds`` (wall-clock time of the point's solve where it ran) and ``error`` (why it
    failed; empty if it did not); for a design with units (``physical``) then
    :data:`PHYSICAL_COLUMN`.
    """
    return ("index", key, "status", *COLUMNS, "seconds", "error",
            *((PHYSICAL_COLUMN,) if physical else ()))


@dataclasses.dataclass(frozen=True)
class SweepRow(Result):
    """One point of a sweep: the linear stability of the design at one value of the key.

    The outputs of a point whose design is invalid are NaN (``multiplicity`` None); a point
    that did not converge keeps the numbers the solver gave (not to be trusted).
    """

    index: int
    value: float
    status: str
    load_factor_critical: float
    load_factor_lower: float
    multiplicity: int | None
    paper_load_factor_critical: float
    residual: float
    seconds: float
    error: str
    #: |natural curvature| (1/m) of the load-factor segment at the critical load factor, for
    #: a design with units (None without units, or for a failed point).
    critical_natural_curvature: float | None = None

    @property
    def converged(self) -> bool:
        """True when the point was solved and its eigen solve converged (status ``ok``)."""
        return self.status == OK

    def record(self, key: str, physical: bool = False) -> dict[str, Any]:
        """Return the row as the CLI's CSV/JSON record, in :func:`columns` order."""
        out = {"index": self.index, key: self.value, "status": self.status} \
            | {c: getattr(self, c) for c in COLUMNS} \
            | {"seconds": self.seconds, "error": self.error}
        if physical:
            out[PHYSICAL_COLUMN] = self.critical_natural_curvature
        return out


@dataclasses.dataclass(frozen=True)
class SweepResult(Result):
    """A sweep of ``key``: one :class:`SweepRow` per value, in the order of the values.

    ``executor`` says where this run solved its points; ``resumed`` counts the rows read
    back from an earlier run's table instead.
    """

    key: str
    rows: tuple[SweepRow, ...]
    elements_per_segment: int | None
    method: str
    executor: str
    resumed: int
    #: Rows carry :data:`PHYSICAL_COLUMN` (a design with units).
    physical: bool = False

    @property
    def converged(self) -> bool:
        """True when every point was solved and converged."""
        return all(r.converged for r in self.rows)

    def failed(self, status: str) -> list[SweepRow]:
        """Return the rows whose status is ``status`` (:data:`INVALID`, :data:`NOT_CONVERGED`)."""
        return [r for r in self.rows if r.status == status]

    def table(self) -> list[dict[str, Any]]:
        """Return the rows as the CLI's CSV/JSON records (:meth:`SweepRow.record`)."""
        return [r.record(self.key, self.physical) for r in self.rows]

    def frame(self) -> pd.DataFrame:
        """Return the table as a pandas DataFrame, one row per point, :func:`columns` order.

        ``multiplicity`` is a nullable integer (``<NA>`` for an invalid point), the outputs of
        an invalid point NaN. ``attrs`` holds ``key``, ``executor`` and ``resumed``.
        """
        pd = _require("pandas", "a sweep's DataFrame")
        df = pd.DataFrame(self.table(), columns=list(columns(self.key, self.physical)))
        df["multiplicity"] = df["multiplicity"].astype("Int64")
        for c in ("load_factor_critical", "load_factor_lower", "paper_load_factor_critical",
                  "residual"):
            df[c] = df[c].astype(float)
        df.attrs.update(key=self.key, executor=self.executor, resumed=self.resumed)
        return df


def _one_line(exc: BaseException) -> str:
    """Return the exception's message on one line (a CSV row is one line, :func:`open_table`)."""
    return " ".join(str(exc).split()) or type(exc).__name__


def _check_key(design: Design, key: str, values: Sequence[float], unit: str | None) -> None:
    """Raise the error of the first value unless ``key`` takes some value of ``values``.

    An unknown key makes every value fail: refused before anything runs, not recorded as a
    table of failed points; so is a sweep none of whose values the key can take.
    """
    first: RodstabInputError | None = None
    for v in values:
        try:
            set_design_value(design.raw, key, v, unit)
            return
        except RodstabInputError as exc:
            first = first or exc
    assert first is not None  # values is not empty
    raise first


def solve_point(design: Design, key: str, elements: int | None, limits: Limits, index: int,
                value: float, unit: str | None = None) -> SweepRow:
    """Solve one point: the design with ``key`` set to ``value``; failures become its status.

    Parameters
    ----------
    design : Design
        The base design.
    key : str
        The varied key.
    elements : int or None
        Elements per segment (None: each modified design's own).
    limits : Limits
        Size limits of the solve.
    index : int
        The point's position in the sweep.
    value : float
        The key's value.
    unit : str, optional
        Its unit (a design with units).

    Returns
    -------
    SweepRow
        Status :data:`OK`, :data:`INVALID` (``RodstabInputError``: the message in ``error``)
        or :data:`NOT_CONVERGED` (``NotConverged`` raised, or the residual above tolerance).
    """
    nan = math.nan
    t0 = time.perf_counter()
    try:
        d = design_at(design, key, value, unit)
        # the mesh policy of `analyze`: one given (--elements, [analysis] elements) is kept,
        # otherwise refined to the FE's stated accuracy
        r = converged_stability(d.assembly, d.elements if elements is None else elements,
                                refine=elements is None and not d.elements_given,
                                limits=limits)
    except (RodstabInputError, NotConverged) as exc:
        status = INVALID if isinstance(exc, RodstabInputError) else NOT_CONVERGED
        return SweepRow(index, value, status, nan, nan, None, nan, nan,
                        time.perf_counter() - t0, _one_line(exc))
    seconds = time.perf_counter() - t0
    error = "" if r.converged else r.reason or (f"the FE eigen solve's residual "
                                                f"{r.residual:.3g} is above the method's "
                                                "tolerance")
    ref = d.assembly.segment(d.load_factor_segment)
    kc = None if d.units is None else \
        abs(d.units.si(r.load_factor_critical * ref.natural_curvature, "curvature"))
    return SweepRow(index, value, OK if r.converged else NOT_CONVERGED, r.load_factor_critical,
                    r.load_factor_interval[0], r.multiplicity,
                    d.paper_load_factor(r.load_factor_critical), r.residual, seconds, error, kc)


def solve_points(design: Design, key: str, elements: int | None, limits: Limits,
                 points: Sequence[tuple[int, float]], unit: str | None = None
                 ) -> list[SweepRow]:
    """Solve several points ``(index, value)`` in turn: one task of an executor.

    A module-level function of picklable arguments, so that a dask worker process can run it.
    """
    return [solve_point(design, key, elements, limits, i, v, unit) for i, v in points]


def sweep(design: Design, key: str, values: Iterable[float], *, elements: int | None = None,
          workers: int | None = None, scheduler: str | None = None, client: Any = None,
          out: str | os.PathLike[str] | None = None, restart: bool = False,
          points_per_task: int | None = None, progress: Callable[[], Any] | None = None,
          limits: Limits = DEFAULT_LIMITS, out_option: str = "out",
          unit: str | None = None) -> SweepResult:
    """Linear stability of ``design`` with the design value ``key`` set to each of ``values``.

    Parameters
    ----------
    design : Design
        The base design (its ``raw`` data is copied and modified, never changed in place).
    key : str
        A dotted design key accepted by :func:`rodstab.io.vary.set_design_value`, e.g.
        ``section.aspect`` or ``segment.arc.length``.
    values : iterable of float
        One or more finite values of ``key``.
    elements : int, optional
        Elements per segment; default: each modified design's ``[analysis] elements``.
    workers : int, optional
        Where the points are solved (:mod:`rodstab.executor`): 0 in this process, N >= 1 on a
        local dask cluster of N worker processes. Default (None, if neither ``scheduler`` nor
        ``client`` is given): :func:`rodstab.executor.run_points` solves the first points here
        and times them; a local cluster of one worker per core solves the rest if they would
        take more than :data:`~rodstab.executor.AUTO_MIN_SECONDS` serially, else they are
        solved here too. ``SweepResult.executor`` says which.
    scheduler : str, optional
        Address of an existing dask scheduler (``tcp://HOST:8786``) to solve the points on.
    client : distributed.Client, optional
        A dask client to solve the points with (not closed here).
    out : path, optional
        Directory of the sweep's table (module docstring): rows stream to ``out/sweep.csv``
        and a rerun with the same ``out`` solves only the missing points.
    restart : bool
        With ``out``: discard the run stored there and start afresh.
    points_per_task : int, optional
        Points grouped into one dask task (default: :func:`rodstab.executor.task_size`).
    progress : callable, optional
        Called with no argument once per point (resumed points first).
    limits : Limits
        Size limits (points: ``max_steps``; each solve: dof and memory).
    out_option : str
        How to name ``out`` in messages (the CLI: ``--out``).
    unit : str, optional
        The unit of ``values`` (a design with units, :func:`rodstab.io.vary.vary_in_units`).

    Returns
    -------
    SweepResult
        One row per value, in the order given.

    Raises
    ------
    RodstabInputError
        Before anything is solved: if ``key`` names no design value, a value is not a finite
        number, ``values`` is empty, ``elements`` or ``points_per_task`` is not a positive
        integer, more than one of ``workers``/``scheduler``/``client`` is given (or they
        cannot be used), or ``out`` holds another sweep (naming the difference).
    """
    vals = [require_finite(f"sweep value of {key!r}", v) for v in values]
    if not vals:
        raise RodstabInputError(f"sweep needs one or more values of {key!r}, got none")
    ne = None if elements is None else require_positive_int("elements", elements)
    require_steps(len(vals), f"{len(vals)} values", "sweep points", limits)
    _check_key(design, key, vals, unit)
    check_workers(workers, scheduler, client)
    if points_per_task is not None:
        task_size(1, 1, points_per_task)  # checked before anything runs
    physical = design.units is not None
    run = {"format": RUN_FORMAT, "design": design.raw, "key": key, "values": vals,
           "elements": ne, "unit": unit, "physical": physical}
    solve = functools.partial(solve_points, design, key, ne, limits, unit=unit)
    rows: dict[int, SweepRow] = {}
    with contextlib.ExitStack() as stack:
        table = None
        if out is not None:
            table = stack.enter_context(open_table(out, run, restart=restart,
                                                   option=out_option))
            rows.update(table.completed)
        resumed = len(rows)

        def record(new: list[SweepRow]) -> None:
            if table is not None:
                table.append(new)
            for r in new:
                rows[r.index] = r
                if progress is not None:
                    progress()

        for _ in range(resumed):
            if progress is not None:
                progress()
        pending = [(i, v) for i, v in enumerate(vals) if i not in rows]
        where = run_points(solve, pending, record, workers=workers, scheduler=scheduler,
                           client=client, points_per_task=points_per_task) if pending \
            else "nothing left to solve: every point was read from the table"
        if table is not None:
            table.finish([rows[i] for i in range(len(vals))])
    return SweepResult(key, tuple(rows[i] for i in range(len(vals))), ne, METHOD, where,
                       resumed, physical)


# ----------------------------------------------------------------------- the stored table


class SweepTable:
    """The open table of a sweep in its output directory (:func:`open_table`).

    ``completed`` holds the rows read back from an earlier run; :meth:`append` streams new
    rows to ``sweep.csv``; :meth:`finish` rewrites it in point order.
    """

    def __init__(self, out: Path, key: str, completed: dict[int, SweepRow],
                 fh: io.TextIOBase, physical: bool = False) -> None:
        self.out = out
        self.key = key
        self.completed = completed
        self._fh = fh
        self.physical = physical

    def append(self, rows: Sequence[SweepRow]) -> None:
        """Append ``rows`` to ``sweep.csv`` in one write, and flush it to the OS."""
        self._fh.write(_csv_lines(self.key, rows, physical=self.physical))
        self._fh.flush()  # a killed process loses nothing written before this returns

    def finish(self, rows: Sequence[SweepRow]) -> None:
        """Replace ``sweep.csv`` atomically by ``rows`` (all points, in point order)."""
        from .io.outputs import write_atomic

        self._fh.close()
        write_atomic(self.out / CSV_FILE, _csv_lines(self.key, rows, header=True,
                                                      physical=self.physical))


def _csv_lines(key: str, rows: Sequence[SweepRow], header: bool = False,
               physical: bool = False) -> str:
    """Return CSV lines of ``rows`` (and the header), each ended by one newline.

    Floats are written as ``repr`` (they read back exactly: a resumed row equals the solved
    one); NaN and None as empty fields.
    """
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    if header:
        w.writerow(columns(key, physical))
    for r in rows:
        w.writerow(["" if v is None or (isinstance(v, float) and math.isnan(v)) else
                    repr(float(v)) if isinstance(v, float) else v
                    for v in r.record(key, physical).values()])
    return buf.getvalue()


def _parse_row(key: str, fields: list[str], values: Sequence[float],
               physical: bool = False) -> SweepRow:
    """Return the row of one CSV line of this sweep, or raise ValueError saying why not."""
    cols = columns(key, physical)
    if len(fields) != len(cols):
        raise ValueError(f"{len(fields)} fields, not {len(cols)}")
    f = dict(zip(cols, fields, strict=True))
    index = int(f["index"])
    if not 0 <= index < len(values) or float(f[key]) != values[index]:
        raise ValueError(f"point {f['index']} = {f[key]} is not one of this sweep's values")
    if f["status"] not in STATUSES:
        raise ValueError(f"status {f['status']!r} is not one of {STATUSES}")

    def num(c: str) -> float:
        return float(f[c]) if f[c] else math.nan

    return SweepRow(index, values[index], f["status"], num("load_factor_critical"),
                    num("load_factor_lower"),
                    int(f["multiplicity"]) if f["multiplicity"] else None,
                    num("paper_load_factor_critical"), num("residual"), num("seconds"),
                    f["error"],
                    float(f[PHYSICAL_COLUMN]) if physical and f[PHYSICAL_COLUMN] else None)


def _difference(stored: Any, now: Any, where: str = "") -> str | None:
    """Return the first place where two JSON values differ, as ``path: stored vs now``."""
    if isinstance(stored, dict) and isinstance(now, dict):
        for k in list(stored) + [k for k in now if k not in stored]:
            if k not in now or k not in stored:
                return (f"{where}{k} is {'only in the stored run' if k in stored else 'new'}")
            d = _difference(stored[k], now[k], f"{where}{k}.")
            if d is not None:
                return d
        return None
    if isinstance(stored, list) and isinstance(now, list):
        if len(stored) != len(now):
            return f"{where.rstrip('.')} has {len(stored)} items stored, {len(now)} now"
        for i, (a, b) in enumerate(zip(stored, now, strict=True)):
            d = _difference(a, b, f"{where.rstrip('.')}[{i}].")
            if d is not None:
                return d
        return None
    return None if stored == now else f"{where.rstrip('.')}: {stored!r} stored, {now!r} now"


def _run_difference(stored: dict, run: dict) -> str | None:
    """Say how the stored ``run.json`` differs from this run's, in the options' terms."""
    if stored.get("key") != run["key"]:
        return f"it varies {stored.get('key')!r}, this run {run['key']!r}"
    sv, nv = stored.get("values"), run["values"]
    if sv != nv:
        if not isinstance(sv, list) or len(sv) != len(nv) or not sv:
            def span(v: list) -> str:
                return f"{len(v)} values" + (f" from {v[0]!r} to {v[-1]!r}" if v else "")
            return (f"it has {span(sv) if isinstance(sv, list) else 'no values'} of "
                    f"{run['key']}, this run {span(nv)}")
        i = next(i for i, (a, b) in enumerate(zip(sv, nv, strict=True)) if a != b)
        return f"its value {i} of {run['key']} is {sv[i]!r}, this run's {nv[i]!r}"
    if stored.get("elements") != run["elements"]:
        def say(e: object) -> str:
            return "the design's own" if e is None else repr(e)
        return f"its --elements is {say(stored.get('elements'))}, this run's " \
               f"{say(run['elements'])}"
    d = _difference(stored.get("design"), run["design"])
    return None if d is None else f"the design differs: {d}"


@contextlib.contextmanager
def open_table(out: str | os.PathLike[str], run: dict, *, restart: bool,
               option: str = "out") -> Iterator[SweepTable]:
    """Open the sweep's table in ``out`` for appending, holding the directory's lock.

    Parameters
    ----------
    out : path
        The output directory (created if missing; checked writable).
    run : dict
        What this run sweeps (``run.json``): ``format``, ``design`` (the design's data),
        ``key``, ``values``, ``elements``.
    restart : bool
        Discard a stored run instead of resuming it.
    option : str
        How to name ``out`` in messages (``--out`` for the CLI).

    Yields
    ------
    SweepTable
        With the rows completed by an earlier run of the same sweep.

    Raises
    ------
    RodstabInputError
        If ``out`` cannot be written, another run holds it, or (without ``restart``) it holds
        another sweep, a ``sweep.csv`` without ``run.json``, or a table that is not this
        sweep's (its line is named); the message says what differs and how to proceed.
    """
    from .io.outputs import check_output, run_lock, write_atomic

    label = f"{option} {os.fspath(out)!r}"
    out = check_output(option, out, directory=True)
    how = ("resume it with the same design, --vary and --elements, or start afresh with "
           "--restart (or use another --out)")
    # JSON round trip: what is compared is what run.json can hold (tuples become lists).
    run = json.loads(json.dumps(run, default=str))
    with run_lock(out, label=label):
        run_path, csv_path = out / RUN_FILE, out / CSV_FILE
        if restart:
            for name in (RUN_FILE, CSV_FILE, PARQUET_FILE, "sweep.png"):
                with contextlib.suppress(FileNotFoundError):
                    (out / name).unlink()
        completed: dict[int, SweepRow] = {}
        if run_path.exists():
            try:
                stored = json.loads(run_path.read_text())
                if not isinstance(stored, dict) or stored.get("format") != RUN_FORMAT:
                    raise ValueError(f"no \"format\": \"{RUN_FORMAT}\"")
            except (ValueError, UnicodeDecodeError) as exc:
                raise RodstabInputError(f"{label}: {run_path} is not a sweep's {RUN_FILE} "
                                        f"({_one_line(exc)}); {how}") from None
            diff = _run_difference(stored, run)
            if diff is not None:
                raise RodstabInputError(f"{label} holds another sweep ({RUN_FILE}): {diff}; "
                                        f"{how}")
            completed = _read_completed(csv_path, run, label, how)
        elif csv_path.exists():
            raise RodstabInputError(f"{label} has a {CSV_FILE} but no {RUN_FILE} (an earlier "
                                    f"rodstab's or another program's table); {how}")
        else:
            write_atomic(run_path, json.dumps(run, indent=1))  # before any row
        if not csv_path.exists():
            write_atomic(csv_path, _csv_lines(run["key"], [], header=True,
                                              physical=bool(run.get("physical"))))
        with csv_path.open("a", newline="", encoding="utf-8") as fh:
            yield SweepTable(out, run["key"], completed, fh, bool(run.get("physical")))


def _read_completed(csv_path: Path, run: dict, label: str, how: str) -> dict[int, SweepRow]:
    """Read the completed rows of ``sweep.csv``; drop (and cut off) a partial last line."""
    if not csv_path.exists():
        return {}
    data = csv_path.read_bytes()
    whole = data[:data.rfind(b"\n") + 1]  # a kill while writing leaves a line without "\n"
    if len(whole) != len(data):
        with csv_path.open("r+b") as fh:
            fh.truncate(len(whole))
    key, values, physical = run["key"], run["values"], bool(run.get("physical"))
    lines = whole.decode("utf-8", errors="replace").splitlines()
    header = ",".join(columns(key, physical))
    if not lines or lines[0] != header:
        raise RodstabInputError(f"{label}: {csv_path} does not start with this sweep's header "
                                f"({header}); {how}")
    completed: dict[int, SweepRow] = {}
    for n, fields in enumerate(csv.reader(lines[1:]), start=2):
        try:
            row = _parse_row(key, fields, values, physical)
        except ValueError as exc:
            raise RodstabInputError(f"{label}: line {n} of {csv_path} is not a row of this "
                                    f"sweep ({_one_line(exc)}); {how}") from None
        completed.setdefault(row.index, row)  # a point solved twice gave the same row
    return completed


# ------------------------------------------------------------------------- the Python API


def _require(module: str, what: str) -> Any:
    """Import an optional dependency, or raise RodstabInputError saying how to install it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise RodstabInputError(f"{what} needs {module}: pip install "
                                '"rodstab[distributed]"') from None


def _vary_values(vary: Mapping[str, Any], default_n: int, design: Design
                 ) -> tuple[str, list[float], str | None]:
    """Return the key, the values and their unit of ``vary`` (values or "START:STOP[:N]").

    A string is read as the CLI's ``--vary`` (:func:`rodstab.io.vary.parse_vary`, units checked
    against ``design`` by :func:`rodstab.io.vary.vary_in_units`); a sequence is plain numbers.
    """
    import numpy as np

    from .io.vary import vary_in_units

    if not isinstance(vary, Mapping) or len(vary) != 1:
        keys = list(vary) if isinstance(vary, Mapping) else vary
        raise RodstabInputError(f"vary must map one design key to its values, got {keys!r} "
                                "(a sweep varies one key)")
    ((key, spec),) = vary.items()
    if isinstance(spec, str):
        s = vary_in_units(design, parse_vary(f"{key}={spec}", default_n=default_n))
        return s.key, np.linspace(s.start, s.stop, s.n).tolist(), s.unit
    if isinstance(spec, (int, float)) or not isinstance(spec, Iterable):
        raise RodstabInputError(f"vary[{key!r}] must be a sequence of values or "
                                f"'START:STOP[:N]', got {spec!r}")
    return key, [v.item() if isinstance(v, np.generic) else v for v in spec], None


def run(design: Design | str | os.PathLike[str], vary: Mapping[str, Any], *,
        client: Any = None, workers: int | None = None, scheduler: str | None = None,
        out: str | os.PathLike[str] | None = None, restart: bool = False,
        parquet: bool = False, elements: int | None = None,
        points_per_task: int | None = None, limits: Limits = DEFAULT_LIMITS) -> pd.DataFrame:
    """Sweep a design and return its table as a pandas DataFrame (``rodstab.sweep(...)``).

    Parameters
    ----------
    design : Design or path
        A parsed design, or a design file (TOML).
    vary : mapping
        One design key and its values: ``{"section.aspect": np.linspace(1, 6, 200)}``, or the
        range as the CLI's ``--vary`` writes it, ``{"section.aspect": "1:6:200"}`` (with units
        for a dimensional key of a design with units: ``"100 mm:200 mm:5"``).
    client : distributed.Client, optional
        Solve the points on this dask client's cluster (not closed here).
    workers, scheduler, out, restart, elements, points_per_task, limits
        As :func:`sweep`.
    parquet : bool
        With ``out``: also write ``out/sweep.parquet`` (pyarrow) of the finished table.

    Returns
    -------
    pandas.DataFrame
        One row per point in the order of the values, columns :func:`columns`; ``attrs``:
        ``key``, ``executor``, ``resumed``. Failed points are rows with their status and
        error (nothing raised).

    Raises
    ------
    RodstabInputError
        As :func:`sweep`, and if pandas (or pyarrow for ``parquet``) is not installed.
    """
    _require("pandas", "rodstab.sweep(...)")
    if parquet:
        if out is None:
            raise RodstabInputError("parquet=True needs out (the directory to write it in)")
        _require("pyarrow", "parquet=True")
    d = design if isinstance(design, Design) else load_design(os.fspath(design))
    key, values, unit = _vary_values(vary, SWEEP_DEFAULT_N, d)
    result = sweep(d, key, values, elements=elements, workers=workers, scheduler=scheduler,
                   client=client, out=out, restart=restart, points_per_task=points_per_task,
                   limits=limits, unit=unit)
    df = result.frame()
    if parquet and out is not None:
        write_parquet(df, Path(out))
    return df


def write_parquet(df: pd.DataFrame, out: Path) -> Path:
    """Write ``out/sweep.parquet`` (pyarrow) of a finished sweep's table, atomically."""
    from .io.outputs import replace_atomic

    path = out / PARQUET_FILE
    replace_atomic(path, lambda fh: df.to_parquet(fh, engine="pyarrow", index=False))
    return path


class _SweepModule(types.ModuleType):
    """The type of this module, callable: ``rodstab.sweep(design, vary={...})`` is :func:`run`.

    The issue's API names the function ``rodstab.sweep``, which is this module's name (its
    import sets the package attribute ``rodstab.sweep`` to the module, so a function of that
    name in ``rodstab/__init__.py`` would be replaced by it). Making the module callable keeps
    both ``rodstab.sweep(...)`` and ``rodstab.sweep.sweep``/``design_at`` working.
    """

    def __call__(self, design: Design | str | os.PathLike[str], vary: Mapping[str, Any],
                 **kwargs: Any) -> pd.DataFrame:
        return run(design, vary, **kwargs)


sys.modules[__name__].__class__ = _SweepModule
