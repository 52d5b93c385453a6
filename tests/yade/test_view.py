"""YADE's 3D view draws yade-flex cylinders, facets and nodes (Gl1 functors, pkg/yade/FlexGl.cpp).

scripts/view_scene.py runs in yade-double with its Qt GUI on a virtual X server and saves PNG
snapshots of one scene in several display states: a red ring (left), a green chain (middle, its
middle node with a yellow display radius 3x the wire's) and a blue membrane sheet (right), seen
along +y and from above. Pixels are compared with the snapshot drawn with no shapes at all
(renderer.shape = False), so the scale overlay does not count.
"""
import json
import os
import shutil
import time

import pytest

from conftest import HERE, run_yade
import yadeflex as yf

np = pytest.importorskip("numpy")
Image = pytest.importorskip("PIL.Image", reason="python3-pil (Debian) reads the snapshots")

MARGIN = 40  # a colour class: its channel exceeds both others by this much [0-255]


def _load(out, name):
    return np.asarray(Image.open(os.path.join(out, name + ".png")).convert("RGB")).astype(int)


def _classes(img, background):
    """Masks of the pixels that differ from the empty view, by dominant colour."""
    fg = np.abs(img - background).max(axis=2) > 0
    R, G, B = img[..., 0], img[..., 1], img[..., 2]
    return dict(
        fg=fg,
        red=fg & (R > G + MARGIN) & (R > B + MARGIN),
        green=fg & (G > R + MARGIN) & (G > B + MARGIN),
        blue=fg & (B > R + MARGIN) & (B > G + MARGIN),
        yellow=fg & (R > B + MARGIN) & (G > B + MARGIN) & (np.abs(R - G) < MARGIN),
        grey=fg & (img.max(axis=2) - img.min(axis=2) < 25),
    )


def _box(mask, what):
    assert mask.any(), f"no {what} pixels in the snapshot"
    ys, xs = np.nonzero(mask)
    return ys.min(), ys.max() + 1, xs.min(), xs.max() + 1


def _count(mask, box):
    y0, y1, x0, x1 = box
    return int(mask[y0:y1, x0:x1].sum())


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb not found (Debian package xvfb): the 3D view needs an X server")
    out = str(tmp_path_factory.mktemp("view"))
    t0 = time.time()
    run_yade(os.path.join(HERE, "scripts", "view_scene.py"), args=[out], timeout=120, display=True)
    wall = time.time() - t0
    with open(os.path.join(out, "view.json")) as f:
        info = json.load(f)
    names = ["all", "none", "no_cylinders", "no_elements", "nodes", "wire", "force_auto", "force_user", "force_auto_later", "running"]
    imgs = {n: _load(out, n) for n in names}
    bg = imgs["none"]
    cls = {n: _classes(imgs[n], bg) for n in names}
    a = cls["all"]
    boxes = {"ring": _box(a["red"], "red (ring)"), "chain": _box(a["green"], "green (chain)"), "sheet": _box(a["blue"], "blue (sheet)")}
    print(f"\nview test: yade run {wall:.1f} s, scene script {info['total_seconds']:.2f} s, screen {info['screen']}, "
          f"foreground {int(a['fg'].sum())} px, regions {boxes}")
    return dict(out=out, info=info, imgs=imgs, cls=cls, boxes=boxes)


def test_snapshot_is_not_empty(shots):
    a, img = shots["cls"]["all"], shots["imgs"]["all"]
    n = a["fg"].size
    assert a["fg"].sum() > 0.01 * n, f"only {a['fg'].sum()} of {n} pixels differ from the empty view"
    colours = len(np.unique(img[a["fg"]].reshape(-1, 3), axis=0))
    assert colours >= 50, f"the elements are drawn in {colours} colours: expected lit, shaded surfaces"
    assert shots["cls"]["none"]["fg"].sum() == 0


