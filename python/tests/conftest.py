"""Shared fixtures of the Python package's tests (run by ctest as python.pytest, with PYTHONPATH
set to the build tree's package and FFDAABB_CLI to the command-line tool)."""

import os
import shutil
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def cli() -> str:
    """The ffdaabb command-line tool of the same build."""
    path = os.environ.get("FFDAABB_CLI") or shutil.which("ffdaabb")
    if not path:
        built = Path(__file__).resolve().parents[2] / "build" / "release" / "bin" / "ffdaabb"
        path = str(built) if built.exists() else None
    if not path:
        pytest.skip("the ffdaabb command-line tool is not built (set FFDAABB_CLI)")
    return path
