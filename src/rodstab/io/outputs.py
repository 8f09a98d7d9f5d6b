"""Output paths checked before any computation starts (one check for every output option).

:func:`check_output` is called by the CLI for ``analyze --plot``, ``equilibrium --render`` and
``--html``, and the ``--out`` directories of ``continue``, ``sweep`` and ``reproduce``, before
the design is solved: the directory is created if missing and a file is written and removed in
it, so that a path that cannot be written (under a regular file, in a read-only directory, the
empty string) is refused at once with :class:`~rodstab.errors.RodstabInputError` (exit 2),
naming the option and the path, instead of failing after the computation.

Files in an output directory are replaced atomically (:func:`write_atomic`: a complete sibling
renamed over the old file), and one run at a time writes into a directory (:func:`run_lock`,
``run.lock``): used by ``continue --out`` and ``sweep --out``.
"""

from __future__ import annotations

import contextlib
import datetime
import json
import os
import socket
import sys
import tempfile
import warnings
from collections.abc import Callable, Collection, Iterator
from pathlib import Path
from typing import IO, Any

from ..errors import RodstabInputError, RodstabWarning


def _blocker(d: Path) -> Path | None:
    """Return the nearest existing ancestor of ``d`` (or ``d``) that is not a directory."""
    for p in (d, *d.parents):
        if os.path.lexists(p):
            return None if os.path.isdir(p) else p
    return None


def check_output(option: str, value: str | os.PathLike[str], *, directory: bool,
                 suffixes: Collection[str] | None = None) -> Path:
    """Check that the output ``value`` of ``option`` can be written; return it as a Path.

    Parameters
    ----------
    option : str
        The option's name as the user typed it, e.g. ``--out`` (used in messages).
    value : str or path-like
        The path given.
    directory : bool
        True if ``value`` is an output directory (created if missing), False if it is a file
        (its parent directory is created if missing).
    suffixes : collection of str, optional
        For a file: the accepted suffixes, lower case with the dot (e.g. ``{".png"}``); a name
        without a suffix is accepted. Default: any.

    Returns
    -------
    Path
        ``value`` as a :class:`~pathlib.Path`; its directory exists and is writable.

    Raises
    ------
    RodstabInputError
        If ``value`` is empty, is (or lies under) a regular file, is a directory where a file
        is wanted, has a suffix not in ``suffixes``, or its directory cannot be created or
        written; the message names ``option`` and ``value``.
    """
    text = os.fspath(value)

    def fail(reason: str) -> RodstabInputError:
        return RodstabInputError(f"cannot write {option} {text!r}: {reason}")

    if not text.strip():
        raise RodstabInputError(f"{option} needs a path, got {text!r}")
    if "\0" in text:
        raise fail("the path contains a NUL character")
    path = Path(text)
    if directory:
        d = path
        if os.path.lexists(path) and not os.path.isdir(path):
            raise fail("it exists and is not a directory")
    else:
        d = path.parent
        if os.path.isdir(path):
            raise fail("it is a directory, not a file")
        if suffixes is not None and path.suffix and path.suffix.lower() not in suffixes:
            raise fail(f"unsupported file type {path.suffix!r} (use one of "
                       f"{', '.join(sorted(suffixes))})")
    blocker = _blocker(d)
    if blocker is not None:
        raise fail(f"{str(blocker)!r} is a file, not a directory")
    try:
        d.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise fail(f"cannot create the directory {str(d)!r} ({exc.strerror or exc})") from None
    try:
        fd, probe = tempfile.mkstemp(prefix=".rodstab-write-test-", dir=d)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise fail(f"the directory {str(d)!r} is not writable ({exc.strerror or exc})") from None
    if not directory and os.path.lexists(path) and not os.access(path, os.W_OK):
        raise fail("the file exists and is not writable")
    return path


# --------------------------------------------------------------- writing into an output

#: The lock file of the run writing into an output directory (:func:`run_lock`).
LOCK = "run.lock"


