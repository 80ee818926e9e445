import os
import subprocess

import pytest


@pytest.fixture(scope="session")
def cli():
    """Runs this build's `fenestra` binary with the given arguments."""
    binary = os.environ.get("FENESTRA_BIN", "fenestra")

    def run(*args):
        done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done

    return run
