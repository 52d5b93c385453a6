"""Tensile-test scenes and drivers, defined once, used by scripts/tensile_*.py and the tests.

Every driver resets O, builds its scene with unit-annotated parameters, runs it and returns a
dict with the measured curve (lists) and the parameters used.
"""
import math

from yade import O
from yade.minieigenHP import Vector3

from .. import builders as B
from .. import checks as C
from ..scene import engines, engine_args, step_until
from .scenes import _check_chain


def single_wire(material, length=0.1, radius=0.0015, segments=1, damping=0.0):
    """A straight wire (or rope, bar) along x, clamped at node 0; the last node is driven (all
    its DOFs blocked) by drive_strains. length, radius [m]; damping [-] Cundall's local damping
    of the free inner nodes (segments > 1). Returns dict(nodes, cylinders, driven, params)."""
    _check_chain(segments, length, radius, material)
    engine_args(damping=damping)
    O.reset()
    nodes, cyls = B.chain([(0, 0, 0), (length, 0, 0)], radius, material, segments=segments, fixed=[0, segments])
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    return dict(nodes=nodes, cylinders=cyls, driven=nodes[-1],
                params=dict(length=length, radius=radius, segments=segments, damping=damping))


def drive_strains(scene, strains, steps_per_unit_strain=2e5, dt=None):
    """Displacement control of `single_wire`: move the driven node so that the wire's total
    strain goes linearly through `strains` (each a target reached exactly, at a step end).
    Between targets the node moves at constant velocity over ceil(|de| x steps_per_unit_strain)
    steps. Returns lists (strain, force of the first cylinder or None once it ruptured, or the
    force on the driven node if `scene` has several segments, iteration)."""
    try:
        strains = [C.number("strains", e, C.Range(-0.9, 10.0)) for e in strains]
    except TypeError:
        raise C.BadValue("strains", strains, "a sequence of numbers") from None
    C.number("steps_per_unit_strain", steps_per_unit_strain, C.Range(1.0, 1e8))
    if dt is not None:
        C.positive("dt", dt, "s")
    L = scene["params"]["length"]
    d = O.bodies[scene["driven"]]
    c0 = scene["cylinders"][0]
    O.step()  # time step and collider set up
    if dt is not None:
        O.dt = dt
    out_e, out_f, out_i = [], [], []
    e_now = (d.state.pos[0] - L) / L
    for target in strains:
        n = max(1, int(math.ceil(abs(target - e_now) * steps_per_unit_strain)))
        x0, x1 = L * (1 + e_now), L * (1 + target)
        for k in range(1, n + 1):
            # position set exactly (no accumulated round-off), velocity consistent with it
            d.state.pos = Vector3(x0 + (x1 - x0) * k / n, 0, 0)
            d.state.vel = Vector3(0, 0, 0)
            O.step()
            b = O.bodies[c0]
            out_e.append((d.state.pos[0] - L) / L)
            if len(scene["cylinders"]) > 1:
                out_f.append(-O.forces.f(scene["driven"])[0])
            else:
                out_f.append(b.shape.axialForce if b is not None else None)
            out_i.append(O.iter)
        e_now = target
    return out_e, out_f, out_i


def wire_through_knots(material, length=0.1, radius=0.0015, steps_per_unit_strain=4e4):
    """A single wire of `material` (a FlexMat with a wire curve) driven to each point ('knot')
    of its input curve in turn. Returns dict(strain, force: the driven record, worst: the largest
    relative force error at the knots, engine: the scene's FlexElementEngine, scene)."""
    s = single_wire(material, length=length, radius=radius)
    O.trackEnergy = True
    knots_e, knots_s = list(material.wireStrain), list(material.wireStress)
    e, f, _ = drive_strains(s, knots_e, steps_per_unit_strain=steps_per_unit_strain)
    A = math.pi * radius ** 2
    worst = 0.0
    for ek, sk in zip(knots_e, knots_s):
        k = min(range(len(e)), key=lambda i: abs(e[i] - ek))
        if abs(e[k] - ek) > 1e-12 or f[k] is None:
            return dict(strain=e, force=f, worst=math.inf, scene=s)
        worst = max(worst, abs(f[k] - sk * A) / (sk * A))
    return dict(strain=e, force=f, worst=worst, scene=s)


