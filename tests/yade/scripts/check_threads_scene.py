"""The scene check's refusals on a scene big enough for its parallel pass (2000 bodies and more):
2500 spheres and a chain of cylinders, corrupted in turn in ways that each refuse one body (a
negative radius, a NaN velocity, a bad material first used in the second half of the ids, two
problems at once: the smaller id must be named, a bad element node), each time the message of
the ValueError O.step() raises, printed as JSON after 'MSG '.
Run: yade-double -n -jN -x check_threads_scene.py"""
import json
import math

from yade import O, Vector3
from yade.wrapper import FrictMat

import yadeflex as yf
from yadeflex.module import _sphere_body


def build():
    O.reset()
    mat = FrictMat(young=1e8, poisson=0.3, density=2650, frictionAngle=0.6, label="grains")
    O.materials.append(mat)
    ids = [_sphere_body(Vector3(0.05 * (k % 50), 0.05 * (k // 50), 0.0), 0.01, mat) for k in range(2500)]
    wire = yf.steel()
    nodes, cyls = yf.chain([(0, -1, 0.5), (1, -1, 0.5), (2, -1, 0.5)], 0.002, wire)
    O.engines = yf.engines(gravity=(0, 0, -9.81), damping=0.0, timestep_safety=0.5)
    O.dt = 1e-6
    O.step()
    return ids, cyls


def refused(corrupt):
    ids, cyls = build()
    corrupt(ids, cyls)
    try:
        O.step()
    except ValueError as e:
        return str(e)
    return None


def bad_material(ids, cyls):
    late = FrictMat(young=-1.0, poisson=0.3, density=2650, frictionAngle=0.6, label="late")
    O.materials.append(late)
    for k in ids[1800:1805]:
        O.bodies[k].material = late


def two_problems(ids, cyls):
    O.bodies[ids[2400]].shape.radius = 0.0
    O.bodies[ids[1000]].state.vel = Vector3(0, math.inf, 0)


def bad_node(ids, cyls):
    O.bodies[cyls[0]].shape.node2 = ids[10]


cases = dict(
    radius=lambda ids, cyls: setattr(O.bodies[ids[2000]].shape, "radius", -0.01),
    velocity=lambda ids, cyls: setattr(O.bodies[ids[300]].state, "vel", Vector3(float("nan"), 0, 0)),
    material=bad_material,
    two=two_problems,
    node=bad_node,
    none=lambda ids, cyls: None,
)
print("MSG " + json.dumps({k: refused(f) for k, f in cases.items()}), flush=True)
