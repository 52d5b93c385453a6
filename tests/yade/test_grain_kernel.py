"""The grains' kernel on arrays of its own (pkg/kernel/GrainNeighbours, GrainContacts; driver
bench/grain_kernel.cpp) computes the plugin's sphere-sphere law: the same bed of overlapping
spheres, stepped by our engines in YADE and by the kernel, gives every sphere the same force and
torque, the same energy terms and the same count of deep onsets; the spheres moving at constant
velocities and angular velocities (every DOF blocked), or free (leap-frog, no gravity). The two
add a body's contacts in another order (pair order against the interaction container's), so the
sums agree to round-off, not bit for bit; free spheres carry that round-off into their motion
(8e-15 of the largest force after 40 steps, 8e-14 after 100, measured)."""
import math
import os
import random
import subprocess

import pytest
from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FrictMat

import yadeflex as yf
from yadeflex.grains import _sphere_body

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
BINARY = os.path.join(os.environ.get("BUILD_DIR", os.path.join(REPO, "build")), "grain_kernel_bench")
DT, STEPS, YOUNG, KS_OVER_KN, FRICTION_DEG, ROLL_K, ROLL_ETA = 1e-5, 40, 1e8, 0.3, 30.0, 1.0, 0.1


def _bed():
    """7 x 7 x 5 spheres of radii 9-11 mm, 20 mm apart with 1 mm of jitter (most touch their
    neighbours, some deep), moving at up to 0.3 m/s and turning at up to 30 rad/s."""
    rnd = random.Random(5)
    out = []
    for i in range(7):
        for j in range(7):
            for k in range(5):
                c = [0.02 * i + rnd.uniform(-1e-3, 1e-3), 0.02 * j + rnd.uniform(-1e-3, 1e-3), 0.02 * k + rnd.uniform(-1e-3, 1e-3)]
                out.append((c, rnd.uniform(0.009, 0.011), [rnd.uniform(-0.3, 0.3) for _ in range(3)], [rnd.uniform(-30, 30) for _ in range(3)]))
    return out


def _plugin(bed, free, steps):
    O.reset()
    mat = FrictMat(young=YOUNG, poisson=KS_OVER_KN, density=2650, frictionAngle=math.radians(FRICTION_DEG))
    O.materials.append(mat)
    for c, r, v, w in bed:
        b = O.bodies[_sphere_body(Vector3(*c), r, mat)]
        if not free:
            b.state.blockedDOFs = "xyzXYZ"  # constant velocities: both codes move the spheres the same way
        b.state.vel, b.state.angVel = Vector3(*v), Vector3(*w)
    O.engines = yf.engines(gravity=(0, 0, 0), rolling_stiffness=ROLL_K, rolling_friction=ROLL_ETA, verlet=0.002)
    for e in O.engines:
        if e.label == "flexDt":
            e.dead = True
    O.dt = DT
    O.trackEnergy = True
    O.run(steps, True)
    law = [f for e in O.engines if e.label == "interactionLoop" for f in e.lawDispatcher.functors if f.label == "flexLaw"][0]
    forces = [(O.forces.f(i), O.forces.t(i)) for i in range(len(bed))]
    energy = dict(elastic=O.energy["flexContactElastic"], friction=O.energy["flexFriction"], rolling=O.energy["flexRolling"])
    return forces, energy, law.deepOnsets, O.interactions.countReal()


def _kernel(bed, tmp_path, free, steps):
    path = tmp_path / "bed.txt"
    path.write_text("".join(" ".join(repr(float(x)) for x in (*c, r, *v, *w)) + "\n" for c, r, v, w in bed))
    opts = {"compare": 2 if free else 1, "steps": steps, "density": 2650, "dt": DT, "young": YOUNG, "ks-over-kn": KS_OVER_KN, "tan-phi": math.tan(math.radians(FRICTION_DEG)),
            "rolling-stiffness": ROLL_K, "rolling-friction": ROLL_ETA, "skin": 0.002}
    out = subprocess.run([BINARY, str(path)] + [x for k, v in opts.items() for x in (f"--{k}", repr(float(v)))], capture_output=True, text=True, check=True)
    forces, energy = {}, None
    for line in out.stdout.splitlines():
        f = line.split()
        if f[0] == "GK_FORCE":
            forces[int(f[1])] = ([float(x) for x in f[2:5]], [float(x) for x in f[5:8]])
        elif f[0] == "GK_ENERGY":
            energy = dict(elastic=float(f[1]), friction=float(f[2]), rolling=float(f[3])), int(f[4])
    return [forces[i] for i in range(len(bed))], energy


@pytest.mark.parametrize("free", [False, True])
def test_kernel_gives_the_plugins_forces_and_energies(scene, tmp_path, free):
    assert os.path.exists(BINARY), f"{BINARY}: built by scripts/setup"
    bed = _bed()
    ours, energy, deep, real = _plugin(bed, free, STEPS)
    kern, (kenergy, kdeep) = _kernel(bed, tmp_path, free, STEPS)
    scale = max(max(abs(x) for x in f) for f, _ in ours)
    tscale = max(max(abs(x) for x in t) for _, t in ours)
    assert real > 150 and scale > 0 and tscale > 0  # (contacts, sliding and rolling under way; free: the bed flies apart)
    for i, ((f, t), (kf, kt)) in enumerate(zip(ours, kern)):
        # one body's contacts summed in another order: round-off of a few terms of size `scale`
        assert max(abs(f[a] - kf[a]) for a in range(3)) <= 1e-12 * scale, (i, f, kf)
        assert max(abs(t[a] - kt[a]) for a in range(3)) <= 1e-12 * tscale, (i, t, kt)
    for k in ("elastic", "friction", "rolling"):
        assert energy[k] > 0
        assert kenergy[k] == pytest.approx(energy[k], rel=1e-12), k
    assert kdeep == deep and deep > 0  # (built overlapping: the first contacts start deep)
