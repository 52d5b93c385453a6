# Benchmark: the module's gravel bed, stepped by the grains' kernel on arrays of its own
# (pkg/kernel/GrainNeighbours, GrainContacts; driver bench/grain_kernel.cpp, no YADE), by our
# plugin in YADE's containers, and by LAMMPS; one thread (issue 59) (GPL-2.0-or-later).
#
#     OMP_NUM_THREADS=1 yade-double -n -j1 -x bench/grain_kernel.py [--rounds 3] [--steps 5000]
#         [--warmup 200] [--quick] [--cache-dir DIR]
#
# The bed, the plugin's runs and LAMMPS's are those of bench/lammps_grains.py (imported: its
# build_yade, run_yade, run_lammps; the cached default module's 3,917 settled grains on a floor in
# a frictionless cylinder, gravity, no damping, dt 3.25e-5 s, neighbour skin 16 mm). The kernel's
# run (build/grain_kernel_bench) reads the same grains and steps them with the same law as the
# plugin's grain-grain contacts (E 1e8 Pa, ks/kn 0.3, friction 38 deg, rolling stiffness 1 and
# friction 0.1, the onset and release correction, energy terms), its own neighbour list (cells,
# rebuilt when a grain has moved half the skin, as LAMMPS's `neigh_modify check yes`) and
# leap-frog integration without orientations (as LAMMPS's nve/sphere). Its floor and cylinder are
# plain springs (grain_kernel.cpp), and it has no element, facet or ownership machinery: what it
# measures is the cost of the grain-grain contacts when their data are streams in pair order
# instead of YADE's heap objects. Cases: "rest", the bed as settled; "impact", lammps_grains.py's
# 800 kg sphere (its sphere_of) at 6.26 m/s touching the bed when the timing starts (the kernel
# pairs it with every grain directly, not by cells: GrainNeighbours.hpp).
#
# Engines, alternated round by round (the order rotated): kernel, kernel_norol (rolling
# stiffness 0), kernel_j2 (kernel on two threads: each runs half the pairs into sums of its
# own), loop, loop_norol (our plugin with the grain-grain contacts in its interaction loop, dt held),
# flex, flex_norol (the same with them in FlexGrainEngine, the kernel inside YADE, as the module's
# impact runs them: lammps_grains.py's flex runs), lmp_gran (LAMMPS granular + rolling sds),
# lmp_hooke (LAMMPS gran/hooke/history); all on one thread but kernel_j2, every run a process of
# its own. Microseconds per particle-step (wall clock), medians and ranges.
# Writes bench/results/grain_kernel[_quick].csv and grain_kernel[_quick]_raw.csv, prints a table.
import argparse
import csv
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("grain_kernel.py")), os.path.join(os.getcwd(), "bench"))
REPO = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import yade  # noqa: E402
from yade import O  # noqa: E402

from yadeflex.module import ModuleParams  # noqa: E402
from machine import machine_line  # noqa: E402

ENGINES = ["kernel", "kernel_norol", "kernel_j2", "loop", "loop_norol", "flex", "flex_norol", "lmp_gran", "lmp_hooke"]
PAIRS = (("rolling", "kernel", "loop", "flex", "lmp_gran"), ("no rolling", "kernel_norol", "loop_norol", "flex_norol", "lmp_hooke"))


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("grain_kernel.py")), 0)
    ap = argparse.ArgumentParser(prog="grain_kernel.py", description="The gravel bed: the grains' kernel, our plugin and LAMMPS, one thread (and the kernel on two).")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--warmup", type=int, default=200)
    ap.add_argument("--quick", action="store_true", help="one round of 300 steps (a smoke test)")
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "grain_kernel_bench"))
    ap.add_argument("--cache-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules"))
    ap.add_argument("--out", default=os.path.join(BENCH, "results"))
    a = ap.parse_args(sys.argv[me + 1:])
    if a.quick:
        a.rounds, a.steps = 1, 300
    return a


def lammps_args(a):
    """lammps_grains.py's settings (its defaults: dt, the LAMMPS binary), with our steps."""
    import lammps_grains as LG
    argv = sys.argv
    sys.argv = ["lammps_grains.py"]
    try:
        la = LG.parse()
    finally:
        sys.argv = argv
    la.steps, la.warmup, la.cache_dir = a.steps, a.warmup, a.cache_dir
    return LG, la


