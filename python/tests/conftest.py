"""What every Python test needs: the dynamap program of the same build (DYNAMAP_EXE), the
source tree (DYNAMAP_SOURCE_DIR) and its bundled logs; ctest sets both (cmake/python.cmake)."""

import json
import os
import subprocess

import pytest

SOURCE = os.environ.get("DYNAMAP_SOURCE_DIR",
                        os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
EXE = os.environ.get("DYNAMAP_EXE", os.path.join(SOURCE, "build", "dynamap"))


def bundled(name):
    """A bundled rawlog: rawlogs/<name>/<name>.rawlog."""
    return os.path.join(SOURCE, "rawlogs", name, name + ".rawlog")


def run_cli(*args):
    """`dynamap map ARGS`: (exit status, stderr)."""
    p = subprocess.run([EXE, "map", *args], capture_output=True, text=True)
    return p.returncode, p.stderr


def summary_of(out_dir, drop=("timing",)):
    with open(os.path.join(out_dir, "summary.json")) as f:
        s = json.load(f)
    for k in drop:
        s.pop(k, None)
    return s


@pytest.fixture(scope="session")
def exe():
    assert os.access(EXE, os.X_OK), f"{EXE}: not built"
    return EXE
