"""The shipped ParaView macro (py/yadeflex/paraview/open_run.py) renders a small run's frame
offscreen, each part in its colour (yadeflex.parts.COLORS).

Needs pvpython (Debian's paraview, installed or unpacked: yadeflex.paraview) and, without a
display, Xvfb; skipped, with the reason, without them. The run: the reduced module with
VTK, 10 ms after the first contact, from the tests' module cache.
"""
import os

import numpy as np
import pytest

from yadeflex import parts as P
from yadeflex import paraview as YP

Image = pytest.importorskip("PIL.Image", reason="python3-pil (Debian) reads the pictures")
colors = pytest.importorskip("matplotlib.colors")

HUE_TOL = 0.04  # [-] of the hue circle: lighting scales a colour, it keeps its hue


def _hue_mask(img, rgb):
    """Pixels of the part colour rgb as lit: its hue, at least half its saturation, not dark."""
    hsv = colors.rgb_to_hsv(img / 255.0)
    h0, s0, _ = colors.rgb_to_hsv(np.array(rgb, dtype=float))
    dh = np.abs(hsv[..., 0] - h0)
    dh = np.minimum(dh, 1 - dh)
    return (dh < HUE_TOL) & (hsv[..., 1] > 0.5 * s0) & (hsv[..., 2] > 0.15)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory, module_cache):
    if YP.pvpython() is None:
        pytest.skip("no pvpython (Debian paraview; it removes python3-vtk9, so unpack it and set YADEFLEX_PVPYTHON: "
                    "see yadeflex/paraview/__init__.py) or, without a display, no Xvfb (Debian package xvfb)")
    from yadeflex.module.impact import run_impact
    from yadeflex.module import ModuleParams
    out = str(tmp_path_factory.mktemp("pvrun"))
    s = run_impact(ModuleParams.small(), out, cache_dir=module_cache, progress=False, duration=0.01)
    assert s["status"] == "done", s
    return out


def _render(run_dir, name, *args):
    png = os.path.join(run_dir, name)
    r = YP.run_open_run([run_dir, "--png", png, "--size", 640, 480, *args], timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert "after the first contact" in r.stdout
    return np.asarray(Image.open(png).convert("RGB")).astype(float)


def test_each_part_in_its_colour(run_dir):
    # cut in half, grains opaque (no force chains): every part shows
    img = _render(run_dir, "parts.png", "--color", "part", "--clip", "--no-contacts")
    counts = {name: int(_hue_mask(img, P.COLORS[name]).sum()) for name in ("mesh", "ring", "lining", "grain", "boulder")}
    # at 640 x 480 the smallest part on screen, the ring, covers some hundred pixels
    assert all(n > 100 for n in counts.values()), counts
    # the background is white: what is not white is the scene
    assert (img.min(axis=2) < 250).mean() > 0.05


def test_colour_by_force_and_force_chains(run_dir):
    parts = _render(run_dir, "parts_chains.png", "--color", "part", "--clip")
    bare = _render(run_dir, "parts.png", "--color", "part", "--clip", "--no-contacts")
    force = _render(run_dir, "force.png", "--clip", "--no-contacts")
    # the same scene coloured by force: the pixels of the wires and the lining leave their part
    # colours (the maps' own blues and greens may fall on some of them); the boulder keeps its own
    for name in ("mesh", "ring", "lining"):
        was = _hue_mask(bare, P.COLORS[name])
        kept = int((was & _hue_mask(force, P.COLORS[name])).sum())
        assert kept < 0.5 * was.sum(), (name, kept, int(was.sum()))
    boulder = _hue_mask(bare, P.COLORS["boulder"])
    assert (boulder & _hue_mask(force, P.COLORS["boulder"])).sum() > 0.9 * boulder.sum() > 1000
    # force chains: black tubes (no part colour is dark), only where contacts are shown
    black = lambda img: int((img.max(axis=2) < 40).sum())
    assert black(parts) > 200 and black(bare) < 0.1 * black(parts), (black(parts), black(bare))


def test_bad_folder_is_named(tmp_path):
    if YP.pvpython() is None:
        pytest.skip("no pvpython")
    r = YP.run_open_run([tmp_path, "--png", tmp_path / "x.png"], timeout=120)
    assert r.returncode == 1 and "no VTK series" in r.stderr


def test_movie_frames(run_dir, tmp_path):
    """scripts/movie.py: one PNG per frame of the series, each showing the scene; an MP4 with ffmpeg."""
    import shutil
    import subprocess
    import sys
    import xml.etree.ElementTree as ET
    from conftest import REPO
    out = tmp_path / "movie"
    r = subprocess.run([sys.executable, os.path.join(REPO, "scripts", "movie.py"), run_dir, "--out", str(out), "--size", "320", "240"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    times = {float(d.get("timestep")) for d in ET.parse(os.path.join(run_dir, "vtk", "flex.pvd")).getroot().iter("DataSet")}
    frames = sorted(f for f in os.listdir(out) if f.startswith("frame_"))
    assert len(frames) == len(times) > 5
    for f in (frames[0], frames[-1]):
        img = np.asarray(Image.open(out / f).convert("RGB")).astype(float)
        assert (img.min(axis=2) < 250).mean() > 0.05, f
    assert (out / "impact.mp4").exists() == (shutil.which("ffmpeg") is not None)
