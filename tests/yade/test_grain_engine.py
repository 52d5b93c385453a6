"""FlexGrainEngine (yadeflex.engines(grains=...)) runs the grains' contacts on a neighbour list of
its own, with the law the interaction loop runs for two spheres: the same bed stepped with and
without it gives every sphere the same force and torque, the same energy terms and deep onsets
(to round-off: the two add a sphere's contacts in another order); a scene switched to it mid-run
carries its contacts' shear, rolling and crossing states over; the time step counts its pairs as
the collider's; a pour balances its energy as the loop does; bad settings are refused by name."""
import math
import random

import pytest
from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FrictMat, FlexTimeStepper, FlexSnapshot
import numpy as np

import yadeflex as yf
from yadeflex.grains import _sphere_body

DT, YOUNG, KS_OVER_KN, FRICTION_DEG, ROLL_K, ROLL_ETA = 1e-5, 1e8, 0.3, 30.0, 1.0, 0.1


def _bed(n=(7, 7, 5)):
    """Spheres of radii 9-11 mm, 20 mm apart with 1 mm of jitter (most touch their neighbours,
    some deep), moving at up to 0.3 m/s and turning at up to 30 rad/s."""
    rnd = random.Random(5)
    out = []
    for i in range(n[0]):
        for j in range(n[1]):
            for k in range(n[2]):
                c = [0.02 * i + rnd.uniform(-1e-3, 1e-3), 0.02 * j + rnd.uniform(-1e-3, 1e-3), 0.02 * k + rnd.uniform(-1e-3, 1e-3)]
                out.append((c, rnd.uniform(0.009, 0.011), [rnd.uniform(-0.3, 0.3) for _ in range(3)], [rnd.uniform(-30, 30) for _ in range(3)]))
    return out


def _law():
    return yf.contact_law()


def _scene(bed, free, friction_deg=FRICTION_DEG):
    O.reset()
    mat = FrictMat(young=YOUNG, poisson=KS_OVER_KN, density=2650, frictionAngle=math.radians(friction_deg), label="gravel")
    O.materials.append(mat)
    for c, r, v, w in bed:
        b = O.bodies[_sphere_body(Vector3(*c), r, mat)]
        if not free:
            b.state.blockedDOFs = "xyzXYZ"
        b.state.vel, b.state.angVel = Vector3(*v), Vector3(*w)
    return mat


def _engines(grains):
    O.engines = yf.engines(gravity=(0, 0, 0), rolling_stiffness=ROLL_K, rolling_friction=ROLL_ETA, verlet=0.002, grains=grains)
    O.engines[[e.label for e in O.engines].index("flexDt")].dead = True
    O.dt = DT
    O.trackEnergy = True


def _result(n):
    forces = [(O.forces.f(i), O.forces.t(i)) for i in range(n)]
    energy = dict(elastic=O.energy["flexContactElastic"], friction=O.energy["flexFriction"], rolling=O.energy["flexRolling"])
    return forces, energy, _law().deepOnsets


def _run(bed, free, engine, steps, friction_deg=FRICTION_DEG):
    mat = _scene(bed, free, friction_deg)
    _engines("gravel" if engine else None)
    O.run(steps, True)
    return _result(len(bed)), mat


def _force_gap(a, b):
    """Largest difference of a force or torque component between two results, and the largest force."""
    fmax = max(max(abs(x) for x in f) for f, _ in a)
    gap = max(max(abs(x - y) for x, y in zip(fa, fb)) for (fa, _), (fb, _) in zip(a, b))
    tgap = max(max(abs(x - y) for x, y in zip(ta, tb)) for (_, ta), (_, tb) in zip(a, b))
    return max(gap, tgap / 0.01), fmax  # torques over a lever of a grain radius


def _grain_pairs():
    return sum(1 for i in O.interactions if isinstance(O.bodies[i.id1].shape, type(O.bodies[i.id2].shape)))


