"""Shared test fixtures: the one way the tests run the ``rodstab`` command.

``run_cli(args)`` calls the real entry point, :func:`rodstab.cli.main` (so exit statuses and
the one-line error messages are those a user sees), and returns a :class:`CliResult`.

The session runs BLAS single-threaded (set here, before numpy is first imported -- this
module imports no numpy -- and a value already in the environment is kept): every matrix of
the suite is small (dense ones up to a few hundred unknowns), where a second BLAS thread only
adds synchronisation. With the other core busy, a 6 x 6 ``expm`` took 96 us instead of 10 us
and a 300 x 300 ``eigh`` 15 ms instead of 7 ms; the suite's CPU time exceeded its wall time.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import subprocess
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

import pytest
from click.testing import CliRunner

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

ROOT = Path(__file__).resolve().parent.parent


@dataclasses.dataclass(frozen=True)
class CliResult:
    """What a run of ``rodstab`` printed, and its exit status."""

    exit_code: int
    stdout: str
    stderr: str


def _exit_code(code: object) -> int:
    """The process exit status ``sys.exit(code)`` gives (None: 0; a message: 1)."""
    if code is None:
        return 0
    return code if isinstance(code, int) else 1


def _runner() -> CliRunner:
    try:
        return CliRunner(mix_stderr=False)  # type: ignore[call-arg]  # click < 8.2
    except TypeError:
        return CliRunner()  # click >= 8.2: stderr is always captured on its own


def run_cli(args: Sequence[str], *, cwd: str | Path = ROOT, fresh_process: bool = False,
            timeout: float | None = None) -> CliResult:
    """Run ``rodstab ARGS`` in directory ``cwd`` (default: the repository root).

    In-process by default: :func:`rodstab.cli.main` with stdout and stderr captured apart
    (click's ``CliRunner`` isolation); the exit status is the ``SystemExit`` code (0 if
    ``main`` returns). Any other exception propagates, as it would end the real program with
    a traceback. ``fresh_process=True`` runs ``python -m rodstab.cli`` in a new interpreter
    instead (for what a real process prints, or one stopped by ``timeout``:
    ``subprocess.TimeoutExpired`` propagates).
    """
    args = [str(a) for a in args]
    if fresh_process:
        env = os.environ.copy()
        env["PYTHONPATH"] = os.pathsep.join(
            [str(ROOT / "src")] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
        proc = subprocess.run([sys.executable, "-m", "rodstab.cli", *args], capture_output=True,
                              text=True, cwd=cwd, env=env, timeout=timeout)
        return CliResult(proc.returncode, proc.stdout, proc.stderr)
    if timeout is not None:
        raise ValueError("run_cli: timeout needs fresh_process=True")
    from rodstab.cli import main  # after the BLAS setting (module docstring)

    with contextlib.chdir(cwd), _runner().isolation() as streams:
        try:
            main(args)
            code = 0
        except SystemExit as exc:
            code = _exit_code(exc.code)
        stdout = streams[0].getvalue().decode()
        stderr = streams[1].getvalue().decode()
    return CliResult(code, stdout, stderr)


@pytest.fixture(name="run_cli", scope="session")
def run_cli_fixture() -> Callable[..., CliResult]:
    """:func:`run_cli`: run ``rodstab`` and return its exit status, stdout and stderr."""
    return run_cli


@pytest.fixture(scope="session")
def reproduction(tmp_path_factory):
    """``rodstab reproduce`` run once per session: (output directory, summary dict).

    Once for the whole session, also on several xdist workers: the first worker that needs it
    runs it (its checks on every core, ~50 s) under a file lock in the directory the workers
    share, and saves the summary there; the others wait for the lock and read the saved
    summary. (Per worker, each worker ran it, with the checks of both on the same two cores.)
    The tests only read the output directory.
    """
    import json

    from filelock import FileLock

    from rodstab.report.reproduce import run_reproduction

    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent  # the session's directory, above each worker's own
    out, saved = shared / "reproduction", shared / "reproduction.json"
    with FileLock(str(shared / "reproduction.lock")):
        if not saved.is_file():
            summary = run_reproduction(out, progress=False)
            saved.write_text(json.dumps(summary))
    return out, json.loads(saved.read_text())


# --------------------------------------------------------------------------- the docs build
#: The docs site build started in the background (tests/test_docs.py's ``site`` fixture waits
#: for it): ``mkdocs build --strict`` runs every example and tutorial (~15 s of one core),
#: while the rest of the suite mostly uses the other core; started once the tests are
#: collected, only if test_docs.py is among them and mkdocs is installed.
DOCS_BUILD: dict[str, object] = {}


def docs_build_command(out: Path) -> tuple[list[str], dict[str, str]]:
    """The site build's command line and environment (no results.json: the checks' rows)."""
    env = {k: v for k, v in os.environ.items() if k != "RODSTAB_RESULTS"}
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", NO_MKDOCS_2_WARNING="1")
    return ([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"),
             "-d", str(out)], env)


#: Workers of ``-n auto`` beyond the usable cores. The suite waits on other processes (the
#: dask sweeps and their killed runs, fresh interpreters, the background docs build, the
#: session's one reproduction that other workers wait for), where a spare worker could run
#: tests; but the reproduction and the docs build run beside the workers on the same cores.
#: Measured on 2 cores, same tree, back to back: 2026-12-05, 2 workers 161 s, 3 workers 147 s;
#: 2026-12-06 (session 19), 2 workers 196.5 s, 3 workers 229.0 s (and 196 s against 224-239 s
#: in earlier runs that day). The later pair decides.
SPARE_WORKERS = 0


def pytest_xdist_auto_num_workers(config: pytest.Config) -> int:
    """``-n auto``: the usable cores (the process's CPU affinity) plus :data:`SPARE_WORKERS`."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return (cores or 1) + SPARE_WORKERS


#: Fixtures whose tests are slow whatever they assert: the session's reproduction (~50 s on 2
#: cores, every claim) and the docs site build (every example and tutorial). Their tests are
#: in the slow tier (pyproject.toml's markers), as are the tests marked slow one by one.
SLOW_FIXTURES = frozenset({"reproduction", "site"})


@pytest.hookimpl(tryfirst=True)  # before -m deselects by the marks
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark slow every test that uses one of :data:`SLOW_FIXTURES`."""
    for item in items:
        if SLOW_FIXTURES.intersection(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.slow)


def pytest_collection_finish(session: pytest.Session) -> None:
    """Start the docs build in the background if test_docs.py runs (see DOCS_BUILD)."""
    import importlib.util
    import tempfile

    if session.config.option.collectonly or importlib.util.find_spec("mkdocs") is None:
        return
    if not any(Path(str(item.fspath)).name == "test_docs.py" for item in session.items):
        return
    if os.environ.get("PYTEST_XDIST_WORKER"):
        # Every xdist worker collects every test but only one runs test_docs.py: started here,
        # each worker would build the site (~15 s of a core each); its fixture builds it.
        return
    out = Path(tempfile.mkdtemp(prefix="rodstab-site-"))
    cmd, env = docs_build_command(out)
    DOCS_BUILD["out"] = out
    DOCS_BUILD["proc"] = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                                          stderr=subprocess.PIPE, text=True)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """Stop a docs build still running (an interrupted or failed-fast session)."""
    import shutil

    proc = DOCS_BUILD.get("proc")
    if isinstance(proc, subprocess.Popen) and proc.poll() is None:
        proc.kill()
        proc.communicate()
    out = DOCS_BUILD.get("out")
    if isinstance(out, Path):
        shutil.rmtree(out, ignore_errors=True)
