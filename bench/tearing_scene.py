# The tearing impact of tests/yade/test_module.py for the contact benchmarks (contact_audit.py,
# contact_endings.py): the reduced module, its lining at its own mass, a boulder cube, no damping,
# the default time step, up to the boulder's first contact (GPL-2.0-or-later).
import os


def options(script, velocity, out):
    """The options of the benchmark `script` (its file name) from the command line after it."""
    import argparse
    import sys
    me = next((k for k, a in enumerate(sys.argv) if a.endswith(script)), 0)
    ap = argparse.ArgumentParser()
    add_options(ap, velocity, out)
    return ap.parse_args(sys.argv[me + 1:])


def add_options(ap, velocity, out):
    """The options both benchmarks take; out: the CSV's default path."""
    ap.add_argument("--velocity", type=float, default=velocity, help="impact speed [m/s]")
    ap.add_argument("--mass", type=float, default=300.0, help="boulder mass [kg]")
    ap.add_argument("--t-end", type=float, default=0.03, help="time looked at from the first contact [s]")
    ap.add_argument("--frictionless", action="store_true", help="every friction angle 0")
    ap.add_argument("--label", default="current")
    ap.add_argument("--out", default=out)


def start(a):
    """Loads (or fills) the module, adds the boulder and steps to its first contact (options a of
    add_options); returns {body id: shape class name}."""
    from yade import O
    from yadeflex.module import ModuleParams, impact_start
    p = ModuleParams.small()
    p.boulder_mass, p.impact_velocity, p.lining_node_mass = a.mass, a.velocity, 0.0
    p.validate()
    impact_start(p)
    if a.frictionless:
        for m in O.materials:
            if hasattr(m, "frictionAngle"):
                m.frictionAngle = 0.0
        for i in O.interactions:
            if i.phys is not None and hasattr(i.phys, "tangensOfFrictionAngle"):
                i.phys.tangensOfFrictionAngle = 0.0
    return {b.id: type(b.shape).__name__ for b in O.bodies if b is not None}


def append_rows(path, cols, rows):
    """Appends rows (dicts) to the CSV at path, with a header if it is new."""
    import csv
    os.makedirs(os.path.dirname(path), exist_ok=True)
    new = not os.path.exists(path)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        if new:
            w.writeheader()
        w.writerows(rows)


def carrying(interactions):
    """The contacts of yade-flex carrying a force now: (interaction, FlexContactGeom, phys)."""
    for i in interactions:
        g = i.geom
        if g is None or not hasattr(g, "onsetDepth") or not g.active or i.phys is None:
            continue
        yield i, g, i.phys
