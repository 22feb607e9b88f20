# SPDX-License-Identifier: GPL-3.0-or-later
"""flexrod.modes, flexrod.contact, flexrod.sweep and flexrod.open_store against the CLI."""

import json
import threading
import _thread
import time

import numpy as np
import pytest

import flexrod
from conftest import cli, same_h5, set_args


def test_modes_equals_the_clis_json(tmp_path):
    path = tmp_path / "modes.json"
    cli("modes", "--material", "brass", "--height", "12.7 mm", "--modes", "6", "--json", str(path))
    ref = json.loads(path.read_text())
    m = flexrod.modes(material="brass", height="12.7 mm", modes=6)
    assert m["inputs"] == ref["inputs"]
    assert m["num_coordinates"] == ref["num_coordinates"]
    assert m["units"] == ref["units"]
    assert m["mode"].dtype == np.int64
    assert list(m["mode"]) == [r["mode"] for r in ref["modes"]]
    for col in ("full_hz", "reduced_hz", "rel_error", "mac", "effective_mass"):
        assert m[col].dtype == np.float64
        expected = np.array([np.nan if r[col] is None else r[col] for r in ref["modes"]])
        assert np.array_equal(m[col], expected, equal_nan=True), col
    assert list(m["rigid_body"]) == [r["rigid_body"] for r in ref["modes"]]
    mechanism = ref["mechanism_modes"]
    assert len(mechanism) > 0
    assert list(m["mechanism_frequency_hz"]) == [r["frequency_hz"] for r in mechanism]
    assert list(m["mechanism_damping_ratio"]) == [r["damping_ratio"] for r in mechanism]


def test_modes_bad_flag_and_value_raise_input_error():
    with pytest.raises(flexrod.InputError) as e:
        flexrod.modes(height="-1 mm")
    assert e.value.key == "rod.height"
    with pytest.raises(flexrod.InputError) as e:
        flexrod.modes(heigth="1 mm")
    assert e.value.key == "heigth" and "height" in e.value.rule


def test_contact_equals_the_clis_json(tmp_path):
    path = tmp_path / "contact.json"
    cli("contact", "--law", "hunt-crossley", "--mass", "2.71 kg", "--velocity", "0.5 m/s",
        "--restitution", "0.8", "--json", str(path))
    ref = json.loads(path.read_text())
    c = flexrod.contact(law="hunt-crossley", mass="2.71 kg", velocity=0.5, restitution=0.8)
    loop, loop_units = c.pop("loop"), c.pop("loop_units")
    assert c == ref
    assert set(loop) == {"time", "penetration", "rate", "force"}
    assert loop_units == {"time": "s", "penetration": "m", "rate": "m/s", "force": "N"}
    n = len(loop["time"])
    assert n > 10
    for values in loop.values():
        assert values.dtype == np.float64 and values.shape == (n,)
    assert np.max(loop["penetration"]) <= ref["peak_penetration"]
    assert np.all(np.diff(loop["time"]) > 0)


def test_contact_bad_input_raises_input_error():
    with pytest.raises(flexrod.InputError) as e:
        flexrod.contact(law="no-such-law", mass=1, velocity=1)
    assert e.value.key == "law" and "hertz" in e.value.rule
    with pytest.raises(flexrod.InputError) as e:
        flexrod.contact(law="hertz", mass=-1, velocity=1)
    assert e.value.key == "mass"
    with pytest.raises(flexrod.InputError) as e:
        flexrod.contact(law="hertz", mass=1, velocity=1, pin_radius="10 mm")
    assert e.value.key == "pin-radius"
    with pytest.raises(flexrod.InputError) as e:
        flexrod.contact(law="hertz", mass=1, velocity=1, stifness=1e9)
    assert e.value.key == "stifness"


# A tiny matrix: sweep-small's 4 runs, shorter (a complete revolution at 150 rpm).
TINY = {"sim.settle": "0.05 s", "sim.capture": "0.45 s"}


def test_sweep_store_equals_the_clis(tmp_path):
    cli_store = tmp_path / "cli.h5"
    cli("sweep", "sweep-small", *set_args(TINY), "--jobs", "1", "--no-plot", "--out",
        str(cli_store))
    py_store = flexrod.sweep("sweep-small", jobs=2, out=tmp_path / "py.h5", set=TINY)
    assert py_store == str(tmp_path / "py.h5")
    assert same_h5(cli_store, py_store)
    assert not (tmp_path / "py.h5.parts").exists()

    runs = flexrod.open_store(py_store)
    ref = flexrod.open_store(cli_store)
    assert len(runs) == 4 and len(ref) == 4
    for r, q in zip(runs, ref):
        assert r.ok and r.id == q.id and r.label == q.label
        assert r.inputs == q.inputs
        assert r.inputs["sim.capture"] == 0.45 and r.inputs["rod.elements"] == 40
        assert list(r.figures) == list(q.figures)
        assert np.array_equal(list(r.figures.values()), list(q.figures.values()))
        assert np.isfinite(r.figures["amplification_positive_p95"])
        assert set(r.summary) >= {"slider_acceleration", "load_amplification"}
        assert list(r.channels)[0] == "time"
        assert set(r.channels) == {"time", "crank_angle", "slider_acceleration",
                                   "contact_normal_force"}
        for name, values in r.channels.items():
            assert values.dtype == np.float64
            assert np.array_equal(values, q.channels[name]), name
        assert r.units["slider_acceleration"] == "m/s^2" and r.channel_rate == 5000.0


def test_sweep_bad_input_raises_input_error(tmp_path):
    with pytest.raises(flexrod.InputError) as e:
        flexrod.sweep("sweep-small", out=tmp_path / "store.txt")
    assert e.value.key == "out"
    with pytest.raises(flexrod.InputError) as e:
        flexrod.sweep("sweep-small", out=tmp_path / "s.h5", set={"sim.capture": "-1 s"})
    assert e.value.key == "sim.capture"
    with pytest.raises(flexrod.InputError):
        flexrod.sweep("sweep-small", jobs=0, out=tmp_path / "s.h5")
    with pytest.raises(flexrod.InputError):
        flexrod.open_store(tmp_path / "missing.h5")
    assert not (tmp_path / "s.h5").exists()


def test_ctrl_c_stops_a_sweep_which_then_resumes(tmp_path):
    store = tmp_path / "s.h5"
    slow = {"sim.settle": "0 s", "sim.capture": "100 s", "sim.sample_rate": "1 kHz",
            "store.rate": "1 kHz"}
    timer = threading.Timer(1.5, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        flexrod.sweep("sweep-small", jobs=2, out=store, set=slow)
    timer.cancel()
    assert time.monotonic() - start < 30.0  # four runs of 100 s would take minutes
    assert not store.exists()
    assert (tmp_path / "s.h5.parts").is_dir()  # the session's directory, resumable
    # The lock was released: a new sweep into the same store runs (here to completion).
    assert flexrod.sweep("sweep-small", jobs=2, out=store, set=TINY) == str(store)
    assert len(flexrod.open_store(store)) == 4
