"""Every public builder, material, scene and driver refuses nonsense arguments (NaN, out of
range, the wrong type, a word that is not true/false/yes/no/1/0, a scene over the body budget)
with a ValueError naming the argument, at once and before anything is built: the scene keeps
the bodies it had."""
import inspect
import math
import time

import pytest
from yade import O

import yadeflex as yf
from yadeflex import builders, checks, materials, membrane, mesh, rope, scene as scene_mod, wire
from yadeflex.harness import membrane_scenes
from yadeflex.harness import scenes
from yadeflex.harness import tensile
from yadeflex.module import ModuleParams

NAN, BIG = math.nan, 1e300
P2 = [(0, 0, 0), (1, 0, 0)]

# (function, lambda ctx: (args, kwargs), text the message must hold); ctx: materials and two nodes
BAD = [
    (yf.node, lambda c: (((0, 0, NAN), 0.01), {}), "node position"),
    (yf.node, lambda c: (((0, 0, 0), -1), {}), "node radius"),
    (yf.node, lambda c: (((0, 0, 0), "0.01"), {}), "node radius"),
    (yf.node, lambda c: (((0, 0, 0), 0.01), dict(fixed="maybe")), "fixed"),
    (yf.cylinder, lambda c: ((c["n0"], c["n1"], NAN, c["steel"]), {}), "cylinder radius"),
    (yf.cylinder, lambda c: ((c["n0"], 999, 0.01, c["steel"]), {}), "999"),
    (yf.cylinder, lambda c: ((c["n0"], c["n0"], 0.01, c["steel"]), {}), "cylinder ends"),
    (yf.chain, lambda c: ((P2, 0.01, c["steel"]), dict(segments=0)), "segments"),
    (yf.chain, lambda c: ((P2, 0.01, c["steel"]), dict(segments=10 ** 9)), "segments"),
    (yf.chain, lambda c: ((P2, 0.01, c["steel"]), dict(segments=2.5)), "segments"),
    (yf.chain, lambda c: ((P2, 0.01, c["steel"]), dict(segments=4, fixed=[5])), "fixed"),
    (yf.chain, lambda c: ((P2, 0.01, c["steel"]), dict(closed="maybe")), "closed"),
    (yf.chain, lambda c: ((P2, math.inf, c["steel"]), {}), "chain radius"),
    # sizes and densities whose nodes would get a mass of 0 (underflow) or a step below any use
    (yf.ring, lambda c: (((0, 0, 0), 0.3, 1e-300, c["steel"]), {}), "chain radius"),
    (yf.cylinder, lambda c: ((c["n0"], c["n1"], 1e-300, c["steel"]), {}), "cylinder radius"),
    (yf.steel, lambda c: ((), dict(density=1e-300)), "density"),
    (yf.steel, lambda c: ((), dict(density=1e10)), "density"),
    (yf.sheet, lambda c: ((4, 4, (1, 1), 1e300, c["gtx"]), {}), "membrane thickness"),
    (yf.edge_ring, lambda c: (([c["n0"], c["n1"]], 1e-300, c["steel"]), dict(closed=False)), "bar_radius"),
    (yf.chain, lambda c: ((["abc", (1, 0, 0)], 0.01, c["steel"]), {}), "point 0"),
    (yf.ring, lambda c: (((0, 0, 0), 0.3, 0.005, c["steel"]), dict(segments=2)), "segments"),
    (yf.ring, lambda c: (((0, 0, 0), 0.3, 0.005, c["steel"]), dict(segments=10 ** 12)), "segments"),
    (yf.ring, lambda c: (((0, 0, 0), 0.3, 0.005, c["steel"]), dict(axis=(0, 0, 0))), "ring axis"),
    (yf.ring, lambda c: (((0, 0, 0), NAN, 0.005, c["steel"]), {}), "ring radius"),
    (yf.helix, lambda c: ((10 ** 9, 0.05, 0.01, 0.002, c["steel"]), {}), "segments"),
    (yf.helix, lambda c: ((20, 0.05, NAN, 0.002, c["steel"]), {}), "pitch"),
    (yf.helix, lambda c: ((20, 0.05, 0.01, 0.002, c["steel"]), dict(turns=0)), "turns"),
    (yf.net, lambda c: ((10 ** 6, 0.05, 0.002, c["steel"]), {}), "n"),
    (yf.net, lambda c: ((5, NAN, 0.002, c["steel"]), {}), "spacing"),
    (yf.net, lambda c: ((5, 0.05, 0.002, c["steel"]), dict(fix_border="maybe")), "fix_border"),
    (yf.fix, lambda c: (([999],), {}), "ids"),
    (yf.fix, lambda c: (([c["n0"]], "abc"), {}), "dofs"),
    (yf.flex_material, lambda c: ((200e9, 7850), dict(contact_ratio=NAN)), "contact_ratio"),
    (yf.flex_material, lambda c: ((200e9, 7850), dict(contact_ratio=2)), "contact_ratio"),
    (yf.flex_material, lambda c: ((BIG, 7850), {}), "young"),
    (yf.flex_material, lambda c: ((200e9, math.inf), {}), "density"),
    (yf.flex_material, lambda c: ((200e9, 7850), dict(tension_only="maybe")), "tension_only"),
    (yf.flex_material, lambda c: ((200e9, 7850), dict(yield_stress=NAN)), "yield_stress"),
    (yf.flex_material, lambda c: ((200e9, 7850), dict(hardening=NAN)), "hardening"),
    (yf.flex_material, lambda c: ((200e9, 7850), dict(element_young=0)), "element_young"),
    (yf.steel, lambda c: ((), dict(friction_deg=NAN)), "friction_deg"),
    (yf.rope_6x7_8mm, lambda c: ((), dict(contact_ratio=NAN)), "contact_ratio"),
    (yf.wire_material, lambda c: (((0.01, 0.02), (1e9, 1.1e9)), dict(slack_scale=NAN)), "slack_scale"),
    (yf.wire_material, lambda c: (((0.01, 0.02), (1e9, 1.1e9)), dict(force_ratio=0)), "force_ratio"),
    (yf.wire_material, lambda c: (((0.01, 0.02), (1e9, 1.1e9)), dict(seed=1.5)), "seed"),
    (yf.tecco_wire, lambda c: ((), dict(slack_scale=-1)), "slack_scale"),
    (yf.membrane_material, lambda c: ((250e3, 0.3), dict(contact_ratio=NAN)), "contact_ratio"),
    (yf.membrane_material, lambda c: ((BIG, 0.3), {}), "stiffness"),
    (yf.membrane_material, lambda c: ((250e3, 0.3), dict(tension_only="maybe")), "tension_only"),
    (yf.membrane_material, lambda c: ((250e3, 0.3), dict(strength=NAN)), "strength"),
    (yf.geotextile, lambda c: ((), dict(areal_density=NAN)), "areal_density"),
    (yf.facet, lambda c: ((c["n0"], c["n1"], c["n2"], c["gtx"], NAN), {}), "thickness"),
    (yf.facet, lambda c: ((c["n0"], c["n1"], c["n0"], c["gtx"], 0.002), {}), "facet corners"),
    (yf.triangle_mesh, lambda c: (([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)], c["gtx"], 0.002), dict(fixed=[9])), "fixed"),
    (yf.sheet, lambda c: ((10 ** 6, 10 ** 6, (1, 1), 0.002, c["gtx"]), {}), "nx"),
    (yf.sheet, lambda c: ((4, 4, (1, 1, 1), 0.002, c["gtx"]), {}), "sheet size"),
    (yf.sheet, lambda c: ((4, 4, (1, NAN), 0.002, c["gtx"]), {}), "sheet size"),
    (yf.sheet, lambda c: ((4, 4, (1, 1), 0.002, c["gtx"]), dict(pattern="zigzag")), "pattern"),
    (yf.sheet, lambda c: ((4, 4, (1, 1), 0.002, c["gtx"]), dict(fix_border="maybe")), "fix_border"),
    (yf.lining, lambda c: ((0.5, 0.6, 10 ** 6, 10 ** 6, 0.002, c["gtx"]), {}), "n_around"),
    (yf.lining, lambda c: ((0.5, 0.6, 12, 4, 0.002, c["gtx"]), dict(fix_bottom="maybe")), "fix_bottom"),
    (yf.mesh_file, lambda c: ((None, c["gtx"], 0.002), {}), "mesh file"),
    (yf.chain_link_panel, lambda c: ((0.3, BIG, c["tecco"]), {}), "panel height"),
    (yf.chain_link_panel, lambda c: ((NAN, 1, c["tecco"]), {}), "panel width"),
    (yf.chain_link_panel, lambda c: ((1, 1, c["tecco"]), dict(dx=1e-300)), "panel width"),
    (yf.chain_link_panel, lambda c: ((1, 1, c["tecco"]), dict(wire_radius=0)), "wire radius"),
    (mesh.panel_counts, lambda c: ((0.3, BIG), {}), "panel height"),
    (yf.chain_link_cylinder, lambda c: ((BIG, 0.6, c["tecco"]), {}), "diameter"),
    (yf.chain_link_cylinder, lambda c: ((1, BIG, c["tecco"]), {}), "height"),
    (yf.chain_link_cylinder, lambda c: ((1, 0.6, c["tecco"]), dict(spirals="diagonal")), "spirals"),
    (yf.edge_ring, lambda c: (([c["n0"], c["n0"], c["n1"]], 0.005, c["steel"]), {}), "edge_nodes"),
    (yf.edge_ring, lambda c: (([c["n0"], 999, c["n1"]], 0.005, c["steel"]), {}), "edge_nodes"),
    (yf.edge_ring, lambda c: (([c["n0"], c["n1"], c["n2"]], NAN, c["steel"]), {}), "bar_radius"),
    (yf.rope_around, lambda c: (([(0, 0)], 0.5, 0.3, c["rope"]), dict(segment_length=1e-300)), "segment length"),
    (yf.rope_around, lambda c: (([(0, 0)], BIG, 0.3, c["rope"]), {}), "segment length"),
    (yf.rope_around, lambda c: (([(NAN, 0)], 0.5, 0.3, c["rope"]), {}), "centers"),
    (yf.rope_around, lambda c: (([], 0.5, 0.3, c["rope"]), {}), "centers"),
    (yf.rope_around, lambda c: (([(0, 0)], 0.5, NAN, c["rope"]), {}), "z"),
    (yf.engines, lambda c: ((), dict(damping=1)), "damping"),
    (yf.engines, lambda c: ((), dict(gravity=(0, 0, NAN))), "gravity"),
    (yf.engines, lambda c: ((), dict(timestep_safety=0)), "timestep_safety"),
    (yf.engines, lambda c: ((), dict(rolling_friction=NAN)), "rolling_friction"),
    (yf.engines, lambda c: ((), dict(timestep_interval=0)), "timestep_interval"),
    (scene_mod.engine_args, lambda c: ((), dict(damping=NAN)), "damping"),
    (yf.step_until, lambda c: ((NAN, 10), {}), "time"),
    (yf.step_until, lambda c: ((1.0, -1), {}), "max_steps"),
    (scenes.sphere, lambda c: (((0, 0, 1), 0.1), dict(contact_ratio=NAN)), "contact_ratio"),
    (scenes.sphere, lambda c: (((0, 0, 1), 0.1), dict(velocity=(NAN, 0, 0))), "sphere velocity"),
    (scenes.sphere, lambda c: (((0, 0, 1), 0.1), dict(friction_deg=NAN)), "friction_deg"),
    (scenes.cantilever, lambda c: ((), dict(damping=1)), "damping"),
    (scenes.cantilever, lambda c: ((), dict(force=NAN)), "force"),
    (scenes.cantilever, lambda c: ((), dict(segments=10 ** 9)), "segments"),
    (scenes.cantilever, lambda c: ((), dict(load="side")), "load"),
    (scenes.helix_scene, lambda c: ((), dict(damping=2)), "damping"),
    (scenes.helix_scene, lambda c: ((), dict(pitch=NAN)), "pitch"),
    (scenes.net_impact, lambda c: ((), dict(sphere_radius=NAN)), "sphere_radius"),
    (scenes.net_impact, lambda c: ((), dict(speed=NAN)), "speed"),
    (scenes.net_impact, lambda c: ((), dict(n=10 ** 6)), "n"),
    (scenes.wire_and_ring, lambda c: ((), dict(ring_segments=2)), "ring_segments"),
    (scenes.wire_and_ring, lambda c: ((), dict(drop_height=NAN)), "drop_height"),
    (scenes.wire_and_ring, lambda c: ((), dict(damping=-1)), "damping"),
    (scenes.advance, lambda c: ((-1,), {}), "n"),
    (scenes.settle, lambda c: (([999],), {}), "ids"),
    (scenes.rotate_rigidly, lambda c: (([c["n0"]], (0, 0, 0), 1.0), {}), "axis"),
    (membrane_scenes.pretensioned_square, lambda c: ((), dict(n=3)), "n"),
    (membrane_scenes.pretensioned_square, lambda c: ((), dict(load=NAN)), "load"),
    (membrane_scenes.pretensioned_square, lambda c: ((), dict(damping=1)), "damping"),
    (membrane_scenes.circular_membrane, lambda c: ((), dict(rings=10 ** 6)), "rings"),
    (membrane_scenes.circular_membrane, lambda c: ((), dict(pressure=NAN)), "pressure"),
    (membrane_scenes.sheet_impact, lambda c: ((), dict(sphere_radius=0)), "sphere_radius"),
    (membrane_scenes.sheet_impact, lambda c: ((), dict(timestep_safety=0)), "timestep_safety"),
    (membrane_scenes.bumpy_surface, lambda c: ((), dict(amplitude=NAN)), "amplitude"),
    (membrane_scenes.bumpy_surface, lambda c: ((), dict(speed=NAN)), "speed"),
    (tensile.single_wire, lambda c: ((c["steel"],), dict(damping=1)), "damping"),
    (tensile.single_wire, lambda c: ((c["steel"],), dict(segments=0)), "segments"),
    (tensile.drive_strains, lambda c: (({}, [NAN]), {}), "strains"),
    (tensile.mesh_panel_scene, lambda c: ((), dict(clamp="glued")), "clamp"),
    (tensile.mesh_panel_scene, lambda c: ((), dict(speed=NAN)), "speed"),
    (tensile.mesh_panel_scene, lambda c: ((), dict(width=BIG)), "panel width"),
    (tensile.mesh_tensile_test, lambda c: (({},), dict(max_elongation=NAN)), "max_elongation"),
    (tensile.tecco_modellers_scene, lambda c: ((), dict(direction="diagonal")), "direction"),
    (tensile.tecco_modellers_scene, lambda c: ((), dict(speed=NAN)), "speed"),
    (tensile.tecco_modellers_test, lambda c: ((), dict(speed=-1.0)), "speed"),
    (tensile.wire_bound_per_m, lambda c: (("diagonal",), {}), "direction"),
    (tensile.ring_point_loads, lambda c: ((), dict(segments=7)), "segments"),
    (tensile.ring_point_loads, lambda c: ((), dict(rel_deflection=NAN)), "rel_deflection"),
    (tensile.ring_pull, lambda c: ((), dict(stretch=NAN)), "stretch"),
    (tensile.wire_through_knots, lambda c: ((c["tecco"],), dict(radius=-1)), "radius"),
    (tensile.tecco_panel_test, lambda c: ((), dict(speed=NAN)), "speed"),
    (mesh.knot_bar, lambda c: ((), dict(young=-1)), "young"),
    (mesh.knot_model, lambda c: (("rope",), {}), "knots"),
    (tensile.rope_tensile_test, lambda c: ((), dict(steps_per_unit_strain=NAN)), "steps_per_unit_strain"),
    (scenes.bouncing_bar, lambda c: ((), dict(drop=NAN)), "drop"),
    (scenes.bouncing_bar, lambda c: ((), dict(segments=0)), "segments"),
    (scenes.bouncing_bar, lambda c: ((), dict(contact_young=-1)), "contact_young"),
    (scenes.bouncing_bar, lambda c: ((), dict(timestep_safety=1.5)), "timestep_safety"),
    (scenes.bouncing_bar, lambda c: ((), dict(timestep_interval=0)), "timestep_interval"),
    (scenes.drop_on_surface, lambda c: ((), dict(structure="rope")), "structure"),
    (scenes.drop_on_surface, lambda c: ((), dict(surface="sphere")), "surface"),
    (scenes.drop_on_surface, lambda c: ((), dict(drop=NAN)), "drop"),
    (scenes.drop_on_surface, lambda c: ((), dict(cells=0)), "cells"),
    (scenes.drop_on_surface, lambda c: ((), dict(contact_young=-1)), "contact_young"),
    (scenes.drop_on_surface, lambda c: ((), dict(velocity=(0, 0, NAN))), "velocity"),
    (scenes.drop_on_surface, lambda c: ((), dict(damping=1.5)), "damping"),
    (scenes.block_on_net, lambda c: ((), dict(speed=NAN)), "speed"),
    (scenes.block_on_net, lambda c: ((), dict(contact_young=0)), "contact_young"),
    (scenes.block_on_net, lambda c: ((), dict(clump="maybe")), "clump"),
    (scenes.net_on_ridge, lambda c: ((), dict(cells=4)), "cells must be odd"),
    (scenes.net_on_ridge, lambda c: ((), dict(slope_deg=90)), "slope_deg"),
    (scenes.net_on_ridge, lambda c: ((), dict(drop=-1)), "drop"),
    (scenes.net_on_ridge, lambda c: ((), dict(damping=NAN)), "damping"),
    (scenes.net_on_ridge, lambda c: ((), dict(structure="rope")), "structure"),
    (scenes.sheet_on_corner, lambda c: ((), dict(cells=4)), "cells must be odd"),
    (scenes.sheet_on_corner, lambda c: ((), dict(box_half=0)), "box_half"),
    (scenes.sheet_on_corner, lambda c: ((), dict(drop=NAN)), "drop"),
    (scenes.sheet_on_corner, lambda c: ((), dict(friction_deg=-5)), "friction_deg"),
    (scenes.mesh_punch, lambda c: ((), dict(size=NAN)), "size"),
    (scenes.mesh_punch, lambda c: ((), dict(size=1e4)), "panel width"),
    (scenes.mesh_punch, lambda c: ((), dict(boulder_mass=-1)), "boulder_mass"),
    (scenes.mesh_punch, lambda c: ((), dict(edge="tied")), "edge"),
    (scenes.mesh_punch, lambda c: ((), dict(velocity=(0, NAN, -4))), "velocity"),
    (membrane_scenes.hanging_fabric, lambda c: ((), dict(n=0)), "n"),
    (membrane_scenes.hanging_fabric, lambda c: ((), dict(size=NAN)), "size"),
    (membrane_scenes.driven_indenter, lambda c: ((), dict(speed=NAN)), "speed"),
    (membrane_scenes.driven_indenter, lambda c: ((), dict(radius=-1)), "radius"),
    (ModuleParams.validate, lambda c: ((ModuleParams(diameter=BIG),), {}), "diameter"),
    (ModuleParams.validate, lambda c: ((ModuleParams(lining="maybe"),), {}), "lining"),
    (ModuleParams.validate, lambda c: ((ModuleParams(impact_offset=(NAN, 0)),), {}), "impact_offset"),
]

