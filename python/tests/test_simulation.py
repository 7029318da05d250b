"""grains from Python: construction errors, stepping, reads, writes, checkpoints."""

import json
import os
import signal
import threading

import numpy as np
import pytest

import grains



def test_unknown_key_is_an_input_error_naming_it(data):
    text = (data / "column_tiny.toml").read_text().replace("[run]", "[run]\nduratoin = 1.0")
    with pytest.raises(grains.InputError, match="duratoin"):
        grains.Simulation.from_toml(text)
    assert issubclass(grains.InputError, ValueError)


def test_wrong_type_is_an_input_error_naming_the_key(data):
    text = (data / "column_tiny.toml").read_text().replace("duration = 0.02", 'duration = "long"')
    # As the command line says it: where, the line (so the key), and what was expected.
    with pytest.raises(
        grains.InputError,
        match=r"line \d+, column \d+ \(duration = \"long\"\): invalid type: string \"long\", expected f64",
    ):
        grains.Simulation.from_toml(text)


def test_from_dict_reads_the_same_schema(data):
    tomllib = pytest.importorskip("tomllib")

    d = tomllib.loads((data / "free_disk.toml").read_text())
    sim = grains.Simulation.from_dict(d)
    assert sim.engine == "dem" and sim.dim == 2
    d["run"]["speed"] = 3
    with pytest.raises(grains.InputError, match="speed"):
        grains.Simulation.from_dict(d)


def test_each_engine_run_to_its_end_gives_the_command_lines_state_hash(data, tmp_path):
    for name in ["column_tiny.toml", "mpm_tiny.toml", "ring_tiny.toml"]:
        sim = grains.Simulation.from_file(data / name)
        assert sim.run() == "completed"
        cli = grains.run(data / name, out=tmp_path / name)
        assert sim.state_hash() == cli["state_hash"], name


def test_particles_are_copies_in_id_order(data):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")
    sim.step(200)
    p = sim.particles()
    assert np.array_equal(p.id, np.arange(len(p)))
    assert p.position.shape == (len(p), 2) and p.position.dtype == np.float64
    for a in (p.omega, p.radius, p.mass):
        assert a.shape == (len(p),)
    p.position[:] = 0.0
    assert not np.all(sim.particles().position == 0.0)


def test_set_rejects_a_wrong_shape_or_dtype_naming_the_array_and_both_shapes(data):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")
    with pytest.raises(ValueError, match=r"values has shape \(2, 3\), expected \(2, 2\)"):
        sim.set("velocity", [0, 1], np.zeros((2, 3)))
    with pytest.raises(ValueError, match="values has dtype float32, expected float64"):
        sim.set("velocity", [0, 1], np.zeros((2, 2), dtype=np.float32))
    sim.set("velocity", np.array([3]), np.array([[1.0, 2.0]]))
    assert np.array_equal(sim.particles().velocity[3], [1.0, 2.0])


def test_a_force_callback_with_a_wrong_shape_is_a_value_error(data):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")
    n = len(sim.particles())
    with pytest.raises(ValueError, match=rf"force has shape \({n}, 3\), expected \({n}, 2\)"):
        sim.add_force(lambda s: np.zeros((n, 3)))


class Boom(Exception):
    pass


def test_an_exception_in_a_callback_reaches_the_caller_with_its_traceback(data):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")

    def explode(s):
        if s.time > 1e-4:
            raise Boom("from the force")
        return np.zeros((len(s.particles()), 2))

    sim.add_force(explode)
    with pytest.raises(Boom) as e:
        sim.run()
    assert any(f.name == "explode" for f in e.traceback)
    sim2 = grains.Simulation.from_file(data / "column_tiny.toml")

    def every(s):
        raise Boom("from run's callback")

    with pytest.raises(Boom) as e:
        sim2.run(callback=every, every=10)
    assert any(f.name == "every" for f in e.traceback)
    assert sim2.steps == 10


def test_ctrl_c_interrupts_a_long_run_between_steps_and_the_state_goes_on(data, tmp_path):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")
    # A shell starts a background job with SIGINT ignored, and Python then keeps it
    # ignored: give Ctrl-C its usual meaning for this test, whoever started pytest.
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.run(until=1e6)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, before)
    at = sim.steps
    assert at > 0
    sim.step(5)
    assert sim.steps == at + 5
    sim.checkpoint(tmp_path / "ck")


