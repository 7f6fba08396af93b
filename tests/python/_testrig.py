"""Shared access to the measured test-rig record for the tests (never copied into the repo).

The record lives beside the repository: ``<repo>/../shared/data/testrig/sample175_0-40s.mat``.
Tests that need it are skipped, with the path in the reason, when it is absent.
"""
from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def sample175_path() -> Path:
    if not SAMPLE175.is_file():
        pytest.skip(f"test-rig record not found at {SAMPLE175} (expected <repo>/../shared/data/testrig/)")
    return SAMPLE175


@functools.lru_cache(maxsize=None)
def _raw():
    from drillpy.records.io import read_mat
    return read_mat(SAMPLE175)


def sample175_raw():
    """The record as read (a fresh copy per call: tests may modify it)."""
    sample175_path()
    r = _raw()
    return r.take(np.arange(len(r)))  # fancy indexing copies


@functools.lru_cache(maxsize=None)
def _cleaned():
    from drillpy.records.cleaning import clean
    return clean(_raw())


def sample175_cleaned():
    """(cleaned record, cleaning report), shared: do not modify."""
    sample175_path()
    return _cleaned()


@functools.lru_cache(maxsize=None)
def _cycles():
    from drillpy.records import signals as sig
    rec, rep = _cleaned()
    cyc = sig.segment_cycles(rec.bit_speed, rec.dt, rep.stick_threshold_rad_s, valid=rec.valid())
    acc = sig.derivative(rec.bit_speed, rec.dt)
    return cyc, acc, cyc.branch_labels(len(rec))


def sample175_cycles():
    """(Cycles, bit acceleration [rad/s^2], branch labels) of the cleaned record, shared."""
    sample175_path()
    return _cycles()
