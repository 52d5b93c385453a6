# pvpython on private virtual displays, several at a time, with busy loops on every core: how
# many renders fail to connect to their own live display (GPL-2.0-or-later).
#
#     /usr/bin/python3 bench/display_stress.py [--renders 45] [--at-once 3] [--busy 2] [--reset]
#         [--out bench/results/display_stress.csv]
#
# Each render: yadeflex.xdisplay.virtual_display() (Xvfb with -displayfd), then pvpython (as
# yadeflex.paraview finds it) draws a sphere to a PNG; one attempt, no retry. --reset starts
# Xvfb without -noreset (X's default: the server resets when its last client leaves), the setting
# before bc735a5. Prints the failures' first error line and the count; appends a row (machine,
# setting, renders, at once, busy loops, failures) to the CSV.
import argparse
import concurrent.futures
import csv
import importlib.util
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402

SCRIPT = """import sys
from paraview.simple import Sphere, Show, SaveScreenshot
Sphere()
Show()
SaveScreenshot(sys.argv[1], ImageResolution=[320, 240])
"""


def _load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--renders", type=int, default=45)
    ap.add_argument("--at-once", type=int, default=3)
    ap.add_argument("--busy", type=int, default=2, help="busy loops (yes >/dev/null) while it runs")
    ap.add_argument("--reset", action="store_true", help="Xvfb without -noreset (the old setting)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "display_stress.csv"))
    a = ap.parse_args()
    xd = _load("yadeflex_xdisplay", os.path.join(REPO, "py", "yadeflex", "xdisplay.py"))
    pv = _load("yadeflex_paraview", os.path.join(REPO, "py", "yadeflex", "paraview", "__init__.py"))
    found = pv.pvpython()
    if found is None:
        sys.exit("display_stress: no pvpython (see yadeflex/paraview/__init__.py)")
    cmd, env, _ = found
    if a.reset:  # the old server command line, for the comparison
        real = subprocess.Popen

        def popen(args, *k, **kw):
            if args and str(args[0]).endswith("Xvfb"):
                args = [x for x in args if x != "-noreset"]
            return real(args, *k, **kw)
        xd.subprocess.Popen = popen
    tmp = tempfile.mkdtemp(prefix="display_stress-")
    script = os.path.join(tmp, "render.py")
    with open(script, "w") as f:
        f.write(SCRIPT)

    def one(i):
        with xd.virtual_display() as d:
            r = subprocess.run(cmd + [script, os.path.join(tmp, f"{i}.png")], capture_output=True, text=True, env=dict(env, DISPLAY=d), timeout=600)
        err = next((l for l in r.stderr.splitlines() if "ERR" in l or "rror" in l), "")
        return r.returncode, err

    busy = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(a.busy)]
    try:
        with concurrent.futures.ThreadPoolExecutor(a.at_once) as ex:
            results = list(ex.map(one, range(a.renders)))
    finally:
        for p in busy:
            p.kill()
            p.wait()
    failed = [(rc, err) for rc, err in results if rc != 0]
    for rc, err in failed[:5]:
        print(f"  exit {rc}: {err.strip()[:160]}")
    setting = "Xvfb default (resets)" if a.reset else "Xvfb -noreset"
    print(f"{setting}: {len(failed)} of {a.renders} renders failed ({a.at_once} at once, {a.busy} busy loops)")
    new = not os.path.exists(a.out)
    with open(a.out, "a", newline="") as f:
        w = csv.writer(f)
        if new:
            w.writerow(["machine", "setting", "renders", "at_once", "busy_loops", "failures"])
        w.writerow([machine_line().strip(), setting, a.renders, a.at_once, a.busy, len(failed)])


if __name__ == "__main__":
    main()
