# SPDX-License-Identifier: GPL-3.0-or-later
"""flexrod — flexible connecting rods in slider-crank mechanisms with a clearance joint.

The Python face of the `flexrod` command line, computing with the same library (the numbers
are bit for bit those of the CLI on the same input):

    >>> import flexrod
    >>> r = flexrod.run("flexible-rig", set={"rod.height": "25.4 mm", "sim.capture": "0.5 s"})
    >>> r.channels["slider_acceleration"]         # numpy float64 [m/s^2]
    >>> r.units["slider_acceleration"]            # 'm/s^2'
    >>> r.summary["load_amplification"]           # summary.json as a dict
    >>> r.ideal.channels["slider_acceleration"]   # the ideal-joint twin

Functions: run, keys, modes, contact, sweep, open_store. Values take units as text
("25.4 mm", "250 rpm", "200 GPa"); bare numbers are SI. Everything returned is SI, with the
unit beside it (Run.units, "units" entries). Bad input raises InputError (a ValueError) with
.key, .value, .rule before any work; a run's numerical failure raises NumericalError with
.time [s], .state, .hint and the partial .run; a file that cannot be written raises IoError (an
OSError) naming it and the system's reason. Runs and sweeps release the GIL and stop on
Ctrl-C (KeyboardInterrupt; a sweep keeps its finished runs and resumes).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any, Mapping, Optional, Union

import numpy as np

__all__ = [
    "InputError",
    "IoError",
    "NumericalError",
    "Run",
    "StoredRun",
    "Store",
    "run",
    "keys",
    "modes",
    "contact",
    "sweep",
    "open_store",
    "reduction_variants",
    "reduction_figures",
]


class InputError(ValueError):
    """Bad input, raised before any work: `key` = `value` breaks `rule`.

    Attributes: key (the input key, flag or argument, e.g. "rod.height"), value (as given,
    text), rule (what it must satisfy, e.g. "must be > 0").
    """

    def __init__(self, key: str, value: str, rule: str):
        super().__init__(f"{key} = {value}: {rule}")
        self.key = key
        self.value = value
        self.rule = rule

    def __reduce__(self):
        return (type(self), (self.key, self.value, self.rule))


class IoError(OSError):
    """A file that cannot be written or read (a full disk, no permission, a file that is not
    flexrod's): the message names the file and the system's reason. What finished before it is
    kept."""


class NumericalError(RuntimeError):
    """A numerical failure: the integrator gave up, a step budget ran out, no convergence.

    Attributes: time (the last time the integrator reached [s], None if the failure is not a
    run's), state (dict: norm_coordinates |p| [m, rad], norm_velocities |v|, norm_multipliers
    |lambda|, worst_residual_variable, worst_residual, worst_error_variable,
    worst_weighted_error), hint (what to try), run (the partial Run: every sample up to the
    failure, its summary), outcome ("integrator-failure", "step-limit", ...).
    """

    def __init__(self, message: str, time: Optional[float] = None,
                 state: Optional[dict] = None, hint: Optional[str] = None,
                 run: Optional["Run"] = None, outcome: Optional[str] = None):
        super().__init__(message)
        self.time = time
        self.state = state
        self.hint = hint
        self.run = run
        self.outcome = outcome


from . import _flexrod  # noqa: E402  (its errors are the classes above)


def _text(value: Any) -> str:
    """A value as the CLI takes it: text as is, True/False as true/false, numbers (SI)."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float, np.integer, np.floating)):
        return repr(float(value)) if isinstance(value, (float, np.floating)) else str(int(value))
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"cannot pass {value!r} ({type(value).__name__}) as an input value")


def _sets(assignments: Optional[Mapping[str, Any]]) -> list:
    return [f"{k}={_text(v)}" for k, v in (assignments or {}).items()]


