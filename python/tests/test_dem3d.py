"""grains from Python on 3D DEM runs (dim = 3): the same calls as in 2D, with 3-vectors."""

import json
from pathlib import Path

import numpy as np
import pytest

import grains

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "dem3d"


def test_a_3d_scenario_run_to_its_end_gives_the_command_lines_state_hash(data, tmp_path):
    for path in [EXAMPLES / "chung_ooi_test1.toml", data / "column3d_tiny.toml"]:
        sim = grains.Simulation.from_file(path)
        assert sim.dim == 3 and sim.engine == "dem"
        assert sim.run() == "completed"
        cli = grains.run(path, out=tmp_path / path.stem)
        assert sim.state_hash() == cli["state_hash"], path.name


def test_3d_particles_are_3_vectors_in_id_order(data):
    sim = grains.Simulation.from_file(data / "column3d_tiny.toml")
    sim.step(300)
    p = sim.particles()
    n = len(p)
    assert n == 60 and np.array_equal(p.id, np.arange(n))
    for a in (p.position, p.velocity, p.omega, p.force, p.torque):
        assert a.shape == (n, 3) and a.dtype == np.float64
    for a in (p.radius, p.mass):
        assert a.shape == (n,)
    assert np.allclose(p.mass, 2500.0 * 4.0 / 3.0 * np.pi * p.radius**3, rtol=1e-12)
    ids = np.asarray(sim.view("id"))
    for name in ("position", "velocity", "omega", "force"):
        v = np.asarray(sim.view(name))
        assert v.shape == (n, 3) and not v.flags.writeable
        assert np.array_equal(v, getattr(p, name)[ids]), name
        del v
    del ids


def test_3d_set_takes_3_vectors_and_names_a_wrong_shape(data):
    sim = grains.Simulation.from_file(data / "column3d_tiny.toml")
    with pytest.raises(ValueError, match=r"values has shape \(2, 2\), expected \(2, 3\)"):
        sim.set("velocity", [0, 1], np.zeros((2, 2)))
    with pytest.raises(ValueError, match="values has dtype float32, expected float64"):
        sim.set("velocity", [0, 1], np.zeros((2, 3), dtype=np.float32))
    sim.set("velocity", np.array([7]), np.array([[1.0, 2.0, 3.0]]))
    assert np.array_equal(sim.particles().velocity[7], [1.0, 2.0, 3.0])
    n = len(sim.particles())
    with pytest.raises(ValueError, match=rf"force has shape \({n}, 2\), expected \({n}, 3\)"):
        sim.add_force(lambda s: np.zeros((n, 2)))
    with pytest.raises(ValueError, match=rf"torque has shape \({n},\), expected \({n}, 3\)"):
        sim.add_force(lambda s: (np.zeros((n, 3)), np.zeros(n)))


def test_a_constant_force_and_torque_give_the_analytic_motion_of_a_free_sphere(data):
    sim = grains.Simulation.from_file(data / "free_sphere.toml")
    p = sim.particles()
    m, r = p.mass[0], p.radius[0]
    inertia = 0.4 * m * r * r
    f = np.array([[1.0e-3, -2.0e-3, 3.0e-3]])
    t = np.array([[0.0, 4.0e-9, -1.0e-9]])
    seen = []

    def force(s):
        seen.append(s.particles().position.shape)
        return f, t

    sim.add_force(force)
    assert sim.run() == "completed"
    time = sim.time
    p = sim.particles()
    v0 = np.array([0.1, 0.0, -0.05])
    want = v0 * time + 0.5 * f[0] / m * time * time
    assert np.allclose(p.position[0], want, rtol=1e-12, atol=1e-15)
    assert np.allclose(p.velocity[0], v0 + f[0] / m * time, rtol=1e-12, atol=1e-15)
    assert np.allclose(p.omega[0], t[0] / inertia * time, rtol=1e-12, atol=1e-15)
    assert seen[0] == (1, 3)


def test_3d_contacts_are_3_vectors_along_and_across_the_branch(data):
    sim = grains.Simulation.from_file(data / "column3d_tiny.toml")
    sim.run()
    c = sim.contacts()
    assert set(c) == {"i", "j", "overlap", "normal_force", "tangential_force", "branch"}
    m = len(c["i"])
    assert m > 0 and np.all(c["overlap"] > 0)
    fn, ft, b = c["normal_force"], c["tangential_force"], c["branch"]
    assert fn.shape == ft.shape == b.shape == (m, 3)
    scale = np.abs(fn).max() * np.abs(b).max()
    assert np.allclose(np.cross(fn, b), 0.0, atol=1e-12 * scale)
    assert np.allclose(np.einsum("ij,ij->i", ft, b), 0.0, atol=1e-12 * scale)
    # Normal forces push the pair apart (on i, against the branch towards j), but for
    # the damping's pull on a few pairs coming apart.
    push = np.einsum("ij,ij->i", fn, b) < 0
    assert push.mean() > 0.8
    p = sim.particles()
    r = p.radius
    assert np.allclose(np.linalg.norm(b, axis=1), r[c["i"]] + r[c["j"]] - c["overlap"])


def test_a_3d_checkpoint_resumes_bitwise(data, tmp_path):
    sim = grains.Simulation.from_file(data / "column3d_tiny.toml")
    sim.step(500)
    sim.checkpoint(tmp_path / "ck")
    sim.run()
    again = grains.Simulation.resume(tmp_path / "ck")
    assert again.dim == 3 and again.steps == 500
    assert again.run() == "completed"
    assert again.state_hash() == sim.state_hash()
    cli = grains.run(data / "column3d_tiny.toml", out=tmp_path / "cli")
    assert again.state_hash() == cli["state_hash"]


def test_a_3d_run_writes_what_the_command_line_writes(data, tmp_path):
    sim = grains.Simulation.from_file(data / "column3d_tiny.toml")
    sim.run()
    sim.write(tmp_path / "out")
    out = tmp_path / "out"
    s = json.loads((out / "summary.json").read_text())
    assert s["state_hash"] == sim.state_hash() and s["dimensions"] == 3
    for f in ["history.csv", "plots/particles_side.png", "plots/particles_top.png"]:
        assert (out / f).is_file(), f
    h = sim.history()
    assert "floor_fz" in h and len(h["time"]) > 1