@pytest.mark.parametrize("free", [False, True])
def test_engine_gives_the_loops_forces_and_energies(scene, free):
    bed = _bed()
    (loop, _), _ = _run(bed, free, False, 40), None
    (eng, _), _ = _run(bed, free, True, 40), None
    ge = O.engines[[e.label for e in O.engines].index("grainEngine")]
    assert ge.grains == len(bed) and ge.contacts > 0 and ge.pairs >= ge.contacts
    assert _grain_pairs() == 0  # no grain pair in O.interactions
    gap, fmax = _force_gap(loop[0], eng[0])
    assert gap <= 1e-12 * fmax, (gap, fmax)
    for k in ("elastic", "friction", "rolling"):
        assert eng[1][k] == pytest.approx(loop[1][k], rel=1e-12, abs=1e-15 * loop[1]["elastic"]), k
    assert loop[2] > 0 and eng[2] == loop[2]
    # one degree more friction moves the forces far past that tolerance (the comparison can fail)
    (other, _), _ = _run(bed, free, True, 40, FRICTION_DEG + 1), None
    assert _force_gap(loop[0], other[0])[0] > 1e-6 * fmax


def test_a_scene_switched_to_the_engine_keeps_its_contacts(scene):
    """20 steps in the loop, then 20 with the engine: the same as 40 in the loop. Starting the
    contacts anew instead (the scene's interactions cleared) is far off."""
    bed = _bed()
    (loop, _), _ = _run(bed, True, False, 40), None
    results = []
    for clear in (False, True):
        _scene(bed, True)
        _engines(None)
        O.run(20, True)
        real = O.interactions.countReal()
        if clear:
            O.interactions.clear()
        _engines("gravel")
        O.run(20, True)
        ge = O.engines[[e.label for e in O.engines].index("grainEngine")]
        assert ge.takenOver == (0 if clear else real) and ge.lostContacts == 0
        results.append(_result(len(bed)))
    gap, fmax = _force_gap(loop[0], results[0][0])
    assert gap <= 1e-12 * fmax, (gap, fmax)
    assert results[0][1]["friction"] == pytest.approx(loop[1]["friction"], rel=1e-12)
    assert _force_gap(loop[0], results[1][0])[0] > 1e-3 * fmax


def test_a_saved_scene_keeps_its_grain_contacts(scene):
    """Saved after 20 steps and loaded again, the scene steps on the same bit for bit: the
    contacts' states are saved with the engine. A new engine on the loaded scene (its states
    left behind) is far off."""
    bed = _bed()
    _scene(bed, True)
    _engines("gravel")
    O.run(20, True)
    O.saveTmp("grains")
    O.run(20, True)
    kept = _result(len(bed))
    O.loadTmp("grains")
    assert O.iter == 20 and _grain_pairs() == 0
    O.run(20, True)
    again = _result(len(bed))
    assert again[0] == kept[0] and again[1] == kept[1]
    O.loadTmp("grains")
    _engines("gravel")  # a new engine: no states
    O.run(20, True)
    gap, fmax = _force_gap(kept[0], _result(len(bed))[0])
    assert gap > 1e-3 * fmax


def test_the_snapshot_lists_the_grain_contacts(scene):
    """FlexSnapshot.contacts (the VTK frames' contacts) lists the engine's contacts as the loop's:
    the same pairs, forces and depths (spheres at constant velocities)."""
    bed = _bed()
    rows = []
    for engine in (False, True):
        _scene(bed, False)
        _engines("gravel" if engine else None)
        O.run(10, True)
        c = {k: np.frombuffer(v, dtype=np.int64 if k in ("id1", "id2") else np.float64) for k, v in FlexSnapshot().contacts().items()}
        key = {(int(a), int(b)): k for k, (a, b) in enumerate(zip(c["id1"], c["id2"]))}
        rows.append((c, key))
    (c0, k0), (c1, k1) = rows
    assert set(k0) == set(k1) and len(k0) > 100
    assert len(k1) == O.engines[[e.label for e in O.engines].index("grainEngine")].contacts
    fmax = np.abs(c0["normalForce"]).max()
    for pair, i in k0.items():
        j = k1[pair]
        for f in ("normalForce", "shearForce", "normal", "contactPoint", "end1", "end2"):
            a, b = c0[f].reshape(-1, 3)[i], c1[f].reshape(-1, 3)[j]
            scale = fmax if f.endswith("Force") else 1.0
            assert np.abs(a - b).max() <= 1e-12 * scale, (pair, f, a, b)
        assert abs(c0["penetrationDepth"][i] - c1["penetrationDepth"][j]) <= 1e-15


