"""The add-on's tests run in CPython 3.11 with the `bpy` module (Blender as a Python module,
from PyPI) and this build's fenestra binary ($FENESTRA_BIN). The add-on is installed as a
user would install it: from the zip scripts/blender-addon-zip makes, into a user folder of
the test's own ($BLENDER_USER_RESOURCES, set before bpy is imported)."""

import os
import pathlib
import subprocess
import sys
import tempfile

import pytest

HERE = pathlib.Path(__file__).parent
REPO = HERE.parent.parent
sys.path.insert(0, str(HERE))

if "BLENDER_USER_RESOURCES" not in os.environ:
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="fenestra-blender-user-")

import bpy  # noqa: E402  (after the user folder is set)


def _install_addon():
    folder = pathlib.Path(tempfile.mkdtemp(prefix="fenestra-addon-zip-"))
    zip_path = folder / "fenestra-blender.zip"
    subprocess.run(
        [str(REPO / "scripts/blender-addon-zip"), str(zip_path)], check=True, capture_output=True
    )
    bpy.ops.preferences.addon_install(filepath=str(zip_path), overwrite=True)
    bpy.ops.preferences.addon_enable(module="fenestra")


_install_addon()


@pytest.fixture(scope="session")
def fenestra_bin():
    path = os.environ.get("FENESTRA_BIN")
    assert path and os.access(path, os.X_OK), "set FENESTRA_BIN to this build's fenestra"
    return path


@pytest.fixture
def workdir(tmp_path):
    return tmp_path
