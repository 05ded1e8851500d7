"""The type stubs say what the extension has: mypy's stubtest compares them with the
runtime (every function, parameter, default and class)."""

import subprocess
import sys

import pytest


def test_stubs_match_the_runtime():
    pytest.importorskip("mypy", reason="pip install mypy (in the [test] extra) for stubtest")
    r = subprocess.run([sys.executable, "-m", "mypy.stubtest", "multires"],
                       capture_output=True, text=True, cwd="/")
    assert r.returncode == 0, r.stdout + r.stderr