def test_time_step_counts_the_engines_pairs(scene):
    """Two touching spheres, one within reach of them and one far: the critical step is the same
    with the engine as with the collider's pairs (the same rows from the same pairs)."""
    crit = []
    for engine in (False, True):
        O.reset()
        mat = FrictMat(young=YOUNG, poisson=KS_OVER_KN, density=2650, frictionAngle=0.5, label="gravel")
        O.materials.append(mat)
        for x, r in ((0, 0.01), (0.0195, 0.01), (0.0398, 0.0099), (0.5, 0.01)):
            _sphere_body(Vector3(x, 0, 0), r, mat)
        O.engines = yf.engines(gravity=(0, 0, 0), rolling_stiffness=ROLL_K, rolling_friction=ROLL_ETA, grains="gravel" if engine else None)
        O.dt = 1e-7
        O.run(1, True)
        crit.append(FlexTimeStepper().critical())
    assert crit[1] == pytest.approx(crit[0], rel=1e-12)
    # and the engine's pairs do count: without them the step would be unbounded by contacts
    assert math.isfinite(crit[1])


def _drop(engine, dt=None):
    """400 grains poured from 0.05-0.23 m onto a floor of 12 x 12 fixed grains (1 mm apart), 0.25 s:
    the energy residual (O.energy.total(), gravity's work included) over gravity's work. Every
    contact is a grain contact: the balance is the law's and the integrator's alone."""
    O.reset()
    rnd = random.Random(2)
    mat = FrictMat(young=5e7, poisson=0.3, density=2650, frictionAngle=math.radians(35), label="gravel")
    O.materials.append(mat)
    for i in range(144):
        b = O.bodies[_sphere_body(Vector3(-0.143 + 0.026 * (i % 12), -0.143 + 0.026 * (i // 12), 0.0), 0.0125, mat)]
        b.state.blockedDOFs = "xyzXYZ"
    for i in range(400):  # 8 x 8 columns 30 mm apart, 1 mm of jitter: apart at the start
        x, y, z = -0.105 + 0.03 * (i % 8), -0.105 + 0.03 * (i // 8 % 8), 0.05 + 0.03 * (i // 64)
        _sphere_body(Vector3(x + rnd.uniform(-1e-3, 1e-3), y + rnd.uniform(-1e-3, 1e-3), z), rnd.uniform(0.008, 0.0135), mat)
    O.engines = yf.engines(rolling_stiffness=ROLL_K, rolling_friction=ROLL_ETA, grains="gravel" if engine else None)
    O.trackEnergy = True
    O.dt = 1e-6
    if dt:
        O.engines[[e.label for e in O.engines].index("flexDt")].dead = True
        O.dt = dt
    yf.step_until(0.25, 10**6)
    e = yf.energy_budget()
    return e["total"] / abs(e["gravWork"]), e, O.dt


def test_a_drop_balances_its_energy_as_the_loop_does(scene):
    """The same pour at the same step (4e-5 s, 0.57 of the critical one) through the engine and
    through the loop: the same energy residual to the scatter of two chaotic runs (the residual
    itself, about 1% of gravity's work, is the law's: the same on both paths, 0.93% and 0.97%
    when measured), and the grains slid and rolled on each other."""
    res_loop, e_loop, _ = _drop(False, 4e-5)
    res_eng, e_eng, _ = _drop(True, 4e-5)
    ge = O.engines[[e.label for e in O.engines].index("grainEngine")]
    assert ge.builds > 10 and ge.lostContacts == 0 and O.interactions.countReal() == 0
    assert e_eng["flexFriction"] > 0.2 * abs(e_eng["gravWork"]) and e_eng["flexRolling"] > 0.1 * abs(e_eng["gravWork"])
    assert abs(res_eng - res_loop) < 2e-3, (res_eng, res_loop)
    assert abs(res_eng) < 0.02 and abs(res_loop) < 0.02, (res_eng, res_loop)


def test_bad_settings_are_refused(scene):
    _scene(_bed((2, 2, 2)), True)
    with pytest.raises(ValueError, match="unknown material 'sand'"):
        yf.engines(grains="sand")
    with pytest.raises(ValueError, match="crush"):
        yf.engines(grains="gravel", crushing_is50=1e6)
    O.engines = yf.engines(grains="gravel")
    O.bodies[3].groupMask = 2
    with pytest.raises(ValueError, match="different groupMask"):
        O.step()
    O.bodies[3].groupMask = 1
    other = _sphere_body(Vector3(1, 1, 1), 0.01, FrictMat(young=1e8, density=2650, label="steel"))
    O.bodies[other].groupMask = 1 | (1 << 14)
    with pytest.raises(ValueError, match=f"body #{other} is not a grain"):
        O.step()
    O.bodies[other].groupMask = 1
    O.bodies[0].shape.radius = -0.01
    with pytest.raises(ValueError, match="radius"):
        O.step()
    O.bodies[0].shape.radius = 0.01
    O.engines = [O.engines[0]] + [e for e in O.engines[1:] if e.label != "grainEngine"][:2] + [e for e in O.engines if e.label == "grainEngine"] + [
        e for e in O.engines[1:] if e.label != "grainEngine"][2:]
    with pytest.raises(ValueError, match="must come before"):
        O.step()


def test_the_module_impact_runs_its_grains_in_the_engine(module_cache):
    """The reduced module's impact with ModuleParams.engines (FlexGrainEngine) against the same
    impact with the grain-grain contacts in the interaction loop, 400 steps after the boulder
    touches, at one fixed step (FlexTimeStepper re-estimates the step when the engine rebuilds its
    list, the loop's path when the collider runs: the step would change at other iterations): the
    same boulder velocity, grain positions and energy to the round-off of sums in another order."""
    from yadeflex.module import ModuleParams, add_boulder, filled_module
    out = []
    for engine in (False, True):
        O.reset()
        p = ModuleParams.small()
        ids, _, _ = filled_module(p, cache_dir=module_cache)
        bid = add_boulder(p, ids)
        O.engines = p.engines(0.0) if engine else p.engines(0.0, grain_engine=False)
        O.engines[[e.label for e in O.engines].index("flexDt")].dead = True
        O.dt = 8e-6  # (about half the critical step, as the module's own)
        O.trackEnergy = True
        while O.forces.f(bid).norm() == 0:
            O.run(50, True)
        v_touch = O.bodies[bid].state.vel.norm()
        O.run(400, True)
        grains = [g for g in ids["grains"] if O.bodies[g] is not None]
        out.append((O.iter, O.bodies[bid].state.vel, [O.bodies[g].state.pos for g in grains], O.energy.total(), yf.grain_engine(), v_touch))
    (it0, v0, x0, e0, ge0, vt0), (it1, v1, x1, e1, ge1, _) = out
    assert ge0 is None and ge1 is not None and ge1.takenOver > 50 and ge1.lostContacts == 0 and ge1.contacts > 50
    assert it0 == it1 and v0.norm() < 0.99 * vt0  # (the grains have slowed the boulder down)
    assert (v1 - v0).norm() <= 1e-9 * v0.norm(), (v0, v1)
    assert max((a - b).norm() for a, b in zip(x0, x1)) <= 1e-12
    assert abs(e1 - e0) <= 1e-9 * abs(e0) + 1e-9


def test_two_threads_give_the_forces_of_one():
    """The engine's step on two threads (each a part of the pairs, force sums of its own added in
    thread order) gives every sphere the force and torque of one thread, to round-off, and the
    same energy terms (1960 falling spheres, 30 steps)."""
    import json
    import os
    from conftest import run_yade
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scripts", "grain_engine_threads.py")
    one, two = (json.loads([s for s in run_yade(script, threads=j).splitlines() if s.startswith("GRAINS ")][-1][7:]) for j in (1, 2))
    assert one["threads"] == 1 and two["threads"] == 2 and one["contacts"] > 1000 and two["contacts"] == one["contacts"]
    scale = max(abs(x) for row in one["ft"] for x in row[:3])
    diff = max(abs(a - b) for ra, rb in zip(one["ft"], two["ft"]) for a, b in zip(ra[:3], rb[:3]))
    tdiff = max(abs(a - b) for ra, rb in zip(one["ft"], two["ft"]) for a, b in zip(ra[3:], rb[3:]))
    assert diff <= 1e-12 * scale and tdiff <= 1e-12 * scale * 0.011, (diff, tdiff, scale)
    for k, v in one["energy"].items():
        assert two["energy"][k] == pytest.approx(v, rel=1e-12), k
