# Where the contact hand-over ledger's net comes from (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/handover_events.py [--steps 2500] [--label NAME] [--small]
#
# Loads the main job's filled module (yadeflex.module, cached), drops the default boulder with
# the main job's engines and, from its first contact on, scans every FlexContactGeom interaction
# after each step for the events the contact law's ledger counts (Law2_FlexContactGeom_FrictPhys_
# CundallStrack.deepOnsets / deepEndings): a deep onset (geom.onsetDepth > 0 after the law) and
# an ending while overlapping (inactive now, active last step, overlap > 0), with their spring
# energy 1/2 kn d^2. Per contact class (Sphere-FlexFacet, FlexCylinder-FlexFacet, ...) it sums
# both. For element-element contacts it pairs each onset with an ending of the same step on a
# pair sharing one element and touching the other's neighbour (a hand-over inside a cluster) and
# sums the hand-overs' net apart from the onsets and endings left unpaired. The scan runs in
# Python over all interactions: about 40 ms per step. Prints a table; appends rows to
# bench/results/handover_events.csv (label, class, quantity, count, energy_J).
import argparse
import collections
import csv
import os
import sys

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("handover_events.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))


def main():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("handover_events.py")), 0)
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=2500, help="impact steps scanned from the first contact")
    ap.add_argument("--label", default="current")
    ap.add_argument("--small", action="store_true", help="the reduced module")
    ap.add_argument("--out", default=os.path.join(BENCH, "results", "handover_events.csv"))
    a = ap.parse_args(sys.argv[me + 1:])
    from yade import O
    from yadeflex.module import ModuleParams, impact_start
    impact_start(ModuleParams.small() if a.small else ModuleParams())
    kind = {b.id: type(b.shape).__name__ for b in O.bodies}

    def nodes(b):
        s = O.bodies[b].shape
        return {s.node1, s.node2} if kind[b] == "FlexCylinder" else {s.node1, s.node2, s.node3}

    count, energy = collections.Counter(), collections.Counter()
    for k in range(a.steps):
        O.step()
        onsets, endings = [], []
        for i in O.interactions:
            g = i.geom
            if g is None or not hasattr(g, "onsetDepth"):
                continue
            cls = "-".join(sorted((kind[i.id1], kind[i.id2])))
            elements = "Sphere" not in cls
            if not g.active and g.lastActiveIter == O.iter - 2 and g.penetrationDepth > 0:
                e = 0.5 * i.phys.kn * g.penetrationDepth ** 2
                count[(cls, "endings")] += 1
                energy[(cls, "endings")] += e
                if elements:
                    endings.append((i.id1, i.id2, e, cls))
            if g.onsetDepth > 0:
                e = 0.5 * i.phys.kn * g.onsetDepth ** 2
                count[(cls, "onsets")] += 1
                energy[(cls, "onsets")] += e
                if elements:
                    onsets.append((i.id1, i.id2, e, cls))
        used = set()
        for (x, y, e, cls) in onsets:
            m = next((j for j, (x2, y2, _, _) in enumerate(endings) if j not in used and
                      ((x == x2 and nodes(y) & nodes(y2)) or (y == y2 and nodes(x) & nodes(x2)))), None)
            if m is None:
                count[(cls, "onsets unpaired")] += 1
                energy[(cls, "onsets unpaired")] += e
            else:
                used.add(m)
                count[(cls, "hand-overs (net)")] += 1
                energy[(cls, "hand-overs (net)")] += e - endings[m][2]
        for j, (_, _, e, cls) in enumerate(endings):
            if j not in used:
                count[(cls, "endings unpaired")] += 1
                energy[(cls, "endings unpaired")] += e
    print(f"\ncontact hand-over events, first {a.steps} impact steps ({a.label})")
    print(f"{'class':28s} {'quantity':20s} {'count':>7s} {'energy J':>10s}")
    if not count:
        print("(no deep onsets or endings)")
    rows = []
    for (cls, q) in sorted(count):
        print(f"{cls:28s} {q:20s} {count[(cls, q)]:7d} {energy[(cls, q)]:10.3f}")
        rows.append(dict(label=a.label, steps=a.steps, module="small" if a.small else "default", cls=cls, quantity=q,
                         count=count[(cls, q)], energy_J=energy[(cls, q)]))
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    new = not os.path.exists(a.out)
    with open(a.out, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["label", "steps", "module", "cls", "quantity", "count", "energy_J"])
        if new:
            w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
