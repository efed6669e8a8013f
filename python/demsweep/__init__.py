"""demsweep from Python: the engine, studies and results of the demsweep library, in-process.

Everything runs in the compiled library (``demsweep._native``); this package only wraps its tables
as pandas DataFrames and its arrays as NumPy arrays. Guide: docs/python.md of the repository.

- ``run(scene, seeds=None, jobs=0)``: the runs of one scene (a dict, or TOML text, of the keys of a
  study's ``[scene]``), one summary row per run as a DataFrame.
- ``run_batch(scenes, seeds=None, jobs=0)``: many scenes on one pool of worker threads (the
  interpreter released), a DataFrame per scene; the values do not depend on ``jobs``.
- ``run_study(path, ...)`` and ``tune(path, ...)``: ``demsweep run`` and ``demsweep tune``.
- ``open(path)``: a results file: ``.summary``, ``.points``, ``.history(run)``,
  ``.stress_profile(run)``, ``.final(run)``, ``.frames(run)``, ``.scene(run)``.

Units are SI, one per quantity: ``UNITS`` maps every summary column, history series and disk field
to its unit; each DataFrame's ``attrs["units"]`` holds its columns' units (swept keys' included), as
the metadata sidecar of a CSV file does. Refused studies and scenes raise
``StudyError`` with the text ``demsweep check`` prints; unreadable results raise ``ResultsError``.
"""

from __future__ import annotations

import json as _json
import os as _os
import pathlib as _pathlib
import typing as _typing
import warnings as _warnings

import numpy as _np
import pandas as _pd

from . import _native
from ._native import DemsweepError, ResultsError, StudyError, scene_study

#: The version of the demsweep library this module was built from (as ``demsweep --version``).
__version__: str = _native.__version__

#: A scene: a dict of the keys of a study's ``[scene]`` (nested, or dotted as in TOML:
#: ``{"material.friction": 0.3}``), or TOML text of them.
Scene = _typing.Union[str, _typing.Mapping[str, _typing.Any]]
#: Placement seeds: None (the scene's own), a number of replicates, or a list of seeds.
Seeds = _typing.Union[None, int, _typing.Sequence[int]]
#: A path, as ``os.fspath`` takes it.
PathLike = _typing.Union[str, "_os.PathLike[str]"]
#: A run of a results file: its id (``"r0007"``) or its index.
RunKey = _typing.Union[str, int]

__all__ = [
    "DemsweepError",
    "DemsweepWarning",
    "PathLike",
    "Results",
    "ResultsError",
    "RunKey",
    "Scene",
    "Seeds",
    "StudyError",
    "UNITS",
    "open",
    "run",
    "run_batch",
    "run_study",
    "scene_study",
    "tune",
]

#: The SI unit of every summary column, history series, stress profile column and disk field ("" when
#: dimensionless).
UNITS: dict[str, str] = _native.units()


class DemsweepWarning(UserWarning):
    """What ``demsweep check`` and ``demsweep run`` warn about: implausible values, predicted
    validity problems, runs that diverged or failed. A notebook can silence these or make them
    errors: ``warnings.simplefilter("error", demsweep.DemsweepWarning)``."""


def _issue(texts: _typing.Iterable[str], stacklevel: int = 3) -> None:
    """Issues each text as a DemsweepWarning pointing at the caller's caller (``stacklevel``)."""
    for text in texts:
        _warnings.warn(text, DemsweepWarning, stacklevel=stacklevel)


def _frame(columns: dict[str, _typing.Any]) -> _pd.DataFrame:
    frame = _pd.DataFrame(columns)
    frame.attrs["units"] = _native.column_units([str(c) for c in frame.columns])  # the CSV sidecar's units
    return frame


def run(scene: Scene, seeds: Seeds = None, jobs: int = 0) -> _pd.DataFrame:
    """Runs one scene; one row per run (columns as in ``demsweep summary``).

    ``seeds``: None for one run with the scene's ``placement.seed``; a number n for n replicates
    (seeds ``placement.seed``, +1, ...); a list for one run per placement seed. What ``demsweep
    check`` warns about, and runs that diverged or failed, are issued as ``DemsweepWarning``.
    """
    table, said = _native.run(scene, seeds, jobs)
    _issue(said)
    return _frame(table)


def run_batch(scenes: _typing.Iterable[Scene], seeds: Seeds = None, jobs: int = 0) -> list[_pd.DataFrame]:
    """Runs many scenes together on ``jobs`` worker threads (0: one per core); a DataFrame per scene."""
    tables, said = _native.run_batch(list(scenes), seeds, jobs)
    _issue(said)
    return [_frame(table) for table in tables]


