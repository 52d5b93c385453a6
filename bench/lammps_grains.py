# Benchmark: the damping module's gravel bed, yade-flex's grain contacts against LAMMPS and plain
# YADE, one thread (issue 59, first step) (GPL-2.0-or-later).
#
#     OMP_NUM_THREADS=1 yade-double -n -j1 -x bench/lammps_grains.py [--quick] [--rounds N] [--steps N]
#         [--steps-big N] [--copies N] [--no-big] [--same-process] [--cache-dir DIR]
#
# The bed: the settled grains of the main job's filled module (bench_grains.py's grains_of: the
# cached default module, ModuleParams()), on the slab (a Wall at z = 0) inside a rigid frictionless
# cylinder of YADE facets (bench_grains.py's scene()), gravity, no damping. The larger bed is
# --copies (default 4) copies of that bed side by side on a 2x2 grid, each in its own cylinder
# (about 16.9k grains): not a 7-module fill (not in the cache; building it takes too long here).
# bench_grains.py's scene and grains are imported (nothing of it is copied here).
#
# Cases: "rest": the bed as settled, from rest; "impact": an 800 kg SPHERE (density 2400 kg/m3,
# 0.861 m across, the fill's material) on the axis of the first copy, starting --warmup steps
# above the bed at 6.26 m/s (sqrt(2 G 2 m)), so that it touches the bed when the timing starts.
# Each run: a new process (yade-double running this script with --child, or LAMMPS), --warmup
# steps untimed, then --steps timed. (--same-process: the YADE runs one after another in this
# process instead, each on a new scene; those built after others ran up to 1.7x slower there,
# most likely their bodies scattered over the heap the earlier scenes left: bench/README.md.)
# Timed: yade O.run(steps, True) wall clock; LAMMPS the "Loop time" of the timed `run` (its setup
# excluded, as our scene building is). Reported in microseconds per particle-step (particles:
# grains + the sphere; the facets and the slab are not counted).
#
# Engines (one thread each: this process is run with -j1 and OMP_NUM_THREADS=1; lmp serial,
# without -sf omp):
#   flex        our yf.engines() of the main job's impact (ModuleParams.engines(0): rolling resistance
#               0.1, rolling stiffness 1, the grain-grain contacts in FlexGrainEngine),
#               FlexTimeStepper turned off (dead) and dt held at --dt
#   flex_norol  the same without rolling resistance, dt held at --dt
#   loop, loop_norol  flex and flex_norol with the grain-grain contacts in the interaction loop
#               (yf.engines() without grains=: as before FlexGrainEngine; bench/grain_kernel.py)
#   shipped     ModuleParams.engines(0) as shipped: FlexTimeStepper (safety ModuleParams's) sets dt
#   plain       plain YADE: InsertionSortCollider, Ig2_*_ScGeom, FrictPhys, CundallStrack,
#               NewtonIntegrator (bench_grains.py's "builtin"), dt held at --dt
#   lmp_hooke   LAMMPS pair gran/hooke/history (no rolling); compared with flex_norol
#   lmp_gran    LAMMPS pair granular hooke / tangential linear_history / rolling sds; compared with flex
# The order of the engines is rotated from round to round (alternated); medians and ranges of
# --rounds rounds.
#
# How the LAMMPS laws differ from ours, and the bias:
#   - Normal stiffness. Ours (YADE FrictPhys): kn = 2 E r1 r2 / (r1 + r2) per pair, E = 1e8 Pa: from
#     1.6e6 N/m (two 32 mm grains) to 3.15e6 N/m (two 63 mm grains), ~2 E r for a grain on the
#     sphere; a grain on the slab or the cylinder E r. LAMMPS `hooke` (both laws, and the walls):
#     one kn for every pair, here E x the mean grain radius (--kn overrides). Same mean
#     stiffness of the bed, no size dependence; the sphere's contacts are about half as stiff in
#     LAMMPS (a softer impact, a lower peak force).
#   - Shear: ours ks = 0.3 kn, incremental shear force rotated with the contact, Coulomb cap
#     tan(38 deg) |Fn|. LAMMPS: kt = 0.3 kn, a shear displacement history rotated into the tangent
#     plane, capped at mu |Fn| (gran/hooke/history) / mu |Fn| (linear_history): the same model.
#   - Damping: ours none (no local damping, no contact damping). LAMMPS: gamma_n = gamma_t = 0
#     (hooke/history, dampflag 0) and eta_n = 0, x_gamma_t = 0, gamma_roll = 0 (granular): none.
#   - Rolling: ours an elastic-plastic moment kr = ks R^2 (rolling stiffness 1), capped at
#     0.1 R |Fn|, R = r1 r2 / (r1 + r2), from the relative rotation, sphere-sphere only. LAMMPS
#     `rolling sds`: a rolling spring k_roll on the rolling displacement R_eff x relative rotation,
#     capped at mu_roll |Fn|, torque R_eff x that force: k_roll = kt and mu_roll = 0.1 give the same
#     moment-rotation law for small rotations. Set on grain-grain (and sphere) contacts only; the
#     walls have no rolling in either (our Wall and facets use CundallStrack). No twisting in either.
#   - Ours does more per contact than LAMMPS's law: energy booking (elastic, friction, rolling
#     dissipation), the onset/release correction (`crossing`: contacts kept two steps past
#     separation), contact ownership; YADE integrates each sphere's orientation (LAMMPS nve/sphere
#     does not). Plain YADE's CundallStrack books no energy by default. These are costs of our
#     model, not of the comparison; the stiffness difference changes the impact's physics a little
#     (the force history), not the bed at rest.
#   - Neighbours: ours and plain YADE InsertionSortCollider with verletDist 16 mm (half the
#     smallest radius: bounds enlarged by 16 mm), LAMMPS `neighbor 0.016 bin` (rest) and
#     `neighbor 0.016 multi` (impact: one 0.86 m sphere makes single-size bins useless), checked
#     every step. The cylinder wall: LAMMPS `fix wall/gran ... zcylinder` for one bed,
#     `fix wall/gran/region` with one cylinder region per copy for the larger bed; the floor
#     `wall/gran ... zplane`.
# Physics check (reported, not asserted): the grains' kinetic energy and fastest grain at the end
# (rest), the sphere's peak contact force (sampled every 10 steps: ours O.forces.f, LAMMPS
# fz + m g), its depth below its start and its speed at the end (impact); contacts per particle
# (ours: real interactions / grains, walls included; LAMMPS: contact/atom summed / 2 / grains,
# walls excluded).
# Where the time goes (lammps_grains[_quick]_sections.csv, printed): LAMMPS's own timing breakdown
# of the timed run (Pair, Neigh, Modify: the fixes, nve/sphere and the walls; Comm, Output and
# Other together), and ours from O.timingEnabled (each engine's execTime in the timed run; the
# rest of the wall time, YADE's own loop between the engines, as "outside the engines"), both in
# microseconds per particle-step, medians over the rounds.
# Writes bench/results/lammps_grains[_quick].csv, lammps_grains[_quick]_raw.csv (every run),
# lammps_grains[_quick]_sections.csv and lammps_grains[_quick]_machine.txt, and prints tables.
import argparse
import csv
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("lammps_grains.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O, utils, geom  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402
from yade.wrapper import FrictMat, PyRunner  # noqa: E402

import yadeflex as yf  # noqa: E402
from yadeflex.constants import G  # noqa: E402
from yadeflex.module import ModuleParams, fill_radii  # noqa: E402
from machine import machine_line  # noqa: E402

ENGINES = ["flex", "flex_norol", "shipped", "plain", "lmp_hooke", "lmp_gran"]
LABELS = {"flex": "yade-flex (rolling, dt held)", "flex_norol": "yade-flex (no rolling, dt held)",
          "loop": "yade-flex, grain contacts in the loop (rolling, dt held)", "loop_norol": "yade-flex, grain contacts in the loop (no rolling, dt held)",
          "shipped": "yade-flex as shipped (FlexTimeStepper)",
          "plain": "plain YADE", "lmp_hooke": "LAMMPS gran/hooke/history", "lmp_gran": "LAMMPS granular + rolling sds"}


import bench_grains as BG  # noqa: E402  (its scene and grains; its main() runs only as a script)


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("lammps_grains.py")), 0)
    ap = argparse.ArgumentParser(prog="lammps_grains.py", description="The module's gravel bed: yade-flex, plain YADE and LAMMPS, one thread.")
    ap.add_argument("--quick", action="store_true", help="one round of 300 steps, the one bed only (a smoke test)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=5000, help="timed steps, one bed")
    ap.add_argument("--steps-big", type=int, default=1000, help="timed steps, the larger bed")
    ap.add_argument("--warmup", type=int, default=200, help="untimed steps before the timing")
    ap.add_argument("--copies", type=int, default=4, help="copies of the bed side by side in the larger bed")
    ap.add_argument("--no-big", action="store_true", help="the one bed only")
    ap.add_argument("--big-engines", default="flex,flex_norol,plain,lmp_hooke,lmp_gran", help="engines run on the larger bed")
    ap.add_argument("--dt", type=float, default=3.25e-5)
    ap.add_argument("--mass", type=float, default=800.0, help="the sphere's mass [kg]")
    ap.add_argument("--speed", type=float, default=6.26, help="its speed [m/s]")
    ap.add_argument("--kn", type=float, default=None, help="LAMMPS kn [N/m] (default E x mean grain radius)")
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--cache-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules"))
    ap.add_argument("--out", default=os.path.join(BENCH, "results"))
    ap.add_argument("--same-process", action="store_true",
                    help="run the YADE engines in this process, one scene after another (as before 2026-12-07 night), not each in a fresh one")
    ap.add_argument("--child", nargs=3, metavar=("ENGINE", "CASE", "COPIES"), help=argparse.SUPPRESS)
    a = ap.parse_args(sys.argv[me + 1:])
    if a.quick:
        a.rounds, a.steps, a.no_big = 1, 300, True
    return a


def bed(p, cache_dir):
    """The cached default module's settled grains as [((x, y, z), r)] in floats, and the cache file."""
    grains, f = BG.grains_of(p, cache_dir)
    return [((float(c[0]), float(c[1]), float(c[2])), float(r)) for c, r in grains], f


def lammps_kn(p, grains):
    """LAMMPS's one kn for every pair: E x the mean grain radius [N/m]."""
    return p.preset()["young"] * statistics.mean(r for _, r in grains)


def alternated(engines, rounds, cases=("rest", "impact")):
    """(round, case, engine) in the order of the runs: every case in each round, the engines'
    order rotated by one from round to round."""
    for rnd in range(rounds):
        order = engines[rnd % len(engines):] + engines[:rnd % len(engines)]
        for case in cases:
            for e in order:
                yield rnd, case, e


def r_in_of(p, grains):
    """The cylinder's radius as bench_grains.scene() computes it."""
    return max(fill_radii(p)[1], max(math.hypot(c[0], c[1]) + r for c, r in grains) + 1e-4)


def offsets(copies, r_in):
    """(x, y) of each copy: a square grid, 5 cm between cylinders."""
    n = math.ceil(math.sqrt(copies))
    s = 2 * r_in + 0.05
    return [((k % n) * s, (k // n) * s) for k in range(copies)]


def sphere_of(a, grains, dt):
    """(radius, z of its centre, density) of the impactor: touching the bed after `warmup` steps."""
    dens = 2400.0
    R = (3 * a.mass / dens / (4 * math.pi)) ** (1 / 3)
    top = max(c[2] + r for c, r in grains if math.hypot(c[0], c[1]) < R)
    return R, top + R + 1e-3 + a.speed * a.warmup * dt, dens


def build_yade(a, p, grains, kind, copies, case):
    """Scene of `kind` (bench_grains.scene for the first copy, the others added the same way);
    returns (number of particles, impactor id or None)."""
    bk = {"plain": "builtin", "flex": "flex", "shipped": "flex", "flex_norol": "norolling", "loop": "flex", "loop_norol": "norolling"}[kind]
    BG.scene(p, grains, bk, a.dt)
    if kind in ("flex_norol", "loop", "loop_norol"):
        # the impact's engines (ModuleParams.engines: the grain-grain contacts in FlexGrainEngine) without
        # rolling resistance; loop*: with those contacts in the interaction loop, as before FlexGrainEngine
        rf = p.preset()["rolling_friction"] if kind == "loop" else 0.0
        O.engines = yf.engines(damping=0.0, timestep_safety=p.timestep_safety, rolling_stiffness=1.0 if rf > 0 else 0.0, rolling_friction=rf,
                               grains=None if kind.startswith("loop") else "fill")
    fill = [m for m in O.materials if m.label == "fill"][0]
    cont = [m for m in O.materials if m.label == "container"][0]
    r_in = r_in_of(p, grains)
    for ox, oy in offsets(copies, r_in)[1:]:
        O.bodies.append(geom.facetCylinder((ox, oy, 0.6 * p.height), r_in, 1.2 * p.height, segmentsNumber=48, wallMask=4, material=cont))
        for c, r in grains:
            O.bodies.append(utils.sphere(Vector3(c[0] + ox, c[1] + oy, c[2]), r, material=fill))
    if kind in ("flex", "flex_norol", "loop", "loop_norol"):
        for e in O.engines:
            if e.label == "flexDt":
                e.dead = True
        O.dt = a.dt
    n = copies * len(grains)
    imp = None
    if case == "impact":
        R, z, dens = sphere_of(a, grains, a.dt)
        mat = FrictMat(young=fill.young, poisson=fill.poisson, density=dens, frictionAngle=fill.frictionAngle, label="impactor")
        O.materials.append(mat)
        imp = O.bodies.append(utils.sphere((0, 0, z), R, material=mat))
        O.bodies[imp].state.vel = Vector3(0, 0, -a.speed)
        n += 1
    return n, imp


def run_yade(a, p, grains, kind, copies, case, steps):
    n, imp = build_yade(a, p, grains, kind, copies, case)
    O.run(a.warmup, True)
    peak = [0.0]
    if imp is not None:
        z0 = O.bodies[imp].state.pos[2]

        def sample():
            peak[0] = max(peak[0], abs(O.forces.f(imp)[2]))
        import builtins  # PyRunner's command runs in YADE's namespace: reach the function through builtins
        builtins._lammps_grains_sample = sample
        O.engines = O.engines + [PyRunner(command="_lammps_grains_sample()", iterPeriod=10, label="sampler")]
    O.timingEnabled = True
    for e in O.engines:
        e.execTime = 0
    t0 = time.perf_counter()
    O.run(steps, True)
    t = time.perf_counter() - t0
    O.timingEnabled = False
    parts = {(e.label or type(e).__name__): e.execTime / 1e3 / (steps * n) for e in O.engines}
    parts["outside the engines"] = max(0.0, 1e6 * t / (steps * n) - sum(parts.values()))
    grains_b = [b for b in O.bodies if b is not None and b.dynamic and b.id != imp and b.shape.__class__.__name__ == "Sphere"]
    ke = sum(0.5 * b.state.mass * b.state.vel.squaredNorm() for b in grains_b)
    vmax = max(b.state.vel.norm() for b in grains_b)
    r = dict(us=1e6 * t / (steps * n), parts=parts, n=n, steps=steps, dt=O.dt, contacts_pp=(O.interactions.countReal() + sum(e.contacts for e in O.engines if e.label == "grainEngine")) / (copies * len(grains)), ke=ke, vmax=vmax)
    if imp is not None:
        r.update(peak_kN=peak[0] / 1e3, depth=z0 - O.bodies[imp].state.pos[2], v_end=O.bodies[imp].state.vel[2])
    return r


def run_yade_fresh(a, copies, case, kind, steps):
    """run_yade in a fresh yade-double process (this script with --child), as LAMMPS runs in one
    (a scene built after others in the same process runs slower: bench/README.md)."""
    # (imported, as by grain_kernel.py: this module's file; run by yade-double -x, where __file__ is
    # not this script's: found from the command line, BENCH)
    me = os.path.abspath(__file__) if __name__ == "lammps_grains" else os.path.join(BENCH, "lammps_grains.py")
    cmd = ["yade-double", "-n", "-j1", "-x", me, "--child", kind, case, str(copies), "--steps", str(steps), "--warmup", str(a.warmup),
           "--dt", repr(a.dt), "--mass", repr(a.mass), "--speed", repr(a.speed), "--cache-dir", a.cache_dir, "--out", a.out]
    out = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    line = next((ln for ln in out.stdout.splitlines() if ln.startswith("LG_CHILD ")), None)
    if out.returncode != 0 or line is None:
        raise RuntimeError(f"lammps_grains: the run of {kind} ({case}, {copies} bed(s)) failed:\n{out.stdout[-2000:]}\n{out.stderr[-2000:]}")
    return json.loads(line[len("LG_CHILD "):])


def child(a):
    """--child ENGINE CASE COPIES: one run_yade, its result printed as one JSON line."""
    kind, case, copies = a.child[0], a.child[1], int(a.child[2])
    p = ModuleParams()
    grains, _ = bed(p, a.cache_dir)
    r = run_yade(a, p, grains, kind, copies, case, a.steps)
    print("LG_CHILD " + json.dumps(r), flush=True)


def write_lammps(a, p, grains, copies, case, law, kn, workdir, steps):
    """The data file and input of one LAMMPS run; returns the input's path."""
    r_in = r_in_of(p, grains)
    offs = offsets(copies, r_in)
    dens = p.preset()["density"]
    atoms = [(c[0] + ox, c[1] + oy, c[2], r, dens, 1) for ox, oy in offs for c, r in grains]
    imp_id = None
    if case == "impact":
        R, z, d = sphere_of(a, grains, a.dt)
        atoms.append((0.0, 0.0, z, R, d, 2))
        imp_id = len(atoms)
    xs = [x for x, y in offs]
    ys = [y for x, y in offs]
    ztop = max(at[2] + at[3] for at in atoms) + 0.5
    data = os.path.join(workdir, f"bed_{copies}_{case}.data")
    with open(data, "w") as fh:
        fh.write(f"yade-flex gravel bed, {copies} cop(y/ies), {case}\n\n{len(atoms)} atoms\n2 atom types\n\n")
        fh.write(f"{min(xs) - r_in - 0.1:.6f} {max(xs) + r_in + 0.1:.6f} xlo xhi\n{min(ys) - r_in - 0.1:.6f} {max(ys) + r_in + 0.1:.6f} ylo yhi\n"
                 f"-0.1 {ztop:.6f} zlo zhi\n\nAtoms # sphere\n\n")
        for k, (x, y, z, r, d, t) in enumerate(atoms, 1):
            fh.write(f"{k} {t} {2 * r!r} {d!r} {x!r} {y!r} {z!r}\n")
    kt = 0.3 * kn
    mu = math.tan(math.radians(p.preset()["friction_deg"]))
    mur = p.preset()["rolling_friction"]
    if law == "lmp_hooke":
        pair = [f"pair_style gran/hooke/history {kn!r} {kt!r} 0.0 0.0 {mu!r} 0", "pair_coeff * *"]
        floor = f"hooke/history {kn!r} {kt!r} 0.0 0.0 {mu!r} 0"
        side = f"hooke/history {kn!r} {kt!r} 0.0 0.0 0.0 0"
    else:
        pair = ["pair_style granular", f"pair_coeff * * hooke {kn!r} 0.0 tangential linear_history {kt!r} 0.0 {mu!r} rolling sds {kt!r} 0.0 {mur!r}"]
        floor = f"granular hooke {kn!r} 0.0 tangential linear_history {kt!r} 0.0 {mu!r}"
        side = f"granular hooke {kn!r} 0.0 tangential linear_nohistory 0.0 0.0"
    L = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f m", "comm_modify vel yes", f"read_data {data}",
         "group grains type 1", f"neighbor 0.016 {'multi' if case == 'impact' else 'bin'}", "neigh_modify delay 0 every 1 check yes"]
    L += pair
    L += [f"fix floor all wall/gran {floor} zplane 0.0 NULL"]
    if copies == 1:
        L += [f"fix side all wall/gran {side} zcylinder {r_in!r}"]
    else:
        for k, (ox, oy) in enumerate(offs):
            L += [f"region cyl{k} cylinder z {ox!r} {oy!r} {r_in!r} -1.0 1000.0 side in", f"fix side{k} all wall/gran/region {side} region cyl{k}"]
    L += [f"fix grav all gravity {G!r} vector 0 0 -1", "fix integ all nve/sphere", f"timestep {a.dt!r}"]  # z shrink-wraps (m): grains thrown up by the impact stay in the box
    if imp_id:
        L += [f"group imp id {imp_id}", f"velocity imp set 0.0 0.0 {-a.speed!r}"]
        L += [f"variable fz equal fz[{imp_id}]", f"variable zi equal z[{imp_id}]", f"variable vzi equal vz[{imp_id}]", "thermo_style custom step ke v_fz v_zi v_vzi"]
    else:
        L += ["thermo_style custom step ke"]
    L += ["thermo_modify lost warn"]  # an atom lost is counted (atoms_lost), not fatal
    L += [f"thermo {a.warmup}", f"run {a.warmup}", "print 'TIMED_START'"]
    if imp_id:
        L += ["thermo 10"]
    else:
        L += [f"thermo {steps}"]
    L += [f"run {steps}", "print 'TIMED_END'",
          "compute cn all contact/atom", "compute csum grains reduce sum c_cn", "compute keg grains ke",
          "variable sp atom sqrt(vx*vx+vy*vy+vz*vz)", "compute vmax grains reduce max v_sp",
          "thermo_style custom step c_keg c_vmax c_csum atoms", "run 0"]
    path = os.path.join(workdir, f"in.{copies}_{case}_{law}")
    with open(path, "w") as fh:
        fh.write("\n".join(L) + "\n")
    return path, len(atoms), imp_id, len(grains) * copies


def thermo_rows(lines, head):
    """The numeric rows following each thermo header starting with `head`."""
    out, on = [], False
    for s in lines:
        f = s.split()
        if f and f[0] == "Step" and s.strip().startswith(head):
            on = True
            out.append([])
            continue
        if on:
            try:
                out[-1].append([float(x) for x in f])
            except ValueError:
                on = False
    return out


def run_lammps(a, p, grains, copies, case, law, kn, workdir, steps):
    inp, n, imp_id, ng = write_lammps(a, p, grains, copies, case, law, kn, workdir, steps)
    log = inp + ".log"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run([a.lmp, "-in", inp, "-log", log, "-screen", "none"], check=True, env=env, cwd=workdir)
    with open(log) as fh:
        text = fh.read()
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", text)
    timed = [float(t) for t, _, s in loops if int(s) == steps]
    if len(loops) < 2 or not timed:
        raise RuntimeError(f"no loop time for the timed run in {log}")
    t = float(loops[1][0])
    lines = text.splitlines()
    r = dict(us=1e6 * t / (steps * n), parts=lammps_sections(text, steps, n), n=n, steps=steps, dt=a.dt)
    last = thermo_rows(lines, "Step c_keg")[-1][-1]
    r.update(ke=last[1], vmax=last[2], contacts_pp=last[3] / 2 / ng, atoms_lost=n - int(last[4]))
    nb = re.findall(r"Total # of neighbors = (\d+)", text)
    if nb:
        r["neigh_pp"] = int(nb[1 if len(nb) > 1 else 0]) / n
    if imp_id:
        rows = thermo_rows(lines, "Step KinEng v_fz")
        timed_rows = rows[1] if len(rows) > 1 else rows[-1]
        R, _, d = sphere_of(a, grains, a.dt)
        m = d * 4 / 3 * math.pi * R ** 3
        z0 = timed_rows[0][3]
        r.update(peak_kN=max(abs(x[2] + m * G) for x in timed_rows[1:]) / 1e3, depth=z0 - timed_rows[-1][3], v_end=timed_rows[-1][4])
    return r


def lammps_sections(text, steps, n):
    """LAMMPS's timing breakdown of the timed run (the table after its "Loop time ... for
    <steps> steps"), average seconds -> microseconds per particle-step: Pair, Neigh, Modify, and
    Comm + Output + Other as other."""
    at = text.find(f"for {steps} steps")
    block = text[at:text.find("Loop time", at + 1)] if at >= 0 else ""
    sec = {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\w+)\s*\|\s*[0-9.eE+-]*\s*\|\s*([0-9.eE+-]+)", block, re.M)}
    if not {"Pair", "Neigh", "Modify"} <= set(sec):
        raise RuntimeError(f"no timing breakdown for the {steps}-step run in the LAMMPS log")
    us = lambda x: 1e6 * x / (steps * n)  # noqa: E731
    return {"Pair": us(sec["Pair"]), "Neigh": us(sec["Neigh"]), "Modify": us(sec["Modify"]),
            "other": us(sec.get("Comm", 0) + sec.get("Output", 0) + sec.get("Other", 0))}


# the parts of the time, ours (engine labels) and LAMMPS's (sections), in the sections table
PARTS = [("grain-grain contacts", ("grainEngine",), ("Pair",)),
         ("neighbour lists", ("collider",), ("Neigh",)),
         ("walls and facets", ("interactionLoop",), ()),
         ("integration", ("newton",), ()),
         ("LAMMPS fixes: integration, walls", (), ("Modify",)),
         ("other", None, ("other",))]


def part_of(parts, names):
    """The sum of these parts (names None: all the others than PARTS names)."""
    if names is None:
        named = {x for _, ours, theirs in PARTS if ours for x in ours} | {x for _, ours, theirs in PARTS for x in theirs}
        return sum(v for k, v in parts.items() if k not in named)
    return sum(parts.get(k, 0.0) for k in names)


def med_range(v):
    return statistics.median(v), min(v), max(v)


def main():
    a = parse()
    if a.child:
        child(a)
        return
    if not shutil.which(a.lmp):
        sys.exit(f"lammps_grains: LAMMPS ({a.lmp}) not found: install it (apt-get install lammps) or give its path with --lmp")
    p = ModuleParams()
    tag = "_quick" if a.quick else ""
    os.makedirs(a.out, exist_ok=True)
    t_all = time.time()
    grains, f = bed(p, a.cache_dir)
    kn = a.kn if a.kn is not None else lammps_kn(p, grains)
    line0 = machine_line(yade.config.version, O.numThreads)
    lv = subprocess.run([a.lmp, "-h"], capture_output=True, text=True).stdout
    lver = next((s.strip() for s in lv.splitlines() if s.startswith("Large-scale")), "?")
    print(f"lammps_grains: the fill of {f}: {len(grains)} grains; kn (LAMMPS) {kn:.4g} N/m; {lver}\n  start: {line0.strip()}", flush=True)
    sizes = [1] + ([] if a.no_big else [a.copies])
    big_eng = a.big_engines.split(",")
    raw = []
    raw_keys = ["copies", "grains", "case", "engine", "round", "us", "parts", "n", "steps", "dt", "contacts_pp", "neigh_pp", "ke", "vmax", "peak_kN", "depth", "v_end", "atoms_lost"]
    raw_fh = open(os.path.join(a.out, f"lammps_grains{tag}_raw.csv"), "w", newline="")
    raw_w = csv.DictWriter(raw_fh, fieldnames=raw_keys)
    raw_w.writeheader()
    workdir = tempfile.mkdtemp(prefix="lammps_grains_")
    for copies in sizes:
        steps = a.steps if copies == 1 else a.steps_big
        engs = ENGINES if copies == 1 else [e for e in ENGINES if e in big_eng]
        for rnd, case, e in alternated(engs, a.rounds):
            t0 = time.time()
            if e.startswith("lmp"):
                r = run_lammps(a, p, grains, copies, case, e, kn, workdir, steps)
            elif a.same_process:
                r = run_yade(a, p, grains, e, copies, case, steps)
            else:
                r = run_yade_fresh(a, copies, case, e, steps)
            r.update(copies=copies, grains=copies * len(grains), case=case, engine=e, round=rnd)
            raw.append(r)
            raw_w.writerow(dict(r, parts=";".join(f"{k}={v:.5f}" for k, v in r["parts"].items())))
            raw_fh.flush()
            extra = f", peak {r['peak_kN']:.1f} kN, depth {r['depth'] * 1e3:.0f} mm, v_end {r['v_end']:.2f} m/s" if case == "impact" else ""
            print(f"  {copies}x {case:6s} round {rnd} {e:10s} {r['us']:7.3f} us/particle-step (dt {r['dt']:.3g}), contacts/grain {r['contacts_pp']:.2f}, "
                  f"KE {r['ke']:.3g} J, vmax {r['vmax']:.3g} m/s{extra}  [{time.time() - t0:.0f} s]", flush=True)
    line1 = machine_line(yade.config.version, O.numThreads)
    print(f"  end: {line1.strip()}")

    def pick(copies, case, e, key="us"):
        return [r[key] for r in raw if r["copies"] == copies and r["case"] == case and r["engine"] == e and key in r]

    rows = []
    for copies in sizes:
        for case in ("rest", "impact"):
            for ours, theirs, what in (("flex", "lmp_gran", "rolling"), ("flex_norol", "lmp_hooke", "no rolling")):
                yo, lo = pick(copies, case, ours), pick(copies, case, theirs)
                if not yo or not lo:
                    continue
                ratios = [x / y for x, y in zip(yo, lo)]
                pl, sh = pick(copies, case, "plain"), pick(copies, case, "shipped")
                g = copies * len(grains)
                row = dict(case=f"{g} grains, {case}, {what}", yadeflex_us_per_particle_step=round(statistics.median(yo), 4),
                           lammps_us_per_particle_step=round(statistics.median(lo), 4), ratio=round(statistics.median(yo) / statistics.median(lo), 3),
                           ratio_range="%.2f-%.2f" % (min(ratios), max(ratios)), yadeflex_range="%.4g-%.4g" % (min(yo), max(yo)),
                           lammps_range="%.4g-%.4g" % (min(lo), max(lo)), lammps_law=LABELS[theirs],
                           plain_yade_us=round(statistics.median(pl), 4) if pl else "", plain_yade_range="%.4g-%.4g" % (min(pl), max(pl)) if pl else "",
                           yadeflex_over_plain=round(statistics.median(yo) / statistics.median(pl), 3) if pl else "",
                           shipped_us=round(statistics.median(sh), 4) if sh else "", shipped_dt="%.3g" % statistics.median(pick(copies, case, "shipped", "dt")) if sh else "",
                           contacts_pp_yadeflex=round(statistics.median(pick(copies, case, ours, "contacts_pp")), 3),
                           contacts_pp_lammps=round(statistics.median(pick(copies, case, theirs, "contacts_pp")), 3),
                           neighbours_pp_lammps=round(statistics.median(pick(copies, case, theirs, "neigh_pp")), 2) if pick(copies, case, theirs, "neigh_pp") else "",
                           ke_end_yadeflex_J="%.3g" % statistics.median(pick(copies, case, ours, "ke")), ke_end_lammps_J="%.3g" % statistics.median(pick(copies, case, theirs, "ke")),
                           vmax_end_yadeflex="%.3g" % statistics.median(pick(copies, case, ours, "vmax")), vmax_end_lammps="%.3g" % statistics.median(pick(copies, case, theirs, "vmax")),
                           peak_kN_yadeflex="", peak_kN_lammps="", depth_mm_yadeflex="", depth_mm_lammps="", steps=yo and pick(copies, case, ours, "steps")[0],
                           rounds=len(yo), dt=a.dt)
                if case == "impact":
                    row.update(peak_kN_yadeflex=round(statistics.median(pick(copies, case, ours, "peak_kN")), 1),
                               peak_kN_lammps=round(statistics.median(pick(copies, case, theirs, "peak_kN")), 1),
                               depth_mm_yadeflex=round(1e3 * statistics.median(pick(copies, case, ours, "depth")), 1),
                               depth_mm_lammps=round(1e3 * statistics.median(pick(copies, case, theirs, "depth")), 1))
                rows.append(row)
    print(f"\nus per particle-step, median (range) of {a.rounds} alternated rounds, one thread; ratio = yade-flex / LAMMPS")
    print(f"{'case':36s} {'yade-flex':>20s} {'LAMMPS':>20s} {'ratio':>16s} {'plain YADE':>20s} {'as shipped':>9s}  LAMMPS law")
    for r in rows:
        print(f"{r['case']:36s} {r['yadeflex_us_per_particle_step']:7.3f} ({r['yadeflex_range']:>11s}) {r['lammps_us_per_particle_step']:7.3f} ({r['lammps_range']:>11s}) "
              f"{r['ratio']:5.2f} ({r['ratio_range']:>9s}) {r['plain_yade_us'] if r['plain_yade_us'] == '' else format(r['plain_yade_us'], '7.3f'):>7} ({r['plain_yade_range']:>11s}) "
              f"{r['shipped_us'] if r['shipped_us'] == '' else format(r['shipped_us'], '9.3f'):>9}  {r['lammps_law']}")
    print("\nphysics (medians): contacts/grain ours/LAMMPS; end KE of the grains [J]; fastest grain [m/s]; sphere peak force [kN], depth [mm]")
    for r in rows:
        print(f"{r['case']:36s} {r['contacts_pp_yadeflex']:.2f}/{r['contacts_pp_lammps']:.2f}; KE {r['ke_end_yadeflex_J']}/{r['ke_end_lammps_J']}; "
              f"vmax {r['vmax_end_yadeflex']}/{r['vmax_end_lammps']}" + (f"; peak {r['peak_kN_yadeflex']}/{r['peak_kN_lammps']} kN, depth {r['depth_mm_yadeflex']}/{r['depth_mm_lammps']} mm"
                                                                        if r["peak_kN_yadeflex"] != "" else ""))
    sec_rows = []
    for copies in sizes:
        for case in ("rest", "impact"):
            for ours, theirs, what in (("flex", "lmp_gran", "rolling"), ("flex_norol", "lmp_hooke", "no rolling")):
                ry = [r for r in raw if r["copies"] == copies and r["case"] == case and r["engine"] == ours]
                rl = [r for r in raw if r["copies"] == copies and r["case"] == case and r["engine"] == theirs]
                if not ry or not rl:
                    continue
                for name, on, tn in PARTS:
                    y = statistics.median(part_of(r["parts"], on) for r in ry) if on is None or on else None
                    lm = statistics.median(part_of(r["parts"], tn) for r in rl) if tn else None
                    sec_rows.append(dict(case=f"{copies * len(grains)} grains, {case}, {what}", part=name,
                                         yadeflex_us_per_particle_step="" if y is None else round(y, 4),
                                         lammps_us_per_particle_step="" if lm is None else round(lm, 4), rounds=len(ry)))
    print("\nwhere the time goes, us per particle-step (medians): yade-flex engines (O.timingEnabled), LAMMPS's timing breakdown")
    for r in sec_rows:
        print(f"{r['case']:36s} {r['part']:34s} {str(r['yadeflex_us_per_particle_step']):>8s} {str(r['lammps_us_per_particle_step']):>8s}")
    with open(os.path.join(a.out, f"lammps_grains{tag}_sections.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(sec_rows[0]))
        w.writeheader()
        w.writerows(sec_rows)
    path = os.path.join(a.out, f"lammps_grains{tag}.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    raw_fh.close()
    shutil.rmtree(workdir, ignore_errors=True)  # the LAMMPS data files, inputs and logs of this run
    with open(os.path.join(a.out, f"lammps_grains{tag}_machine.txt"), "w") as fh:
        fh.write("start: " + line0 + "end: " + line1 + f"{lver}; grains from {os.path.basename(f)}; LAMMPS kn {kn:.6g} N/m\n")
    print(f"wrote {path} ({time.time() - t_all:.0f} s)")


if __name__ == "__main__":
    main()
