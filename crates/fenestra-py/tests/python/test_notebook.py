"""docs/python.py, the notebook, runs end to end (small) and finds what the docs say."""

import os
import runpy
from pathlib import Path

import pytest


def test_the_notebook_runs_and_portals_win(tmp_path, monkeypatch, capsys):
    notebook = Path(os.environ.get("FENESTRA_DOCS", "docs")) / "python.py"
    monkeypatch.setenv("FENESTRA_NOTEBOOK_QUICK", "1")
    monkeypatch.setenv("FENESTRA_NOTEBOOK_FIGURE", str(tmp_path / "figure.png"))
    # A portal cache of its own: estimated within the render's time, as on a fresh machine.
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    pytest.importorskip("matplotlib")
    ns = runpy.run_path(str(notebook), run_name="__main__")
    assert ns["ratio"] > 2, capsys.readouterr().out
    assert (tmp_path / "figure.png").stat().st_size > 10_000
