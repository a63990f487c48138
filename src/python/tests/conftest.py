"""Fixtures shared by the Python tests."""

import os

import pytest

import barnbench


@pytest.fixture
def barn():
    """The barn executable of the build tree this barnbench module was built in (build/barn)."""
    return os.path.normpath(os.path.join(os.path.dirname(barnbench.__file__), os.pardir, os.pardir, "barn"))