class Run:
    """One run's results (SI units throughout).

    channels: dict name -> 1-D numpy float64 array, "time" [s] first, then every channel of
        the run (all of them, also those output.channels = standard leaves out of run.h5:
        slider_acceleration [m/s^2], bearing_force [N], ...)
    units: dict name -> unit string ("time": "s", "slider_acceleration": "m/s^2", ...)
    summary: dict, the content of summary.json (peaks, per-revolution statistics, load
        amplification, impacts, energy balance, integrator statistics, wall time [s])
    ideal: the ideal-joint twin's Run (clearance runs), else None
    impacts: dict column -> numpy float64 array, one entry per impact (run.h5 impacts/): time [s],
        crank_angle [rad], approach_velocity [m/s], peak_force [N], time_of_peak_force [s],
        duration [s], peak_penetration [m], dissipated_energy [J], complete [1]
    impact_units: dict column -> unit
    status: dict with the integrator's outcome, time [s], message, hint, state, wall_seconds
    """

    def __init__(self, channels, units, summary, ideal=None, impacts=None, impact_units=None,
                 status=None):
        self.channels = channels
        self.units = units
        self.summary = summary
        self.ideal = ideal
        self.impacts = impacts if impacts is not None else {}
        self.impact_units = impact_units if impact_units is not None else {}
        self.status = status

    @property
    def ok(self) -> bool:
        """True if the integrator completed the run."""
        return self.status is None or self.status.get("outcome") == "completed"

    def __repr__(self) -> str:
        n = len(self.channels.get("time", ()))
        return (f"<flexrod.Run {n} samples, {len(self.channels) - 1} channels, "
                f"{len(next(iter(self.impacts.values()), ()))} impacts, "
                f"ideal twin: {'yes' if self.ideal is not None else 'no'}>")


def _make_run(raw: dict) -> Run:
    ideal = None
    if raw.get("ideal") is not None:
        i = raw["ideal"]
        ideal = Run(i["channels"], i["units"], i["summary"])
    return Run(raw["channels"], raw["units"], raw["summary"], ideal, raw["impacts"],
               raw["impact_units"], raw["status"])


def run(input: Union[str, os.PathLike] = "flexible-rig",
        set: Optional[Mapping[str, Any]] = None,
        out: Union[str, os.PathLike, None] = None,
        check: bool = False,
        vtk: Union[str, os.PathLike, None] = None) -> Run:
    """Run one simulation, as `flexrod run INPUT --set k=v ... [--out OUT] [--check] [--vtk VTK]`.

    input: a preset ("flexible-rig" (default), "rigid-rig", "simeon-crank",
        "flexible-pendulum") or a TOML input file
    set: overrides {key: value}, values with units as text ("25.4 mm", "250 rpm", "0.5 s") or
        bare SI numbers (0.0254 for 25.4 mm); `flexrod.keys()` lists every key with its unit
    out: None writes no file; a directory gets what `flexrod run --out DIR` writes
        (resolved.toml, summary.json, run.h5 or the CSV files of output.format), without the
        plots
    check: the accuracy estimate of `flexrod run --check`: the same run at 100x tighter
        sim.rel_tol and sim.abs_tol; each headline figure's difference [%] is in
        summary["accuracy_check"]
    vtk: None draws nothing; a directory gets the ParaView frames of `flexrod run --vtk DIR`
        (run.pvd and one .vtu per frame; keys vtk.rate, vtk.scale, vtk.duration)

    Returns a Run (channels [SI, see Run.units], summary, ideal twin, impacts). Raises
    InputError before any work for bad input; NumericalError (with .time [s], .state, .hint
    and the partial .run) if the integrator fails; KeyboardInterrupt on Ctrl-C. The GIL is
    released while the run computes.
    """
    raw = _flexrod.run(os.fspath(input), _sets(set), None if out is None else os.fspath(out),
                       bool(check), None if vtk is None else os.fspath(vtk))
    result = _make_run(raw)
    if not raw["ok"]:
        st = raw["status"]
        raise NumericalError(st["summary"], time=st["time"], state=st["state"], hint=st["hint"],
                             run=result, outcome=st["outcome"])
    return result


def keys() -> list:
    """Every input key: a list of dicts with "key", "default" (as typed, with its unit),
    "unit" (the SI unit of a quantity, "" for counts, choices and text) and "rule" (what the
    value must satisfy, and what it means); "choices" for choice keys."""
    return _flexrod.keys()


