"""Record the ``--json`` output of every command line of ``tests/cli_cases.py``.

Run it with the checkout to record on ``PYTHONPATH``::

    PYTHONPATH=/path/to/old/checkout/src python tests/data/record_cli_outputs.py OUT.json [later]

``tests/data/cli_outputs_07ed206.json`` was recorded this way from commit 07ed206 (the last
commit before the issue-9 redesign) and ``cli_outputs_e0b77e8.json`` (``later``: the
``LATER_CASES``) from e0b77e8 (the last before the issue-20 split of the command line). They
are regression records of this project's own earlier output (``new``: the commands added
since, ``cli_outputs_new.json``, each recorded by the commit that added it):
``tests/test_cli_outputs.py`` checks that a refactoring changed no number, not that the
numbers are right.
"""

from __future__ import annotations

import contextlib
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from cli_cases import CASES, LATER_CASES, NEW_CASES, ROOT, case_id  # noqa: E402


def main(out: str, cases: list[list[str]] = CASES) -> None:
    """Run every case in a fresh interpreter and write ``{case id: {exit, json}}``."""
    import rodstab

    rows: dict[str, dict[str, object]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for args in cases:
            argv = [a.replace("{tmp}", tmp) for a in args] + ["--json"]
            p = subprocess.run([sys.executable, "-c", "from rodstab.cli import main; main()",
                                *argv], cwd=ROOT, capture_output=True, text=True, check=False)
            payload = json.loads(p.stdout) if p.stdout.strip() else None
            rows[case_id(args)] = {"exit": p.returncode, "json": payload}
            print(p.returncode, case_id(args), file=sys.stderr)
    meta = {"rodstab": rodstab.__file__, "cases": len(rows)}
    with contextlib.suppress(Exception):
        meta["commit"] = subprocess.run(
            ["git", "-C", str(Path(rodstab.__file__).parent), "rev-parse", "HEAD"],
            capture_output=True, text=True, check=True).stdout.strip()
    Path(out).write_text(json.dumps({"meta": meta, "outputs": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], {"later": LATER_CASES, "new": NEW_CASES}.get(
        sys.argv[2] if sys.argv[2:] else "", CASES))
