# Contacts that end while still overlapping, and what becomes of their spring (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/contact_endings.py [--velocity 10.5] [--frictionless] [--label NAME]
#
# The scene of bench/contact_audit.py (the reduced module, its lining at its own mass, a 300 kg
# cube, no damping, default step), 30 ms from the first contact. After every step, each contact
# that carried a normal force at the last step and carries none now, with a spring still loaded
# (1/2 F^2 / kn > 0; a piercing wire's spring counts as 0 here), is sorted by what carries on
# beside it: a contact of the same body on a neighbouring element (sharing a node with its own
# element) that STARTS this step (a hand-over: the new contact takes the force over), one that was
# already carrying before (two contacts merged into one: this spring's energy is lost), none, or
# the element broke (erased). Sums the springs' energy per class and kind. Prints a table;
# appends rows to bench/results/contact_endings.csv.
import collections
import os
import sys

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("contact_endings.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import tearing_scene  # noqa: E402

COLS = ("label", "velocity_m_s", "frictionless", "cls", "ending", "count", "energy_J")


def main():
    a = tearing_scene.options("contact_endings.py", 10.5, os.path.join(BENCH, "results", "contact_endings.csv"))
    from yade import O
    kind = tearing_scene.start(a)

    def nodes(b):
        s = O.bodies[b].shape if O.bodies[b] is not None else None
        if s is None:
            return set()
        if kind[b] == "FlexCylinder":
            return {s.node1, s.node2}
        if kind[b] == "FlexFacet":
            return {s.node1, s.node2, s.node3}
        return {b}

    def carried():
        out = {}
        for i, g, ph in tearing_scene.carrying(O.interactions):
            out[(i.id1, i.id2)] = 0.0 if getattr(g, "pierced", False) else 0.5 * ph.normalForce.norm() ** 2 / ph.kn
        return out

    def beside(c, body, other):
        """c is a contact of body with a neighbour of other (its element shares a node with other's)."""
        if body not in c:
            return False
        x = c[0] if c[1] == body else c[1]
        return x != other and bool(nodes(x) & nodes(other))

    energy, count = collections.Counter(), collections.Counter()
    prev = carried()
    t0 = O.time
    while O.time - t0 < a.t_end:
        O.step()
        now = carried()
        for k, U in prev.items():
            if k in now or U <= 0:
                continue
            if O.bodies[k[0]] is None or O.bodies[k[1]] is None:
                ending = "erased with a broken element"
            else:
                nxt = [c for c in now if c != k and (beside(c, k[0], k[1]) or beside(c, k[1], k[0]))]
                if not nxt:
                    ending = "no neighbour carries on"
                elif any(c in prev for c in nxt):
                    ending = "merged (a neighbour carried before)"
                else:
                    ending = "handed over (a neighbour starts)"
            row = ("-".join(sorted(kind.get(x, "?") for x in k)), ending)
            energy[row] += U
            count[row] += 1
        prev = now
    print(f"\ncontacts that ended overlapping ({a.label}): {a.mass:g} kg at {a.velocity:g} m/s on the reduced module, lining at its own mass"
          f"{', frictionless' if a.frictionless else ''}, {1e3 * a.t_end:g} ms")
    print(f"{'class':28s} {'ending':38s} {'count':>7s} {'energy J':>10s}")
    rows = []
    for row in sorted(energy, key=lambda r: -energy[r]):
        print(f"{row[0]:28s} {row[1]:38s} {count[row]:7d} {energy[row]:10.1f}")
        rows.append(dict(label=a.label, velocity_m_s=a.velocity, frictionless=int(a.frictionless), cls=row[0], ending=row[1],
                         count=count[row], energy_J=round(energy[row], 3)))
    tearing_scene.append_rows(a.out, COLS, rows)

if __name__ == "__main__":
    main()
