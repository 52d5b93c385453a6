# Benchmark: the collider's sweep and the interaction loop's quick rejection on the damping-module
# impact (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/loop_settings.py [--small] [--rounds 3] [--window 600] [--warmup 200] [--settings 100:1 off:2 100:1:noqr 100:1:nofuse 100:1:nosums 100:1:norem 100:1:nocompact ...]
#
# Why: a step of the impact costs the interaction loop (every potential pair the time stepper did
# not mark unreachable is visited: bodies, shapes, states read), the collider, and the time
# stepper (it runs whenever the collider ran: the marks are valid until the next collider run).
# A larger sweep (InsertionSortCollider.verletDist) runs the collider less often but lists more
# pairs, and marks fewer of them (a pair is marked when its gap exceeds how far both sides can
# still travel inside their sweeps). InsertionSortCollider.targetInterv (YADE's default 100)
# shrinks each body's sweep to its recent motion (a slow grain gets 0.1 x verletDist; one that did
# not move at all, 0); -1 gives every body the full verletDist. FlexInteractionLoop.quickReject
# leaves out the sphere pairs that are apart from a table of centres and radii, before their
# bodies are read (a setting ending in :noqr switches it off). FlexInteractionLoop.fuseSpheres runs
# the existing sphere contacts from a table of the spheres' motion, without their bodies or the
# functors' dispatch (:nofuse switches it off). FlexInteractionLoop.threadSums sums the contact law's
# forces in the loop's own arrays, added to O.forces once per body, with several threads only (:nosums
# switches it off; at -j1 it changes nothing. Sums at one thread too were tried: 10,097 against
# 10,231 us per step at -j1, 8 rounds of 300 steps, within the windows' scatter, so left out).
# FlexInteractionLoop.rememberSkips leaves out the pairs of the two kinds above from a record of the
# last steps, without reading their interaction objects (:norem switches it off).
# FlexInteractionLoop.compactEvery copies the contacts' geometry and physics side by side, in the
# loop's order, every 100 steps (:nocompact: never; each window starts from O.loadTmp, whose objects
# the allocator places where the last run's were freed).
# What it does: the main job's impact (yadeflex.module.impact_start, the filled module from the
# cache), stepped to 5 ms after first contact, kept with O.saveTmp; then for each setting, --rounds
# times, interleaved: O.loadTmp, set targetInterv, verletDist, quickReject, fuseSpheres, threadSums, rememberSkips and compactEvery, --warmup steps, then
# --window steps timed (wall clock, and each engine's execTime). Medians over the rounds, and the
# median of each setting's ratio to the first one within a round (paired: this VM's speed drifts
# by 20% from minute to minute).
# Writes bench/results/loop_settings[_small].csv and _machine.txt, prints a table.
import argparse
import csv
import os
import statistics
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("loop_settings.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O  # noqa: E402

from machine import machine_line  # noqa: E402
from yadeflex.module import ModuleParams, impact_start  # noqa: E402

# (targetInterv, verletDist as a multiple of yadeflex.engines()'s default, half the wire radius,
# quickReject, fuseSpheres, threadSums, rememberSkips, compactEvery on)
SETTINGS = [(100, 1.0, True, True, True, True, True), (100, 1.0, False, True, True, True, True), (100, 1.0, True, False, True, True, True),
            (100, 1.0, True, True, True, False, True), (100, 0.5, True, True, True, True, True), (100, 2.0, True, True, True, True, True),
            (-1, 1.0, True, True, True, True, True), (-1, 2.0, True, True, True, True, True), (-1, 4.0, True, True, True, True, True)]
FLAGS = ("noqr", "nofuse", "nosums", "norem", "nocompact")  # the switches of s[2:], in order


def label(s):
    return f"{s[0] if s[0] > 0 else 'off'}:{s[1]:g}" + "".join("" if on else ":" + f for f, on in zip(FLAGS, s[2:]))


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("loop_settings.py")), 0)
    ap = argparse.ArgumentParser(prog="loop_settings.py", description="Collider sweep and loop settings on the damping-module impact.")
    ap.add_argument("--small", action="store_true", help="the reduced module (ModuleParams.small())")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--window", type=int, default=600, help="timed steps per window")
    ap.add_argument("--warmup", type=int, default=200, help="steps after each reload before timing")
    ap.add_argument("--settings", nargs="+", default=None, metavar="TI:F[:noqr][:nofuse][:nosums][:norem][:nocompact]",
                    help="targetInterv:factor (targetInterv an integer > 0, or 'off' for -1; factor x the default verletDist; "
                    ":noqr: FlexInteractionLoop.quickReject off; :nofuse: FlexInteractionLoop.fuseSpheres off; :nosums: FlexInteractionLoop.threadSums off; :norem: FlexInteractionLoop.rememberSkips off; :nocompact: FlexInteractionLoop.compactEvery = 0); "
                    "the first is the reference "
                    "(default: %s)" % " ".join(label(s) for s in SETTINGS))
    a = ap.parse_args(sys.argv[me + 1:])
    if a.rounds < 1 or a.window < 1 or a.warmup < 0:
        ap.error("--rounds and --window must be positive, --warmup non-negative")
    try:
        out = []
        for x in a.settings or []:
            f = x.split(":")
            if len(f) < 2 or any(k not in FLAGS for k in f[2:]) or len(set(f[2:])) != len(f[2:]):
                raise ValueError(x)
            out.append((-1 if f[0] == "off" else int(f[0]), float(f[1]), *(k not in f[2:] for k in FLAGS)))
        a.settings = out or SETTINGS
    except ValueError:
        ap.error(f"--settings takes targetInterv:factor[:noqr][:nofuse][:nosums][:norem][:nocompact] such as 100:1 off:2 100:1:noqr 100:1:nofuse, got {a.settings}")
    if any(f <= 0 or t == 0 or t < -1 for t, f, *_ in a.settings):
        ap.error("targetInterv must be positive or 'off', verletDist factors positive")
    return a


