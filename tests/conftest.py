"""Shared fixtures."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def reproduction(tmp_path_factory):
    """``rodstab reproduce`` run once per session: (output directory, summary dict)."""
    from rodstab.report.reproduce import run_reproduction

    out = tmp_path_factory.mktemp("results")
    return out, run_reproduction(out, progress=False)