def _edge_force(ids, axis):
    return sum(O.forces.f(i)[axis] for i in ids)


def _panel(direction, width, height, speed, damping, material, seed, knots):
    """The inputs of a panel test checked, O reset, the TECCO G65/3 panel width x height [m] of
    material (None: yadeflex.wire.tecco_wire(seed=seed)) built; (panel dict, material, the pull's
    axis: 1 longitudinal, along the spirals; 0 transverse)."""
    from ..mesh import chain_link_panel, panel_counts
    from ..wire import tecco_wire
    C.choice("direction", direction, ("longitudinal", "transverse"))
    B._positive("speed", speed)
    engine_args(damping=damping)
    if material is not None:
        B._material(material, append=False)
    panel_counts(width, height)
    O.reset()
    mat = material if material is not None else tecco_wire(seed=seed)
    return chain_link_panel(width, height, mat, knots=knots), mat, (1 if direction == "longitudinal" else 0)


def mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=0.5, damping=0.2, seed=12345, material=None,
                     clamp="pinned", knots=False):
    """TECCO G65/3 panel (yadeflex.mesh.chain_link_panel) clamped on two opposite edges; one
    edge held, the other driven outwards at `speed` [m/s] (all its DOFs blocked).
    direction: 'longitudinal' (pull along the spirals, y: the datasheet's 150 kN/m, see
    yadeflex.mesh) or 'transverse' (across the spirals, x). width, height [m] along x, y; damping [-] Cundall's
    local damping (quasi-static); clamp: 'pinned' (edge knots held in translation, free to turn,
    as wires wrapped around a clamping bar) or 'fixed'; knots: the panel's knot model
    (yadeflex.mesh.chain_link_panel). Returns dict(held, driven, axis, length, loaded_width, ...)."""
    C.choice("clamp", clamp, ("pinned", "fixed"))
    p, mat, axis = _panel(direction, width, height, speed, damping, material, seed, knots)
    held, driven = (p["edges"]["left"], p["edges"]["right"]) if axis == 0 else (p["edges"]["bottom"], p["edges"]["top"])
    dofs = "xyz" if clamp == "pinned" else "xyzXYZ"
    B.fix(held, dofs)
    B.fix(driven, dofs)
    v = Vector3(0, 0, 0)
    v[axis] = B._positive("speed", speed)
    for i in driven:
        O.bodies[i].state.vel = v
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    length = p["params"]["width"] if axis == 0 else p["params"]["height"]
    loaded_width = p["params"]["height"] if axis == 0 else p["params"]["width"]
    p.update(held=held, driven=driven, axis=axis, length=length, loaded_width=loaded_width, material=mat,
             params=dict(p["params"], direction=direction, clamp=clamp, speed=speed, damping=damping, seed=seed, knots=knots,
                         slack_scale=mat.wireSlackScale, force_ratio=mat.wireForceRatio))
    return p


# the largest difference of the two clamped edges' forces (relative) at which a panel test is
# quasi-static (the shared-node panels' peaks are balanced far more closely: mesh_summary.csv's
# edge_unbalance_at_peak)
QUASI_STATIC = 0.02


