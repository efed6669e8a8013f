"""Type stubs of ``demsweep._native``, the compiled library (python/src/lib.rs): what each function
takes and returns. Tables come back as dicts of columns (name → list); ``demsweep`` wraps them as
pandas DataFrames."""

import os
import pathlib
from typing import Any, Mapping, NoReturn, Optional, Sequence, Union, final

_Scene = Union[str, Mapping[str, Any]]
_Seeds = Union[None, int, Sequence[int]]
_Columns = dict[str, list[Any]]

__version__: str

class DemsweepError(Exception):
    """Any error the demsweep library reports."""

class StudyError(DemsweepError):
    """A study, scene or tune file the library refuses (the text ``demsweep check`` prints)."""

    problems: list[dict[str, Any]]
    study_text: Optional[str]

class ResultsError(DemsweepError):
    """A results file that cannot be read or written."""

@final
class Results:
    def __new__(cls, path: Union[str, os.PathLike[str]]) -> Results: ...
    @property
    def path(self) -> pathlib.Path: ...
    def summary(self) -> _Columns: ...
    def points(self) -> _Columns: ...
    def history(self, run: Union[str, int]) -> Optional[dict[str, list[float]]]: ...
    def stress_profile(
        self, run: Union[str, int]
    ) -> Optional[tuple[dict[str, list[float]], dict[str, str]]]: ...
    def final_state(self, run: Union[str, int]) -> Optional[dict[str, Any]]: ...
    def frames(self, run: Union[str, int]) -> list[dict[str, Any]]: ...
    def scene_json(self, run: Union[str, int]) -> str: ...

def run(scene: _Scene, seeds: _Seeds = None, jobs: int = 0) -> _Columns: ...
def run_batch(scenes: Sequence[_Scene], seeds: _Seeds = None, jobs: int = 0) -> list[_Columns]: ...
def scene_study(scene: _Scene, seeds: _Seeds = None) -> str: ...
def run_study(
    path: str,
    out: Optional[str] = None,
    resume: bool = False,
    force: bool = False,
    jobs: int = 0,
    progress: str = "quiet",
    checkpoint_every: Optional[float] = None,
) -> dict[str, Any]: ...
def tune(
    path: str,
    out: Optional[str] = None,
    resume: bool = False,
    force: bool = False,
    jobs: int = 0,
    verbose: bool = False,
) -> dict[str, Any]: ...
def units() -> dict[str, str]: ...
def column_units(names: Sequence[str]) -> dict[str, str]: ...
def main(argv: Sequence[str]) -> NoReturn: ...