def run_kernel(a, LG, la, p, grains, rolling, case, workdir, threads=1):
    pre = p.preset()
    path = os.path.join(workdir, "grains.txt")
    if not os.path.exists(path):
        with open(path, "w") as fh:
            for c, r in grains:
                fh.write(f"{c[0]!r} {c[1]!r} {c[2]!r} {r!r}\n")
    opts = {"steps": a.steps, "warmup": a.warmup, "dt": la.dt, "young": pre["young"], "ks-over-kn": 0.3,
            "tan-phi": math.tan(math.radians(pre["friction_deg"])), "rolling-stiffness": 1.0 if rolling else 0.0,
            "rolling-friction": pre["rolling_friction"] if rolling else 0.0, "density": pre["density"], "gravity": 9.81,
            "cylinder": LG.r_in_of(p, grains), "skin": 0.016, "threads": threads}
    if case == "impact":
        R, z, dens = LG.sphere_of(la, grains, la.dt)
        opts.update({"imp-radius": R, "imp-z": z, "imp-speed": la.speed, "imp-density": dens})
    cmd = [a.binary, path] + [x for k, v in opts.items() for x in (f"--{k}", repr(float(v)))]
    out = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
    if out.returncode != 0:
        raise RuntimeError(f"grain_kernel_bench failed: {out.stderr.strip()}")
    f = next(s for s in out.stdout.splitlines() if s.startswith("GK_RESULT")).split()
    n = len(grains) + (case == "impact")
    r = dict(us=float(f[1]), contacts_pp=int(f[2]) / len(grains), pairs=int(f[3]), builds=int(f[4]), ke=float(f[5]), vmax=float(f[6]), n=n)
    if case == "impact":
        r.update(peak_kN=float(f[10]), depth=float(f[11]), v_end=float(f[12]))
    return r


