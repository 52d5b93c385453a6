#!/usr/bin/python3
# The impact cut in half, as a movie, from a run's VTK series (GPL-2.0-or-later).
#
#     scripts/movie.py RUN [--out DIR] [--color force|part] [--fps N] [--size W H] [--whole]
#
# RUN: a results folder of the main job (RUN/vtk/flex.pvd). Renders every frame with the ParaView
# macro py/yadeflex/paraview/open_run.py (pvpython; see yadeflex/paraview/__init__.py for
# installing it beside python3-vtk9) into DIR/frame_NNNN.png (default RUN/movie), cut by the
# vertical plane through the boulder (--whole: not cut), and with ffmpeg, if present, into
# DIR/impact.mp4. No YADE needed. Exit status 0 done, 1 no pvpython or a failed render.
import argparse
import importlib.util
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("yadeflex_paraview", os.path.join(HERE, "..", "py", "yadeflex", "paraview", "__init__.py"))
YP = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(YP)  # (without yadeflex's __init__, which needs YADE)


def main(argv):
    ap = argparse.ArgumentParser(prog="movie.py", description="The impact cut in half: PNG frames and an MP4 (ffmpeg) from a run's VTK series.")
    ap.add_argument("run", help="results folder of the main job (with vtk/flex.pvd)")
    ap.add_argument("--out", help="folder of the frames and the movie; default RUN/movie")
    ap.add_argument("--color", default="force", choices=("force", "part"))
    ap.add_argument("--fps", type=int, default=10, help="frames per second of the MP4 (a frame per 1 ms at 10 fps: 100x slower than real)")
    ap.add_argument("--size", nargs=2, type=int, default=(1280, 960), metavar=("W", "H"))
    ap.add_argument("--whole", action="store_true", help="not cut in half")
    a = ap.parse_args(argv)
    out = a.out or os.path.join(a.run, "movie")
    args = [a.run, "--frames", out, "--color", a.color, "--size", *a.size] + ([] if a.whole else ["--clip"])
    try:
        r = YP.run_open_run(args, timeout=3600)
    except RuntimeError as e:
        print(f"movie.py: {e}", file=sys.stderr)
        return 1
    if r.returncode != 0:
        print(f"movie.py: rendering failed:\n{r.stdout[-2000:]}{r.stderr[-2000:]}", file=sys.stderr)
        return 1
    print(r.stdout.strip())
    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        print("no ffmpeg: PNG frames only (Debian: apt-get install ffmpeg)")
        return 0
    mp4 = os.path.join(out, "impact.mp4")
    cmd = [ffmpeg, "-y", "-loglevel", "error", "-framerate", str(a.fps), "-i", os.path.join(out, "frame_%04d.png"),
           "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p", mp4]
    f = subprocess.run(cmd, capture_output=True, text=True)
    if f.returncode != 0:
        print(f"movie.py: ffmpeg failed: {f.stderr[-2000:]}", file=sys.stderr)
        return 1
    print(mp4)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
