"""ParaView for yade-flex runs: open_run.py (a pvpython script and ParaView macro) opens a
results folder with colours, tubes and glyphs set, and renders frames to PNG; this module finds
pvpython and runs it (for scripts/movie.py and the tests).

pvpython comes with Debian's paraview package. On Debian 12 that package's python3-paraview
conflicts with python3-vtk9, which yade-flex's VTK writer needs (installing paraview removes
python3-vtk9). Both can live on one machine with paraview unpacked beside the system rather
than installed: `apt-get download paraview python3-paraview` and `dpkg -x` both into DIR; then
set YADEFLEX_PVPYTHON=DIR/usr/bin/pvpython (its libraries and Python modules are found under DIR).
scripts/setup does this into UNPACKED (as root), which is looked at last.
"""
import os
import shutil
import subprocess

OPEN_RUN = os.path.join(os.path.dirname(os.path.abspath(__file__)), "open_run.py")
UNPACKED = "/opt/yadeflex-paraview/usr/bin/pvpython"  # where scripts/setup unpacks ParaView


def pvpython():
    """(command, environment, display) to run pvpython, or None if there is none: YADEFLEX_PVPYTHON
    (a pvpython, installed or unpacked; an unpacked one gets its libraries and modules), else
    pvpython on PATH, else the one scripts/setup unpacked (UNPACKED). display: whether it needs a
    virtual X display (no DISPLAY set: Debian's ParaView renders through X, also offscreen; then
    Xvfb must be installed, else None)."""
    env = dict(os.environ)
    exe = os.environ.get("YADEFLEX_PVPYTHON") or shutil.which("pvpython") or (UNPACKED if os.path.exists(UNPACKED) else None)
    if not exe or not os.access(exe, os.X_OK):
        return None
    prefix = os.path.dirname(os.path.dirname(os.path.abspath(exe)))  # DIR/usr
    if prefix != "/usr":
        libs = os.path.join(prefix, "lib", "x86_64-linux-gnu")
        mods = os.path.join(prefix, "lib", "python3", "dist-packages")
        env["LD_LIBRARY_PATH"] = os.pathsep.join(p for p in (libs, env.get("LD_LIBRARY_PATH")) if p)
        env["PYTHONPATH"] = mods  # its own vtkmodules, not the system's
    display = not env.get("DISPLAY")
    if display and shutil.which("Xvfb") is None:
        return None
    return [exe, "--force-offscreen-rendering"], env, display


def _xdisplay():
    """yadeflex/xdisplay.py, loaded from its file: this module is also loaded on its own, without
    the yadeflex package (which needs YADE), by scripts/movie.py."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("yadeflex_xdisplay", os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "xdisplay.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def run_open_run(args, timeout=600):
    """Run open_run.py with args under pvpython (on a virtual display of its own when there is no
    DISPLAY, see yadeflex.xdisplay); returns the CompletedProcess (text output). Raises
    RuntimeError if there is no pvpython (see pvpython())."""
    found = pvpython()
    if found is None:
        raise RuntimeError("no pvpython: install Debian's paraview (it removes python3-vtk9, see yadeflex.paraview), "
                           "or set YADEFLEX_PVPYTHON; without a display Xvfb (Debian package xvfb) is needed too")
    cmd, env, display = found
    cmd = cmd + [OPEN_RUN] + [str(a) for a in args]
    if not display:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    # each attempt on a display of its own; a failed attempt's output is kept above the next one's
    earlier = ""
    for attempt in range(3):
        with _xdisplay().virtual_display() as d:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=dict(env, DISPLAY=d))
        if "bad X server connection" not in r.stderr and not (r.returncode != 0 and "XOpenGLRenderWindow" in r.stderr):
            break
        earlier += f"--- pvpython attempt {attempt + 1} on display {d} failed (exit {r.returncode}):\n{r.stderr[-3000:]}\n"
    r.stderr = earlier + r.stderr
    return r
