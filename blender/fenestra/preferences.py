"""The add-on's preferences: where the fenestra binary is."""

import os
import shutil

import bpy

from . import ADDON_ID


class FenestraPreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON_ID

    binary: bpy.props.StringProperty(
        name="fenestra binary",
        description="The fenestra executable (empty: `fenestra` on PATH, or $FENESTRA_BIN)",
        subtype="FILE_PATH",
        default="",
    )

    def draw(self, context):
        self.layout.prop(self, "binary")
        found = binary_or_none(self.binary)
        self.layout.label(
            text=f"Using {found}" if found else "fenestra not found: set its path above",
            icon="CHECKMARK" if found else "ERROR",
        )


def binary_or_none(configured=""):
    """The fenestra executable: the configured path, $FENESTRA_BIN, or `fenestra` on PATH."""
    for candidate in (configured, os.environ.get("FENESTRA_BIN", "")):
        if candidate:
            path = bpy.path.abspath(candidate)
            return path if os.access(path, os.X_OK) else None
    return shutil.which("fenestra")


def binary(context):
    """The fenestra executable, or a RuntimeError saying how to set it."""
    prefs = context.preferences.addons.get(ADDON_ID) if context else None
    configured = prefs.preferences.binary if prefs else ""
    found = binary_or_none(configured)
    if not found:
        raise RuntimeError(
            "fenestra binary not found: install it (cargo install --path crates/fenestra-cli) "
            "or set its path in the add-on's preferences"
        )
    return found


def register():
    bpy.utils.register_class(FenestraPreferences)


def unregister():
    bpy.utils.unregister_class(FenestraPreferences)