# public functions that take no user values to check, or only read the scene
NOT_BUILDERS = {"lookup_material", "check_finite", "membrane_state", "read_mesh", "critical_timestep", "energy_budget", "bond_forces",
                "contacts_on", "contact_law", "grain_engine", "write_curve", "curve_at", "square_membrane_deflection", "foppl_hencky_centre_deflection"}


def _public(mod):
    return {f for n, f in inspect.getmembers(mod, inspect.isfunction) if f.__module__ == mod.__name__ and not n.startswith("_")}


def test_the_table_covers_every_public_builder():
    every = set().union(*(_public(m) for m in (builders, materials, wire, membrane, mesh, rope, scene_mod, scenes, membrane_scenes, tensile)))
    covered = {f for f, _, _ in BAD}
    assert {f.__name__ for f in every - covered} <= NOT_BUILDERS, {f.__name__ for f in every - covered} - NOT_BUILDERS


@pytest.fixture
def ctx(scene):
    c = dict(steel=yf.steel(), tecco=yf.tecco_wire(), gtx=yf.geotextile(), rope=yf.rope_6x7_8mm())
    c["n0"], c["n1"], c["n2"] = (yf.node(p, 0.005, c["steel"]) for p in [(5, 0, 0), (6, 0, 0), (5, 1, 0)])
    return c