def mesh_tensile_test(scene, max_elongation=0.8, chunk=200, stop_fraction=0.3, measure="mean"):
    """Run `mesh_panel_scene` (or `tecco_modellers_scene`) until links have ruptured and the force fell below
    stop_fraction x its peak, or the elongation reaches max_elongation [-]. Returns dict with lists elongation [-]
    and force per metre of loaded width [N/m] (measure 'mean': the mean of the driven and the held
    edge; 'driven': the driven edge's reaction alone), the peak
    and the elongation at the peak, the quasi-static peak (the largest force while the two edges'
    forces agree within QUASI_STATIC: a transient of a rupture, where they do not, is inertia,
    not strength) and its elongation, ruptured links and the engines' time, and the lists of the
    driven and the held edge's reactions along the pull per metre [N/m] (driven_per_m, held_per_m:
    the supports' forces on the edge nodes, positive pulling the panel apart). A scene with
    restrained side edges (`sides`) adds side_per_m: the reaction across the pull on the side at
    the far coordinate (positive holding the panel from contracting) per metre of length along
    the pull [N/m], and side_per_m_at_peak."""
    C.positive("max_elongation", max_elongation, hi=10.0)
    C.integer("chunk", chunk, 1)
    C.number("stop_fraction", stop_fraction, C.Range(0.0, 1.0, hi_open=True))
    C.choice("measure", measure, ("mean", "driven"))
    ax, L, w = scene["axis"], scene["length"], scene["loaded_width"]
    x0 = O.bodies[scene["driven"][0]].state.pos[ax]
    el, fm, unbalance, drv, hld, side = [], [], [], [], [], []
    across = 1 - ax
    sides = scene.get("sides") or []
    far = [i for i in sides if O.bodies[i].state.pos[across] > 0.5 * max(O.bodies[j].state.pos[across] for j in sides)] if sides else []
    peak, e_peak = 0.0, 0.0
    eng = next(x for x in O.engines if type(x).__name__ == "FlexElementEngine")
    O.step()
    while True:
        step_until(math.inf, chunk)
        e = (O.bodies[scene["driven"][0]].state.pos[ax] - x0) / L
        f_drv = -_edge_force(scene["driven"], ax)
        f_hld = _edge_force(scene["held"], ax)
        f = (0.5 * (f_drv + f_hld) if measure == "mean" else f_drv) / w
        el.append(e)
        fm.append(f)
        drv.append(f_drv / w)
        hld.append(f_hld / w)
        side.append(-_edge_force(far, across) / L)
        unbalance.append(abs(f_drv - f_hld) / max(abs(f_drv), abs(f_hld), 1e-30))
        if f > peak:
            peak, e_peak = f, e
        if (eng.nRuptured > 0 and f < stop_fraction * peak) or e >= max_elongation:
            break
    k_peak = fm.index(peak)
    qs = [k for k in range(len(fm)) if unbalance[k] <= QUASI_STATIC]
    k_qs = max(qs, key=lambda k: fm[k]) if qs else None
    return dict(elongation=el, force_per_m=fm, peak=peak, elongation_at_peak=e_peak, ruptured=eng.nRuptured,
                unbalance_at_peak=unbalance[k_peak], quasi_static_peak=fm[k_qs] if qs else float("nan"),
                elongation_at_quasi_static_peak=el[k_qs] if qs else float("nan"), iterations=O.iter, dt=O.dt,
                driven_per_m=drv, held_per_m=hld, **(dict(side_per_m=side, side_per_m_at_peak=side[k_peak]) if sides else {}))


def tecco_panel_test(direction="longitudinal", width=1.0, speed=1.0, seed=12345, slack_scale=None, knots=False):
    """The TECCO G65/3 panel test of scripts/tensile_mesh.py and the validation report: a panel 1 m
    long in the pulling direction and `width` [m] across it, the wire of yadeflex.wire.tecco_wire
    (seed, slack_scale: None for its calibration), pulled at speed [m/s] to rupture
    (mesh_tensile_test); knots: the knot model (yadeflex.mesh.chain_link_panel).
    Returns (scene, result, wall seconds)."""
    import time
    from ..wire import tecco_wire
    t = time.time()
    mat = tecco_wire(seed=seed, slack_scale=slack_scale)
    w, h = (width, 1.0) if direction == "longitudinal" else (1.0, width)  # loaded width across the pull
    s = mesh_panel_scene(width=w, height=h, direction=direction, speed=speed, seed=seed, material=mat, knots=knots)
    r = mesh_tensile_test(s, chunk=400, max_elongation=0.9)
    return s, r, time.time() - t


