# SPDX-License-Identifier: GPL-3.0-or-later
"""flexrod.run against `flexrod run`: the same numbers bit for bit, the same files, the
documented types and units, the error classes, the GIL and Ctrl-C."""

import _thread
import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import flexrod
from conftest import (PYTHON, SHORT, cli, read_cli_channels, read_cli_impacts, read_summary,
                      same_h5, set_args, without_timing)


# The CLI's run writes every channel into run.h5, to compare with every channel of Run.
CLI_SET = {**SHORT, "output.channels": "all"}


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "run"
    cli("run", "flexible-rig", "--no-plot", *set_args(CLI_SET), "--out", str(out))
    return out


@pytest.fixture(scope="module")
def py_run():
    return flexrod.run("flexible-rig", set=SHORT)


def test_summary_is_the_clis_bit_for_bit(cli_run, py_run):
    assert without_timing(py_run.summary) == without_timing(read_summary(cli_run))
    assert py_run.summary["integrator"]["outcome"] == "completed"


def test_channels_are_the_clis_bit_for_bit(cli_run, py_run):
    channels, units = read_cli_channels(cli_run)
    assert list(py_run.channels) == list(channels)  # "time" first, then the CLI's order
    for name, values in channels.items():
        assert np.array_equal(py_run.channels[name], values), name
    assert py_run.units == units


def test_ideal_twin_is_the_clis_bit_for_bit(cli_run, py_run):
    assert py_run.ideal is not None and py_run.ideal.ideal is None
    channels, units = read_cli_channels(cli_run, "ideal/channels")
    for name, values in channels.items():
        assert np.array_equal(py_run.ideal.channels[name], values), name
    assert py_run.ideal.units == units
    assert without_timing(py_run.ideal.summary) == without_timing(
        read_summary(cli_run)["ideal"])


def test_impacts_are_the_clis_bit_for_bit(cli_run, py_run):
    columns, units = read_cli_impacts(cli_run)
    assert len(columns["time"]) > 0  # the short run has impacts to compare
    assert list(py_run.impacts) == list(columns)
    for name, values in columns.items():
        assert np.array_equal(py_run.impacts[name], values), name
    assert py_run.impact_units == units
    assert len(py_run.impacts["time"]) == py_run.summary["impacts"]["count"] + \
        py_run.summary["impacts"]["incomplete"]


def test_dtypes_and_units(py_run):
    n = py_run.summary["samples"]
    assert n > 2
    for name, values in py_run.channels.items():
        assert isinstance(values, np.ndarray) and values.dtype == np.float64, name
        assert values.shape == (n,), name
    for values in py_run.impacts.values():
        assert values.dtype == np.float64 and values.ndim == 1
    assert py_run.units["time"] == "s"
    assert py_run.units["slider_acceleration"] == "m/s^2"
    assert py_run.units["bearing_force"] == "N"
    assert py_run.units["crank_angle"] == "rad"
    assert set(py_run.units) == set(py_run.channels)
    # Sample i at capture_start + i / sample_rate, as the CSV's time column.
    t = py_run.channels["time"]
    assert t[0] == py_run.summary["capture_start [s]"]
    assert np.allclose(np.diff(t), 1 / 20e3, rtol=1e-9)
    assert isinstance(py_run.summary, dict)


def test_out_writes_what_the_cli_writes(cli_run, tmp_path):
    out = tmp_path / "py"
    flexrod.run("flexible-rig", set=CLI_SET, out=out)
    listing = lambda d: sorted(p.relative_to(d) for p in d.rglob("*")
                               if p.is_file() and p.suffix != ".png")
    files = listing(cli_run)
    assert listing(out) == files
    assert {"resolved.toml", "summary.json"} <= {str(f) for f in files}
    for f in files:
        if f.suffix == ".json":
            assert without_timing(json.loads((out / f).read_text())) == \
                without_timing(json.loads((cli_run / f).read_text())), f
        elif f.suffix == ".h5":
            assert same_h5(out / f, cli_run / f)
        else:
            assert (out / f).read_bytes() == (cli_run / f).read_bytes(), f


