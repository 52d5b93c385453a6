# The state of a filled module in a cache folder, one JSON line (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/fill_state.py CACHE_DIR [--small]
#
# Loads the filled module in CACHE_DIR (the one there, by any build: the default one, or --small's) and
# prints "FILLSTATE {json}": grains kept, the fill's height, the solid fraction of its core
# (away from the lining, the slab and the trimmed top by a largest grain; grains counted by
# their centres), the grain-grain contacts per grain, the grain-lining contacts and the
# normal force they put on it, and YADE's unbalanced force. Used by bench/time_to_result.py to
# show that a faster fill settles as well.
import glob
import json
import math
import os
import sys

me = next(k for k, a in enumerate(sys.argv) if a.endswith("fill_state.py"))
args = sys.argv[me + 1:]
from yade import O, utils  # noqa: E402
from yadeflex import module  # noqa: E402


def state(cache_dir, small):
    p = module.ModuleParams.small() if small else module.ModuleParams()
    files = glob.glob(os.path.join(cache_dir, "module-*.yade.gz"))
    if len(files) != 1:
        raise SystemExit(f"fill_state.py: expected one filled module in {cache_dir}, found {files}")
    O.load(files[0])  # (whichever build filled it: its key may be another version's)
    ids = json.loads(O.tags["yadeflex_module"])
    grains = ids["grains"]
    H, dmax = p.height, p.preset()["grain_max"]
    _, r_in = module.fill_radii(p)
    rc, z0, z1 = r_in - dmax, dmax, H - 2 * dmax
    core = 0.0
    for g in grains:
        b = O.bodies[g]
        if z0 <= b.state.pos[2] <= z1 and math.hypot(b.state.pos[0], b.state.pos[1]) <= rc:
            core += 4 / 3 * math.pi * b.shape.radius ** 3
    c = module.fill_contacts(ids)
    O.engines = p.engines(p.settle_damping, module.FILL_TIMESTEP_SAFETY)
    O.step()  # forces of the loaded state (the cache holds positions, not forces)
    return dict(grains=len(grains), fill_top_m=round(module.fill_top(ids), 4), core_solid_fraction=round(core / (math.pi * rc ** 2 * (z1 - z0)), 4),
                contacts_per_grain=round(2 * c["grain_grain"] / len(grains), 3), grain_lining_contacts=c["grain_lining"],
                lining_normal_force_N=round(c["grain_lining_force"], 1),
                unbalanced_force=round(utils.unbalancedForce(), 4))


print("FILLSTATE " + json.dumps(state(args[0], "--small" in args)), flush=True)