@pytest.mark.parametrize("fn, call, text", BAD, ids=[f"{f.__qualname__}-{k}" for k, (f, _, _) in enumerate(BAD)])
def test_bad_call_names_the_argument_and_builds_nothing(ctx, fn, call, text):
    args, kw = call(ctx)
    before, n = [b.id for b in O.bodies if b is not None], len(O.bodies)
    t0 = time.time()
    with pytest.raises(ValueError) as err:
        fn(*args, **kw)
    assert time.time() - t0 < 2, "refused at once, before building"
    assert text in str(err.value) and "\n" not in str(err.value), str(err.value)
    assert [b.id for b in O.bodies if b is not None] == before and len(O.bodies) == n, "the scene keeps the bodies it had, and no more"


@pytest.mark.parametrize("word, value", [(True, True), (0, False), ("yes", True), ("No", False), ("TRUE", True), ("0", False)])
def test_boolean_words(word, value):
    assert checks.boolean("x", word) is value


@pytest.mark.parametrize("word", ["maybe", 2, 0.5, None, "", "y"])
def test_other_booleans_are_refused(word):
    with pytest.raises(ValueError, match="x: got .*; allowed true/false/yes/no/1/0"):
        checks.boolean("x", word)


def test_body_budget_names_the_limit(scene):
    with pytest.raises(ValueError, match=f"MAX_BODIES = {checks.MAX_BODIES}"):
        yf.chain_link_panel(0.3, 1e300, yf.tecco_wire())
    assert len(O.bodies) == 0


def test_a_density_above_five_steels_is_mass_scaling_with_a_warning(scene):
    """Users scale density to lengthen the step in quasi-static tests: allowed, said once."""
    with pytest.warns(UserWarning, match=r"density 1e\+06 kg/m3 is 127x steel's: taken as mass scaling"):
        m = yf.steel(density=1e6)
    assert m.density == 1e6
    with pytest.warns(UserWarning, match="sphere density"):
        scenes.sphere((0, 0, 0), 0.01, density=1e5)
