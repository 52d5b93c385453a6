# Where an impact's energy residual comes from, contact by contact (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/contact_audit.py [--velocity 11] [--mass 300] [--t-end 0.03]
#                                                [--frictionless] [--label NAME]
#
# The scene: the tearing impact of tests/yade/test_module.py (the reduced module, its lining at
# its own mass, a 300 kg cube at 11 m/s, no damping, the default time step), loaded with
# yadeflex.module.impact_start. From the boulder's first contact on, after every step, each
# FlexContactGeom that carried a force at this step or the last is audited on its NORMAL spring:
#     e = U(n+1) - U(n) + 1/2 (F(n) + F(n+1)) . relVel(n+1) dt
# U = |F_spring|^2 / (2 kn) the spring's energy, F the normal force on side 2 (the spring's and the
# crossing correction's), relVel the velocity of side 2 relative to side 1 at the contact point,
# read at step n+1 (the mid-step velocity of the leap-frog scheme). For a linear spring whose
# overlap changes as the velocities say (d overlap / dt = -n . relVel) e is zero at every step
# (the scheme integrates the trapezoid exactly); e > 0 is energy the contact put into the bodies
# beyond what its spring gave up. The sums go by contact class (Sphere-FlexFacet, ...), by overlap
# band (overlap / reach, reach the sum of the contact radii: 1 is a wire whose axis reaches the
# facet's midplane) and by event: carried on, started (onset), ended (inactive, separated or handed
# over) and erased with a broken element. The shear spring is left out (with friction, its work
# is the friction's); --frictionless sets every friction angle to 0 so that the audit covers the
# whole contact force. The scan runs in Python over all interactions (a few ms per step on the
# reduced module). Prints a table; appends rows to bench/results/contact_audit.csv.
import collections
import os
import sys

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("contact_audit.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import tearing_scene  # noqa: E402
from machine import machine_line  # noqa: E402

BANDS = ((0.0, 0.5, "below 0.5"), (0.5, 1.0 - 1e-9, "0.5 to 1"), (1.0 - 1e-9, 1.0 + 1e-9, "1 (axis on the midplane)"), (1.0 + 1e-9, float("inf"), "above 1"))
COLS = ("label", "velocity_m_s", "frictionless", "cls", "band", "event", "step_contacts", "energy_J")


def band(ratio):
    return next(name for lo, hi, name in BANDS if lo <= ratio < hi)


def main():
    a = tearing_scene.options("contact_audit.py", 11.0, os.path.join(BENCH, "results", "contact_audit.csv"))
    from yade import O
    kind = tearing_scene.start(a)
    O.trackEnergy = True
    O.energy.clear()
    O.step()  # (the balance from this step on, as the main job's)

    def carried():
        """{(id1, id2): (normal force on side 2, spring energy, overlap ratio)} of the contacts carrying a force now."""
        out = {}
        for i, g, ph in tearing_scene.carrying(O.interactions):
            spring = ph.normalForce.norm()
            cross = g.crossForce - spring if g.crossIter == O.iter else 0.0
            held = 0.5 * ph.kn * max(0.0, g.penetrationDepth - g.plasticOverlap) ** 2 if getattr(g, "pierced", False) else 0.5 * spring * spring / ph.kn  # (pierced: no force, see FlexContactGeom.pierced)
            out[(i.id1, i.id2)] = (ph.normalForce + cross * g.normal, held, g.penetrationDepth / (g.refR1 + g.refR2))
        return out

    energy, count = collections.Counter(), collections.Counter()
    total0 = O.energy.total()
    prev = carried()
    t0 = O.time
    while O.time - t0 < a.t_end:
        dt = O.dt
        O.step()
        now = carried()
        for key in set(prev) | set(now):
            F0, U0, r0 = prev.get(key, (None, 0.0, 0.0))
            F1, U1, r1 = now.get(key, (None, 0.0, 0.0))
            try:
                I = O.interactions[key[0], key[1]]
            except IndexError:
                I = None
            if I is None or I.geom is None:
                event, work = "erased with a broken element", 0.0
            else:
                Fsum = (F0 if F0 is not None else 0 * I.geom.relVel) + (F1 if F1 is not None else 0 * I.geom.relVel)
                work = 0.5 * Fsum.dot(I.geom.relVel) * dt
                event = "carried on" if F0 is not None and F1 is not None else ("onset" if F0 is None else "ended")
            cls = "-".join(sorted(kind.get(k, "?") for k in key))
            row = (cls, band(max(r0, r1)), event)
            energy[row] += U1 - U0 + work
            count[row] += 1
        prev = now
    residual = O.energy.total() - total0
    e_impact = 0.5 * a.mass * a.velocity ** 2
    print(f"\ncontact energy audit ({a.label}): {a.mass:g} kg at {a.velocity:g} m/s on the reduced module, lining at its own mass, "
          f"{'frictionless, ' if a.frictionless else ''}{1e3 * a.t_end:g} ms from the first contact")
    print(f"energy residual {residual:+.1f} J ({100 * residual / e_impact:+.2f}% of {e_impact:.0f} J); audited contacts "
          f"{sum(energy.values()):+.1f} J (normal springs{'' if a.frictionless else ', shear left out'})")
    print(f"{'class':28s} {'overlap / reach':26s} {'event':30s} {'step-contacts':>14s} {'energy J':>10s}")
    rows = []
    for row in sorted(energy, key=lambda r: -abs(energy[r])):
        if abs(energy[row]) < 0.05:
            continue
        print(f"{row[0]:28s} {row[1]:26s} {row[2]:30s} {count[row]:14d} {energy[row]:+10.1f}")
        rows.append(dict(label=a.label, velocity_m_s=a.velocity, frictionless=int(a.frictionless), cls=row[0], band=row[1], event=row[2],
                         step_contacts=count[row], energy_J=round(energy[row], 3)))
    rows.append(dict(label=a.label, velocity_m_s=a.velocity, frictionless=int(a.frictionless), cls="(all)", band="(all)",
                     event="energy residual of the run", step_contacts=0, energy_J=round(residual, 3)))
    tearing_scene.append_rows(a.out, COLS, rows)
    with open(os.path.splitext(a.out)[0] + "_machine.txt", "w") as f:
        f.write(machine_line() + "\n")


if __name__ == "__main__":
    main()
