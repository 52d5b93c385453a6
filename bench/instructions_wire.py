# Instructions per step on the TECCO panel of bench/bench_wire.py, counted by valgrind's callgrind:
# YADE's WirePM against yade-flex (beams and bars) (GPL-2.0-or-later).
#
#     /usr/bin/python3 bench/instructions_wire.py [--steps 1000] [--impl all]   # about 3 min
#
# Why: on this shared VM the speed of one run drifts by 20-50% within minutes, so that a change
# of a few percent in one engine cannot be seen in times (bench_wire.py takes the median of 11
# interleaved rounds for the headline ratio). The number of instructions executed repeats from
# run to run (to 0.02% here): it tells whether a change does less work, and where. It is not a time: a cache
# miss costs many instructions' worth, and prefetching adds instructions that save time.
#
# Each implementation runs in its own `valgrind --tool=callgrind` process (a YADE step is about
# 50x slower there), which builds the same panel as bench_wire.py (the same curve, distortion
# and damping 0.2), moves its top row at 0.05 m/s, steps 101 times, then counts the
# instructions of --steps more steps (only inside Scene::moveToNextTimeStep, so Python and
# start-up are left out). Prints instructions per step and per link-step and the functions with
# the most instructions; writes bench/results/instructions_wire.csv and keeps the callgrind
# files in bench/results/callgrind/ (open them with callgrind_annotate or kcachegrind).
import argparse
import csv
import os
import re
import shutil
import subprocess
import sys

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("instructions_wire.py")), os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(HERE)
IMPLS = ("builtin WirePM", "yade-flex", "yade-flex bars")
WARMUP = 101


def inner(impl, steps):
    """Run inside YADE (under callgrind): build the panel, warm up, step."""
    sys.path.insert(0, HERE)
    sys.path.insert(0, os.path.join(ROOT, "py"))
    from yade import O, Vector3
    from yadeflex import mesh, wire
    from yadeflex.harness import tensile
    slack, ratio = mesh.TECCO_MESH_CALIBRATION["slack_scale"], mesh.TECCO_MESH_CALIBRATION["force_ratio"]
    if impl == "builtin WirePM":
        import builtin_wire as bw
        curve = list(zip(wire.TECCO_WIRE_STRAIN, wire.TECCO_WIRE_STRESS))
        bw.panel(topology="rhombic", width=1.0, height=1.0, cell=(mesh.TECCO_G65_DX, mesh.TECCO_G65_DY), wire_d=0.003,
                 strain_stress=curve, wire_type=2, lambda_u=slack, lambda_F=ratio, seed=12345, damping=0.2)
        for b in bw._PANEL["top"]:
            O.bodies[b].state.vel = Vector3(0, 0.05, 0)
        links = lambda: bw.linked_count()  # noqa: E731
    else:
        s = tensile.mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=0.05, damping=0.2,
                                     material=wire.tecco_wire(slack_scale=slack, force_ratio=ratio,
                                                              bending_factor=0.0 if impl.endswith("bars") else 1.0))
        links = lambda: sum(1 for c in s["cylinders"] if O.bodies[c] is not None)  # noqa: E731
    for _ in range(WARMUP + steps):
        O.step()
    print(f"INNER links={links()} bodies={len(O.bodies)} interactions={len(O.interactions)} iter={O.iter}", flush=True)


