"""The worked examples (examples/*.py), each at a reduced size, run in this process as a user
runs them (their command line), their results checked against physics: the energy balance, the
supports' loads against the forces on the boulder, grains kept inside their containers."""
import json
import os
import sys

import pytest
from yade import O

from conftest import REPO

EXAMPLES = os.path.join(REPO, "examples")


def run_example(name, *args):
    """examples/NAME.py with args on its command line; returns (exit status, the globals it left)."""
    argv, path = sys.argv, os.path.join(EXAMPLES, name)
    sys.argv = [path, *map(str, args)]
    g = dict(__name__="example", __file__=path)
    try:
        with open(path) as fh:
            exec(compile(fh.read(), path, "exec"), g)
        code = 0
    except SystemExit as e:
        code = e.code
    finally:
        sys.argv = argv
    return code, g


def summary(out):
    return json.loads((out / "summary.json").read_text())


def test_tecco_punch(scene, tmp_path):
    """A 1 m panel punched by a 100 kg sphere at 5 m/s: the panel holds it and its edges take
    the force on the boulder (the panel's own mass, 2 kg against 100, barely adds inertia)."""
    code, _ = run_example("tecco_punch.py", "--size", 1.0, "--mass", 100, "--speed", 5, "--out", tmp_path / "out")
    s = summary(tmp_path / "out")
    assert code == 0 and s["status"] == "done" and s["rebound"], s
    assert s["energy_residual_max_fraction"] < 0.01
    assert s["reaction_edges_max"] == pytest.approx(s["peak_impact_force"], rel=0.1)
    assert s["broken_elements_total"] == 0
    assert (tmp_path / "out" / "vtk" / "flex.pvd").exists() and (tmp_path / "out" / "impact.png").exists()


def test_drapery(scene, tmp_path):
    """A 1 x 2 m drapery: the boulder released under it rolls out at its foot, the anchors hold."""
    code, g = run_example("drapery.py", "--width", 1.0, "--length", 2.0, "--out", tmp_path / "out", "--no-vtk")
    s = summary(tmp_path / "out")
    assert code == 0 and s["status"] == "done", s
    assert s["energy_residual_max_fraction"] < 0.01
    assert s["reaction_anchors_max"] > 0
    stone = O.bodies[g["stone"]].state
    assert (stone.pos - g["on_slope"](0.0, g["a"].length - 1.0, g["r"])).dot(-g["up"]) > g["a"].length - 1.0  # below the panel's foot


def test_gabion(scene, tmp_path):
    """A 0.5 x 0.5 x 0.3 m gabion: no stone escapes through the laced panels (each stays within
    the panels' nodes as they bulge), the ground carries at least the weight of block, stones
    and mesh at the peak."""
    code, g = run_example("gabion.py", "--size", 0.5, 0.5, 0.3, "--out", tmp_path / "out", "--no-vtk")
    s = summary(tmp_path / "out")
    assert code == 0 and s["status"] == "done", s
    assert s["energy_residual_max_fraction"] < 0.01
    nodes = [O.bodies[n].state.pos for p in g["panels"] for n in p["nodes"].values()]
    lo = [min(p[k] for p in nodes) for k in range(3)]
    hi = [max(p[k] for p in nodes) for k in range(3)]
    for i in g["fill"].grains:
        p = O.bodies[i].state.pos
        assert all(lo[k] < p[k] < hi[k] for k in range(3)), (i, p, lo, hi)
    weight = sum(b.state.mass for b in O.bodies if b is not None and b.dynamic and not b.isClumpMember) * 9.81
    assert s["reaction_ground_max"] > weight


def test_geotextile_bag(scene, tmp_path):
    """A 0.4 x 0.3 x 0.3 m bag: no grain leaves the closed fabric, before or after the block."""
    code, g = run_example("geotextile_bag.py", "--size", 0.4, 0.3, 0.3, "--out", tmp_path / "out", "--no-vtk")
    s = summary(tmp_path / "out")
    assert code == 0 and s["status"] == "done", s
    assert s["energy_residual_max_fraction"] < 0.01
    nodes = [O.bodies[n].state.pos for n in g["bag"]["nodes"] if n >= 0]
    lo = [min(p[k] for p in nodes) for k in range(3)]
    hi = [max(p[k] for p in nodes) for k in range(3)]
    for i in g["fill"].grains:
        p = O.bodies[i].state.pos
        assert all(lo[k] < p[k] < hi[k] for k in range(3)), (i, p, lo, hi)
    assert s["broken_elements_total"] == 0


def test_cushion_of_three_modules(scene, tmp_path, module_cache):
    """Three reduced modules tied by the rope: the rope carries load, the energy closes."""
    code, _ = run_example("cushion.py", "--small", "--cache-dir", module_cache, "--out", tmp_path / "out", "--no-vtk")
    s = summary(tmp_path / "out")
    assert code == 0 and s["status"] == "done" and s["n_modules"] == 3, s
    assert s["rope_force_max"] > 0 and s["energy_residual_max_fraction"] < 0.02


def test_the_docs_example_runs_as_written(scene, tmp_path):
    """docs/structures.md's first Python block, run as written (its results folder here): a
    filled bag hit by a block; no grain leaves the bag, the energy closes."""
    text = open(os.path.join(REPO, "docs", "structures.md")).read()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    assert '"out/mine"' in code
    g = {}
    exec(compile(code.replace('"out/mine"', repr(str(tmp_path / "mine"))), "docs/structures.md", "exec"), g)
    s = g["s"]
    assert s["status"] == "done" and s["exit_status"] == 0, s
    assert s["energy_residual_max_fraction"] < 0.01 and s["reaction_ground_max"] > 0
    nodes = [O.bodies[n].state.pos for n in g["bag"]["nodes"] if n >= 0]
    for i in g["fill"].grains:
        p = O.bodies[i].state.pos
        assert all(min(q[k] for q in nodes) < p[k] < max(q[k] for q in nodes) for k in range(3)), (i, p)
