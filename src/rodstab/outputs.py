"""Output paths checked before any computation starts (one check for every output option).

:func:`check_output` is called by the CLI for ``analyze --plot``, ``equilibrium --render`` and
``--html``, and the ``--out`` directories of ``continue``, ``sweep`` and ``reproduce``, before
the design is solved: the directory is created if missing and a file is written and removed in
it, so that a path that cannot be written (under a regular file, in a read-only directory, the
empty string) is refused at once with :class:`~rodstab.errors.RodstabInputError` (exit 2),
naming the option and the path, instead of failing after the computation.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Collection
from pathlib import Path

from .errors import RodstabInputError


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