def count(impl, steps, outdir):
    yade = shutil.which("yade-double") or "/usr/bin/yade-double"
    out = os.path.join(outdir, "callgrind." + impl.replace(" ", "_"))
    cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--collect-atstart=no",
           "--toggle-collect=yade::Scene::moveToNextTimeStep*", "/usr/bin/python3", yade, "-n", "-j1", "-x",
           os.path.join(HERE, "instructions_wire.py"), "--inner", impl, "--steps", str(steps)]
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "py"))
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    m = re.search(r"INNER links=(\d+) bodies=(\d+) interactions=(\d+) iter=(\d+)", p.stdout)
    ir = re.search(r"I\s+refs:\s+([\d,]+)", p.stderr)
    if p.returncode != 0 or not m or not ir:
        raise SystemExit(f"instructions_wire: the callgrind run of {impl} failed (exit {p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    total = int(ir.group(1).replace(",", ""))
    # the counted steps: all steps inside moveToNextTimeStep, warm-up included (collection is
    # switched on at each call); the warm-up is the first WARMUP of them
    nsteps = int(m.group(4))
    top = subprocess.run(["callgrind_annotate", "--inclusive=no", out], capture_output=True, text=True).stdout
    rows = []
    for line in top.splitlines():
        t = re.match(r"\s*([\d,]+)\s+\(\s*([\d.]+)%\)\s+(.*)", line)
        if t and "PROGRAM TOTALS" not in line:
            name = re.sub(r"\s*\[[^\]]*\]\s*$", "", t.group(3)).split(":", 1)[-1]
            rows.append((int(t.group(1).replace(",", "")), name[:90]))
    return dict(impl=impl, links=int(m.group(1)), bodies=int(m.group(2)), interactions=int(m.group(3)), steps=nsteps,
                ir=total, ir_per_step=total / nsteps, ir_per_link_step=total / nsteps / int(m.group(1)), top=rows[:8], file=out)


def main():
    ap = argparse.ArgumentParser(prog="instructions_wire.py")
    ap.add_argument("--steps", type=int, default=1000, help="steps after the warm-up (default 1000)")
    ap.add_argument("--impl", default="all", help="all, or one of: " + ", ".join(IMPLS))
    ap.add_argument("--inner", default=None, help=argparse.SUPPRESS)
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("instructions_wire.py")), 0)
    a = ap.parse_args(sys.argv[me + 1:])
    if a.steps < 1:
        ap.error("--steps must be positive")
    if a.inner:
        return inner(a.inner, a.steps)
    impls = IMPLS if a.impl == "all" else (a.impl,)
    if any(i not in IMPLS for i in impls):
        ap.error(f"unknown --impl {a.impl!r}; one of: all, " + ", ".join(IMPLS))
    for tool in ("valgrind", "callgrind_annotate"):
        if not shutil.which(tool):
            raise SystemExit(f"instructions_wire: {tool} not found (apt-get install valgrind)")
    outdir = os.path.join(HERE, "results", "callgrind")
    os.makedirs(outdir, exist_ok=True)
    res = []
    for impl in impls:
        print(f"counting {impl} ({WARMUP} + {a.steps} steps under callgrind) ...", flush=True)
        r = count(impl, a.steps, outdir)
        res.append(r)
        print(f"  {r['ir_per_step']:,.0f} instructions per step, {r['ir_per_link_step']:,.0f} per link-step ({r['links']} links)")
        for ir, name in r["top"]:
            print(f"    {ir / r['steps']:10,.0f}  {name}")
    ref = next((r for r in res if r["impl"] == "builtin WirePM"), None)
    print(f"\n{'implementation':16s} {'links':>5s} {'instr/step':>11s} {'instr/link-step':>15s} {'WirePM / this':>13s}")
    for r in res:
        ratio = ref["ir_per_link_step"] / r["ir_per_link_step"] if ref else float("nan")
        r["builtin_over_this"] = ratio
        print(f"{r['impl']:16s} {r['links']:5d} {r['ir_per_step']:11,.0f} {r['ir_per_link_step']:15,.0f} {ratio:13.2f}")
    path = os.path.join(HERE, "results", "instructions_wire.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["impl", "links", "bodies", "interactions", "steps_counted", "instructions", "per_step", "per_link_step", "builtin_over_this"])
        for r in res:
            w.writerow([r["impl"], r["links"], r["bodies"], r["interactions"], r["steps"], r["ir"], round(r["ir_per_step"]),
                        round(r["ir_per_link_step"], 1), round(r["builtin_over_this"], 3)])
    print("wrote", path)


if __name__ == "__main__":
    main()
