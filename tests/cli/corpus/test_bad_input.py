# SPDX-License-Identifier: GPL-3.0-or-later
"""Bad-input corpus of the flexrod command line.

The rule (README, "Commands"): every input -- key, flag, file, matrix, every run of a sweep or
study, output location -- is validated before any work and before any file is written; the
message names the user's key or flag, the value (quoted, also when empty) and the rule; the exit
code is 2 (0 ok, 1 numerical failure, 2 bad input, 3 I/O error, 4 internal).

Each case is one line of data: an id, the argv, the expected exit code and the substrings that
must appear on stderr (the user's key or flag and the offending value, as flexrod spells them).
Each case runs in a fresh temporary directory (also its working directory, so that default
output locations such as out/run land there); every output location the case names is a fresh,
non-existent path in it, and the test checks that afterwards the directory holds exactly the
files the test itself put there, unchanged. Each case must finish within 60 s.

Cases that flexrod does not (yet) refuse cleanly keep the correct expectation and are marked
xfail(strict=True) with what actually happens.

    FLEXROD_BINARY=/work/main/build/flexrod /usr/bin/python3 -m pytest -q tests/cli/corpus

Environment: FLEXROD_BINARY (default /work/main/build/flexrod), FLEXROD_SOURCE_DIR (default the
repository root: this file's directory tests/cli/corpus/../../..).
Standard library and pytest only.
"""

import errno
import hashlib
import os
import pathlib
import resource
import subprocess
import time

import pytest

HERE = pathlib.Path(__file__).resolve().parent
BINARY = os.environ.get("FLEXROD_BINARY") or "/work/main/build/flexrod"
SOURCE_DIR = pathlib.Path(os.environ.get("FLEXROD_SOURCE_DIR") or HERE.parents[2])
TIMEOUT = 60  # seconds per case
# Address-space limit of each flexrod process [bytes] (a shared machine); none for a binary
# built with AddressSanitizer (scripts/sanitize.sh sets ASAN_OPTIONS), which reserves terabytes
# of shadow address space at start-up.
MEMORY = None if "ASAN_OPTIONS" in os.environ else 4 << 30

# Placeholders in argv, expected substrings and file contents: {tmp} the case's directory,
# {src} the source tree. As the content of an input file: STORE a small sweep store, RUNH5 the
# run.h5 of a tiny run, CUT the first 5000 bytes of that store (made once per session).
STORE, RUNH5, CUT = object(), object(), object()
# As the content of a file: a FIFO (os.mkfifo) there instead; a symbolic link to "plain".
FIFO, LINK = object(), object()
# A name longer than the file systems allow for one (NAME_MAX = 255 bytes).
LONG = "n" * 300

# Every case gets these inputs in its directory: a regular file (a location that cannot be a
# directory) and an empty directory.
COMMON_FILES = {"plain": "keep\n"}
COMMON_DIRS = ("adir",)


class Case:
    def __init__(self, cid, argv, expect, rc=2, files=None, xfail=None):
        self.id = cid
        self.argv = list(argv)
        self.expect = list(expect)
        self.rc = rc
        self.files = dict(files or {})
        self.xfail = xfail

    def param(self):
        marks = [pytest.mark.xfail(strict=True, reason=self.xfail)] if self.xfail else []
        return pytest.param(self, id=self.id, marks=marks)


# --------------------------------------------------------------------------------------------
# run
# --------------------------------------------------------------------------------------------
# A short horizon, so that an input that is wrongly accepted costs a fraction of a second; the
# case's own --set values come after these and win.
CHEAP = ["--set", "sim.settle=0s", "--set", "sim.capture=0.002s", "--set", "sim.sample_rate=10kHz"]


def sets(*kv):
    out = []
    for s in kv:
        out += ["--set", s]
    return out


def R(cid, kv, expect, input=None, extra=(), out=True, files=None, xfail=None, rc=2):
    """`flexrod run [input] CHEAP --set kv... extra... --no-plot --out {tmp}/out`."""
    argv = ["run"] + (input.split(" ") if input else []) + CHEAP + sets(*kv) + list(extra)
    if out:
        argv += ["--no-plot", "--out", "{tmp}/out"]
    return Case("run-" + cid, argv, expect, rc=rc, files=files, xfail=xfail)


