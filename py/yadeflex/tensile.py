"""Tensile-test scenes and drivers, defined once, used by scripts/tensile_*.py and the tests.

Every driver resets O, builds its scene with unit-annotated parameters, runs it and returns a
dict with the measured curve (lists) and the parameters used.
"""
import math

from yade import O
from yade.minieigenHP import Vector3

from . import builders as B
from .scene import engines


def single_wire(material, length=0.1, radius=0.0015, segments=1):
    """A straight wire along x, clamped at node 0; the last node is driven (all its DOFs
    blocked) at a velocity set by the driver. Returns dict(nodes, cylinders, driven)."""
    O.reset()
    nodes, cyls = B.chain([(0, 0, 0), (length, 0, 0)], radius, material, segments=segments, fixed=[0, segments])
    O.engines = engines(gravity=(0, 0, 0), damping=0.0)
    return dict(nodes=nodes, cylinders=cyls, driven=nodes[-1], params=dict(length=length, radius=radius, segments=segments))


def drive_strains(scene, strains, steps_per_unit_strain=2e5, dt=None):
    """Displacement control of `single_wire`: move the driven node so that the wire's total
    strain goes linearly through `strains` (each a target reached exactly, at a step end).
    Between targets the node moves at constant velocity over ceil(|de| x steps_per_unit_strain)
    steps. Returns lists (strain, force of the first cylinder or None once ruptured, iteration)."""
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
            out_f.append(b.shape.axialForce if b is not None else None)
            out_i.append(O.iter)
        e_now = target
    return out_e, out_f, out_i


def _edge_force(ids, axis):
    return sum(O.forces.f(i)[axis] for i in ids)


def mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=0.5, damping=0.2, seed=12345, material=None):
    """TECCO G65/3 panel (yadeflex.mesh.chain_link_panel) clamped on two opposite edges; one
    edge held, the other driven outwards at `speed` [m/s] (all its DOFs blocked).
    direction: 'longitudinal' (pull across the spirals, x: the datasheet's 150 kN/m) or
    'transverse' (along the spirals, y). width, height [m] along x, y; damping [-] Cundall's
    local damping (quasi-static). Returns dict(held, driven, axis, length, loaded_width, ...)."""
    from .mesh import chain_link_panel
    from .wire import tecco_wire
    if direction not in ("longitudinal", "transverse"):
        raise ValueError(f"direction must be 'longitudinal' or 'transverse', got {direction!r}")
    O.reset()
    mat = material if material is not None else tecco_wire(seed=seed)
    p = chain_link_panel(width, height, mat)
    axis = 0 if direction == "longitudinal" else 1
    held, driven = (p["edges"]["left"], p["edges"]["right"]) if axis == 0 else (p["edges"]["bottom"], p["edges"]["top"])
    B.fix(held)
    B.fix(driven)
    v = Vector3(0, 0, 0)
    v[axis] = B._positive("speed", speed)
    for i in driven:
        O.bodies[i].state.vel = v
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    length = p["params"]["width"] if axis == 0 else p["params"]["height"]
    loaded_width = p["params"]["height"] if axis == 0 else p["params"]["width"]
    p.update(held=held, driven=driven, axis=axis, length=length, loaded_width=loaded_width, material=mat,
             params=dict(p["params"], direction=direction, speed=speed, damping=damping, seed=seed,
                         slack_scale=mat.wireSlackScale, force_ratio=mat.wireForceRatio))
    return p


def mesh_tensile_test(scene, max_elongation=0.8, chunk=200, stop_fraction=0.3):
    """Run `mesh_panel_scene` until the force falls below stop_fraction x its peak (after the
    peak) or the elongation reaches max_elongation [-]. Returns dict with lists elongation [-]
    and force per metre of loaded width [N/m] (mean of the driven and the held edge), the peak
    and the elongation at the peak, ruptured links and the engines' time."""
    ax, L, w = scene["axis"], scene["length"], scene["loaded_width"]
    x0 = O.bodies[scene["driven"][0]].state.pos[ax]
    el, fm, unbalance = [], [], []
    peak, e_peak = 0.0, 0.0
    O.step()
    while True:
        O.run(chunk, True)
        e = (O.bodies[scene["driven"][0]].state.pos[ax] - x0) / L
        f_drv = -_edge_force(scene["driven"], ax)
        f_hld = _edge_force(scene["held"], ax)
        f = 0.5 * (f_drv + f_hld) / w
        el.append(e)
        fm.append(f)
        unbalance.append(abs(f_drv - f_hld) / max(abs(f_drv), abs(f_hld), 1e-30))
        if f > peak:
            peak, e_peak = f, e
        if (peak > 0 and f < stop_fraction * peak and e > e_peak) or e >= max_elongation:
            break
    eng = next(x for x in O.engines if type(x).__name__ == "FlexElementEngine")
    k_peak = fm.index(peak)
    return dict(elongation=el, force_per_m=fm, peak=peak, elongation_at_peak=e_peak, ruptured=eng.nRuptured,
                unbalance_at_peak=unbalance[k_peak], iterations=O.iter, dt=O.dt)
