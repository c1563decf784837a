"""Shared fixtures of the Python package's tests: the repository, its real logs and
the `gloc` command line the package is compared with."""

import os
import shutil

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(ROOT, "data")


@pytest.fixture(scope="session")
def gloc_bin():
    """The CLI: $GLOC_BIN, else the workspace's debug or release build."""
    for candidate in (
        os.environ.get("GLOC_BIN"),
        os.path.join(ROOT, "target", "debug", "gloc"),
        os.path.join(ROOT, "target", "release", "gloc"),
    ):
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    found = shutil.which("gloc")
    if found is None:
        pytest.fail("no gloc binary: build it (cargo build -p gloc-cli) or set GLOC_BIN")
    return found