def main():
    a = parse()
    if not os.path.exists(a.binary):
        sys.exit(f"grain_kernel.py: {a.binary} not found: build the project first (scripts/setup, or cmake --build build)")
    LG, la = lammps_args(a)
    p = ModuleParams()
    grains, f = LG.bed(p, a.cache_dir)
    kn = LG.lammps_kn(p, grains)
    tag = "_quick" if a.quick else ""
    os.makedirs(a.out, exist_ok=True)
    line0 = machine_line(yade.config.version, O.numThreads)
    print(f"grain_kernel: {len(grains)} grains of {os.path.basename(f)}, {a.rounds} rounds of {a.steps} steps\n  start: {line0.strip()}", flush=True)
    workdir = tempfile.mkdtemp(prefix="grain_kernel_")
    raw = []
    for rnd, case, e in LG.alternated(ENGINES, a.rounds):
        t0 = time.time()
        if e.startswith("kernel"):
            r = run_kernel(a, LG, la, p, grains, e != "kernel_norol", case, workdir, 2 if e == "kernel_j2" else 1)
        elif e.startswith("lmp"):
            r = LG.run_lammps(la, p, grains, 1, case, e, kn, workdir, a.steps)
        else:
            r = LG.run_yade_fresh(la, 1, case, e, a.steps)  # (a process of its own, as lammps_grains.py runs it)
        r.update(engine=e, round=rnd, case=case)
        raw.append(r)
        extra = f", peak {r['peak_kN']:.1f} kN, depth {r['depth'] * 1e3:.0f} mm" if case == "impact" else ""
        print(f"  round {rnd} {case:6s} {e:12s} {r['us']:7.3f} us/particle-step, contacts/grain {r['contacts_pp']:.2f}, KE {r['ke']:.3g} J, "
              f"vmax {r['vmax']:.3g} m/s{extra}  [{time.time() - t0:.0f} s]", flush=True)
    shutil.rmtree(workdir, ignore_errors=True)  # the grains file and LAMMPS's data files, inputs and logs
    line1 = machine_line(yade.config.version, O.numThreads)

    rows = []
    for case, what, kern, flex, eng, lmp in [(c,) + q for c in ("rest", "impact") for q in PAIRS]:
        def pick(e, key="us"):
            return [r[key] for r in raw if r["engine"] == e and r["case"] == case and key in r]

        def med(e, key, scale=1.0):
            v = pick(e, key)
            return round(scale * statistics.median(v), 1) if v else ""
        k, y, m, g = pick(kern), pick(flex), pick(lmp), pick(eng)
        rows.append(dict(case=f"{len(grains)} grains, {case}, {what}", kernel_us=round(statistics.median(k), 4), kernel_range="%.4g-%.4g" % (min(k), max(k)),
                         plugin_us=round(statistics.median(y), 4), plugin_range="%.4g-%.4g" % (min(y), max(y)),
                         engine_us=round(statistics.median(g), 4), engine_range="%.4g-%.4g" % (min(g), max(g)),
                         lammps_us=round(statistics.median(m), 4), lammps_range="%.4g-%.4g" % (min(m), max(m)),
                         kernel_over_lammps=round(statistics.median(k) / statistics.median(m), 3),
                         plugin_over_lammps=round(statistics.median(y) / statistics.median(m), 3),
                         plugin_over_kernel=round(statistics.median(y) / statistics.median(k), 3),
                         engine_over_lammps=round(statistics.median(g) / statistics.median(m), 3),
                         plugin_over_engine=round(statistics.median(y) / statistics.median(g), 3),
                         contacts_pp_kernel=round(statistics.median(pick(kern, "contacts_pp")), 3),
                         contacts_pp_plugin=round(statistics.median(pick(flex, "contacts_pp")), 3),
                         contacts_pp_lammps=round(statistics.median(pick(lmp, "contacts_pp")), 3),
                         contacts_pp_engine=round(statistics.median(pick(eng, "contacts_pp")), 3),
                         ke_end_kernel_J="%.3g" % statistics.median(pick(kern, "ke")), ke_end_plugin_J="%.3g" % statistics.median(pick(flex, "ke")),
                         ke_end_lammps_J="%.3g" % statistics.median(pick(lmp, "ke")),
                         peak_kN_kernel=med(kern, "peak_kN"), peak_kN_plugin=med(flex, "peak_kN"), peak_kN_lammps=med(lmp, "peak_kN"),
                         peak_kN_engine=med(eng, "peak_kN"),
                         depth_mm_kernel=med(kern, "depth", 1e3), depth_mm_plugin=med(flex, "depth", 1e3), depth_mm_lammps=med(lmp, "depth", 1e3),
                         depth_mm_engine=med(eng, "depth", 1e3),
                         kernel_two_threads_speedup=round(statistics.median(k) / statistics.median(pick("kernel_j2")), 3) if kern == "kernel" else "",
                         lammps_law=LG.LABELS[lmp], steps=a.steps, rounds=a.rounds, dt=la.dt))
    print(f"\nus per particle-step, median (range) of {a.rounds} alternated rounds, one thread")
    print(f"{'case':38s} {'kernel':>20s} {'plugin':>20s} {'grain engine':>20s} {'LAMMPS':>20s} {'kernel/LAMMPS':>14s} {'plugin/LAMMPS':>14s} {'engine/LAMMPS':>14s}")
    for r in rows:
        print(f"{r['case']:38s} {r['kernel_us']:7.3f} ({r['kernel_range']:>11s}) {r['plugin_us']:7.3f} ({r['plugin_range']:>11s}) {r['engine_us']:7.3f} ({r['engine_range']:>11s}) "
              f"{r['lammps_us']:7.3f} ({r['lammps_range']:>11s}) {r['kernel_over_lammps']:14.2f} {r['plugin_over_lammps']:14.2f} {r['engine_over_lammps']:14.2f}")
    print("\nphysics (medians), kernel/plugin/grain engine/LAMMPS: contacts per grain (the plugin's count includes the walls, LAMMPS's does not); "
          "the sphere's peak force [kN] and depth [mm]")
    for r in rows:
        print(f"{r['case']:38s} {r['contacts_pp_kernel']:.2f}/{r['contacts_pp_plugin']:.2f}/{r['contacts_pp_engine']:.2f}/{r['contacts_pp_lammps']:.2f}"
              + (f"; peak {r['peak_kN_kernel']}/{r['peak_kN_plugin']}/{r['peak_kN_engine']}/{r['peak_kN_lammps']} kN, "
                 f"depth {r['depth_mm_kernel']}/{r['depth_mm_plugin']}/{r['depth_mm_engine']}/{r['depth_mm_lammps']} mm"
                 if r["peak_kN_kernel"] != "" else ""))
    path = os.path.join(a.out, f"grain_kernel{tag}.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    keys = ["case", "engine", "round", "us", "n", "contacts_pp", "ke", "vmax", "pairs", "builds", "peak_kN", "depth", "v_end", "steps", "dt"]
    with open(os.path.join(a.out, f"grain_kernel{tag}_raw.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(raw)
    with open(os.path.join(a.out, f"grain_kernel{tag}_machine.txt"), "w") as fh:
        fh.write("start: " + line0 + "end: " + line1)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
