"""A bed of 1960 overlapping spheres (14 x 14 x 10, radii 9-11 mm, 20 mm apart, seeded): more
than 4096 interactions and about 1,000 contacts after one step, spread over the whole container.
For the scripts that check engines' passes on several threads."""
import random

from yade import O
from yade.wrapper import FrictMat
from yade import Vector3

from yadeflex.module import _sphere_body


def sphere_bed():
    """O reset and filled with the bed; returns the number of spheres."""
    random.seed(3)
    O.reset()
    mat = FrictMat(young=1e8, poisson=0.3, density=2650, frictionAngle=0.6)
    O.materials.append(mat)
    n = 0
    for i in range(14):
        for j in range(14):
            for k in range(10):
                r = random.uniform(0.009, 0.011)
                x = Vector3(0.02 * i + random.uniform(-1e-3, 1e-3), 0.02 * j + random.uniform(-1e-3, 1e-3), 0.02 * k + 0.011)
                _sphere_body(x, r, mat)
                n += 1
    return n