def modes(config: Union[str, os.PathLike, None] = None, **flags: Any) -> dict:
    """Modal analysis of one rod, as `flexrod modes --FLAG value ...`: full FE against the
    reduced model, per mode.

    config: optional TOML file with rod.*, reduction.*, modes.* keys
    flags (the CLI's flags without the dashes, values with units or SI numbers):
        material (steel|brass|aluminium), E [Pa] ("200 GPa"), nu [1], rho [kg/m^3],
        thickness [m] ("3.175 mm"), height [m], length [m], elements (count),
        element (euler-bernoulli|timoshenko), bending (weak|strong), mass (consistent|lumped),
        dim (planar|spatial), bc (clamped-clamped|clamped-free|free-free|pinned-pinned|
        clamped-pinned), reduction (craig-bampton|orthonormal-cb|free-free|full),
        modes (k), cutoff [Hz] ("5 kHz"), interface (small-end|ends|node list), report (rows)

    Returns what `flexrod modes --json` writes ("inputs", "num_coordinates", "units") with the
    table as numpy arrays: "mode" (int), "full_hz" [Hz], "reduced_hz" [Hz], "rel_error" [1],
    "mac" [1], "effective_mass" [kg] (float64, NaN where undefined), "rigid_body" (bool);
    the run's rod in its assembled mechanism (crank held at 0, ideal small-end joint) as
    "mechanism_frequency_hz" [Hz] and the ratio damping.* gives each, "mechanism_damping_ratio"
    [1] (empty for a rigid rod or Rayleigh damping); "warning" ("" if none). Raises InputError
    for bad flags.
    """
    raw = _flexrod.modes("" if config is None else os.fspath(config),
                         [(k, _text(v)) for k, v in flags.items()])
    rows = raw.pop("modes", None) or []
    out = dict(raw)
    out["mode"] = np.array([r["mode"] for r in rows], dtype=np.int64)
    for col in ("full_hz", "reduced_hz", "rel_error", "mac", "effective_mass"):
        out[col] = np.array([np.nan if r[col] is None else r[col] for r in rows],
                            dtype=np.float64)
    out["rigid_body"] = np.array([r["rigid_body"] for r in rows], dtype=bool)
    mechanism = out.pop("mechanism_modes", None) or []
    out["mechanism_frequency_hz"] = np.array([m["frequency_hz"] for m in mechanism],
                                             dtype=np.float64)
    out["mechanism_damping_ratio"] = np.array([m["damping_ratio"] for m in mechanism],
                                              dtype=np.float64)
    return out


def contact(law: str, mass: Any, velocity: Any, **params: Any) -> dict:
    """One impact of a mass on a rigid wall through a normal contact law, as
    `flexrod contact --law LAW --mass M --velocity V [--param value ...] --json`.

    law: hertz, hunt-crossley, lankarani-nikravesh, flores, hybrid, ... (an unknown name
        raises InputError listing them)
    mass: impacting mass [kg] ("2.71 kg" or 2.71); velocity: approach speed [m/s]
    params (values with units or SI numbers): pin_E [Pa], pin_nu [1], bush_E [Pa],
        bush_nu [1] (default steel), pin_radius [m] (default 9.025 mm), bush_radius [m]
        (9.525 mm), length [m] (12.7 mm); the law's: restitution [1], stiffness [N/m^n, SI],
        exponent [1], damping [N*s/m], stiffness_2 [N/m], working_penetration [m],
        min_approach_velocity [m/s], max_damping [N*s/m], damping_penetration [m],
        calibration_velocity [m/s], compliance [1/Pa], effective_mass [kg]

    Returns the figures of `flexrod contact --json`: achieved_restitution [1],
    peak_force [N], peak_penetration [m], contact_duration [s], dissipated_energy [J],
    outgoing_speed [m/s], "units", "inputs", the resolved "parameters", any "warnings"; and
    the hysteresis loop as float64 arrays: "loop" {"time" [s], "penetration" [m],
    "rate" [m/s], "force" [N]} with "loop_units".
    """
    return _flexrod.contact(law, _text(mass), _text(velocity),
                            [(k, _text(v)) for k, v in params.items()])


