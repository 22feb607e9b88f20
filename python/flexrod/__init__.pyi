# SPDX-License-Identifier: GPL-3.0-or-later
# Type stub of the flexrod package (python/flexrod/__init__.py). SI units throughout; values
# passed as text carry their unit ("25.4 mm", "250 rpm"), bare numbers are SI.
import os
from collections.abc import Sequence
from typing import Any, Mapping, Optional, Union, overload

import numpy as np
import numpy.typing as npt

Float64Array = npt.NDArray[np.float64]
PathLike = Union[str, os.PathLike[str]]

class InputError(ValueError):
    """Bad input, raised before any work: `key` = `value` breaks `rule`."""

    key: str
    value: str
    rule: str
    def __init__(self, key: str, value: str, rule: str) -> None: ...

class IoError(OSError):
    """A file that cannot be written or read: the message names the file and the reason."""

class NumericalError(RuntimeError):
    """A numerical failure; `run` holds everything computed up to it."""

    time: Optional[float]  # [s], last time the integrator reached
    state: Optional[dict[str, Any]]  # |p|, |v|, |lambda|, worst residual / local error
    hint: Optional[str]
    run: Optional[Run]
    outcome: Optional[str]  # "integrator-failure", "step-limit", ...
    def __init__(
        self,
        message: str,
        time: Optional[float] = ...,
        state: Optional[dict[str, Any]] = ...,
        hint: Optional[str] = ...,
        run: Optional[Run] = ...,
        outcome: Optional[str] = ...,
    ) -> None: ...

class Run:
    """One run: channels [SI, see units] with "time" [s], summary.json, twin, impacts."""

    channels: dict[str, Float64Array]
    units: dict[str, str]
    summary: dict[str, Any]
    ideal: Optional[Run]
    impacts: dict[str, Float64Array]  # time [s], crank_angle [rad], peak_force [N], ...
    impact_units: dict[str, str]
    status: Optional[dict[str, Any]]
    @property
    def ok(self) -> bool: ...

class StoredRun:
    """One run of a sweep store."""

    id: int
    label: str
    status: str
    message: str
    fingerprint: str
    inputs: dict[str, Union[float, int, bool, str]]  # resolved, SI
    input_toml: str
    summary: dict[str, Any]
    figures: dict[str, float]
    figure_units: dict[str, str]
    channels: dict[str, Float64Array]  # "time" [s] first, at channel_rate
    units: dict[str, str]
    channel_rate: float  # [Hz]
    wall_time: float  # [s]
    @property
    def ok(self) -> bool: ...

class Store(Sequence[StoredRun]):
    path: str
    @overload
    def __getitem__(self, index: int) -> StoredRun: ...
    @overload
    def __getitem__(self, index: slice) -> list[StoredRun]: ...
    def __len__(self) -> int: ...

def run(
    input: PathLike = "flexible-rig",
    set: Optional[Mapping[str, Union[str, float, int, bool]]] = None,
    out: Optional[PathLike] = None,
    check: bool = False,
    vtk: Optional[PathLike] = None,
) -> Run:
    """One simulation, as `flexrod run INPUT --set k=v ... [--out OUT] [--check] [--vtk VTK]`
    (no plots)."""

def keys() -> list[dict[str, Any]]:
    """Every input key: {"key", "default", "unit" (SI, "" if none), "rule"}."""

def modes(config: Optional[PathLike] = None, **flags: Union[str, float, int]) -> dict[str, Any]:
    """`flexrod modes --json` with the table as arrays: mode, full_hz [Hz], reduced_hz [Hz],
    rel_error [1], mac [1], effective_mass [kg], rigid_body."""

def contact(
    law: str, mass: Union[str, float], velocity: Union[str, float], **params: Union[str, float]
) -> dict[str, Any]:
    """`flexrod contact --json` (mass [kg], velocity [m/s]) plus "loop": time [s],
    penetration [m], rate [m/s], force [N]."""

def sweep(
    matrix: PathLike,
    jobs: Optional[int] = None,
    out: PathLike = "sweep.h5",
    set: Optional[Mapping[str, Union[str, float, int, bool]]] = None,
) -> str:
    """`flexrod sweep MATRIX --jobs N --out OUT` on threads; returns the store's path."""

def open_store(path: PathLike) -> Store:
    """The runs of a sweep store: inputs, summary, figures, channels."""

def reduction_variants() -> list[dict[str, Any]]:
    """The modal reduction study's variants: {"name", "set", "modes"}; the exact rod first."""

def reduction_figures(run: Run) -> dict[str, float]:
    """The reduction study's figures of a run, {name [unit]: value}, NaN where undefined."""