RUN = [
    # issue 60 items 4 and 6: names the system cannot hold, a matrix or an array of tables
    R("input-name-too-long", [], ["input = " + LONG + ".toml", "255"], input=LONG + ".toml"),
    R("out-name-too-long", [], ["--out = {tmp}/" + LONG, "255"], out=False,
      extra=["--no-plot", "--out", "{tmp}/" + LONG]),
    R("vtk-name-too-long", [], ["--vtk = {tmp}/" + LONG, "255"], extra=["--vtk", "{tmp}/" + LONG]),
    R("thickness-above-length", ["rod.thickness=3175 m"],
      ["rod.thickness = 3175 m", "must be below rod.length"]),
    R("control-character", ["rod.material=st\x01eel"], ["rod.material = st\\x01eel"]),
    R("clearance-below-the-default-penetration", ["joint.clearance=1e-9 m"],
      ["joint.clearance = ", "too small for the ESDU-78035 law"]),
    R("array-of-tables", [], ["[[rod]]", "array of tables is not allowed"],
      input="{tmp}/a.toml", files={"a.toml": '[[rod]]\nheight = "1 mm"\n'}),
    # unknown and misspelt keys
    R("unknown-key", ["rod.colour=red"], ["rod.colour", "unknown key"]),
    R("misspelt-key", ["rod.heigth=3mm"], ["rod.heigth", "unknown key"]),
    R("unknown-key-width", ["rod.width=3mm"], ["rod.width", "unknown key"]),
    R("unknown-section", ["rodd.height=3mm"], ["rodd.height", "unknown key"]),
    R("key-double-dot", ["rod..height=3mm"], ["rod..height", "unknown key"]),
    R("key-section-only", ["rod=3mm"], ["error: rod = ", "unknown key"]),
    R("key-leading-dot", [".height=3mm"], [".height", "unknown key"]),
    R("key-trailing-space", ["rod.height =3mm"], ["rod.height ", "unknown key"]),
    R("unknown-key-vtk", ["vtk.colour=red"], ["vtk.colour", "unknown key"],
      extra=["--vtk", "{tmp}/vtk"]),
    R("unknown-key-value-named", ["rod.colour=red"], ["rod.colour", "red"]),
    # lengths and other positive quantities
    R("height-negative", ["rod.height=-3mm"], ["rod.height", "-0.003"]),
    R("height-zero", ["rod.height=0"], ["rod.height = 0", "> 0"]),
    R("length-negative", ["rod.length=-1m"], ["rod.length", "-1"]),
    R("length-zero", ["rod.length=0"], ["rod.length = 0", "> 0"]),
    R("thickness-zero", ["rod.thickness=0mm"], ["rod.thickness = 0", "> 0"]),
    R("thickness-negative", ["rod.thickness=-1mm"], ["rod.thickness", "-0.001"]),
    R("crank-length-zero", ["crank.length=0"], ["crank.length = 0", "> 0"]),
    R("crank-length-negative", ["crank.length=-30mm"], ["crank.length", "-0.03"]),
    R("crank-longer-than-rod", ["crank.length=400 mm"], ["crank.length", "0.4"]),
    R("joint-length-zero", ["joint.length=0"], ["joint.length = 0"]),
    R("bush-radius-zero", ["joint.bush_radius=0"], ["joint.bush_radius = 0"]),
    R("bush-radius-negative", ["joint.bush_radius=-1mm"], ["joint.bush_radius", "-0.001"]),
    R("slider-mass-zero", ["slider.mass=0"], ["slider.mass = 0"]),
    R("slider-mass-negative", ["slider.mass=-1 kg"], ["slider.mass", "-1"]),
    # wrong units
    R("height-in-rpm", ["rod.height=3 rpm"], ["rod.height", '"3 rpm"', "wrong dimension"]),
    R("speed-in-kg", ["drive.speed=200 kg"], ["drive.speed", '"200 kg"']),
    R("sample-rate-in-s", ["sim.sample_rate=10 s"], ["sim.sample_rate", '"10 s"']),
    R("settle-in-rpm", ["sim.settle=1 rpm"], ["sim.settle", '"1 rpm"']),
    R("index-angle-in-m", ["sim.index_angle=1 m"], ["sim.index_angle", '"1 m"']),
    R("initial-angle-in-kg", ["drive.initial_angle=1 kg"], ["drive.initial_angle", '"1 kg"']),
    R("offset-in-s", ["slider.offset=1 s"], ["slider.offset", '"1 s"']),
    R("big-end-x-in-kg", ["rod.big_end_x=1 kg"], ["rod.big_end_x", '"1 kg"']),
    R("max-step-in-m", ["sim.max_step=1 m"], ["sim.max_step", '"1 m"']),
    R("unit-upper-case", ["rod.height=3 MM"], ["rod.height", '"3 MM"', "unknown unit"]),
    R("unit-twice", ["rod.height=3 mm mm"], ["rod.height", '"3 mm mm"']),
    R("gauges-in-kg", ["output.gauges=0.1 kg"], ["output.gauges", '"0.1 kg"']),
    # malformed numbers
    R("height-abc", ["rod.height=abc"], ["rod.height", '"abc"', "must be a number"]),
    R("height-1e", ["rod.height=1e"], ["rod.height", '"1e"']),
    R("height-empty", ["rod.height="], ['rod.height = ""', "must be a number"]),
    R("speed-fast", ["drive.speed=fast"], ["drive.speed", '"fast"']),
    R("height-hex", ["rod.height=0x10"], ["rod.height", '"0x10"']),
    R("height-double-minus", ["rod.height=--3mm"], ["rod.height", '"--3mm"']),
    R("height-overflow", ["rod.height=1e400"], ["rod.height", '"1e400"']),
    R("height-nan", ["rod.height=nan"], ["rod.height", '"nan"', "finite"]),
    R("height-inf", ["rod.height=inf"], ["rod.height", '"inf"', "finite"]),
    R("speed-inf", ["drive.speed=inf"], ["drive.speed", '"inf"']),
    R("capture-nan", ["sim.capture=nan"], ["sim.capture", '"nan"']),
    R("gravity-abc", ["gravity.x=abc"], ["gravity.x", '"abc"']),
    R("midspan-abc", ["output.midspan=abc"], ["output.midspan", '"abc"']),
    R("gauges-abc", ["output.gauges=0.02,abc"], ["output.gauges", '"abc"']),
    R("output-rate-abc", ["output.rate=abc"], ["output.rate", '"abc"']),
    R("initial-angle-nan", ["drive.initial_angle=nan"], ["drive.initial_angle", '"nan"']),
    # integers
    R("elements-zero", ["rod.elements=0"], ["rod.elements = 0", "[1, 100000]"]),
    R("elements-negative", ["rod.elements=-3"], ["rod.elements = -3"]),
    R("elements-1e12", ["rod.elements=1e12"], ["rod.elements", "1e12"]),
    R("elements-fraction", ["rod.elements=2.5"], ["rod.elements", "2.5", "integer"]),
    R("elements-above-max", ["rod.elements=100001"], ["rod.elements", "100001"]),
    R("modes-negative", ["reduction.modes=-1"], ["reduction.modes", "-1"]),
    R("modes-too-many", ["reduction.modes=5000"], ["reduction.modes", "5000"]),
    R("max-steps-negative", ["sim.max_steps=-1"], ["sim.max_steps", "-1"]),
    R("max-steps-fraction", ["sim.max_steps=1.5"], ["sim.max_steps", "1.5"]),
    R("max-wall-time-negative", ["sim.max_wall_time=-1 s"], ["sim.max_wall_time", "-1"]),
    R("max-wall-time-nan", ["sim.max_wall_time=nan"], ["sim.max_wall_time", "nan"]),
    R("steady-revolutions-one", ["sim.steady_revolutions=1"], ["sim.steady_revolutions", "= 1"]),
    R("elements-one", ["rod.elements=1"], ["rod.elements", "= 1"]),
    # unknown enum values
    R("material-wood", ["rod.material=wood"], ["rod.material", "wood", "must be one of"]),
    R("material-capitalised", ["rod.material=Steel"], ["rod.material", "Steel"]),
    R("joint-type", ["joint.type=loose"], ["joint.type", "loose"]),
    R("joint-law", ["joint.law=hertzian"], ["joint.law", "hertzian"]),
    R("friction-law", ["joint.friction_law=stribeck2"], ["joint.friction_law", "stribeck2"]),
    R("damping-type", ["damping.type=heavy"], ["damping.type", "heavy"]),
    R("reduction-method", ["reduction.method=magic"], ["reduction.method", "magic"]),
    R("sim-start", ["sim.start=warm"], ["sim.start", "warm"]),
    R("drive-type", ["drive.type=turbo"], ["drive.type", "turbo"]),
    R("output-format", ["output.format=xml"], ["output.format", '"xml"']),
    R("output-format-case", ["output.format=HDF5"], ["output.format", '"HDF5"']),
    R("output-format-list", ["output.format=csv,xml"], ["output.format", "xml"]),
    R("output-format-empty", ["output.format="], ['output.format = ""']),
    R("output-channel", ["output.channels=penetrashun"], ["output.channels", "penetrashun"]),
    R("output-channel-of-other-rod", ["output.channels=slider_acceleration,rod_deflection"],
      ["output.channels", "rod_deflection"], input="rigid-rig"),
    R("output-channels-empty", ["output.channels="], ['output.channels = ""']),
    R("element", ["rod.element=kirchhoff"], ["rod.element", "kirchhoff"]),
    R("bending", ["rod.bending=diagonal"], ["rod.bending", "diagonal"]),
    R("mass-matrix", ["rod.mass=heavy"], ["rod.mass", "heavy"]),
    R("rod-type", ["rod.type=rubber"], ["rod.type", "rubber"]),
    R("mechanism-type", ["mechanism.type=four-bar"], ["mechanism.type", "four-bar"]),
    R("linear-solver", ["sim.linear_solver=mumps"], ["sim.linear_solver", "mumps"]),
    R("pin-material", ["joint.pin_material=wood"], ["joint.pin_material", "wood"]),
    R("bush-material", ["joint.bush_material=wood"], ["joint.bush_material", "wood"]),
    R("bool-maybe", ["gravity.enabled=maybe"], ["gravity.enabled", "maybe", "true or false"]),
    R("bool-2", ["reduction.axial_modes=2"], ["reduction.axial_modes = 2"]),
    R("bool-on", ["rod.geometric_stiffening=on"], ["rod.geometric_stiffening", "on"]),
    R("bool-yes", ["sim.eliminate_prescribed=yes"], ["sim.eliminate_prescribed", "yes"]),
    R("modes-bc", ["modes.bc=glued"], ["modes.bc", "glued"]),
    # the clearance joint
    R("pin-larger-than-bore", ["joint.clearance=10 mm"],
      ["joint.clearance", "0.01", "joint.bush_radius"]),
    R("bore-smaller-than-clearance", ["joint.bush_radius=0.4mm"],
      ["joint.bush_radius", "0.0004"]),
    R("bore-equal-to-clearance", ["joint.bush_radius=0.5mm"], ["joint.bush_radius", "0.0005"]),
    R("clearance-zero", ["joint.clearance=0"], ["joint.clearance = 0"]),
    R("clearance-negative", ["joint.clearance=-1mm"], ["joint.clearance", "-0.001"]),
    R("restitution-zero", ["joint.restitution=0"], ["joint.restitution = 0", "(0, 1]"]),
    R("restitution-above-one", ["joint.restitution=1.5"], ["joint.restitution", "1.5"]),
    R("friction-negative", ["joint.friction=-0.1"], ["joint.friction", "-0.1"]),
    R("exponent-low", ["joint.exponent=0.5"], ["joint.exponent", "0.5", "[1, 10]"]),
    R("exponent-high", ["joint.exponent=11"], ["joint.exponent", "11"]),
    R("stiffness-negative", ["joint.stiffness=-1"], ["joint.stiffness", "-1"]),
    R("damping-not-taken-by-law", ["joint.damping=5"], ["joint.damping = 5", "hybrid"]),
    R("damping-negative", ["joint.law=kelvin-voigt", "joint.damping=-1"],
      ["joint.damping", "-1", ">= 0"]),
    R("effective-mass-not-taken", ["joint.effective_mass=-1kg"], ["joint.effective_mass", "-1"]),
    R("working-penetration", ["joint.working_penetration=-1um"],
      ["joint.working_penetration", "-1e-06"]),
    R("min-approach-velocity", ["joint.min_approach_velocity=-1"],
      ["joint.min_approach_velocity", "-1"]),
    # positions along the rod
    R("midspan-off-rod", ["output.midspan=0.3 m"], ["output.midspan", "0.3", "on the rod"]),
    R("midspan-negative", ["output.midspan=-0.1 m"], ["output.midspan", "-0.1"]),
    R("gauge-off-rod", ["output.gauges=0.02,0.5"], ["output.gauges", "0.5", "on the rod"]),
    R("gauge-negative", ["output.gauges=0.02,-0.1"], ["output.gauges", "-0.1"]),
    # sample rate, capture, settle, tolerances
    R("capture-zero", ["sim.capture=0 s"], ["sim.capture = 0", "> 0"]),
    R("capture-negative", ["sim.capture=-1 s"], ["sim.capture", "-1"]),
    R("capture-one-sample", ["sim.sample_rate=100kHz", "sim.capture=10 us"],
      ["sim.capture", "1e-05", "2 samples"]),
    R("capture-one-and-a-half-samples", ["sim.sample_rate=100kHz", "sim.capture=15 us"],
      ["sim.capture", "1.5e-05", "2 samples"]),
    R("settle-negative", ["sim.settle=-1 s"], ["sim.settle", "-1", ">= 0"]),
    R("sample-rate-zero", ["sim.sample_rate=0"], ["sim.sample_rate = 0"]),
    R("sample-rate-negative", ["sim.sample_rate=-10 kHz"], ["sim.sample_rate", "-10000"]),
    R("rel-tol-below-floor", ["sim.rel_tol=1e-300"], ["sim.rel_tol", "1e-300", "1e-14"]),
    R("rel-tol-zero", ["sim.rel_tol=0"], ["sim.rel_tol = 0"]),
    R("rel-tol-above-one", ["sim.rel_tol=2"], ["sim.rel_tol = 2"]),
    R("abs-tol-below-floor", ["sim.abs_tol=1e-300"], ["sim.abs_tol", "1e-300", "1e-20"]),
    R("abs-tol-zero", ["sim.abs_tol=0"], ["sim.abs_tol = 0"]),
    R("max-step-negative", ["sim.max_step=-1"], ["sim.max_step", "-1"]),
    R("check-rel-tol-floor", ["sim.rel_tol=1e-13"], ["--check", "sim.rel_tol", "1e-13"],
      input="rigid-rig", extra=["--check"]),
    R("check-abs-tol-floor", ["sim.abs_tol=1e-19"], ["--check", "sim.abs_tol", "1e-19"],
      input="rigid-rig", extra=["--check"]),
    # Beyond the memory budget (half the memory available): refused before any work, naming
    # both keys and the user's values.
    R("capture-beyond-memory", ["sim.capture=1e9 s"], ["sim.capture", "1e"]),
    R("sample-rate-beyond-memory", ["sim.sample_rate=1e15 Hz"], ["sim.sample_rate", "1e"]),
    R("output-rate-not-dividing", ["sim.sample_rate=100kHz", "output.rate=30 kHz"],
      ["output.rate", "30000", "divide"]),
    R("output-rate-above-sample-rate", ["sim.sample_rate=100kHz", "output.rate=200 kHz"],
      ["output.rate", "200000"]),
    R("output-rate-negative", ["output.rate=-1 kHz"], ["output.rate", "-1000"]),
    # drive, motor, damping, masses, materials
    R("speed-zero", ["drive.speed=0"], ["drive.speed = 0", "> 0"]),
    R("speed-negative", ["drive.speed=-200 rpm"], ["drive.speed", "-20.94"]),
    R("profile-odd-pair", ["drive.type=profile", "drive.profile=0:0,0.5"],
      ["drive.profile", "0:0,0.5", "time:speed"]),
    R("profile-bad-time", ["drive.type=profile", "drive.profile=0:0,abc:200"],
      ["drive.profile", '"abc"']),
    R("profile-decreasing", ["drive.type=profile", "drive.profile=0.5:200,0:0"],
      ["drive.profile", "0.5:200,0:0", "increasing"]),
    R("motor-stall-torque", ["drive.type=motor", "motor.stall_torque=-20 N m"],
      ["motor.stall_torque", "-20"]),
    R("motor-belt-ratio", ["drive.type=motor", "motor.belt_ratio=0"], ["motor.belt_ratio = 0"]),
    R("motor-no-load-speed", ["drive.type=motor", "motor.no_load_speed=-1"],
      ["motor.no_load_speed", "-1"]),
    R("motor-flywheel", ["drive.type=motor", "motor.flywheel_inertia=-1"],
      ["motor.flywheel_inertia", "-1"]),
    R("damping-ratio-negative", ["damping.type=ratio", "damping.ratio=-0.1"],
      ["damping.ratio", "-0.1"]),
    R("damping-ratio-nan", ["damping.type=ratio", "damping.ratio=nan"],
      ["damping.ratio", '"nan"']),
    R("rayleigh-alpha-negative", ["damping.type=rayleigh", "damping.alpha=-1"],
      ["damping.alpha", "-1"]),
    R("rayleigh-beta-negative", ["damping.type=rayleigh", "damping.beta=-1"],
      ["damping.beta", "-1"]),
    R("slider-damping", ["slider.damping=-1"], ["slider.damping", "-1"]),
    R("slider-friction", ["slider.friction=-1 N"], ["slider.friction", "-1"]),
    R("slider-friction-velocity", ["slider.friction_velocity=0"], ["slider.friction_velocity = 0"]),
    R("crank-mass", ["crank.mass=-1"], ["crank.mass", "-1"]),
    R("crank-inertia", ["crank.inertia=-1"], ["crank.inertia", "-1"]),
    R("young-negative", ["rod.E=-200 GPa"], ["rod.E", "-2e+11"]),
    R("poisson-high", ["rod.nu=0.6"], ["rod.nu", "0.6"]),
    R("poisson-low", ["rod.nu=-2"], ["rod.nu", "-2"]),
    R("density-negative", ["rod.rho=-1"], ["rod.rho", "-1"]),
    R("yield-negative", ["rod.yield=-1"], ["rod.yield", "-1"]),
    R("cutoff-negative", ["reduction.cutoff=-5 kHz"], ["reduction.cutoff", "-5000"]),
    R("rigid-mass-negative", ["rod.type=rigid", "rod.rigid_mass=-1"], ["rod.rigid_mass", "-1"]),
    R("rigid-inertia-negative", ["rod.type=rigid", "rod.rigid_inertia=-1"],
      ["rod.rigid_inertia", "-1"]),
    R("clamp-mass", ["clamp.big_mass=-1"], ["clamp.big_mass", "-1"]),
    R("clamp-inertia", ["clamp.small_inertia=-1"], ["clamp.small_inertia", "-1"]),
    # values of keys the configuration does not use are not validated
    R("unused-rayleigh-alpha", ["damping.alpha=-1"], ["damping.alpha", "-1"]),
    R("unused-damping-ratio", ["damping.ratio=-0.1"], ["damping.ratio", "-0.1"]),
    R("unused-motor-belt-ratio", ["motor.belt_ratio=0"], ["motor.belt_ratio", "0"]),
    R("unused-drive-profile", ["drive.profile=garbage"], ["drive.profile", "garbage"]),
    R("unused-clearance", ["joint.type=ideal", "joint.clearance=-1mm"],
      ["joint.clearance", "-0.001"]),
    R("unused-restitution", ["joint.type=ideal", "joint.restitution=5"],
      ["joint.restitution", "5"]),
    R("unused-rigid-mass", ["rod.rigid_mass=-1"], ["rod.rigid_mass", "-1"]),
    R("unused-vtk-scale", ["vtk.scale=-1"], ["vtk.scale", "-1"]),
    R("unused-modes-count", ["modes.count=-1"], ["modes.count", "-1"]),
    R("unused-modes-interface", ["modes.interface=999"], ["modes.interface", "999"]),
    R("unused-midspan-rigid-rod", ["output.midspan=5 m"], ["output.midspan", "5"],
      input="rigid-rig"),
    R("unused-joint-friction", ["joint.friction_law=none", "joint.friction=-1"],
      ["joint.friction", "-1"]),
    # comma lists
    R("gauges-empty-item", ["output.gauges=0.02,,0.1"], ["output.gauges", "0.02,,0.1"]),
    R("channels-empty-item", ["output.channels=slider_acceleration,,crank_angle"],
      ["output.channels", "slider_acceleration,,crank_angle"]),
    R("format-repeated", ["output.format=hdf5,hdf5"], ["output.format", "hdf5,hdf5"]),
    # --vtk and vtk.*
    R("vtk-scale-negative", ["vtk.scale=-1"], ["vtk.scale", "-1"], input="rigid-rig",
      extra=["--vtk", "{tmp}/vtk"]),
    R("vtk-scale-abc", ["vtk.scale=abc"], ["vtk.scale", '"abc"'], input="rigid-rig",
      extra=["--vtk", "{tmp}/vtk"]),
    R("vtk-rate-zero", ["vtk.rate=0"], ["vtk.rate = 0"], input="rigid-rig",
      extra=["--vtk", "{tmp}/vtk"]),
    R("vtk-rate-negative", ["vtk.rate=-1 kHz"], ["vtk.rate", "-1000"], input="rigid-rig",
      extra=["--vtk", "{tmp}/vtk"]),
    R("vtk-duration-negative", ["vtk.duration=-1 s"], ["vtk.duration", "-1"], input="rigid-rig",
      extra=["--vtk", "{tmp}/vtk"]),
    R("vtk-duration-in-kg", ["vtk.duration=1 kg"], ["vtk.duration", '"1 kg"'],
      input="rigid-rig", extra=["--vtk", "{tmp}/vtk"]),
    R("vtk-under-file", [], ["--vtk", "{tmp}/plain/vtk"], input="rigid-rig",
      extra=["--vtk", "{tmp}/plain/vtk"]),
    R("vtk-is-file", [], ["--vtk", "{tmp}/plain"], input="rigid-rig",
      extra=["--vtk", "{tmp}/plain"]),
    R("vtk-empty", [], ["--vtk", '""'], input="rigid-rig", extra=["--vtk", ""]),
    R("vtk-missing-value", [], ["--vtk"], input="rigid-rig", extra=["--no-plot", "--vtk"],
      out=False),
    # the input: presets and files
    R("unknown-preset", [], ["no-such-preset", "preset"], input="no-such-preset"),
    R("missing-file", [], ["{tmp}/nonexistent.toml"], input="{tmp}/nonexistent.toml"),
    R("directory-as-input", [], ["{tmp}/adir", "regular"], input="{tmp}/adir"),
    R("device-as-input", [], ["/dev/null", "regular"], input="/dev/null"),
    R("builtin-matrix-as-input", [], ["sweep-small"], input="sweep-small"),
    R("matrix-file-as-input", [], ["sweep-small.toml", "is a sweep matrix", "flexrod sweep"],
      input="{src}/examples/sweep-small.toml"),
    R("tmp-matrix-as-input", [], ["{tmp}/m.toml", "is a sweep matrix", "flexrod sweep"],
      input="{tmp}/m.toml",
      files={"m.toml": '[sweep]\nname = "x"\n[axes]\n"rod.height" = ["3 mm"]\n'}),
    R("toml-syntax-error", [], ["bad.toml", "malformed TOML", "line 1"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod\nheight = "}),
    R("toml-unquoted-unit", [], ["bad.toml", "malformed TOML", "line 2"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod]\nheight = 3 mm\n"}),
    R("toml-bool-for-length", [], ["rod.height", '"true"'], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod]\nheight = true\n"}),
    R("toml-word-for-integer", [], ["rod.elements", '"forty"'], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nelements = "forty"\n'}),
    R("toml-float-for-integer", [], ["rod.elements", "40.5"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod]\nelements = 40.5\n"}),
    R("toml-number-for-enum", [], ["rod.material = 3"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod]\nmaterial = 3\n"}),
    R("toml-empty-array-for-integer", [], ["rod.elements = []", "not an array"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod]\nelements = []\n"}),
    R("toml-array-for-enum", [], ["rod.material", "steel"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nmaterial = ["steel"]\n'}),
    R("toml-array-for-length", [], ["rod.height", "3 mm"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nheight = ["3 mm"]\n'}),
    R("toml-date-for-length", [], ["rod.height", "1979-05-27"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod]\nheight = 1979-05-27\n"}),
    R("toml-inline-table-for-time", [], ["sim.capture.value", "unknown key"],
      input="{tmp}/bad.toml", files={"bad.toml": "[sim]\ncapture = { value = 1 }\n"}),
    R("toml-table-for-length", [], ["rod.height.value", "unknown key"], input="{tmp}/bad.toml",
      files={"bad.toml": "[rod.height]\nvalue = 3\n"}),
    R("toml-unknown-table", [], ["rodd.height", "unknown key"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rodd]\nheight = "3 mm"\n'}),
    R("toml-unknown-key", [], ["rod.heigth", "unknown key"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nheigth = "3 mm"\n'}),
    R("toml-unknown-key-value-named", [], ["rod.colour", "red"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\ncolour = "red"\n'}),
    R("toml-top-level-key", [], ["height", "unknown key"], input="{tmp}/bad.toml",
      files={"bad.toml": 'height = "3 mm"\n'}),
    R("toml-duplicate-key", [], ["'height'", "redefine"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nheight = "3 mm"\nheight = "4 mm"\n'}),
    R("toml-duplicate-table", [], ["'rod'", "redefine"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nheight = "3 mm"\n[rod]\nlength = "1 m"\n'}),
    R("toml-key-then-table", [], ["'drive.speed'", "redefine"], input="{tmp}/bad.toml",
      files={"bad.toml": '[drive]\nspeed = "100 rpm"\n[drive.speed]\nx = 1\n'}),
    R("toml-duplicate-quoted-key", [], ['"speed"', "redefine"], input="{tmp}/bad.toml",
      files={"bad.toml": '[drive]\n"speed" = "100 rpm"\n"speed" = "200 rpm"\n'}),
    R("toml-invalid-utf8", [], ["bad.toml", "utf-8"], input="{tmp}/bad.toml",
      files={"bad.toml": b"\xff\xfe[rod]\n"}),
    R("toml-negative-height", [], ["rod.height", "-0.003"], input="{tmp}/bad.toml",
      files={"bad.toml": '[rod]\nheight = "-3 mm"\n'}),
    # flags
    R("set-without-equals", ["rod.height"], ["--set", "rod.height", "key=value"]),
    R("set-empty-key", ["=3mm"], ["--set", "=3mm", "key=value"]),
    R("set-empty", [""], ['--set = ""']),
    R("set-blank-key", [" =3"], ["--set", '" "']),
    R("set-missing-value", [], ["--set"], input="rigid-rig", extra=["--no-plot", "--set"],
      out=False),
    R("unknown-flag", [], ["--frobnicate"], extra=["--frobnicate"]),
    R("misspelt-flag", [], ["--no-plto"], extra=["--no-plto"]),
    # (after --set, a word is one more --set value: the extra positional comes before them)
    R("extra-positional", [], ["extra-positional"], input="rigid-rig extra-positional"),
    R("out-missing-value", [], ["--out"], input="rigid-rig", extra=["--no-plot", "--out"],
      out=False),
    R("out-twice", [], ["--out"], input="rigid-rig",
      extra=["--no-plot", "--out", "{tmp}/out1", "--out", "{tmp}/out2"], out=False),
    R("out-swallows-flag", [], ["--out", "--no-plot"], input="rigid-rig",
      extra=["--out", "--no-plot"], out=False),
    R("out-empty", [], ['--out = ""'], input="rigid-rig", extra=["--no-plot", "--out", ""],
      out=False),
    R("out-is-file", [], ["--out", "{tmp}/plain", "not a directory"], input="rigid-rig",
      extra=["--no-plot", "--out", "{tmp}/plain"], out=False),
    R("out-under-file", [], ["--out", "{tmp}/plain/sub"], input="rigid-rig",
      extra=["--no-plot", "--out", "{tmp}/plain/sub"], out=False),
    R("out-device", [], ["--out", "/dev/null"], input="rigid-rig",
      extra=["--no-plot", "--out", "/dev/null"], out=False),
    # An output location that cannot be created: flexrod classes it as bad input (2), found
    # before any work; I/O error (3) is for writes that fail during the run.
    R("out-in-proc", [], ["--out", "/proc/flexrod-corpus"], input="rigid-rig",
      extra=["--no-plot", "--out", "/proc/flexrod-corpus"], out=False),
    R("out-in-sys", [], ["--out", "/sys/flexrod-corpus/x"], input="rigid-rig",
      extra=["--no-plot", "--out", "/sys/flexrod-corpus/x"], out=False),
    # empty values are to be quoted
    R("quoted-empty-material", ["rod.material="], ['rod.material = ""']),
    R("quoted-empty-profile", ["drive.type=profile", "drive.profile="], ['drive.profile = ""']),
]

# --------------------------------------------------------------------------------------------
# keys and the command line itself
# --------------------------------------------------------------------------------------------
KEYS = [
    Case("cli-no-subcommand", [], ["subcommand is required"]),
    Case("cli-unknown-subcommand", ["runn"], ["runn"]),
    Case("cli-unknown-flag", ["--frobnicate"], ["--frobnicate"]),
    Case("keys-unknown-flag", ["keys", "--frobnicate"], ["--frobnicate", "not expected"]),
    Case("keys-positional", ["keys", "rod"], ["not expected: rod"]),
    Case("keys-set", ["keys", "--set", "rod.height=3mm"], ["--set", "rod.height=3mm"]),
    Case("keys-out", ["keys", "--out", "{tmp}/out"], ["--out", "{tmp}/out"]),
    Case("keys-jobs", ["keys", "-j", "2"], ["-j"]),
]

# --------------------------------------------------------------------------------------------
# modes
# --------------------------------------------------------------------------------------------


def M(cid, args, expect, json=True, files=None, xfail=None, rc=2):
    argv = ["modes"] + list(args) + (["--json", "{tmp}/m.json"] if json else [])
    return Case("modes-" + cid, argv, expect, rc=rc, files=files, xfail=xfail)



MODES = [
    M("json-fifo", ["--json", "{tmp}/fifo"], ["--json = {tmp}/fifo", "FIFO"], json=False,
      files={"fifo": FIFO}),
    M("json-symlink", ["--json", "{tmp}/link"], ["--json = {tmp}/link", "symbolic link"],
      json=False, files={"link": LINK}),
    M("json-under-a-file", ["--json", "{tmp}/plain/m.json"], ["{tmp}/plain", "is a file"],
      json=False),
    M("json-name-too-long", ["--json", "{tmp}/" + LONG], ["--json", "has a name of 300 bytes"],
      json=False),
    M("height-negative", ["--height", "-3mm"], ["rod.height", "-0.003"]),
    M("height-zero", ["--height", "0"], ["rod.height = 0"]),
    M("height-in-rpm", ["--height", "3 rpm"], ["rod.height", '"3 rpm"']),
    M("height-empty", ["--height", ""], ['--height = ""', "must not be empty"]),
    M("height-missing-value", ["--height"], ["--height"], json=False),
    M("height-twice", ["--height", "1mm", "--height", "2mm"], ["--height"]),
    M("material-unknown", ["--material", "unobtainium"], ["rod.material", "unobtainium"]),
    M("material-empty", ["--material", ""], ['--material = ""', "must not be empty"]),
    M("modes-negative", ["--modes", "-1"], ["reduction.modes", "-1"]),
    M("modes-too-many", ["--modes", "5000"], ["reduction.modes", "5000"]),
    M("modes-fraction", ["--modes", "2.5"], ["reduction.modes", "2.5"]),
    M("modes-abc", ["--modes", "abc"], ["reduction.modes", '"abc"']),
    M("elements-zero", ["--elements", "0"], ["rod.elements = 0"]),
    M("elements-negative", ["--elements", "-3"], ["rod.elements", "-3"]),
    M("elements-1e12", ["--elements", "1e12"], ["rod.elements", "1e12"]),
    M("young-abc", ["--E", "abc"], ["rod.E", '"abc"']),
    M("young-negative", ["--E", "-200 GPa"], ["rod.E", "-2e+11"]),
    M("young-in-m", ["--E", "200 m"], ["rod.E", '"200 m"']),
    M("poisson", ["--nu", "0.7"], ["rod.nu", "0.7"]),
    M("density", ["--rho", "-1"], ["rod.rho", "-1"]),
    M("thickness", ["--thickness", "-1mm"], ["rod.thickness", "-0.001"]),
    M("length-in-kg", ["--length", "3 kg"], ["rod.length", '"3 kg"']),
    M("length-zero", ["--length", "0"], ["rod.length = 0"]),
    M("element", ["--element", "kirchhoff"], ["rod.element", "kirchhoff"]),
    M("bending", ["--bending", "diagonal"], ["rod.bending", "diagonal"]),
    M("mass", ["--mass", "heavy"], ["rod.mass", "heavy"]),
    M("dim", ["--dim", "3d"], ["modes.dim", "3d"]),
    M("bc", ["--bc", "glued"], ["modes.bc", "glued"]),
    M("reduction", ["--reduction", "magic"], ["reduction.method", "magic"]),
    M("cutoff-negative", ["--cutoff", "-5kHz"], ["reduction.cutoff", "-5000"]),
    M("cutoff-in-m", ["--cutoff", "5 m"], ["reduction.cutoff", '"5 m"']),
    M("interface-node", ["--interface", "999"], ["modes.interface", "999"]),
    M("interface-word", ["--interface", "middle"], ["modes.interface", "middle"]),
    M("interface-list", ["--interface", "1,abc"], ["modes.interface", "1,abc"]),
    M("report-negative", ["--report", "-1"], ["modes.count", "-1"]),
    M("report-abc", ["--report", "abc"], ["modes.count", '"abc"']),
    M("unknown-flag", ["--frobnicate"], ["--frobnicate"]),
    M("config-missing", ["--config", "{tmp}/nonexistent.toml"], ["{tmp}/nonexistent.toml"]),
    M("config-preset-name", ["--config", "rigid-rig"], ["rigid-rig"]),
    M("config-directory", ["--config", "{tmp}/adir"], ["{tmp}/adir", "regular"]),
    M("config-malformed", ["--config", "{tmp}/c.toml"], ["c.toml", "malformed TOML"],
      files={"c.toml": "[rod\n"}),
    M("config-unknown-key", ["--config", "{tmp}/c.toml"], ["rod.heigth", "unknown key"],
      files={"c.toml": '[rod]\nheigth = "3 mm"\n'}),
    M("config-bc", ["--config", "{tmp}/c.toml"], ["modes.bc", "glued"],
      files={"c.toml": '[modes]\nbc = "glued"\n'}),
    M("config-count", ["--config", "{tmp}/c.toml"], ["modes.count", "-2"],
      files={"c.toml": "[modes]\ncount = -2\n"}),
    M("config-unused-bad-key", ["--config", "{tmp}/c.toml"], ["joint.clearance = -0.001"],
      files={"c.toml": '[joint]\nclearance = "-1 mm"\n'}),
    M("json-under-file", ["--json", "{tmp}/plain/m.json"], ["--json", "{tmp}/plain/m.json"],
      json=False),
    M("json-is-directory", ["--json", "{tmp}/adir"], ["--json", "{tmp}/adir"], json=False),
    M("json-in-missing-directory", ["--json", "{tmp}/nodir/m.json"],
      ["--json", "{tmp}/nodir/m.json"], json=False),
    M("json-in-proc", ["--json", "/proc/flexrod-corpus/m.json"],
      ["--json", "/proc/flexrod-corpus/m.json"], json=False),
    M("json-empty", ["--json", ""], ["--json", '""'], json=False),
]

# --------------------------------------------------------------------------------------------
# contact
# --------------------------------------------------------------------------------------------
B = ["--mass", "1", "--velocity", "0.5"]


def C(cid, args, expect, out=True, xfail=None, rc=2, files=None):
    argv = ["contact"] + list(args)
    if out:
        argv += ["--json", "{tmp}/c.json", "--plot", "{tmp}/c.png"]
    return Case("contact-" + cid, argv, expect, rc=rc, xfail=xfail, files=files)



CONTACT = [
    C("json-fifo", ["--law", "hertz", "--mass", "1 kg", "--velocity", "1 m/s", "--json",
                    "{tmp}/fifo.json"], ["--json = {tmp}/fifo.json", "FIFO"], out=False,
      files={"fifo.json": FIFO}),
    C("law-unknown", ["--law", "hertzian"] + B, ["law", '"hertzian"', "must be one of"]),
    C("law-empty", ["--law", ""] + B, ['law = ""']),
    C("law-missing", B, ["--law", "required"]),
    C("mass-missing", ["--law", "hertz", "--velocity", "0.5"], ["--mass", "required"]),
    C("velocity-missing", ["--law", "hertz", "--mass", "1"], ["--velocity", "required"]),
    C("law-missing-value", B + ["--law"], ["--law"], out=False),
    C("mass-negative", ["--law", "hertz", "--mass", "-1", "--velocity", "0.5"],
      ["mass = -1", "> 0"]),
    C("mass-zero", ["--law", "hertz", "--mass", "0", "--velocity", "0.5"], ["mass = 0"]),
    C("mass-in-m", ["--law", "hertz", "--mass", "1 m", "--velocity", "0.5"],
      ["mass", '"1 m"']),
    C("mass-abc", ["--law", "hertz", "--mass", "abc", "--velocity", "0.5"], ["mass", '"abc"']),
    C("mass-nan", ["--law", "hertz", "--mass", "nan", "--velocity", "0.5"], ["mass", '"nan"']),
    C("velocity-negative", ["--law", "hertz", "--mass", "1", "--velocity", "-0.5"],
      ["velocity = -0.5"]),
    C("velocity-zero", ["--law", "hertz", "--mass", "1", "--velocity", "0"], ["velocity = 0"]),
    C("velocity-in-kg", ["--law", "hertz", "--mass", "1", "--velocity", "0.5 kg"],
      ["velocity", '"0.5 kg"']),
    C("velocity-empty", ["--law", "hertz", "--mass", "1", "--velocity", ""],
      ['velocity = ""']),
    C("restitution-above-one", ["--law", "flores", "--restitution", "1.5"] + B,
      ["restitution = 1.5", "(0, 1]"]),
    C("restitution-zero", ["--law", "flores", "--restitution", "0"] + B, ["restitution = 0"]),
    C("restitution-negative", ["--law", "flores", "--restitution", "-0.5"] + B,
      ["restitution = -0.5"]),
    C("restitution-not-taken", ["--law", "hertz", "--restitution", "0.5"] + B,
      ["restitution = 0.5", "hertz"]),
    C("stiffness-negative", ["--law", "hertz", "--stiffness", "-1"] + B, ["stiffness = -1"]),
    C("stiffness-abc", ["--law", "hertz", "--stiffness", "abc"] + B, ["stiffness", '"abc"']),
    C("exponent-low", ["--law", "hertz", "--exponent", "0.5"] + B, ["exponent = 0.5"]),
    C("exponent-high", ["--law", "hertz", "--exponent", "20"] + B, ["exponent = 20"]),
    C("damping-negative", ["--law", "kelvin-voigt", "--damping", "-5"] + B, ["damping = -5"]),
    C("damping-in-kg", ["--law", "kelvin-voigt", "--damping", "5 kg"] + B,
      ["damping", '"5 kg"']),
    C("stiffness-2", ["--law", "standard-linear-solid", "--stiffness-2", "-1"] + B,
      ["stiffness-2 = -1"]),
    C("working-penetration", ["--law", "hybrid", "--working-penetration", "-1um"] + B,
      ["working-penetration", "-1e-06"]),
    C("min-approach-velocity", ["--law", "flores", "--min-approach-velocity", "-1"] + B,
      ["min-approach-velocity = -1"]),
    C("max-damping", ["--law", "impact", "--max-damping", "-1"] + B, ["max-damping = -1"]),
    C("damping-penetration", ["--law", "impact", "--damping-penetration", "-1mm"] + B,
      ["damping-penetration", "-0.001"]),
    C("calibration-velocity", ["--law", "impact", "--calibration-velocity", "-1"] + B,
      ["calibration-velocity = -1"]),
    C("compliance", ["--law", "johnson", "--compliance", "-1"] + B, ["compliance = -1"]),
    C("effective-mass", ["--law", "kelvin-voigt", "--effective-mass", "-1"] + B,
      ["effective-mass = -1"]),
    C("pin-young", ["--law", "hertz", "--pin-E", "-1"] + B, ["pin-E", "-1"]),
    C("pin-poisson", ["--law", "hertz", "--pin-nu", "0.7"] + B, ["pin-nu = 0.7"]),
    C("bush-young", ["--law", "hertz", "--bush-E", "-3 GPa"] + B, ["bush-E", "-3000000000"]),
    C("bush-poisson", ["--law", "hertz", "--bush-nu", "-1.5"] + B, ["bush-nu = -1.5"]),
    C("pin-larger-than-bore", ["--law", "hertz", "--pin-radius", "10 mm"] + B,
      ["pin-radius", "0.01", "bush_radius"]),
    C("pin-radius-negative", ["--law", "hertz", "--pin-radius", "-1 mm"] + B,
      ["pin-radius", "-0.001"]),
    C("bush-radius-zero", ["--law", "hertz", "--bush-radius", "0 mm"] + B,
      ["bush-radius = 0"]),
    C("length-negative", ["--law", "johnson", "--length", "-1 mm"] + B, ["length", "-0.001"]),
    C("unknown-flag", ["--law", "hertz", "--frobnicate"] + B, ["--frobnicate"]),
    C("plot-not-png", ["--law", "hertz"] + B + ["--plot", "{tmp}/c.jpg"],
      ["plot", "{tmp}/c.jpg", ".png"], out=False),
    C("plot-is-directory", ["--law", "hertz"] + B + ["--plot", "{tmp}/adir"],
      ["plot", "{tmp}/adir"], out=False),
    C("json-under-file", ["--law", "hertz"] + B + ["--json", "{tmp}/plain/c.json"],
      ["--json", "{tmp}/plain/c.json"], out=False),
    C("json-is-directory", ["--law", "hertz"] + B + ["--json", "{tmp}/adir"],
      ["--json", "{tmp}/adir"], out=False),
    C("json-in-missing-directory", ["--law", "hertz"] + B + ["--json", "{tmp}/nodir/c.json"],
      ["--json", "{tmp}/nodir/c.json"], out=False),
    C("plot-under-file", ["--law", "hertz"] + B + ["--plot", "{tmp}/plain/c.png"],
      ["--plot", "{tmp}/plain/c.png"], out=False),
    C("plot-under-file-json-written",
      ["--law", "hertz"] + B + ["--json", "{tmp}/c.json", "--plot", "{tmp}/plain/c.png"],
      ["--plot", "{tmp}/plain/c.png"], out=False),
    C("json-empty", ["--law", "hertz"] + B + ["--json", ""], ["--json", '""'], out=False),
    C("plot-empty", ["--law", "hertz"] + B + ["--plot", ""], ["--plot", '""'], out=False),
]

# --------------------------------------------------------------------------------------------
# study
# --------------------------------------------------------------------------------------------
CHEAP_STUDY = ["--set", "sim.settle=0s", "--set", "sim.capture=0.01s",
               "--set", "sim.sample_rate=5kHz"]


def S(cid, positional, args, expect, out=True, files=None, xfail=None, rc=2):
    argv = ["study"] + list(positional) + CHEAP_STUDY + list(args)
    if out:
        argv += ["--no-plot", "--out", "{tmp}/out"]
    return Case("study-" + cid, argv, expect, rc=rc, files=files, xfail=xfail)


FRICTION = ["rigid-rig-friction"]

STUDY = [
    S("unknown-name", ["rigid-rig-everything"], [], ["rigid-rig-everything", "not in"]),
    S("empty-name", [""], [], ['name: "" not in']),
    S("missing-name", [], [], ["name is required"]),
    S("bore-too-small-friction", FRICTION, ["--set", "joint.bush_radius=0.8mm"],
      ["joint.bush_radius", "0.0008"]),
    S("bore-too-small-laws", ["rigid-rig-laws"], ["--set", "joint.bush_radius=0.8mm"],
      ["joint.bush_radius", "0.0008"]),
    S("unknown-key", FRICTION, ["--set", "rod.colour=red"], ["rod.colour", "unknown key"]),
    S("capture-zero", FRICTION, ["--set", "sim.capture=0 s"], ["sim.capture = 0"]),
    S("rel-tol-floor", FRICTION, ["--set", "sim.rel_tol=1e-300"], ["sim.rel_tol", "1e-300"]),
    S("set-without-equals", FRICTION, ["--set", "rod.height"], ["--set", "rod.height"]),
    S("law", ["rigid-rig-laws"], ["--set", "joint.law=hertzian"], ["joint.law", "hertzian"]),
    S("friction-negative", FRICTION, ["--set", "joint.friction=-1"], ["joint.friction", "-1"]),
    S("clearance-negative", FRICTION, ["--set", "joint.clearance=-1mm"],
      ["joint.clearance", "-0.001"]),
    S("speed-negative", FRICTION, ["--set", "drive.speed=-1"], ["drive.speed", "-1"]),
    S("output-rate", FRICTION, ["--set", "output.rate=30 kHz"], ["output.rate", "30000"]),
    S("unknown-flag", FRICTION, ["--frobnicate"], ["--frobnicate"]),
    S("input-for-rigid-rig-study", ["rigid-rig-friction", "no-such-input"], [],
      ["no-such-input"]),
    S("reduction-unknown-input", ["reduction", "no-such-preset"], [], ["no-such-preset"]),
    S("reduction-directory-input", ["reduction", "{tmp}/adir"], [], ["{tmp}/adir", "regular"]),
    S("reduction-malformed-input", ["reduction", "{tmp}/bad.toml"], [],
      ["bad.toml", "malformed TOML"], files={"bad.toml": "[rod\n"}),
    S("within-negative", ["reduction"], ["--within", "-1"], ["--within", "-1"]),
    S("within-zero", ["reduction"], ["--within", "0"], ["--within = 0"]),
    S("within-abc", ["reduction"], ["--within", "abc"], ["--within", "abc"]),
    S("within-nan", ["reduction"], ["--within", "nan"], ["--within", "nan"]),
    S("within-inf", ["reduction"], ["--within", "inf"], ["--within", "inf"]),
    S("reduction-height", ["reduction"], ["--set", "rod.height=-3mm"], ["rod.height", "-0.003"]),
    S("reduction-modes", ["reduction"], ["--set", "reduction.modes=-1"],
      ["reduction.modes", "-1"]),
    S("out-is-file", FRICTION, ["--no-plot", "--out", "{tmp}/plain"], ["--out", "{tmp}/plain"],
      out=False),
    S("out-under-file", FRICTION, ["--no-plot", "--out", "{tmp}/plain/sub"],
      ["--out", "{tmp}/plain/sub"], out=False),
    S("out-empty", FRICTION, ["--no-plot", "--out", ""], ['--out = ""'], out=False),
]

# --------------------------------------------------------------------------------------------
# sweep
# --------------------------------------------------------------------------------------------


def W(cid, matrix, expect, extra=(), out=True, xfail=None, rc=2, files=None, jobs=True):
    """`flexrod sweep MATRIX --no-plot [--jobs 2] extra... --out {tmp}/out.h5`; a matrix text
    is written to {tmp}/m.toml."""
    files = dict(files or {})
    if matrix is not None and "\n" in matrix:
        files["m.toml"] = matrix
        matrix = "{tmp}/m.toml"
    argv = ["sweep"] + ([matrix] if matrix is not None else []) + ["--no-plot"]
    argv += ["--jobs", "2"] if jobs else []
    argv += list(extra)
    if out:
        argv += ["--out", "{tmp}/out.h5"]
    return Case("sweep-" + cid, argv, expect, rc=rc, files=files, xfail=xfail)


RIG = '[sweep]\nbase = "rigid-rig"\n'
SMALL = "{src}/examples/sweep-small.toml"
SHORT = ["--set", "sim.settle=0s", "--set", "sim.capture=0.05s"]

SWEEP = [
    W("matrix-name-too-long", "{tmp}/" + LONG + ".toml", ["sweep matrix", "255"]),
    W("out-name-too-long", "sweep-small", ["--out = {tmp}/" + LONG + ".h5", "239"], out=False,
      extra=["--out", "{tmp}/" + LONG + ".h5"]),
    W("axis-unknown-key", RIG + '[axes]\n"rod.colour" = ["red"]\n', ["rod.colour", "red"]),
    W("axis-empty", RIG + '[axes]\n"drive.speed" = []\n', ["drive.speed", "at least one value"]),
    W("range-without-step",
      RIG + '[axes]\n"drive.speed" = { from = "100 rpm", to = "200 rpm" }\n',
      ["drive.speed", "step"]),
    W("range-negative-step",
      RIG + '[axes]\n"drive.speed" = { from = "100 rpm", to = "200 rpm", step = "-10 rpm" }\n',
      ["drive.speed.step", "-10 rpm"]),
    W("range-zero-step",
      RIG + '[axes]\n"drive.speed" = { from = "100 rpm", to = "200 rpm", step = "0 rpm" }\n',
      ["drive.speed.step", "0 rpm"]),
    W("range-reversed",
      RIG + '[axes]\n"drive.speed" = { from = "200 rpm", to = "100 rpm", step = "10 rpm" }\n',
      ["drive.speed.to", "100 rpm"]),
    W("range-wrong-unit",
      RIG + '[axes]\n"drive.speed" = { from = "100 rpm", to = "200 mm", step = "10 rpm" }\n',
      ["drive.speed.to", '"200 mm"']),
    W("range-unknown-field",
      RIG + '[axes]\n"drive.speed" = { from = "100 rpm", to = "200 rpm", step = "10 rpm", '
            'by = 2 }\n',
      ["drive.speed.by"]),
    W("range-bad-step-in-combination",
      RIG + '[[combinations]]\n"drive.speed" = { from = "100 rpm", to = "200 rpm", '
            'step = "abc" }\n',
      ["drive.speed.step", '"abc"']),
    W("range-too-many-values",
      RIG + '[axes]\n"drive.speed" = { from = "1 rpm", to = "1e9 rpm", step = "1 rpm" }\n',
      ["drive.speed.step", "10^6"]),
    W("axis-table-value", RIG + '[axes]\n"drive.speed" = { values = ["1 rpm"] }\n',
      ["drive.speed.values"]),
    W("axis-duplicate-toml-key", RIG + '[axes]\ndrive.speed = ["100 rpm"]\n'
                                        'drive.speed = ["200 rpm"]\n',
      ["'drive.speed'", "redefine"]),
    W("axis-duplicate-quoted-key", RIG + '[axes]\n"drive.speed" = ["100 rpm"]\n'
                                          '"drive.speed" = ["200 rpm"]\n',
      ['"drive.speed"', "redefine"]),
    W("axis-twice-via-zip", RIG + '[axes]\n"drive.speed" = ["100 rpm"]\n'
                                   '"rod.length,drive.speed" = [["300 mm", "200 rpm"]]\n',
      ["drive.speed", "twice"]),
    W("axis-and-combination", RIG + '[axes]\n"drive.speed" = ["100 rpm"]\n[[combinations]]\n'
                                     '"drive.speed" = "200 rpm"\n',
      ["drive.speed", "[[combinations]]"]),
    W("duplicate-runs", RIG + '[axes]\n"drive.speed" = ["100 rpm", "100 rpm"]\n',
      ["drive.speed=100 rpm", "same resolved input"]),
    W("zip-row-short", RIG + '[axes]\n"rod.material,rod.height" = [["brass"], '
                              '["steel", "25.4 mm"]]\n',
      ["rod.material,rod.height", "row 1"]),
    W("zip-row-not-list", RIG + '[axes]\n"rod.material,rod.height" = ["brass", "steel"]\n',
      ["rod.material,rod.height", "row 1"]),
    W("zip-same-key", RIG + '[axes]\n"rod.height,rod.height" = [["12.7 mm", "19.05 mm"]]\n',
      ["rod.height", "twice"]),
    W("zip-empty-key", RIG + '[axes]\n"rod.height," = [["12.7 mm", "19.05 mm"]]\n',
      ["rod.height,", "two or more keys"]),
    W("axis-bad-value", RIG + '[axes]\n"rod.material" = ["steel", "wood"]\n',
      ["rod.material", "wood"]),
    W("axis-negative-settle", RIG + '[axes]\n"sim.settle" = ["0.1 s", "-1 s"]\n',
      ["sim.settle", "-1"]),
    W("matrix-set-bad-value", RIG + '[set]\n"sim.capture" = "0 s"\n', ["sim.capture = 0"]),
    W("matrix-set-unknown-key", RIG + '[set]\n"rod.colour" = "red"\n', ["rod.colour", "red"]),
    W("matrix-set-wrong-unit", RIG + '[set]\n"rod.length" = "3 rpm"\n', ["rod.length", '"3 rpm"']),
    W("matrix-set-one-element-array", RIG + '[set]\n"rod.material" = ["steel"]\n',
      ["rod.material = [ 'steel' ]", "single value, not an array"]),
    W("matrix-set-section-as-key", RIG + '[set]\nrod = 5\n', ["rod = 5", "unknown input key"]),
    W("matrix-set-midspan-off-rod", '[sweep]\nbase = "flexible-rig"\n[set]\n'
                             '"output.midspan" = "0.3 m"\n',
      ["output.midspan", "0.3"]),
    W("matrix-set-overridden-by-axis",
      RIG + '[set]\n"drive.speed" = "-100 rpm"\n"sim.settle" = "0 s"\n"sim.capture" = "0.01 s"\n'
            '[axes]\n"drive.speed" = ["100 rpm"]\n',
      ["drive.speed", "-10.47"]),
    W("combination-bad-value", RIG + '[[combinations]]\n"joint.clearance" = "-1 mm"\n',
      ["joint.clearance", "-0.001"]),
    W("combination-empty", RIG + "[[combinations]]\n", ["[[combinations]] #1", "at least one"]),
    W("name-dotdot", '[sweep]\nname = "../x"\nbase = "rigid-rig"\n', ['sweep.name = "../x"']),
    W("name-empty", '[sweep]\nname = ""\nbase = "rigid-rig"\n', ['sweep.name = ""']),
    W("name-slash", '[sweep]\nname = "a/b"\nbase = "rigid-rig"\n', ['sweep.name = "a/b"']),
    W("base-unknown", '[sweep]\nbase = "no-such-preset"\n', ["sweep.base", "no-such-preset"]),
    W("base-directory", '[sweep]\nbase = "."\n', ["sweep.base = ."]),
    W("base-missing-file", '[sweep]\nbase = "nonexistent.toml"\n',
      ["sweep.base", "nonexistent.toml"]),
    W("base-malformed-file", '[sweep]\nbase = "base.toml"\n', ["base.toml", "malformed TOML"],
      files={"base.toml": "[rod\n"}),
    W("base-is-a-matrix", '[sweep]\nbase = "sweep-small"\n', ["sweep.base", "sweep-small"]),
    W("sweep-unknown-key", RIG + 'colour = "red"\n', ["sweep.colour", "red"]),
    W("unknown-section", RIG + "[matrix]\nx = 1\n", ["unknown matrix section"]),
    W("store-unknown-option", RIG + '[store]\ncolour = "red"\n', ["store.colour", "red"]),
    W("store-unknown-channel", RIG + '[store]\nchannels = "slider_jerk"\n',
      ["store.channels", "slider_jerk"]),
    W("store-no-channel", RIG + '[store]\nchannels = ""\n', ['store.channels = ""']),
    W("store-rate-not-dividing", RIG + '[store]\nrate = "30 kHz"\n', ["store.rate", "30000"]),
    W("store-rate-negative", RIG + '[store]\nrate = "-10 kHz"\n', ["store.rate", "-10000"]),
    W("store-rate-abc", RIG + '[store]\nrate = "abc"\n', ["store.rate", '"abc"']),
    W("store-window", RIG + '[store]\nspectrum_window = "triangle"\n',
      ["store.spectrum_window", "triangle"]),
    W("store-spectrum-max", RIG + '[store]\nspectrum_max = "-5 kHz"\n',
      ["store.spectrum_max", "-5000"]),
    W("store-spectrum-max-unit", RIG + '[store]\nspectrum_max = "5 m"\n',
      ["store.spectrum_max", '"5 m"']),
    W("store-inflection-floor", RIG + '[store]\ninflection_floor = "-20 m/s^2"\n',
      ["store.inflection_floor", "-20"]),
    W("store-inflection-floor-unit", RIG + '[store]\ninflection_floor = "20 m"\n',
      ["store.inflection_floor", '"20 m"']),
    W("store-poincare-channel", RIG + '[set]\n"sim.settle" = "0 s"\n"sim.capture" = "0.01 s"\n'
                                      '[store]\npoincare_channels = "slider_jerk"\n',
      ["store.poincare_channels", "slider_jerk"]),
    W("malformed-toml", RIG + "[axes\n", ["m.toml", "malformed TOML"]),
    W("list-with-bad-matrix", RIG + '[axes]\n"rod.colour" = ["red"]\n', ["rod.colour", "red"],
      extra=["--list"]),
    W("missing-matrix-file", "{tmp}/nonexistent.toml", ["{tmp}/nonexistent.toml"]),
    W("unknown-builtin", "no-such-matrix", ["no-such-matrix", "built-in"]),
    W("directory-as-matrix", "{tmp}/adir", ["{tmp}/adir"]),
    W("device-as-matrix", "/dev/null", ["/dev/null"]),
    W("preset-as-matrix", "rigid-rig", ["matrix = rigid-rig"]),
    W("run-input-as-matrix", "{src}/examples/rigid-rig.toml", ["unknown matrix section"]),
    W("jobs-negative", SMALL, ["--jobs", "-1"], extra=["--jobs", "-1"], jobs=False),
    W("jobs-very-negative", SMALL, ["--jobs", "-8"], extra=["--jobs", "-8"], jobs=False),
    W("jobs-abc", SMALL, ["--jobs", "abc"], extra=["--jobs", "abc"], jobs=False),
    W("jobs-fraction", SMALL, ["--jobs", "1.5"], extra=["--jobs", "1.5"], jobs=False),
    W("jobs-huge", SMALL, ["--jobs", "100000000000"], extra=["--jobs", "100000000000"], jobs=False),
    W("out-not-h5", SMALL, ["--out", "{tmp}/x.txt", ".h5"], extra=["--out", "{tmp}/x.txt"],
      out=False),
    W("out-no-extension", SMALL, ["--out", "{tmp}/x", ".h5"], extra=["--out", "{tmp}/x"],
      out=False),
    W("out-only-extension", SMALL, ["--out", "{tmp}/.h5"], extra=["--out", "{tmp}/.h5"],
      out=False),
    W("out-is-file", SMALL, ["--out", "{tmp}/plain"], extra=["--out", "{tmp}/plain"],
      out=False),
    W("out-under-file", SMALL, ["--out", "{tmp}/plain/x.h5"],
      extra=["--out", "{tmp}/plain/x.h5"], out=False),
    W("out-is-directory", SMALL, ["--out", "{tmp}/dir.h5", "not a flexrod sweep store"],
      extra=["--out", "{tmp}/dir.h5"], out=False, files={"dir.h5/keep": "x"}),
    W("out-foreign-file", SMALL, ["--out", "{tmp}/foreign.h5", "not a flexrod sweep store"],
      extra=["--out", "{tmp}/foreign.h5"], out=False, files={"foreign.h5": "garbage\n"}),
    W("out-in-proc", SMALL, ["--out", "/proc/flexrod-corpus.h5"],
      extra=["--out", "/proc/flexrod-corpus.h5"], out=False),
    W("out-empty", SMALL, ["--out", '""'], extra=SHORT + ["--out", ""], out=False),
    W("set-unknown-key", SMALL, ["rod.colour", "red"], extra=["--set", "rod.colour=red"]),
    W("set-without-equals", SMALL, ["--set", "rod.height"], extra=["--set", "rod.height"]),
    W("set-store-unknown", SMALL, ["store.colour", "red"], extra=["--set", "store.colour=red"]),
    W("set-store-rate", SMALL, ["store.rate", "3000"], extra=["--set", "store.rate=3 kHz"]),
    W("set-store-window", SMALL, ["store.spectrum_window", "triangle"],
      extra=["--set", "store.spectrum_window=triangle"]),
    W("set-store-channel", SMALL, ["store.channels", "slider_jerk"],
      extra=["--set", "store.channels=slider_jerk"]),
    W("set-capture-negative", SMALL, ["sim.capture", "-1"], extra=["--set", "sim.capture=-1 s"]),
    W("set-overridden-by-axis", SMALL, ["rod.height", "-0.001"],
      extra=SHORT + ["--set", "rod.height=-1mm"]),
    W("unknown-flag", SMALL, ["--frobnicate"], extra=["--frobnicate"]),
    W("extra-positional", SMALL, ["extra"], extra=["extra"]),
]

# --------------------------------------------------------------------------------------------
# compare
# --------------------------------------------------------------------------------------------


def K(cid, store, args, expect, out=True, files=None, xfail=None, rc=2):
    files = dict(files or {})
    argv = ["compare"] + ([store] if store is not None else []) + list(args)
    if out:
        argv += ["--no-plot", "--out", "{tmp}/out"]
    return Case("compare-" + cid, argv, expect, rc=rc, files=files, xfail=xfail)


STORE_ARG = "{tmp}/store.h5"
WITH_STORE = {"store.h5": STORE}

COMPARE = [
    K("group-iv", STORE_ARG, ["--group", "IV"], ["--group", "IV"], files=WITH_STORE),
    K("group-lower-case", STORE_ARG, ["--group", "i"], ["--group = i"], files=WITH_STORE),
    K("group-empty", STORE_ARG, ["--group", ""], ['--group = ""'], files=WITH_STORE),
    K("comparison-26", STORE_ARG, ["--comparison", "26"], ["--comparison", "26"],
      files=WITH_STORE),
    K("comparison-zero", STORE_ARG, ["--comparison", "0"], ["--comparison = 0"],
      files=WITH_STORE),
    K("comparison-negative", STORE_ARG, ["--comparison", "-1"], ["--comparison", "-1"],
      files=WITH_STORE),
    K("comparison-abc", STORE_ARG, ["--comparison", "abc"], ["--comparison", "abc"],
      files=WITH_STORE),
    K("comparison-fraction", STORE_ARG, ["--comparison", "1.5"], ["--comparison", "1.5"],
      files=WITH_STORE),
    K("comparison-outside-group", STORE_ARG, ["--comparison", "13", "--group", "I"],
      ["--comparison", "13", "group I"], files=WITH_STORE),
    K("missing-store", "{tmp}/nonexistent.h5", [], ["store", "{tmp}/nonexistent.h5"]),
    K("no-store", None, [], ["store is required"]),
    K("empty-store-argument", "", [], ['store = ""']),
    K("directory-as-store", "{tmp}/adir", [], ["store", "{tmp}/adir", "directory"]),
    K("device-as-store", "/dev/null", [], ["store", "/dev/null", "regular"]),
    K("text-file-as-store", "{tmp}/plain", [], ["store", "{tmp}/plain", "not an HDF5 file"]),
    K("empty-file-as-store", "{tmp}/empty.h5", [], ["store", "{tmp}/empty.h5", "HDF5"],
      files={"empty.h5": b""}),
    K("random-bytes-as-store", "{tmp}/random.h5", [], ["store", "{tmp}/random.h5", "HDF5"],
      files={"random.h5": bytes((i * 131 + 7) % 256 for i in range(100))}),
    K("truncated-store", "{tmp}/cut.h5", [], ["store", "{tmp}/cut.h5"], files={"cut.h5": CUT}),
    K("run-file-as-store", "{tmp}/run.h5", [],
      ["store", "{tmp}/run.h5", "not a flexrod sweep store"], files={"run.h5": RUNH5}),
    K("out-is-file", STORE_ARG, ["--no-plot", "--out", "{tmp}/plain"], ["--out", "{tmp}/plain"],
      out=False, files=WITH_STORE),
    K("out-under-file", STORE_ARG, ["--no-plot", "--out", "{tmp}/plain/sub"],
      ["--out", "{tmp}/plain/sub"], out=False, files=WITH_STORE),
    K("out-empty", STORE_ARG, ["--no-plot", "--out", ""], ['--out = ""'], out=False,
      files=WITH_STORE),
    K("unknown-flag", STORE_ARG, ["--frobnicate"], ["--frobnicate"], files=WITH_STORE),
    K("extra-positional", STORE_ARG, ["extra"], ["extra"], files=WITH_STORE),
]

# --------------------------------------------------------------------------------------------
# good-input controls (not counted in the corpus)
# --------------------------------------------------------------------------------------------
CONTROLS = [
    Case("control-keys", ["keys"], ["rod.height"], rc=0),
    Case("control-modes-zero-modes-is-allowed", ["modes", "--modes", "0"], ["craig-bampton"],
         rc=0),
    Case("control-sweep-list-all-cores", ["sweep", SMALL, "--jobs", "0", "--list"],
         ["small: 4 runs"], rc=0),
    Case("control-run-max-steps-zero-is-the-default-budget",
         ["run", "rigid-rig", "--no-plot", "--set", "sim.settle=0s", "--set",
          "sim.capture=0.002s", "--set", "sim.max_steps=0", "--out", "{tmp}/out"],
         ["flexrod run rigid-rig"], rc=0),
]

# --------------------------------------------------------------------------------------------
# machinery
# --------------------------------------------------------------------------------------------


def _wait_for_binary(limit=180.0):
    """The binary may be relinking while another build runs: wait for it."""
    deadline = time.monotonic() + limit
    while not (os.path.isfile(BINARY) and os.access(BINARY, os.X_OK)):
        if time.monotonic() > deadline:
            pytest.fail("flexrod binary not found: %s (set FLEXROD_BINARY)" % BINARY)
        time.sleep(2.0)


def _limit_memory():
    if MEMORY:
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def _exec(argv, cwd, timeout=TIMEOUT):
    """Runs flexrod; retries while the binary is being relinked (missing or busy)."""
    deadline = time.monotonic() + 180.0
    env = dict(os.environ)
    env.pop("FLEXROD_FAIL_WRITE", None)
    env.setdefault("MPLBACKEND", "Agg")
    while True:
        _wait_for_binary()
        try:
            return subprocess.run([BINARY] + argv, cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  timeout=timeout, preexec_fn=_limit_memory)
        except OSError as e:
            if e.errno in (errno.ENOENT, errno.ETXTBSY) and time.monotonic() < deadline:
                time.sleep(2.0)
                continue
            raise


@pytest.fixture(scope="session")
def artifacts(tmp_path_factory):
    """A small sweep store and a run.h5, produced by legitimate runs, for the compare cases."""
    root = tmp_path_factory.mktemp("artifacts")
    store = root / "small.h5"
    p = _exec(["sweep", str(SOURCE_DIR / "examples" / "sweep-small.toml"), "--jobs", "2",
               "--no-plot", "--set", "sim.settle=0.05s", "--set", "sim.capture=0.1s", "--out",
               str(store)], cwd=root, timeout=120)
    assert p.returncode == 0 and store.is_file(), p.stderr.decode(errors="replace")
    run = root / "run"
    p = _exec(["run", "rigid-rig", "--no-plot", "--set", "sim.settle=0s", "--set",
               "sim.capture=0.01s", "--out", str(run)], cwd=root)
    assert p.returncode == 0 and (run / "run.h5").is_file(), p.stderr.decode(errors="replace")
    return {STORE: store.read_bytes(), RUNH5: (run / "run.h5").read_bytes(),
            CUT: store.read_bytes()[:5000]}


def _subst(text, tmp):
    return text.replace("{tmp}", str(tmp)).replace("{src}", str(SOURCE_DIR))


def _snapshot(root):
    """Every path under root, with a digest of each regular file's content."""
    snap = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for d in dirnames:
            snap[os.path.relpath(os.path.join(dirpath, d), root)] = "<dir>"
        for f in filenames:
            p = os.path.join(dirpath, f)
            if not os.path.isfile(p):  # a FIFO: its type, not its content (reading would block)
                snap[os.path.relpath(p, root)] = "<not regular>"
                continue
            with open(p, "rb") as fh:
                snap[os.path.relpath(p, root)] = hashlib.sha256(fh.read()).hexdigest()
    return snap


OUTPUT_FLAGS = ("--out", "--json", "--plot", "--vtk")


def check(case, tmp_path, artifacts=None):
    tmp = tmp_path / "case"
    tmp.mkdir()
    # The inputs the test creates.
    for name, content in COMMON_FILES.items():
        (tmp / name).write_text(content)
    for name in COMMON_DIRS:
        (tmp / name).mkdir()
    for name, content in case.files.items():
        path = tmp / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if content is FIFO:
            os.mkfifo(path)
        elif content is LINK:
            os.symlink("plain", path)
        elif content in (STORE, RUNH5, CUT):
            path.write_bytes(artifacts[content])
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(_subst(content, tmp))
    argv = [_subst(a, tmp) for a in case.argv]
    # The expected substrings keep {tmp}; the output has the case directory replaced by {tmp},
    # so that the words of pytest's directory names (the test id) cannot satisfy them.
    expect = [e.replace("{src}", str(SOURCE_DIR)) for e in case.expect]
    # Output locations inside tmp that do not exist before the run.
    fresh = []
    for flag, value in zip(argv, argv[1:]):
        if flag in OUTPUT_FLAGS and value.startswith(str(tmp)) and not os.path.lexists(value):
            fresh.append(value)
    before = _snapshot(tmp)

    try:
        p = _exec(argv, cwd=tmp)
    except subprocess.TimeoutExpired:
        pytest.fail("timed out after %d s: flexrod %s" % (TIMEOUT, " ".join(argv)))
    err = p.stderr.decode(errors="replace").replace(str(tmp), "{tmp}")
    out = p.stdout.decode(errors="replace").replace(str(tmp), "{tmp}")
    shown = "flexrod %r\nexit %d\n--- stderr\n%s--- stdout\n%s" % (argv, p.returncode, err,
                                                                   out[:2000])

    # (a) the exit code (a negative code is a signal: a crash)
    assert p.returncode == case.rc, shown
    # (b) the message names the key or flag and the value
    for s in expect:
        assert s in (err if case.rc != 0 else err + out), "missing %r\n%s" % (s, shown)
    if case.rc == 0:
        return
    # (c) nothing written: no output location, nothing new, nothing changed
    for path in fresh:
        assert not os.path.lexists(path), "%s was written\n%s" % (path, shown)
    after = _snapshot(tmp)
    new = sorted(set(after) - set(before))
    gone = sorted(set(before) - set(after))
    changed = sorted(k for k in set(before) & set(after) if before[k] != after[k])
    assert not new and not gone and not changed, (
        "new: %s; removed: %s; changed: %s\n%s" % (new, gone, changed, shown))


@pytest.mark.parametrize("case", [c.param() for c in RUN])
def test_run(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.parametrize("case", [c.param() for c in KEYS])
def test_keys(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.parametrize("case", [c.param() for c in MODES])
def test_modes(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.parametrize("case", [c.param() for c in CONTACT])
def test_contact(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.parametrize("case", [c.param() for c in STUDY])
def test_study(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.parametrize("case", [c.param() for c in SWEEP])
def test_sweep(case, tmp_path):
    check(case, tmp_path)


@pytest.mark.parametrize("case", [c.param() for c in COMPARE])
def test_compare(case, tmp_path, artifacts):
    check(case, tmp_path, artifacts)


@pytest.mark.parametrize("case", [c.param() for c in CONTROLS])
def test_good_input_controls(case, tmp_path):
    check(case, tmp_path)


def test_corpus_size():
    """At least 150 bad-input cases, every id unique; the README states the count and the
    number of known defects (strict xfails) as they are."""
    cases = RUN + KEYS + MODES + CONTACT + STUDY + SWEEP + COMPARE
    assert len(cases) >= 150
    ids = [c.id for c in cases + CONTROLS]
    assert len(ids) == len(set(ids)), sorted(i for i in ids if ids.count(i) > 1)
    readme = " ".join((SOURCE_DIR / "README.md").read_text().split())
    xfails = sum(1 for c in cases if c.xfail)
    stated = "%d bad inputs over every command" % len(cases)
    assert stated in readme, "README must say `%s`" % stated
    defects = ("none is a known defect" if xfails == 0
               else "%d are known defects (strict xfails)" % xfails)
    assert defects in readme, "README must say `%s`" % defects
