"""What the fenestra binary offers, as `fenestra list --json` says it: its integrators, light
selections, the option groups each integrator reads and every option's default. The add-on's
settings are made from it, so they cannot drift from the binary; it is asked once per binary."""

import json
import subprocess

import bpy

from . import ADDON_ID, preferences

_asked = {}
_items = {}


def _binary():
    prefs = bpy.context.preferences.addons.get(ADDON_ID)
    return preferences.binary_or_none(prefs.preferences.binary if prefs else "")


def read():
    """The catalogue of the binary in use (empty lists when there is none, or it says nothing
    readable)."""
    binary = _binary()
    if binary not in _asked:
        _asked[binary] = _ask(binary)
    return _asked[binary]


def _ask(binary):
    empty = {"integrators": [], "light_samplers": [], "options": []}
    if not binary:
        return empty
    try:
        out = subprocess.run(
            [binary, "list", "--json"], capture_output=True, text=True, timeout=60, check=True
        )
        return json.loads(out.stdout)
    except (OSError, subprocess.SubprocessError, ValueError):
        return empty


def reads(integrator, group):
    """Whether `integrator` reads the option group `group` (`path`, `light`, `portals`)."""
    entry = next((e for e in read()["integrators"] if e["name"] == integrator), None)
    return entry is not None and group in entry["groups"]


def default(key):
    """The default of option `key` (`light.selection`), or None."""
    return next((o["default"] for o in read()["options"] if o["key"] == key), None)


def enum_items(kind, first=None):
    """Blender enum items (name, name, what it does) of the catalogue's `kind`
    (`integrators`, `light_samplers`), `first` first; kept here, as Blender needs the strings
    of dynamic items to outlive the call."""
    entries = read()[kind]
    entries = sorted(entries, key=lambda e: e["name"] != first)
    items = [(e["name"], e["name"], e["about"]) for e in entries]
    if not items:
        items = [("none", "fenestra not found", "Set the fenestra binary in the preferences")]
    _items[kind] = items
    return items
