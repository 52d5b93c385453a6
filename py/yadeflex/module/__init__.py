"""The damping module: a chain-link mesh cylinder with steel rings, a geotextile lining and a
granular fill on a rigid slab, hit by a boulder. One builder with declared parameters, used
by the main job (scripts/damping_module.py), the tests and parametric studies; built from the
library (yadeflex: builders, grains and deposition, the runner). By concept: params (ModuleParams),
fill (stages 1-2), fill_cache (the cache of filled modules), boulder (stage 3), ids (ModuleIds:
the bodies of a filled module), impact (the main job's run), cli (its command line), study,
study_task, study_plots (parametric studies), cushion (the design formulas); this package
gathers the names of the first five.

Stages
  1. fill: grains placed on a close-packed lattice in a rigid, frictionless cylindrical
     container of the lining's radius (grains only: a long time step) settle under gravity,
     first without friction or rolling resistance (so that they pack densely, as a compacted
     fill), then with them; grains above the module's height are removed. (Settled with their
     friction from the start, the grains froze in a loose packing, 0.40 solid fraction and 2.3
     contacts per grain, that kept collapsing during the impact: bench/fill_equilibrium.py);
  2. structure: the mesh, rings and lining are built around the settled fill, the rigid
     container removed, and the whole settled again until it is at rest and in equilibrium
     (unbalanced force too): the fill, released by the container, spreads out onto the lining
     and ends bearing on it. The structure's nodes are made heavier meanwhile (their weight
     kept), so that this quasi-static settle runs at the grains' time step, not the wires';
  3. impact: the boulder is placed to touch the module (fill, rings, wires or lining) after a
     5 mm fall, with the free-fall velocity of its drop height less that fall's, and the run
     starts without numerical damping unless asked.
Stages 1-2 are cached (O.save) under a key made of every parameter they depend on, so impacts
with other boulders reuse the filled module.

Simplifications (stated, not hidden): the module's base nodes (mesh, rings, lining) are pinned
to the slab (no sliding of the base); the slab is a rigid plane (a YADE Wall) whose reaction is
the force on the wall plus the reactions at the pinned nodes; grains are spheres (the
angularity of gravel is represented by its friction angle and a rolling resistance); a cubic boulder is a
rigid clump of overlapping spheres with the mass and inertia of the solid cube (its edges are
rounded by the member radius).
"""
from .params import (  # noqa: F401
    UNBALANCED_TOL, FILL_TIMESTEP_SAFETY, MAX_NODE_MASS_SCALING, PLACED_HEIGHT, FILLS, WITHDRAWN_FILLS,
    check_fill, BOULDER_SHAPES, N_MODULES, MAX_IMPACT_SPEED, BOULDER_MIN_SIZE, TIMESTEP_SAFETY,
    ModuleParams, PARAMS, LIMITS, SMALL, lining_cells_around, fill_radii)
from ..grains import _grain_material, _sphere_body, fill_engines, fill_preset  # noqa: F401
from ..mass_scaling import _heavier_nodes, _restore_nodes  # noqa: F401
from .fill import (  # noqa: F401
    _placement, _container, _settle, _relayout, settle_fill, _floor_grains, settle_grains,
    build_filled, fill_contacts, fill_top)
from .fill_cache import (  # noqa: F401
    CACHE_FORMAT, cache_files, save_compressed, check_written, check_saved, _sha256,
    cache_problem, _remove_stale_temps, filled_module)
from ..boulder import touches  # noqa: F401
from .boulder import add_boulder, scale_lining_nodes, impact_start  # noqa: F401
from .ids import ModuleIds, ModuleStructureIds  # noqa: F401