def _read_umask() -> int:
    """Return the process's file-creation mask (read by setting it, then restored at once)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


#: Read once, at import: reading it means setting it, which is not safe while other threads
#: create files (two runs writing one output, tests/test_robust_runs.py).
_UMASK = _read_umask()


def replace_atomic(path: Path, write: Callable[[IO[bytes]], Any]) -> None:
    """Write ``path`` through ``write(file)`` into a uniquely named sibling, then rename it.

    The file gets the mode an ordinary ``open(path, "w")`` would give (``0o666`` less the
    umask; ``mkstemp``'s own 0600 would hide a sweep's CSV from the user's group).
    """
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, 0o666 & ~_UMASK)
        with os.fdopen(fd, "wb") as fh:
            write(fh)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_atomic(path: Path, text: str) -> None:
    """Replace ``path`` by ``text`` atomically (write a uniquely named sibling, then rename)."""
    replace_atomic(path, lambda fh: fh.write(text.encode()))


#: Output directories (resolved) locked by this process, with their nesting depth: a caller
#: holding the lock (the CLI) may call a library function that takes it again (e.g.
#: :func:`rodstab.nonlinear.continuation.continuation` on the same directory).
_HELD: dict[str, int] = {}


def _alive(pid: int) -> bool:
    """Return True unless the process ``pid`` on this host is known to be gone."""
    if pid <= 0:
        return False
    if sys.platform == "win32":  # os.kill would terminate it: cannot tell, assume alive
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # e.g. EPERM: it exists, owned by someone else
        return True
    return True


def _read_lock(lock: Path) -> dict | None:
    """Return the holder recorded in ``lock`` (pid, host, started), or None if unreadable."""
    try:
        info = json.loads(lock.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(info, dict) or isinstance(info.get("pid"), bool) \
            or not isinstance(info.get("pid"), int) or not isinstance(info.get("host"), str):
        return None
    return info


@contextlib.contextmanager
def run_lock(out: Path, label: str | None = None) -> Iterator[None]:
    """Hold ``out/run.lock`` while the body runs: one run at a time writes into ``out``.

    Parameters
    ----------
    out : Path
        The output directory (it must exist).
    label : str, optional
        How to name the directory in messages (default: its path), e.g. ``--out 'cont'``.

    Raises
    ------
    RodstabInputError
        If another live process (or a process on another host) holds the lock; the message
        names its process id, host and start time, and the lock file.

    Notes
    -----
    The lock file is created with its content in one step (a hard link of a complete unique
    file), so a concurrent reader never sees it half written. A lock whose process is gone
    (same host, no such process id) or that is unreadable is taken over with a
    :class:`~rodstab.errors.RodstabWarning`. Re-entrant within a process.
    """
    key = os.path.realpath(out)
    if _HELD.get(key):
        _HELD[key] += 1
        try:
            yield
        finally:
            _HELD[key] -= 1
        return
    lock = out / LOCK
    me = {"pid": os.getpid(), "host": socket.gethostname(),
          "started": datetime.datetime.now().astimezone().isoformat(timespec="seconds")}
    text = json.dumps(me)
    where = label or repr(str(out))
    for _ in range(3):
        fd, tmp = tempfile.mkstemp(prefix=f".{LOCK}.", suffix=".tmp", dir=out)
        try:
            with os.fdopen(fd, "w") as fh:
                fh.write(text)
            try:
                os.link(tmp, lock)  # created with its content, or not at all
                break
            except FileExistsError:
                pass
            holder = _read_lock(lock)
            if holder is not None and (holder["host"] != me["host"] or _alive(holder["pid"])):
                raise RodstabInputError(
                    f"{where} is in use by another rodstab run (process {holder['pid']} on "
                    f"host {holder['host']}, started {holder.get('started', '?')}); wait for "
                    f"it to finish, or remove {lock} if that process is not rodstab")
            if not os.path.lexists(lock):
                continue  # its holder just released it
            what = ("an unreadable lock" if holder is None else
                    f"a stale lock of process {holder['pid']} (no longer running)")
            # Take over: replace it by ours in one rename, then check that ours stayed.
            os.replace(tmp, lock)
            if lock.read_text() == text:
                warnings.warn(f"{where}: took over {what}", RodstabWarning, stacklevel=3)
                break
        finally:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    else:
        raise RodstabInputError(f"{where}: could not take the lock {lock} (other runs keep "
                                "taking it)")
    _HELD[key] = 1
    try:
        yield
    finally:
        del _HELD[key]
        with contextlib.suppress(OSError):
            if lock.read_text() == text:
                lock.unlink()
