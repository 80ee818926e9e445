"""Render progress in Python: a tqdm bar per stage when tqdm is installed, or a callback."""

import contextlib
import sys


class _Bars:
    """One tqdm bar per stage (photons, then samples, ...); notes printed above them."""

    def __init__(self, tqdm):
        self.tqdm = tqdm
        self.stage = 0
        self.bar = None

    def __call__(self, stage, done, total, notes):
        for note in notes:
            (self.tqdm.write if self.bar else print)(note, file=sys.stderr)
        if stage != self.stage:
            self.close()
            self.stage = stage
            self.bar = self.tqdm(total=total, unit=" samples" if total is None else "", leave=False)
        if self.bar is not None:
            self.bar.update(done - self.bar.n)

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _notes_only(stage, done, total, notes):
    for note in notes:
        print(note, file=sys.stderr)


@contextlib.contextmanager
def reporter(progress):
    """What `render` hands the renderer as its progress callback, for `progress` as given:
    True (a tqdm bar, or only the notes without tqdm), False (nothing) or a callable."""
    if progress is False or progress is None:
        yield None
    elif progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            yield _notes_only
            return
        bars = _Bars(tqdm)
        try:
            yield bars
        finally:
            bars.close()
    else:
        yield progress