# The TECCO G65/3 tensile test as the mesh's modellers set it up in YADE (their published scripts,
# anna-effeindzourou/trunk, examples/anna_scripts/tensile_test): a specimen of
# 13 openings across the spirals (x) by 7 along them (y), 1.079 x 1.001 m; the edges parallel to
# the pull held across it and out of the plane, free along it; the test stops at 70 mm.
MODELLERS_WIDTH = 13 * 0.083  # [m] along x, across the spirals (13 x TECCO_G65_DX)
MODELLERS_LENGTH = 7 * 0.143  # [m] along y, along the spirals (7 x TECCO_G65_DY)
MODELLERS_STOP = 0.070  # [m] the driven edge's travel at which their test stops
# Their trial stress-strain points of the 3 mm TECCO wire (strain [-], stress [Pa]), for comparison only
MODELLERS_WIRE_POINTS = ((0.0125, 1.67e9), (0.020, 1.77e9), (0.027, 1.77e9), (0.035, 1.32e9))
# A force per width against strain curve of the mesh in their module script (ring_example.py), no
# source stated (strain [-], force per width [N/m]): a comparison of shape only
MODELLERS_MESH_CURVE = ((0.01, 20e3), (0.02, 60e3), (0.03, 100e3), (0.04, 130e3), (0.0589, 165.7e3))


def wire_bound_per_m(direction, strain=None):
    """[N/m] every leg that crosses a section across the pull at the wire's breaking force: 2/Dx
    legs per metre longitudinally, 2/Dy transversely. Their component along the pull at the legs'
    angle of the panel stretched uniformly by `strain` [-] along the pull and held across it
    (the modellers' edges); strain None: the legs pointing along the pull (no more can be carried)."""
    from ..mesh import TECCO_G65_DX, TECCO_G65_DY, TECCO_G65_WIRE_RADIUS
    from ..wire import TECCO_WIRE_STRESS
    C.choice("direction", direction, ("longitudinal", "transverse"))
    a, h = TECCO_G65_DX / 2, TECCO_G65_DY / 2
    f = TECCO_WIRE_STRESS[-1] * math.pi * TECCO_G65_WIRE_RADIUS ** 2
    along, across = (h, a) if direction == "longitudinal" else (a, h)
    if strain is None:
        return f / across
    return f / across * along * (1 + strain) / math.hypot(along * (1 + strain), across)