def test_no_out_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    flexrod.run("rigid-rig", set={"sim.settle": "0 s", "sim.capture": "0.01 s",
                                  "sim.sample_rate": "2 kHz"})
    assert list(tmp_path.iterdir()) == []


def test_numbers_and_units_in_set():
    a = flexrod.run("rigid-rig", set={"sim.settle": 0.0, "sim.capture": "0.02 s",
                                      "drive.speed": "150 rpm", "sim.sample_rate": "2 kHz"})
    b = flexrod.run("rigid-rig", set={"sim.settle": "0 s", "sim.capture": 0.02,
                                      "drive.speed": 150 * 2 * np.pi / 60,
                                      "sim.sample_rate": 2000})
    assert np.array_equal(a.channels["slider_acceleration"], b.channels["slider_acceleration"])


def test_keys_match_the_schema():
    keys = flexrod.keys()
    printed = [line.split()[0] for line in cli("keys").stdout.splitlines() if line.strip()]
    assert [k["key"] for k in keys] == printed
    by_key = {k["key"]: k for k in keys}
    assert set(by_key["rod.height"]) >= {"key", "default", "unit", "rule"}
    assert by_key["rod.height"]["default"] == "19.05 mm"
    assert by_key["rod.height"]["unit"] == "m"
    assert by_key["drive.speed"]["unit"] == "rad/s"
    assert by_key["rod.elements"]["unit"] == ""
    assert all(k["rule"] for k in keys)


# ---- errors ----------------------------------------------------------------------------------

@pytest.mark.parametrize("sets,key,rule", [
    ({"rod.height": "-3 mm"}, "rod.height", "> 0"),
    ({"rod.heigth": "3 mm"}, "rod.heigth", "unknown"),
    ({"drive.speed": "fast"}, "drive.speed", ""),
])
def test_bad_input_raises_input_error_before_any_work(tmp_path, sets, key, rule):
    out = tmp_path / "out"
    with pytest.raises(flexrod.InputError) as e:
        flexrod.run("flexible-rig", set=sets, out=out)
    assert isinstance(e.value, ValueError)
    assert e.value.key == key
    assert e.value.value != ""
    assert rule in e.value.rule
    assert str(e.value) == f"{e.value.key} = {e.value.value}: {e.value.rule}"
    assert not out.exists()


def test_unknown_input_names_the_presets():
    with pytest.raises(flexrod.InputError) as e:
        flexrod.run("no-such-rig")
    assert e.value.key == "input" and e.value.value == "no-such-rig"
    assert "flexible-rig" in e.value.rule


def test_out_that_cannot_be_a_directory_is_input_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(flexrod.InputError) as e:
        flexrod.run("rigid-rig", set={"sim.capture": "0.01 s"}, out=blocker / "run")
    assert e.value.key == "out"
    assert blocker.read_text() == "x"


def test_numerical_failure_raises_with_time_state_hint_and_partial_run(tmp_path):
    with pytest.raises(flexrod.NumericalError) as e:
        flexrod.run("rigid-rig", set={"sim.settle": "0 s", "sim.capture": "0.05 s",
                                      "sim.max_steps": 10}, out=tmp_path / "run")
    err = e.value
    assert err.outcome == "step-limit"
    assert isinstance(err.time, float) and 0 < err.time < 0.05
    assert "sim.max_steps" in err.hint
    assert err.state["norm_coordinates"] > 0 and "worst_residual_variable" in err.state
    assert isinstance(err.run, flexrod.Run) and not err.run.ok
    assert err.run.summary["integrator"]["outcome"] == "step-limit"
    assert err.run.channels["time"].dtype == np.float64
    assert len(err.run.channels["time"]) == err.run.summary["samples"]
    assert "step-limit at t = " in str(err)
    # As the CLI, everything computed is written before the error.
    assert read_summary(tmp_path / "run")["integrator"]["outcome"] == "step-limit"


