"""Style gate: ruff (pyflakes, pycodestyle, import order, bugbear; numpy docstrings on src)
over src, tests, benchmarks and docs (the site's hook and tutorials), and mypy over the
package, as configured in pyproject.toml.
"""

from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.skipif(shutil.which("ruff") is None and
                    subprocess.run([sys.executable, "-m", "ruff", "--version"],
                                   capture_output=True).returncode != 0,
                    reason="ruff is in the test extras; not installed here")
def test_ruff_is_clean_on_src_tests_benchmarks_and_docs():
    r = subprocess.run([sys.executable, "-m", "ruff", "check", "src", "tests", "benchmarks",
                        "docs"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.mark.skipif(importlib.util.find_spec("mypy") is None,
                    reason="mypy is in the test extras; not installed here")
def test_mypy_is_clean_on_src():
    r = subprocess.run([sys.executable, "-m", "mypy", "src"], cwd=ROOT,
                       capture_output=True, text=True)
    assert r.returncode == 0 and "error:" not in r.stdout, r.stdout + r.stderr