def tecco_modellers_scene(direction="longitudinal", knots=False, speed=1.0, damping=0.2, seed=12345, material=None,
                          width=MODELLERS_WIDTH, length=MODELLERS_LENGTH):
    """The modellers' TECCO G65/3 tensile test: a chain_link_panel `width` [m] across the spirals
    (x) by `length` [m] along them (y), in the plane z = 0, gravity off.
    direction 'longitudinal' (pull along y): the nodes of the side edges (x = 0, x = width) held
    in x and z, free in y; the bottom edge's nodes held in y and z; the top edge's held in z and
    driven in +y at `speed` [m/s]; the node nearest the middle of each of those two edges also
    held in x (corner nodes carry both edges' constraints). 'transverse' (pull along x): the same
    with the axes swapped (left edge held, right edge driven in +x, top and bottom edges held in
    y and z, free in x). Rotations free everywhere. damping [-] Cundall's local damping
    (quasi-static); knots: the knot model (yadeflex.mesh.chain_link_panel); material None: the
    wire of yadeflex.wire.tecco_wire(seed=seed). Returns the dict of chain_link_panel with held,
    driven, sides (the restrained edges' node ids), axis, length (along the pull) and
    loaded_width (across it) [m], material, params: as mesh_panel_scene's, for mesh_tensile_test."""
    p, mat, axis = _panel(direction, width, length, speed, damping, material, seed, knots)
    E = p["edges"]
    across = 1 - axis
    held, driven = (E["bottom"], E["top"]) if axis == 1 else (E["left"], E["right"])
    sides = E["left"] + E["right"] if axis == 1 else E["bottom"] + E["top"]
    xyz = "xyz"
    blocked = {}
    for ids, letters in ((sides, xyz[across] + "z"), (held + driven, xyz[axis] + "z")):
        for i in ids:
            blocked.setdefault(i, set()).update(letters)
    mid = 0.5 * (p["params"]["width"] if across == 0 else p["params"]["height"])
    for edge in (held, driven):
        blocked[min(edge, key=lambda i: abs(O.bodies[i].state.pos[across] - mid))].add(xyz[across])
    for i, letters in blocked.items():
        B.fix([i], "".join(c for c in xyz if c in letters))
    v = Vector3(0, 0, 0)
    v[axis] = speed
    for i in driven:
        O.bodies[i].state.vel = v
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    L = p["params"]["height"] if axis == 1 else p["params"]["width"]
    w = p["params"]["width"] if axis == 1 else p["params"]["height"]
    p.update(held=held, driven=driven, sides=sorted(set(sides)), axis=axis, length=L, loaded_width=w, material=mat,
             params=dict(p["params"], direction=direction, edges="modellers", speed=speed, damping=damping, seed=seed,
                         slack_scale=mat.wireSlackScale, force_ratio=mat.wireForceRatio))
    return p


def tecco_modellers_test(direction="longitudinal", knots=False, speed=1.0, seed=12345, slack_scale=None, chunk=400, max_elongation=0.5):
    """The modellers' test (tecco_modellers_scene) of the wire of yadeflex.wire.tecco_wire (seed,
    slack_scale: None for its calibration), pulled at speed [m/s] until links have ruptured and the
    force fell to 30% of its peak (or the elongation reached max_elongation [-]): past their
    test's end at MODELLERS_STOP when the peak comes later. The force per metre is the driven
    edge's reaction along the pull over the loaded width (their measure; the held edge's is in
    held_per_m). Returns (scene, the result of mesh_tensile_test with at_stop: the force per metre
    [N/m] when the driven edge had moved MODELLERS_STOP (None if it did not), wall seconds)."""
    import time
    from ..wire import tecco_wire
    t = time.time()
    mat = tecco_wire(seed=seed, slack_scale=slack_scale)
    s = tecco_modellers_scene(direction=direction, knots=knots, speed=speed, seed=seed, material=mat)
    r = mesh_tensile_test(s, chunk=chunk, max_elongation=max_elongation, measure="driven")
    r["at_stop"] = curve_at(r["elongation"], r["force_per_m"], MODELLERS_STOP / s["length"])
    return s, r, time.time() - t


def curve_at(xs, ys, x):
    """ys linearly interpolated at x in the increasing xs (None outside them)."""
    for k in range(1, len(xs)):
        if xs[k - 1] <= x <= xs[k]:
            t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]) if xs[k] > xs[k - 1] else 0.0
            return ys[k - 1] + t * (ys[k] - ys[k - 1])
    return None


