"""Shared helpers of the natura tests: the reference values the Rust API
computes (tests/reference.json, checked by `cargo test -p natura-python
--test reference`) and the hash both sides use."""

import json
import math
import pathlib

import numpy as np
import pytest

REFERENCE = json.loads((pathlib.Path(__file__).parent / "reference.json").read_text())


def fnv(data: bytes) -> int:
    """FNV-1a 64 of `data` (as tests/reference.rs computes it)."""
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def hash_array(a: np.ndarray) -> int:
    """FNV-1a of an array's values as little-endian bytes, in C order."""
    return fnv(np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<")).tobytes())


def points2() -> np.ndarray:
    """The 2-D points of tests/reference.rs (math.sin: the C library's sin, as Rust's)."""
    return np.array(
        [[t * 0.173 - 3.1, math.sin(t * 0.61) * 4.7 + 0.05] for t in map(float, range(37))],
        dtype=np.float64,
    )


def points3() -> np.ndarray:
    p = points2()
    z = np.array([i * 0.29 - 5.3 for i in range(len(p))], dtype=np.float64)
    return np.column_stack([p, z])


@pytest.fixture
def reference():
    return REFERENCE


_SKIPPED = []


def pytest_runtest_logreport(report):
    if report.skipped:
        _SKIPPED.append(report.nodeid)


def pytest_sessionfinish(session, exitstatus):
    """Under NATURA_FAIL_ON_SKIP=1 (CI) a skipped test fails the run: CI
    proves the package, it does not skip what it cannot run."""
    import os

    if os.environ.get("NATURA_FAIL_ON_SKIP") == "1" and _SKIPPED:
        print(f"\nFAIL: {len(_SKIPPED)} tests skipped: {', '.join(_SKIPPED)}")
        session.exitstatus = 1
