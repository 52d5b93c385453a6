# Single TECCO wire (d = 3 mm) pulled to rupture with one unload-reload cycle, displacement
# controlled; writes validation/tensile/wire.{csv,png,json}.
#   YADE_PREFIX=... PYTHONPATH=py yade-double -n -j1 -x scripts/tensile_wire.py [OUTDIR]
import math
import sys

from yade import O

from yadeflex import wire

from yadeflex.harness import tensile

out = sys.argv[1] if len(sys.argv) > 1 else "validation/tensile"
mat = wire.tecco_wire(slack_scale=0.0)
A = math.pi * 0.0015 ** 2
s = tensile.single_wire(mat, length=0.1)
O.trackEnergy = True
path = [0.015, 0.008, 0.03, 0.02, wire.TECCO_WIRE_STRAIN[-1] * 1.01]
e, f, _ = tensile.drive_strains(s, path, steps_per_unit_strain=4e4)
worst, emax = 0.0, [max(e[: i + 1]) for i in range(len(e))]
on_curve = [i for i in range(len(e)) if f[i] is not None and e[i] >= emax[i]]  # loading steps
for ek, sk in zip(wire.TECCO_WIRE_STRAIN, wire.TECCO_WIRE_STRESS):
    k = min(on_curve, key=lambda i: abs(e[i] - ek))
    worst = max(worst, abs(f[k] - sk * A) / (sk * A))
print(f"knots: worst force error {worst:.2e}; ruptured {next(e for e in O.engines if e.label == 'flexElements').nRuptured}; "
      f"plastic {O.energy['flexBondPlastic']:.4f} J, rupture {O.energy['flexRupture']:.4f} J")
tensile.write_curve(out + "/wire", dict(elongation=e, force=[x / 1e3 if x is not None else None for x in f]),
                    "strain [-]", "force [kN]", "TECCO wire d = 3 mm: curve, cycle, rupture", y="force",
                    reference={f"input point {k}": (ek, sk * A / 1e3) for k, (ek, sk) in enumerate(zip(wire.TECCO_WIRE_STRAIN, wire.TECCO_WIRE_STRESS))},
                    params=dict(path=path, curve_strain=list(mat.wireStrain), curve_stress=list(mat.wireStress)))
