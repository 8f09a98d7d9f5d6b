"""One BLAS thread while rodstab solves its small dense systems (rodstab.numerics.threads)."""

from __future__ import annotations

import os

import pytest
import scipy.linalg  # noqa: F401  (its BLAS must be loaded to be counted)
from threadpoolctl import threadpool_info, threadpool_limits

from rodstab.numerics import serial_blas, serially
from rodstab.numerics.threads import USER_THREAD_VARIABLES


def _blas_threads() -> set[int]:
    return {lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"}


@pytest.fixture
def no_user_choice(monkeypatch):
    for v in USER_THREAD_VARIABLES:  # the suite sets them (conftest.py); a user may not
        monkeypatch.delenv(v, raising=False)


def test_serial_blas_sets_one_thread_and_restores_the_count(no_user_choice):
    with threadpool_limits(limits=2, user_api="blas"):
        assert _blas_threads() == {2}
        with serial_blas():
            assert _blas_threads() == {1}
            assert all(os.environ[v] == "1" for v in USER_THREAD_VARIABLES)
        assert _blas_threads() == {2}
    assert not any(os.environ.get(v) for v in USER_THREAD_VARIABLES)


def test_a_thread_count_the_user_chose_is_left_as_set(monkeypatch):
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")
    with threadpool_limits(limits=2, user_api="blas"):
        with serial_blas():
            assert _blas_threads() == {2}


def test_the_drivers_run_serially(no_user_choice):
    from rodstab.multistable.string_method import relax_string
    from rodstab.nonlinear.newton import newton

    seen = []
    probe = serially(lambda: seen.append(_blas_threads()))
    with threadpool_limits(limits=2, user_api="blas"):
        probe()
    assert seen == [{1}]
    for driver in (newton, relax_string):  # decorated: functools.wraps keeps the original
        assert driver.__wrapped__ is not driver
