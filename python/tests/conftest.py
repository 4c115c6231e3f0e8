"""Shared fixtures: the vts CLI next to the package under test."""
import os
import subprocess

import pytest


@pytest.fixture(scope="session")
def vts_cli():
    """Runs build/bin/vts with arguments; returns its stdout (fails the test on a non-zero exit)."""
    exe = os.path.join(os.environ.get("VTS_BIN_DIR", "build/bin"), "vts")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built")

    def run(*args):
        p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        assert p.returncode == 0, f"vts {' '.join(map(str, args))}: {p.stderr}"
        return p.stdout

    return run