def test_each_element_type_is_drawn_where_it_is(shots):
    a, boxes = shots["cls"]["all"], shots["boxes"]
    # ring 0.3 m across, bar d = 20 mm; chain 0.5 m long; sheet 0.3 x 0.3 m: sizes on screen
    assert a["red"].sum() > 1000 and a["green"].sum() > 500 and a["blue"].sum() > 2500, {k: int(a[k].sum()) for k in ("red", "green", "blue")}
    # left to right as along x in the scene, not overlapping
    assert boxes["ring"][3] < boxes["chain"][2] and boxes["chain"][3] < boxes["sheet"][2], boxes
    # a ring, not a disc: its centre shows the background
    y0, y1, x0, x1 = boxes["ring"]
    assert not a["fg"][(y0 + y1) // 2, (x0 + x1) // 2]
    assert a["fg"][(y0 + y1) // 2, x0:x0 + 15].any()
    # the snapshot is the three elements and nothing else
    assert sum(_count(a["fg"], b) for b in boxes.values()) == a["fg"].sum()


def test_hiding_the_elements_removes_their_pixels(shots):
    cls, boxes = shots["cls"], shots["boxes"]
    nc = cls["no_cylinders"]
    assert _count(nc["fg"], boxes["ring"]) == 0 and _count(nc["fg"], boxes["chain"]) == 0
    assert _count(nc["blue"], boxes["sheet"]) == _count(cls["all"]["blue"], boxes["sheet"])
    # all elements hidden: the nodes (not drawn by default) leave the view empty
    assert np.array_equal(shots["imgs"]["no_elements"], shots["imgs"]["none"])


def test_nodes_are_drawn_on_request_at_their_position(shots):
    cls, boxes = shots["cls"], shots["boxes"]
    assert cls["all"]["yellow"].sum() == 0
    yellow = cls["nodes"]["yellow"]
    assert yellow.sum() > 100, f"{yellow.sum()} yellow pixels for the middle node (radius 30 mm)"
    # the middle node of the chain: at the middle of the chain's box, both ways
    ys, xs = np.nonzero(yellow)
    y0, y1, x0, x1 = boxes["chain"]
    assert abs(xs.mean() - 0.5 * (x0 + x1)) < 10 and abs(ys.mean() - 0.5 * (y0 + y1)) < 10, (xs.mean(), ys.mean(), boxes["chain"])


def test_wire_mode_draws_outlines(shots):
    cls, boxes = shots["cls"], shots["boxes"]
    for name, colour in (("ring", "red"), ("chain", "green"), ("sheet", "blue")):
        solid, wire = _count(cls["all"][colour], boxes[name]), _count(cls["wire"][colour], boxes[name])
        assert 0 < wire < 0.5 * solid, f"{name}: {wire} wire pixels, {solid} solid"


def test_colour_by_force(shots):
    info, cls, boxes = shots["info"], shots["cls"], shots["boxes"]
    M, Mn = info["max_abs_axial_force"], info["max_abs_n1"]
    assert M > 0 and Mn > 0
    # automatic range: +- the largest |value| in the scene, computed at the start of the frame
    assert info["cylinder_range_auto"] == [-M, M]
    assert info["facet_range_auto"] == [-Mn, Mn]
    fa = cls["force_auto"]
    ring = boxes["ring"]
    # the fully clamped ring carries no force: grey (lit), no red nor blue
    assert _count(fa["red"], ring) == 0 and _count(fa["blue"], ring) == 0
    assert _count(fa["grey"], ring) > 0.9 * _count(fa["fg"], ring)
    # the chain: no longer its own green; the element at the largest |force| is fully red or blue
    chain = boxes["chain"]
    assert _count(fa["green"], chain) == 0
    assert _count(fa["red"], chain) + _count(fa["blue"], chain) > 50
    # the sheet: n1 >= 0 (tension-only fabric), no blue
    assert _count(fa["blue"], boxes["sheet"]) == 0 and _count(fa["red"], boxes["sheet"]) > 0.5 * _count(fa["fg"], boxes["sheet"])
    M2 = info["max_abs_axial_force_later"]
    assert M2 != M and info["cylinder_range_auto_later"] == [-M2, M2], "the automatic range did not follow the forces"
    # user ranges: every force above the cylinders' range (all red), every n1 below the facets' (all blue)
    fu = cls["force_user"]
    assert info["cylinder_range_user"][1] < -M and info["facet_range_user"][0] > Mn
    for name in ("ring", "chain"):
        assert _count(fu["red"], boxes[name]) == _count(fu["fg"], boxes[name]) > 0
    assert _count(fu["blue"], boxes["sheet"]) == _count(fu["fg"], boxes["sheet"]) > 0


def test_drawing_while_running(shots):
    assert shots["info"]["iter_after_running"] > 3001
    r, boxes = shots["cls"]["running"], shots["boxes"]
    assert _count(r["red"], boxes["ring"]) > 0.9 * _count(shots["cls"]["all"]["red"], boxes["ring"])  # the ring is clamped
    assert _count(r["green"], boxes["chain"]) > 0 and _count(r["blue"], boxes["sheet"]) > 0


@pytest.fixture(scope="module")
def part_shots(tmp_path_factory):
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb not found (Debian package xvfb): the 3D view needs an X server")
    out = str(tmp_path_factory.mktemp("view_parts"))
    run_yade(os.path.join(HERE, "scripts", "view_parts.py"), args=[out], timeout=120, display=True)
    with open(os.path.join(out, "parts.json")) as f:
        info = json.load(f)
    imgs = {n: _load(out, n) for n in ("parts", "force", "none")}
    return dict(info=info, imgs=imgs)


def _part_pixels(img, background, rgb):
    """Pixels drawn (not the empty view's) in the hue of rgb, at least half its saturation: lighting
    scales a colour and keeps its hue."""
    from matplotlib.colors import rgb_to_hsv
    hsv = rgb_to_hsv(img / 255.0)
    h0, s0, _ = rgb_to_hsv(np.array(rgb, dtype=float))
    dh = np.abs(hsv[..., 0] - h0)
    dh = np.minimum(dh, 1 - dh)
    fg = np.abs(img - background).max(axis=2) > 0
    return fg & (dh < 0.04) & (hsv[..., 1] > 0.5 * s0) & (hsv[..., 2] > 0.15)


def test_view_colours_the_parts(part_shots):
    """Ring, mesh, rope, lining, grains, boulder left to right, each in its part's colour."""
    P = yf.parts
    info, imgs = part_shots["info"], part_shots["imgs"]
    assert info["counts"] == {"ring": 24, "mesh": 13 + 24, "rope": 13, "lining": 16 * 2 + 25, "grain": 2, "boulder": 9}
    names = ("ring", "mesh", "rope", "lining", "grain", "boulder")
    masks = {n: _part_pixels(imgs["parts"], imgs["none"], P.COLORS[n]) for n in names}
    counts = {n: int(m.sum()) for n, m in masks.items()}
    assert all(c > 150 for c in counts.values()), counts
    # where they stand: left to right in the order built (x of each part's pixels, median)
    xs = [float(np.median(np.nonzero(masks[n])[1])) for n in names]
    assert xs == sorted(xs), dict(zip(names, xs))


def test_view_colour_by_force_recolours_the_elements_only(part_shots):
    P = yf.parts
    info, imgs = part_shots["info"], part_shots["imgs"]
    assert max(info["mesh_forces"]) > 0
    parts = {n: int(_part_pixels(imgs["parts"], imgs["none"], P.COLORS[n]).sum()) for n in P.COLORS}
    force = {n: int(_part_pixels(imgs["force"], imgs["none"], P.COLORS[n]).sum()) for n in P.COLORS}
    for n in ("ring", "mesh", "rope", "lining"):  # by force: red, grey, blue; not their part colours (red ring aside)
        assert force[n] < (0.5 if n == "ring" else 0.1) * parts[n], (n, force[n], parts[n])
    for n in ("grain", "boulder"):
        assert force[n] > 0.9 * parts[n], (n, force[n], parts[n])


def test_without_a_display_the_view_says_so(scene):
    # in-process YADE runs without GUI, like yade -n
    with pytest.raises(RuntimeError, match="Qt GUI"):
        yf.view()
    with pytest.raises(RuntimeError, match="view"):
        yf.snapshot("never.png")