def sweep(matrix: Union[str, os.PathLike], jobs: Optional[int] = None,
          out: Union[str, os.PathLike] = "sweep.h5",
          set: Optional[Mapping[str, Any]] = None) -> str:
    """Run a test matrix into one HDF5 store, as `flexrod sweep MATRIX --jobs N --out OUT`
    (threads on this machine; resumable; the store is the CLI's bit for bit).

    matrix: a built-in matrix ("sweep-small", "sweep-table2") or a matrix TOML file
    jobs: worker threads, None = every core
    out: the store file, must end in .h5
    set: overrides of the base input or store options {key: value}, as --set
        ({"sim.capture": "0.5 s", "store.rate": "20 kHz"})

    Returns the store's path. Raises InputError before any run for a bad matrix or store;
    KeyboardInterrupt on Ctrl-C (finished runs stay in OUT.parts/ and a new call resumes).
    Unlike the CLI it writes neither OUT.summary.csv nor the amplification plot.
    """
    return _flexrod.sweep(os.fspath(matrix), _sets(set), jobs, os.fspath(out))


class StoredRun:
    """One run of a sweep store.

    id, label (its matrix values), status ("completed" or the failure), message,
    inputs: dict key -> resolved value (quantities as SI floats, counts as int, flags as bool,
        choices and text as str), input_toml (the run's input as TOML),
    summary: dict, the run's summary.json,
    figures: dict name -> the store's summary scalars (peak_positive [m/s^2], ...,
        amplification_positive [1]; see figure_units),
    channels: dict name -> numpy float64 array at channel_rate [Hz], "time" [s] first;
        units: dict name -> unit,
    wall_time [s].
    """

    def __init__(self, raw: dict):
        self.id = raw["id"]
        self.label = raw["label"]
        self.status = raw["status"]
        self.message = raw["message"]
        self.fingerprint = raw["fingerprint"]
        self.inputs = raw["inputs"]
        self.input_toml = raw["input_toml"]
        self.summary = raw["summary"]
        self.figures = raw["figures"]
        self.figure_units = raw["figure_units"]
        self.channels = raw["channels"]
        self.units = raw["units"]
        self.channel_rate = raw["channel_rate"]
        self.wall_time = raw["wall_time"]

    @property
    def ok(self) -> bool:
        return self.status == "completed"

    def __repr__(self) -> str:
        return f"<flexrod.StoredRun {self.id} {self.label} {self.status}>"


class Store(Sequence):
    """The runs of a sweep store, in run-id order (a read-only sequence of StoredRun)."""

    def __init__(self, path: str, runs: list):
        self.path = path
        self._runs = runs

    def __getitem__(self, index):
        return self._runs[index]

    def __len__(self) -> int:
        return len(self._runs)

    def __repr__(self) -> str:
        return f"<flexrod.Store {self.path}: {len(self)} runs>"


def open_store(path: Union[str, os.PathLike]) -> Store:
    """Read a sweep store (`flexrod sweep` or `flexrod.sweep`): a sequence of StoredRun with
    inputs, summary, figures and channels. Raises InputError if it is not a flexrod store."""
    p = os.fspath(path)
    return Store(p, [StoredRun(r) for r in _flexrod.open_store(p)])


def reduction_variants() -> list:
    """The variants of the modal reduction study (`flexrod study reduction`), in its table
    order, the reference (the exact rod) first: dicts with "name" ("exact", "full", "cb-0",
    ..., "cb-16", "orthonormal-cb-8", "free-free-8"), "set" ({key: value} to add to the case's
    input) and "modes" (the Craig-Bampton k, -1 for the others)."""
    out = []
    for v in _flexrod.reduction_variants():
        pairs = [a.split("=", 1) for a in v["sets"]]
        out.append({"name": v["name"], "set": {k: val for k, val in pairs}, "modes": v["modes"]})
    return out


def reduction_figures(run: Run) -> dict:
    """The figures the modal reduction study judges a variant by, {name with unit: value}
    (NaN where the run has none): peak |slider acc.| [m/s^2], p95 per-rev. peak |slider acc.|
    [m/s^2], amplification + (p95) [1], amplification - (p95) [1], peak bearing force [N],
    peak gauge strain [1], first impact [s]."""
    import json
    times = run.impacts.get("time", ())
    first = float(times[0]) if len(times) else float("nan")
    return dict(_flexrod.reduction_figures(json.dumps(run.summary), first))
