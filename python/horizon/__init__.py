"""Horizon, a peridynamics engine, from Python.

    import horizon
    sim = horizon.Simulation("examples/glass_branching.yaml", coarsen=4)
    sim.run(callback=lambda s: print(s.steps, s.damage.max()), every=100)
    print(sim.summary["damage"]["mean"])

docs/python.md documents every call.
"""
import csv
import io
import json
import os

import numpy as np

from . import _core
from ._core import Deck, DeckError, Error, models

__version__ = _core.__version__

__all__ = ["Deck", "DeckError", "Error", "Simulation", "load", "loads", "from_dict", "convert_peridigm",
           "models", "read_frame", "render", "run"]


def load(path):
    """A deck read from a file (native or Peridigm YAML)."""
    return Deck.from_file(os.fspath(path))


def loads(text, name="<string>"):
    """A deck parsed from YAML text; `name` is what error messages call it."""
    return Deck.from_text(text, name)


def from_dict(data, name="<dict>"):
    """A deck from nested dicts and lists (the same keys as a deck file)."""
    return Deck.from_dict(data, name)


def read_frame(path):
    """A frame (.vtu), or the last frame of a .pvd index or of a run's output folder, as
    {"time", "step", "points": (N, 3) array, "fields": {name: array}} (copies)."""
    return _core.read_frame(os.fspath(path))


def render(path, field="damage", output=None, width=1200, scale=1.0):
    """Draws a frame (or a run folder's last frame) coloured by `field` to PNG, as
    `horizon render` does; returns the PNG's path (default: <field>.png beside the frame)."""
    return _core.render(os.fspath(path), field, None if output is None else os.fspath(output), int(width),
                        float(scale))


def convert_peridigm(path):
    """The native deck (YAML text) equivalent to the Peridigm deck at `path` (`horizon convert`)."""
    return _core.convert_peridigm(os.fspath(path))


def _as_deck(deck):
    if isinstance(deck, Deck):
        return deck
    if isinstance(deck, dict):
        return from_dict(deck)
    if isinstance(deck, (str, os.PathLike)):
        return load(deck)
    raise TypeError("expected a horizon.Deck, a dict or a deck file's path, got %r" % type(deck).__name__)


class Simulation(_core.Simulation):
    """A run of a deck.

    Simulation(deck, output_dir=None, coarsen=1, end_time=None, threads=0, quiet=True,
               set=None)

    `deck` is a horizon.Deck, a dict or a path; `set` maps deck paths to values
    ({"materials.glass.density": 2500}) applied before the run is built. Explicit decks
    are built at once (particles, bonds, initial frame) and can be stepped; static and
    implicit decks run in run().
    """

    def __init__(self, deck, output_dir=None, coarsen=1.0, end_time=None, threads=0, quiet=True, set=None):
        deck = _as_deck(deck)
        if set:
            for path, value in set.items():
                deck.set(path, value)
        self.deck = deck
        _core.Simulation.__init__(self, deck, None if output_dir is None else os.fspath(output_dir), float(coarsen),
                                  end_time, int(threads), bool(quiet))
        self._summary = None

    def step(self, n=1):
        """Takes up to n steps (fewer at the end of the run); returns how many were taken.
        The GIL is released while the steps run."""
        return self._advance(int(n))

    def run(self, callback=None, every=100):
        """Runs to the end and writes history.csv and summary.json; returns the summary.

        With a callback, callback(sim) is called every `every` steps (and once at the
        end); returning False (or any false value but None: numpy.False_, 0) stops the run there: the final frame,
        history and summary are written as for a completed run, with status "stopped".
        An exception in the callback, or Ctrl-C, also ends the run cleanly and is raised.
        """
        if not self.is_explicit:
            if callback is not None:
                raise Error("a callback needs an explicit run; static and implicit_dynamic decks run to the end")
            self._finish()
            return self.summary
        every = int(every)
        if every < 1:
            raise ValueError("every must be >= 1")
        chunk = every if callback is not None else 1000
        try:
            while not self.done:
                self._advance(chunk)
                if callback is not None:
                    verdict = callback(self)
                    # None (no return) goes on; False, numpy.False_, 0 stop.
                    if verdict is not None and not verdict:
                        self._stop("stopped by the callback")
        except BaseException as e:  # KeyboardInterrupt included: end the run cleanly, then raise
            if not self.done:
                self._stop("stopped by %s" % type(e).__name__)
            self._finish()
            raise
        return self.finish()

    def finish(self):
        """Ends the run where it is (status "stopped" if it had steps left) and writes the
        final frame, history.csv and summary.json; returns the summary."""
        if self.is_explicit and not self.done:
            self._stop("finished by the caller")
        self._finish()
        return self.summary

    @property
    def summary(self):
        """summary.json as a dict, once the run is finished (None before)."""
        if not self.finished:
            return None
        if self._summary is None:
            text = self._summary_json() if self.is_explicit else None
            if text:
                self._summary = json.loads(text)
            else:
                with open(os.path.join(self.output_dir, "summary.json")) as f:
                    self._summary = json.load(f)
        return self._summary

    @property
    def history(self):
        """The history rows so far as a dict of column name -> NumPy array."""
        if self.is_explicit:
            return _parse_csv(self._history_csv())
        return read_history(self.output_dir)


def _parse_csv(text):
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return {}
    header, data = rows[0], rows[1:]
    cols = np.array([[float(x) for x in r] for r in data], dtype=float).reshape(len(data), len(header))
    return {name: cols[:, i].copy() for i, name in enumerate(header)}


def read_history(path):
    """A run's history.csv (the file or its folder) as a dict of NumPy arrays."""
    path = os.fspath(path)
    if os.path.isdir(path):
        path = os.path.join(path, "history.csv")
    with open(path) as f:
        return _parse_csv(f.read())


def read_summary(path):
    """A run's summary.json (the file or its folder) as a dict."""
    path = os.fspath(path)
    if os.path.isdir(path):
        path = os.path.join(path, "summary.json")
    with open(path) as f:
        return json.load(f)


def run(deck, callback=None, every=100, **options):
    """Simulation(deck, **options).run(callback, every): runs a deck, returns the Simulation."""
    sim = Simulation(deck, **options)
    sim.run(callback=callback, every=every)
    return sim


__all__ += ["read_history", "read_summary"]
