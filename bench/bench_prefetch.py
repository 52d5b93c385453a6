# What prefetching gains in the damping module's step (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/bench_prefetch.py [--small] [--rounds 6] [--window 150]
#
# FlexInteractionLoop, FlexNewtonIntegrator and FlexTimeStepper ask for the data of the
# interactions and bodies a few iterations ahead (pkg/yade/speed/FlexLoop.hpp); each has a `prefetch`
# switch. This script loads the main job's filled module (cached; built on first use), adds the
# boulder with the main job's engines, steps until 5 ms after its first contact, then checks
# that the three settings below give the same state bit for bit over 200 steps from one saved
# state, and times them in windows of --window steps that alternate between the settings
# (rotating their order each round), so that all see the same machine load and the same
# stage of the impact:
#     none   every switch off (YADE's InteractionLoop.action, no prefetching)
#     loop   FlexInteractionLoop's only
#     all    all three (the default)
# The step time is the sum of all engines' execTime (O.timingEnabled). Prints the median per engine and the median of the paired ratios (none / setting, per round),
# writes bench/results/prefetch[_small].csv (one row per window) and _machine.txt.
import argparse
import csv
import hashlib
import os
import statistics
import struct
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("bench_prefetch.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

from yade import O  # noqa: E402

from machine import machine_line  # noqa: E402
from yadeflex.module import ModuleParams, add_boulder, filled_module  # noqa: E402

SETTINGS = {"none": (False, False, False), "loop": (True, False, False), "all": (True, True, True)}
ENGINES = ("interactionLoop", "newton", "flexDt")


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("bench_prefetch.py")), 0)
    ap = argparse.ArgumentParser(prog="bench_prefetch.py", description="Time per step with and without prefetching, interleaved.")
    ap.add_argument("--small", action="store_true", help="the reduced module of damping_module.py --small")
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("--window", type=int, default=150, help="steps per timed window")
    a = ap.parse_args(sys.argv[me + 1:])
    if a.rounds < 1 or a.window < 1:
        ap.error("--rounds and --window must be positive")
    return a


def state_hash():
    h = hashlib.sha256()
    for b in O.bodies:
        if b is not None:
            s = b.state
            h.update(struct.pack("<i13d", b.id, *s.pos, *s.vel, *s.angVel, *s.ori))
    return h.hexdigest()[:16]


def engines():
    return {e.label: e for e in O.engines if e.label in ENGINES}


def apply(name):
    e = engines()
    for label, on in zip(ENGINES, SETTINGS[name]):
        e[label].prefetch = on


def main():
    a = parse()
    p = ModuleParams.small() if a.small else ModuleParams()
    ids, cache_file, cached = filled_module(p)
    bid = add_boulder(p, ids)
    O.engines = p.engines(p.damping)
    O.trackEnergy = True
    t_contact = None
    while t_contact is None or O.time < t_contact + 5e-3:
        O.run(50, True)
        if t_contact is None and O.forces.f(bid).norm() > 0:
            t_contact = O.time
    print(f"module {'--small' if a.small else 'default'}: {len(ids['grains'])} grains; timed from t = {O.time * 1e3:.2f} ms "
          f"(first contact + {(O.time - t_contact) * 1e3:.1f} ms), {len(O.interactions)} interactions, {O.interactions.countReal()} real", flush=True)
    O.saveTmp("prefetch")
    hashes = {}
    for name in SETTINGS:
        O.loadTmp("prefetch")
        apply(name)
        O.run(200, True)
        hashes[name] = (state_hash(), O.energy.total())
    same = len(set(hashes.values())) == 1
    print(f"state after 200 steps from one saved state: {'bit-identical' if same else 'DIFFERENT'} across {', '.join(SETTINGS)}", flush=True)
    O.loadTmp("prefetch")
    O.timingEnabled = True
    rows, names = [], list(SETTINGS)
    for r in range(a.rounds):
        order = names[r % len(names):] + names[:r % len(names)]
        for name in order:
            apply(name)
            for e in O.engines:
                e.execTime = 0
            w = time.time()
            O.run(a.window, True)
            w = time.time() - w
            e = engines()
            # the step: the sum of every engine's execTime (O.run's wait polls, which blurs the
            # wall time of short windows); wall_us for reference
            rows.append(dict(round=r, setting=name, step_us=sum(x.execTime for x in O.engines) / a.window / 1e3, wall_us=w / a.window * 1e6,
                             **{f"{k}_us": e[k].execTime / a.window / 1e3 for k in ENGINES},
                             loop_fast_path=int(e["interactionLoop"].usedFastPath), t_ms=O.time * 1e3))
        print(f"  round {r}: " + ", ".join(f"{x['setting']} {x['step_us']:.0f} us" for x in rows[-len(names):]), flush=True)
    out = os.path.join(BENCH, "results", "prefetch" + ("_small" if a.small else ""))
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(out + "_machine.txt", "w") as f:
        f.write(machine_line().strip() + "\n")

    def med(name, key):
        return statistics.median(x[key] for x in rows if x["setting"] == name)

    def ratio(name, key):
        base = {x["round"]: x[key] for x in rows if x["setting"] == "none"}
        return statistics.median(base[x["round"]] / x[key] for x in rows if x["setting"] == name and x[key] > 0)

    print()
    print("| setting | µs per step | InteractionLoop | integrator | time stepper | step, none / this (paired) | InteractionLoop, none / this |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        print(f"| {name} | {med(name, 'step_us'):.0f} | {med(name, 'interactionLoop_us'):.0f} | {med(name, 'newton_us'):.0f} | "
              f"{med(name, 'flexDt_us'):.0f} | {ratio(name, 'step_us'):.3f}x | {ratio(name, 'interactionLoop_us'):.3f}x |")
    print(f"\n{a.rounds} rounds of {a.window} steps per setting; {machine_line().strip()}; written {out}.csv")
    return 0 if same else 1


if __name__ == "__main__":
    rc = main()
    if rc:
        sys.exit(rc)