def main():
    a = parse()
    impact_start(ModuleParams.small() if a.small else ModuleParams())
    t0 = O.time
    while O.time < t0 + 5e-3:
        O.run(50, True)
    O.saveTmp("settings")
    col = next(e for e in O.engines if e.label == "collider")
    v0 = col.verletDist  # yadeflex.engines()'s default
    runs = {s: [] for s in a.settings}
    for rnd in range(a.rounds):
        for s in a.settings:
            O.loadTmp("settings")
            col = next(e for e in O.engines if e.label == "collider")
            dt = next(e for e in O.engines if e.label == "flexDt")
            col.targetInterv, col.verletDist = s[0], s[1] * v0
            il = next(e for e in O.engines if e.label == "interactionLoop")
            il.quickReject = s[2]
            il.fuseSpheres = s[3]
            il.threadSums = s[4]
            il.rememberSkips = s[5]
            il.compactEvery = 100 if s[6] else 0
            O.run(a.warmup, True)
            O.timingEnabled = True
            for e in O.engines:
                e.execTime = 0
            n0 = col.numAction
            w = time.perf_counter()
            O.run(a.window, True)
            w = time.perf_counter() - w
            O.timingEnabled = False
            runs[s].append(dict(us=1e6 * w / a.window, collider_runs=(col.numAction - n0) / a.window, interactions=len(O.interactions),
                                live=len(O.interactions) - dt.skippedPairs, quick_rejected=il.quickRejected, fused=il.fusedContacts,
                                real=O.interactions.countReal(), dt=O.dt,
                                **{f"{e.label or type(e).__name__}_us": e.execTime / 1e3 / a.window for e in O.engines}))
            print(f"  round {rnd}: {label(s):18s} (verletDist {1e3 * s[1] * v0:.3f} mm): {runs[s][-1]['us']:.0f} us per step", flush=True)
    rows = []
    base = statistics.median(r["us"] for r in runs[a.settings[0]])
    for s in a.settings:
        med = {k: statistics.median(r[k] for r in runs[s]) for k in runs[s][0]}
        paired = statistics.median(r["us"] / q["us"] for r, q in zip(runs[s], runs[a.settings[0]]))
        rows.append(dict(setting=label(s), target_interv=s[0], verlet_mm=1e3 * s[1] * v0, quick_reject=s[2], fuse_spheres=s[3], thread_sums=s[4], remember_skips=s[5], compact=s[6], us_per_step=med["us"], vs_first=med["us"] / base,
                         vs_first_paired=paired, windows=" ".join(f"{r['us']:.0f}" for r in runs[s]), **{k: v for k, v in med.items() if k != "us"}))
    out = os.path.join(os.path.dirname(BENCH), "bench", "results", "loop_settings" + ("_small" if a.small else "") + ".csv")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(out.replace(".csv", "_machine.txt"), "w") as f:
        f.write(machine_line(yade.config.version, 1))
    print(f"\nmedians of {a.rounds} windows of {a.window} steps (first row: the reference)")
    print("setting             verlet mm  dt us  us/step  vs first  paired  collider runs/step  live pairs  quick-rejected  fused  interactions  loop us  collider us  stepper us")
    for r in rows:
        print(f"{r['setting']:18s}  {r['verlet_mm']:9.3f}  {1e6 * r['dt']:5.3f}  {r['us_per_step']:7.0f}  {r['vs_first']:8.3f}  {r['vs_first_paired']:6.3f}  {r['collider_runs']:18.3f}  "
              f"{r['live']:10.0f}  {r['quick_rejected']:14.0f}  {r['fused']:5.0f}  {r['interactions']:12.0f}  {r['interactionLoop_us']:7.0f}  {r['collider_us']:11.0f}  {r['flexDt_us']:10.0f}")
    print(f"written {out}")


main()