def test_a_view_is_zero_copy_read_only_and_raises_after_a_rebuild(data):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")
    v = sim.view("position")
    a = np.asarray(v)
    assert a.shape == (len(v), 2) and not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0] = 1.0
    ids = np.asarray(sim.view("id"))
    p = sim.particles()
    assert np.array_equal(np.asarray(v), p.position[ids])
    tail = a[1:]
    del a, ids
    with pytest.raises(RuntimeError, match="still referenced"):
        sim.step()  # a slice of a view's array still points into the engine's memory
    del tail
    for _ in range(400):
        sim.step(10)
        if not v.valid:
            break
    assert not v.valid, "no neighbour-list rebuild in 4000 steps"
    with pytest.raises(grains.StaleViewError):
        np.asarray(v)
    with pytest.raises(grains.StaleViewError):
        v[0]


def test_a_checkpoint_resumes_bitwise(data, tmp_path):
    for name in ["column_tiny.toml", "ring_tiny.toml"]:
        sim = grains.Simulation.from_file(data / name)
        sim.step(150)
        sim.checkpoint(tmp_path / name)
        sim.run()
        again = grains.Simulation.resume(tmp_path / name)
        assert again.steps == 150
        again.run()
        assert again.state_hash() == sim.state_hash(), name


def test_a_constant_force_gives_the_analytic_trajectory_of_a_free_particle(data):
    sim = grains.Simulation.from_toml((data / "free_disk.toml").read_text())
    m = sim.particles().mass[0]
    f = np.array([[0.0, 2.0e-3]])
    sim.add_force(lambda s: f)
    sim.run()
    t = sim.time
    p = sim.particles()
    want = np.array([0.1 * t, 0.5 * f[0, 1] / m * t * t])
    assert np.allclose(p.position[0], want, rtol=1e-12, atol=1e-15)
    assert np.isclose(p.velocity[0, 1], f[0, 1] / m * t, rtol=1e-12)


def test_contacts_history_summary_and_write(data, tmp_path):
    sim = grains.Simulation.from_file(data / "column_tiny.toml")
    sim.run(until=0.01)
    h = sim.history()
    assert "time" in h and len(h["time"]) == len(h["step"]) > 1
    sim.run()
    c = sim.contacts()
    assert set(c) == {"i", "j", "overlap", "normal_force", "tangential_force", "branch"}
    assert len(c["i"]) > 0 and np.all(c["overlap"] > 0)
    fn, b = c["normal_force"], c["branch"]
    cross = fn[:, 0] * b[:, 1] - fn[:, 1] * b[:, 0]
    assert np.allclose(cross, 0.0, atol=1e-12 * np.abs(fn).max() * np.abs(b).max())
    assert np.allclose(np.einsum("ij,ij->i", c["tangential_force"], b), 0.0, atol=1e-15)
    s = sim.summary()
    assert s["status"] == "completed" and s["state_hash"] == sim.state_hash()
    sim.write(tmp_path / "out")
    on_disk = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert on_disk["state_hash"] == s["state_hash"]
    assert (tmp_path / "out" / "history.csv").is_file()
    with pytest.raises(RuntimeError):
        sim.step()


def test_points_and_charge(data):
    m = grains.Simulation.from_file(data / "mpm_tiny.toml")
    p = m.points()
    assert p["position"].shape == (len(p["id"]), 2) and p["stress"].shape == (len(p["id"]), 3)
    with pytest.raises(ValueError):
        m.add_force(lambda s: None)
    b = grains.Simulation.from_file(data / "ring_tiny.toml")
    c = b.charge()
    assert c["triangles"].shape[1] == 3 and len(c["pressure"]) == len(c["triangles"])


def test_a_rust_panic_is_an_internal_error_not_an_abort():
    with pytest.raises(grains.InternalError, match="on purpose"):
        grains._panic("on purpose")
    with pytest.raises(grains.InternalError, match="on a worker"):
        grains._panic("on a worker", pool=True)
    assert issubclass(grains.InternalError, RuntimeError)


SPEC = """
name = "tiny"
seed = 3

[domain]
shape = "rectangle"
width = 0.02
height = 0.02
periodic_x = true

[sizes]
distribution = "gaussian"
d0 = 1.0e-3
delta = 0.113

[protocol]
rate = 2e-3
target_fraction = 0.8
"""


def test_pack_and_analyze(tmp_path):
    spec = tmp_path / "tiny.toml"
    spec.write_text(SPEC)
    d = grains.pack(spec, out=tmp_path / "pack")
    assert d["position"].shape == (len(d["radius"]), 2) and len(d["radius"]) > 100
    a = grains.analyze(tmp_path / "pack" / "packing.txt", out=tmp_path / "analysis")
    assert (tmp_path / "analysis" / "analysis.json").is_file() and len(a) > 0
    with pytest.raises(grains.InputError):
        grains.pack(tmp_path / "missing.toml")