def write_curve(path_base, columns, xlabel, ylabel, title, x="elongation", y="force", reference=None, params=None, label="yade-flex"):
    """Write path_base.csv (the columns, dict name -> list, in order) and path_base.png (y
    against x; reference: dict label -> (x, y) point, ('h', y) horizontal or ('v', x) vertical
    line, or (xs, ys) lists: a curve, its points marked if few; with more than two the legend goes
    under the plot), plus path_base.json with params; label: the legend of the columns' curve.
    Returns the paths."""
    import csv
    import json
    import os
    os.makedirs(os.path.dirname(path_base) or ".", exist_ok=True)
    names = list(columns)
    with open(path_base + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for row in zip(*(columns[n] for n in names)):
            w.writerow(["" if v is None else repr(float(v)) for v in row])
    if params is not None:
        with open(path_base + ".json", "w") as fh:
            json.dump(params, fh, indent=1, sort_keys=True, default=str)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    many = len(reference or {}) > 2
    fig, ax = plt.subplots(figsize=(6, 4))
    xs = [a for a, b in zip(columns[x], columns[y]) if b is not None]
    ys = [b for b in columns[y] if b is not None]
    ax.plot(xs, ys, "-", lw=1.2, label=label)
    for label, ref in (reference or {}).items():
        if isinstance(ref[0], (list, tuple)):
            ax.plot(ref[0], ref[1], "o-" if len(ref[0]) < 20 else "-", lw=1.0, ms=4, label=label)
        elif ref[0] == "h":
            ax.axhline(ref[1], color="k", ls="--", lw=0.8, label=label)
        elif ref[0] == "v":
            ax.axvline(ref[1], color="0.4", ls=":", lw=1.0, label=label)
        else:
            ax.plot([ref[0]], [ref[1]], "o", label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, lw=0.3)
    if many:
        ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.16), frameon=False)
    else:
        ax.legend()
        fig.tight_layout()
    fig.savefig(path_base + ".png", dpi=110, **(dict(bbox_inches="tight") if many else {}))
    plt.close(fig)
    return path_base + ".csv", path_base + ".png"


def _check_ring(segments, ring_radius, bar_radius, material):
    """A ring loaded at two opposite nodes, checked before O.reset."""
    _check_chain(segments, ring_radius, bar_radius, material, names=("segments", "ring_radius", "bar_radius"))
    if segments % 2 or segments < 4:
        raise C.BadValue("segments", segments, "an even number >= 4 (two opposite nodes)")


