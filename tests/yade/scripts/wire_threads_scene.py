# Run by test_wire.py in yade-double with -j1 / -j2: a distorted TECCO mesh panel pulled
# apart. Prints one ROW per link: id, drawn slack (repr, compared bitwise) and axial force.
#   wire_threads_scene.py TIME PARALLEL   TIME: simulated time [s] (the top edge moves at 4 m/s);
#   PARALLEL=1: element loop and integrator on all
#   threads even for this small scene (default: serial below their parallelMin)
import sys

from yade import O

from yadeflex.harness import tensile

T = float(sys.argv[1]) if len(sys.argv) > 1 else 4.8e-3
parallel = len(sys.argv) > 2 and sys.argv[2] == "1"
s = tensile.mesh_panel_scene(width=0.5, height=0.5, seed=31, speed=4.0)
O.trackEnergy = True
for e in O.engines:
    if parallel and type(e).__name__ in ("FlexElementEngine", "FlexNewtonIntegrator"):
        e.parallelMin = 1
while O.time < T:
    O.step()
print("ENERGY", repr(O.energy["flexBondPlastic"]), next(e for e in O.engines if e.label == "flexElements").nRuptured)
for c in s["cylinders"]:
    b = O.bodies[c]
    print("ROW", c, repr(b.shape.wireSlack) if b else "broken", repr(b.shape.axialForce) if b else "0.0")
