"""Shared fixtures of the pytest tests (run by ctest: tests/CMakeLists.txt sets
OCG_TOOLS to the folder of the built tools and OCG_SOURCE_DIR; PYTHONPATH holds the built
module for the binding tests)."""
import os
import subprocess

import pytest


def _folder(variable):
    value = os.environ.get(variable)
    if not value:
        pytest.fail("%s is not set: run these tests through ctest (tests/CMakeLists.txt)" % variable)
    return value


@pytest.fixture(scope="session")
def tools():
    return _folder("OCG_TOOLS")


@pytest.fixture(scope="session")
def source_dir():
    return _folder("OCG_SOURCE_DIR")


@pytest.fixture(scope="session")
def shared_data(source_dir):
    """../shared/data beside the project (or $OCG_SHARED_DATA), as the C++ tests find it."""
    folder = os.environ.get("OCG_SHARED_DATA") or os.path.join(source_dir, "..", "shared", "data")
    if not os.path.isdir(folder):
        pytest.skip("real data not found at %s (set OCG_SHARED_DATA): skipped" % folder)
    return folder


def run_tool(tools, name, *arguments):
    """Runs a built tool; fails the test with its output when it fails."""
    result = subprocess.run([os.path.join(tools, name), *arguments], capture_output=True, text=True)
    if result.returncode != 0:
        pytest.fail("%s %s failed:\n%s%s" % (name, " ".join(arguments), result.stdout, result.stderr))
    return result.stdout
