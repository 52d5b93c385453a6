# Energy balance and contact count of a rigid boulder on bare chain-link mesh (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/punch_energy.py [--t-end 0.11] [--cases normal,stiff,...]
#
# The scene (yadeflex.harness.scenes.mesh_punch): a 2 x 2 m TECCO G65/3 panel, every edge node held (or a
# rope edge held at the corners), hit at its centre by a rigid 300 kg sphere of radius 0.3 m at
# 4 m/s, no damping, time step 0.5 x the critical one. Per case: the largest |residual| of the
# energy balance over the run (O.energy.total() against its value after the first step) as a
# share of the impact energy, the active contacts on the boulder (median and largest, sampled
# every 20 steps while in contact), the samples in contact with no force on the boulder, the
# hand-over ledger (contacts that started or ended at a finite overlap, and their spring
# energy), the elements broken. Prints a table and writes bench/results/punch_energy.csv.
import argparse
import csv
import os
import statistics
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if os.path.basename(a) == "punch_energy.py"), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O  # noqa: E402

import yadeflex as yf  # noqa: E402
from yadeflex.harness import scenes  # noqa: E402
from machine import machine_line  # noqa: E402

BASE = dict(size=2.0, boulder_mass=300.0, boulder_radius=0.3, velocity=(0, 0, -4.0), timestep_safety=0.5)
CASES = {
    "normal": dict(),
    "stiff": dict(contact_young=2e10),             # the damping module's steel contact modulus
    "oblique": dict(velocity=(2.0, 1.0, -3.5)),
    "bar_links": dict(wire="bar"),                 # tecco_wire(bending_factor=0)
    "rope_edge": dict(edge="rope"),
    "rupture": dict(velocity=(0, 0, -12.0)),       # 21.6 kJ: the mesh tears
}
COLS = ("case", "impact_energy_J", "max_abs_residual_J", "residual_pct", "contacts_median", "contacts_max", "samples_in_contact",
        "samples_without_force", "deep_onsets", "deep_onset_energy_J", "deep_endings", "deep_ending_energy_J", "broken", "steps", "wall_s")


def run(name, t_end):
    kw = dict(BASE, **CASES[name])
    if kw.get("wire") == "bar":
        kw["wire"] = yf.tecco_wire(bending_factor=0.0)
    s = scenes.mesh_punch(**kw)
    b = s["boulder"]
    O.trackEnergy = True
    t0 = time.time()
    O.step()
    st = O.bodies[b].state
    e0 = 0.5 * st.mass * st.vel.squaredNorm()
    tot0 = O.energy.total()
    worst, counts, idle, k = 0.0, [], 0, 0
    while O.time < t_end:
        O.step()
        k += 1
        worst = max(worst, abs(O.energy.total() - tot0))
        if k % 20 == 0:
            n = len(yf.contacts_on(b))
            if n:
                counts.append(n)
                idle += O.forces.f(b).norm() == 0
    law = yf.contact_law()
    broken = sum(1 for c in s["panel"]["cylinders"] + s["rope"] if O.bodies[c] is None)
    return dict(case=name, impact_energy_J=e0, max_abs_residual_J=worst, residual_pct=100 * worst / e0,
                contacts_median=statistics.median(counts) if counts else 0, contacts_max=max(counts, default=0), samples_in_contact=len(counts),
                samples_without_force=idle, deep_onsets=law.deepOnsets, deep_onset_energy_J=law.deepOnsetEnergy, deep_endings=law.deepEndings,
                deep_ending_energy_J=law.deepEndingEnergy, broken=broken, steps=k + 1, wall_s=time.time() - t0)


def main():
    ap = argparse.ArgumentParser(prog="punch_energy.py")
    ap.add_argument("--t-end", type=float, default=0.11, help="simulated time [s]")
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated, of " + ", ".join(CASES))
    me = next((k for k, a in enumerate(sys.argv) if os.path.basename(a) == "punch_energy.py"), 0)
    a = ap.parse_args(sys.argv[me + 1:])
    line = machine_line(yade.config.version, O.numThreads)
    print(line, end="")
    rows = []
    for name in a.cases.split(","):
        if name not in CASES:
            raise SystemExit(f"unknown case {name!r}: one of {', '.join(CASES)}")
        r = run(name, a.t_end)
        rows.append(r)
        print(" | ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in r.items()), flush=True)
    os.makedirs(os.path.join(BENCH, "results"), exist_ok=True)
    path = os.path.join(BENCH, "results", "punch_energy.csv")
    with open(path, "w", newline="") as f:
        f.write("# " + line)
        w = csv.DictWriter(f, fieldnames=COLS)
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")


main()