# ---- GIL and Ctrl-C ---------------------------------------------------------------------------

LONG = {"sim.settle": "0 s", "sim.capture": "200 s", "sim.sample_rate": "1 kHz",
        "joint.type": "ideal"}  # a minute or more of computing


def test_gil_is_released_while_a_run_computes():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    try:
        start = time.monotonic()
        flexrod.run("flexible-rig", set={**LONG, "sim.capture": "30 s"})
        end = time.monotonic()
    finally:
        done.set()
        counter.join()
    during = [t for t in ticks if start < t < end]
    # With the GIL held the counter could not tick until the run returned.
    assert end - start > 0.5
    assert len(during) > 50
    assert np.max(np.diff([start, *during, end])) < 0.5 * (end - start)


def test_ctrl_c_stops_a_run_with_keyboard_interrupt():
    timer = threading.Timer(1.0, _thread.interrupt_main)  # SIGINT as if typed, after 1 s
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        flexrod.run("flexible-rig", set=LONG)
    elapsed = time.monotonic() - start
    timer.cancel()
    assert elapsed < 30.0  # the whole run takes minutes; it stopped at the next step
    # The module still works afterwards.
    assert flexrod.run("rigid-rig", set={"sim.capture": "0.01 s", "sim.settle": "0 s",
                                         "sim.sample_rate": "2 kHz"}).ok


def test_sigint_stops_a_run_in_another_process():
    """A real SIGINT (Ctrl-C in a terminal), not a simulated one."""
    code = ("import sys, flexrod\n"
            "print('computing', flush=True)\n"
            "try:\n"
            f"    flexrod.run('flexible-rig', set={LONG!r})\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True)\n"
            "    sys.exit(0)\n"
            "sys.exit(3)\n")
    proc = subprocess.Popen([PYTHON, "-c", code], stdout=subprocess.PIPE, text=True,
                            env=os.environ.copy())
    assert proc.stdout.readline().strip() == "computing"
    time.sleep(1.0)  # inside the run
    start = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0, out
    assert "interrupted" in out
    assert time.monotonic() - start < 30.0


def test_check_is_the_clis_accuracy_check(tmp_path):
    """check=True is `flexrod run --check`: the same reference run, the same differences."""
    out = tmp_path / "cli"
    cli("run", "flexible-rig", "--no-plot", "--check", *set_args(SHORT), "--out", str(out))
    expected = read_summary(out)["accuracy_check"]
    got = flexrod.run("flexible-rig", set=SHORT, check=True).summary["accuracy_check"]
    assert got == expected
    assert got["rel_tol"] == pytest.approx(1e-8) and got["figures"]


def test_vtk_writes_the_clis_paraview_frames(tmp_path):
    """vtk=DIR writes the frames `flexrod run --vtk DIR` writes, byte for byte, with or
    without out=."""
    sets = {**SHORT, "vtk.rate": "2 kHz"}
    cli("run", "flexible-rig", "--no-plot", *set_args(sets), "--out", str(tmp_path / "cli"),
        "--vtk", str(tmp_path / "cli_vtk"))
    flexrod.run("flexible-rig", set=sets, vtk=tmp_path / "py_vtk")
    flexrod.run("flexible-rig", set=sets, out=tmp_path / "py", vtk=tmp_path / "py_vtk2")
    expected = sorted(os.listdir(tmp_path / "cli_vtk"))
    assert "run.pvd" in expected and len(expected) == 301  # 0.15 s at 2 kHz, and the collection
    for d in ("py_vtk", "py_vtk2"):
        assert sorted(os.listdir(tmp_path / d)) == expected
        for name in expected[::50] + ["run.pvd"]:
            assert (tmp_path / d / name).read_bytes() == (tmp_path / "cli_vtk" / name).read_bytes()


def test_vtk_directory_that_cannot_be_created_fails_before_the_run(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(flexrod.InputError, match="vtk"):
        flexrod.run("flexible-rig", set=SHORT, vtk=blocker / "vtk")