def ring_point_loads(ring_radius=0.3, bar_radius=0.005, segments=48, rel_deflection=1e-4, material=None):
    """Steel ring (bar radius [m]) pulled apart by two opposite point loads P along z: node
    at the bottom held in translation, the top node loaded with +P, damped to rest.

    Thin-ring theory (inextensible, Euler-Bernoulli; e.g. Roark, Formulas for Stress and
    Strain, table 9.2 case 1): delta = (pi/4 - 2/pi) P R^3 / (EI). Roark's correction for the
    hoop (extensional) deformation multiplies pi/4 by K1 = 1 - alpha and 2/pi by K2^2 = (1 -
    alpha)^2, alpha = I/(A R^2); our beam has no shear deformation (beta = 0). P is chosen so
    that delta = rel_deflection x R (linear range). Returns dict(delta, theory, theory_thin, P)."""
    from ..materials import steel
    from .scenes import settle
    _check_ring(segments, ring_radius, bar_radius, material)
    C.positive("rel_deflection", rel_deflection, hi=0.01)
    O.reset()
    mat = material if material is not None else steel()
    nodes, cyls = B.ring((0, 0, 0), ring_radius, bar_radius, mat, segments=segments, axis=(0, 1, 0))
    bottom, top = nodes[0], nodes[segments // 2]
    E = mat.young
    I = math.pi * bar_radius ** 4 / 4
    A = math.pi * bar_radius ** 2
    R = ring_radius
    c_thin = math.pi / 4 - 2 / math.pi
    alpha = I / (A * R * R)
    c_full = (1 - alpha) * math.pi / 4 - 2 * (1 - alpha) ** 2 / math.pi
    P = rel_deflection * R * E * I / (c_thin * R ** 3)
    B.fix([bottom], "xyz")
    O.engines = engines(gravity=(0, 0, 0), damping=0.8)
    p0 = Vector3(O.bodies[top].state.pos) - O.bodies[bottom].state.pos
    O.forces.setPermF(top, Vector3(0, 0, P) if p0[2] > 0 else Vector3(0, 0, -P))
    settle([top], rel_tol=1e-8, chunk=4000)
    p1 = O.bodies[top].state.pos - O.bodies[bottom].state.pos
    delta = (p1 - p0).norm()
    return dict(delta=delta, theory=c_full * P * R ** 3 / (E * I), theory_thin=c_thin * P * R ** 3 / (E * I), P=P,
                alpha=alpha, params=dict(ring_radius=R, bar_radius=bar_radius, segments=segments, young=E))


def rope_tensile_test(length=1.0, segments=1, damping=0.0, steps_per_unit_strain=2e5, material=None):
    """6x7 FC rope (yadeflex.rope_6x7_8mm) pulled to rupture. Returns dict(strain, force, EA
    (secant at 20% of the breaking force), rupture_force (largest force carried), ...)."""
    from ..materials import rope_6x7_8mm
    C.number("steps_per_unit_strain", steps_per_unit_strain, C.Range(1.0, 1e8))
    mat = material if material is not None else rope_6x7_8mm()
    s = single_wire(mat, length=length, radius=0.004, segments=segments, damping=damping)
    e_break = mat.tensileStrength * math.pi * 0.004 ** 2 / (mat.young * math.pi * 0.004 ** 2)
    e, f, _ = drive_strains(s, [1.3 * e_break], steps_per_unit_strain=steps_per_unit_strain)
    eng = next(x for x in O.engines if type(x).__name__ == "FlexElementEngine")
    k = next(i for i in range(len(f)) if f[i] is not None and f[i] >= 0.2 * mat.tensileStrength * math.pi * 0.004 ** 2)
    carried = [x for x, el in zip(f, e) if x is not None]
    return dict(strain=e, force=f, EA=f[k] / e[k], rupture_force=max(carried), ruptured=eng.nRuptured,
                params=dict(length=length, segments=segments, damping=damping))


def ring_pull(ring_radius=0.3, bar_radius=0.005, segments=48, stretch=0.3, speed=0.05, damping=0.5, chunk=2000, material=None):
    """Steel ring pulled apart at two opposite nodes, displacement controlled: the bottom node
    held, the top node driven along the load line at speed [m/s] (local damping: quasi-static)
    until the diameter grew by stretch x ring_radius. Returns dict(deflection [m], force [N],
    linear_stiffness [N/m] of thin-ring theory, params)."""
    from ..materials import steel
    _check_ring(segments, ring_radius, bar_radius, material)
    C.positive("stretch", stretch, hi=2.0)
    B._positive("speed", speed)
    engine_args(damping=damping)
    C.integer("chunk", chunk, 1)
    O.reset()
    mat = material if material is not None else steel()
    nodes, cyls = B.ring((0, 0, 0), ring_radius, bar_radius, mat, segments=segments, axis=(0, 1, 0))
    bottom, top = nodes[0], nodes[segments // 2]
    B.fix([bottom], "xyz")
    B.fix([top], "xyz")
    up = Vector3(O.bodies[top].state.pos - O.bodies[bottom].state.pos).normalized()
    O.bodies[top].state.vel = up * B._positive("speed", speed)
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    I = math.pi * bar_radius ** 4 / 4
    k_lin = mat.young * I / ((math.pi / 4 - 2 / math.pi) * ring_radius ** 3)
    p0 = Vector3(O.bodies[top].state.pos)
    d, f = [0.0], [0.0]
    O.step()
    while d[-1] < stretch * ring_radius:
        step_until(math.inf, chunk)
        d.append((O.bodies[top].state.pos - p0).dot(up))
        f.append(-O.forces.f(top).dot(up))
    return dict(deflection=d, force=f, linear_stiffness=k_lin,
                params=dict(ring_radius=ring_radius, bar_radius=bar_radius, segments=segments, speed=speed, damping=damping))