def _warn(answer: dict[str, _typing.Any]) -> dict[str, _typing.Any]:
    _issue(answer["warnings"] + answer.get("notes", []), stacklevel=4)
    return answer


def run_study(path: PathLike, out: PathLike | None = None, resume: bool = False, force: bool = False,
              jobs: int = 0, progress: str = "quiet",
              checkpoint_every: float | None = 600.0) -> dict[str, _typing.Any]:
    """``demsweep run PATH``: the results file, CSV files and report page; returns what it did.

    ``checkpoint_every``: ``--checkpoint-every`` in seconds (None: off): each run in progress saves
    its state that often beside the results; ``resume=True`` continues it from there, to the bits the
    uninterrupted run stores.

    Keys: ``results`` (the HDF5 file, for ``open``), ``summary_csv``, ``points_csv``, ``report``,
    ``selected``, ``already_done``, ``ran``, ``failed``, ``missing``, ``exit_code`` (the command's),
    ``warnings`` (the study's), ``notes`` (what it found in an existing results file: stored runs
    that run again and why, stored runs the study no longer plans; both also issued as Python
    warnings) and ``run_warnings``.
    """
    return _warn(_native.run_study(_os.fspath(path), _path(out), resume, force, jobs, progress, checkpoint_every))


def tune(path: PathLike, out: PathLike | None = None, resume: bool = False, force: bool = False,
         jobs: int = 0, verbose: bool = False) -> dict[str, _typing.Any]:
    """``demsweep tune PATH``; returns ``results``, ``recommendation`` (the paragraph),
    ``recommended`` (its settings, or None), ``files``, ``report``, ``ran``, ``reused``,
    ``particle_steps`` and ``warnings``."""
    return _warn(_native.tune(_os.fspath(path), _path(out), resume, force, jobs, verbose))


def _path(path: PathLike | None) -> str | None:
    return None if path is None else _os.fspath(path)


def _arrays(state: dict[str, _typing.Any] | None) -> dict[str, _typing.Any] | None:
    if state is None:
        return None
    return {k: _arrays(v) if isinstance(v, dict) else v if k == "time" else _np.asarray(v)
            for k, v in state.items()}


class Results:
    """A results file read through the library's readers; ``run`` is a run id or a run index."""

    def __init__(self, path: PathLike) -> None:
        self._file = _native.Results(_os.fspath(path))

    @property
    def path(self) -> _pathlib.Path:
        """The results file."""
        return self._file.path

    @property
    def summary(self) -> _pd.DataFrame:
        """One row per run: identity, swept parameters, status, outcome and final values."""
        return _frame(self._file.summary())

    @property
    def points(self) -> _pd.DataFrame:
        """One row per grid point: n, status counts and each metric's mean, std, ci95, min, max."""
        return _frame(self._file.points())

    def history(self, run: RunKey) -> dict[str, _typing.Any] | None:
        """The run's sampled series (``t`` and the rest, see ``UNITS``) as arrays, or None."""
        return _arrays(self._file.history(run))

    def stress_profile(self, run: RunKey) -> _pd.DataFrame | None:
        """The run's stress profile, or None: one row per height band of its settled pile from the
        floor up, as ``demsweep history RESULTS RUN --stress-profile`` prints it (``bottom``, ``top``
        in m; the band's Love–Weber stress ``stress_xx``, ``stress_yy``, ``stress_xy``, its
        ``stress_pressure`` and ``stress_deviatoric``, the side walls' ``wall_normal_stress`` and
        ``wall_shear_stress``, in Pa, compression positive); stored with the histories."""
        stored = self._file.stress_profile(run)
        if stored is None:
            return None
        columns, units = stored
        frame = _pd.DataFrame(columns)
        frame.attrs["units"] = units
        return frame

    def final(self, run: RunKey) -> dict[str, _typing.Any] | None:
        """The run's final state: ``time``, one array per disk field, ``contacts`` (arrays)."""
        return _arrays(self._file.final_state(run))

    def frames(self, run: RunKey) -> list[dict[str, _typing.Any]]:
        """The run's recorded frames, in time order, each like ``final``."""
        return [_arrays(frame) or {} for frame in self._file.frames(run)]

    def scene(self, run: RunKey) -> dict[str, _typing.Any]:
        """The run's complete scene, every key of a study's ``[scene]``."""
        return _json.loads(self._file.scene_json(run))

    def __repr__(self) -> str:
        return f"demsweep.Results({self.path!r})"


def open(path: PathLike) -> Results:  # noqa: A001 - the module's reader, like io.open
    """Opens a results file (``.h5``) written by ``run_study``, ``tune`` or the command line, or the
    one results file in a folder (``results/<study name>``), as the commands do."""
    return Results(path)


del annotations  # the __future__ import's name: not one of the module's
