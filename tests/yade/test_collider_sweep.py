"""The collider's sweep (FlexBoundDispatcher, FlexNewtonIntegrator.sweepFloor): on a bed of grains
at rest, YADE's BoundDispatcher gives a zero sweep to every grain that did not move between two
bound updates, and the collider then runs as soon as such a grain moves at all (a grain dropped on
the bed sets them moving one by one). With the floor, each run needs some grain to travel the
smallest sweep first, and no contact is missed."""
import math
import random

import pytest
from yade import O, utils
from yade.minieigenHP import Vector3
from yade.wrapper import FrictMat

import yadeflex as yf


def _bed(n=343, seed=3):
    """n grains (radii 10-15 mm) dropped into a 0.25 m box of walls and settled with damping."""
    rnd = random.Random(seed)
    mat = FrictMat(young=1e7, poisson=0.3, density=2600, frictionAngle=math.radians(30), label="grains")
    O.materials.append(mat)
    L = 0.25
    for axis, pos, sense in ((2, 0, 1), (0, 0, 1), (0, L, -1), (1, 0, 1), (1, L, -1)):
        O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))
    k = round(n ** (1 / 3))
    s = L / k
    for i in range(n):
        x, y, z = i % k, (i // k) % k, i // (k * k)
        O.bodies.append(utils.sphere(((x + 0.5) * s, (y + 0.5) * s, 0.02 + (z + 0.5) * s), rnd.uniform(0.010, 0.015), material=mat))
    O.engines = yf.engines(damping=0.4)
    O.dt = 0.5 * yf.critical_timestep()
    O.engines[-3].dead = True  # flexDt: the step held, so that both runs below take the same steps
    for _ in range(60):
        O.run(100, True)
        if max(b.state.vel.norm() for b in _grains()) < 0.02:
            break
    O.engines[-1].damping = 0.0


def _grains():
    return [b for b in O.bodies if b is not None and type(b.shape).__name__ == "Sphere"]


def _missed():
    """Pairs of overlapping grains the collider did not give an interaction (every pair checked; a
    pair that began to overlap in this step's integrator becomes real in the next step's loop)."""
    g = _grains()
    out = []
    for i, a in enumerate(g):
        for b in g[i + 1:]:
            if (a.state.pos - b.state.pos).norm() < a.shape.radius + b.shape.radius:
                if O.interactions[a.id, b.id] is None:
                    out.append((a.id, b.id))
    return out


def _run(floor, steps):
    O.loadTmp("drop")
    newton = next(e for e in O.engines if e.label == "newton")
    col = next(e for e in O.engines if e.label == "collider")
    newton.sweepFloor = floor
    O.step()  # the dispatcher put in place (or back) for the runs below
    runs0, vmax, missed = col.numAction, 0.0, []
    for k in range(steps):
        O.step()
        vmax = max(vmax, max(b.state.vel.norm() for b in _grains()))
        if k % 50 == 0:
            missed += _missed()
    return col.numAction - runs0, vmax, missed, col, newton


@pytest.mark.timeout(600)
def test_a_bed_at_rest_runs_the_collider_only_when_a_grain_travelled_the_smallest_sweep(scene):
    _bed()
    # a grain dropped onto the bed at rest at 1 m/s
    top = max(b.state.pos[2] + b.shape.radius for b in _grains())
    O.bodies.append(utils.sphere((0.125, 0.125, top + 0.03), 0.012, material=O.materials[0]))
    O.bodies[len(O.bodies) - 1].state.vel = Vector3(0, 0, -1.0)
    O.step()
    O.saveTmp("drop")
    steps = 1000
    yade_runs, _, _, col, newton = _run(False, steps)
    assert not newton.sweepFloorInPlace and type(col.boundDispatcher).__name__ == "BoundDispatcher"
    runs, vmax, missed, col, newton = _run(True, steps)
    assert newton.sweepFloorInPlace and type(col.boundDispatcher).__name__ == "FlexBoundDispatcher"
    assert not missed
    # between two runs some grain travels at least the smallest sweep, at most vmax dt per step
    min_sweep = col.minSweepDistFactor * col.verletDist
    bound = 1 + steps * vmax * O.dt / min_sweep
    assert runs <= bound, (runs, bound, vmax)
    # YADE's own dispatcher, on the same bed and steps, runs it past that bound (the defect)
    assert yade_runs > bound, (yade_runs, bound)
    print(f"collider runs in {steps} steps: {yade_runs} (BoundDispatcher), {runs} (FlexBoundDispatcher), bound {bound:.1f}")
