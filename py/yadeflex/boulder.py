"""Boulders: a sphere, a cube (a clump of spheres) or a clump from member spheres, placed and set
moving (yadeflex.scene_impact's Boulder, the damping module's add_boulder); its material."""
import math

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import Body, Sphere, FrictMat

from .grains import _sphere_body


def boulder_material(density, label="boulder"):
    """The boulder's material (concrete or rock against steel and grains): contact modulus 3 GPa,
    Poisson 0.2, friction 35 deg, `density` [kg/m3]; appended to O.materials."""
    mat = FrictMat(young=3e9, poisson=0.2, density=density, frictionAngle=math.radians(35), label=label)
    O.materials.append(mat)
    return mat


def make_boulder(shape, size, mass, mat, x, y, bottom, velocity):
    """A boulder of `shape` ('sphere': one sphere of diameter `size` [m], its mass from mat's
    density; 'cube': a clump of 4 x 4 x 4 spheres filling a cube of side `size`, of mass `mass`
    [kg] with a solid cube's inertia; or a list of (x, y, z, r) member spheres [m], relative to
    the boulder's centre, clumped, of mass `mass` with the inertia YADE computes for the
    members, scaled to that mass), centred on (x, y), its lowest point at z = bottom, moving at
    `velocity` [m/s]. Returns its body id (the clump's for a clump)."""
    if shape == "sphere":
        r = 0.5 * size
        bid = _sphere_body(Vector3(x, y, bottom + r), r, mat)
        O.bodies[bid].state.vel = velocity
        return bid
    if shape == "cube":
        n = 4  # member spheres per side: radius s/(2n), centres on a grid inset by that radius
        r = size / (2 * n)
        members = []
        for i in range(n):
            for j in range(n):
                for k in range(n):
                    c = Vector3(x - size / 2 + r + 2 * r * i, y - size / 2 + r + 2 * r * j, bottom + r + 2 * r * k)
                    b = Body()
                    b.shape = Sphere(radius=r * 1.0)
                    b.material = mat
                    b.state.pos = c
                    members.append(b)
        cid = O.bodies.appendClumped(members)[0]
        cl = O.bodies[cid]
        cl.state.mass = mass
        cl.state.inertia = Vector3(1, 1, 1) * mass * size * size / 6
        cl.aspherical = False  # isotropic inertia (a solid cube): the spherical rotation update is exact
        cl.state.vel = velocity
        return cid
    low = min(m[2] - m[3] for m in shape)
    members = []
    for mx, my, mz, mr in shape:
        b = Body()
        b.shape = Sphere(radius=mr)
        b.material = mat
        b.state.pos = Vector3(x + mx, y + my, bottom + (mz - low))
        members.append(b)
    cid = O.bodies.appendClumped(members)[0]
    cl = O.bodies[cid]
    scale = mass / cl.state.mass
    cl.state.mass = mass
    cl.state.inertia = cl.state.inertia * scale
    cl.state.vel = velocity
    return cid


def touches(bid):
    """Whether body bid (a clump: one of its members) has a real interaction."""
    b = O.bodies[bid]
    return any(i.isReal for m in (list(b.shape.members.keys()) if b.isClump else [bid]) for i in O.interactions.withBody(m))
