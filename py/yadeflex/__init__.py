"""yade-flex: deformable cylinders (wires, rings, ropes) and facets (membranes) for YADE.

Use inside a YADE session or script::

    import yadeflex as yf
    steel = yf.steel()
    nodes, cyls = yf.chain([(0, 0, 0), (1, 0, 0)], radius=0.005, material=steel, segments=10, fixed=[0])
    O.engines = yf.engines(damping=0.0)

Units are SI throughout: m, kg, s, N, Pa.
"""
from .errors import Unstable
from .materials import flex_material, steel, rope_6x7_8mm
from .builders import node, cylinder, chain, ring, helix, net, fix, check_finite
from .membrane import (membrane_material, geotextile, facet, triangle_mesh, sheet, lining, read_mesh, mesh_file,
                       membrane_state)
from .scene import engines, critical_timestep, energy_budget, bond_forces, contacts_on, contact_law, grain_engine, step_until
from .wire import wire_material, tecco_wire
from .mesh import chain_link_panel, chain_link_cylinder, edge_ring
from .rope import rope_around
from .output import VtkRecorder, write_vtk_snapshot, EnergyRecorder, read_csv, plot_timeseries, plot_energy
from .view import view, snapshot, scene_box, color_by_part, legend
from . import parts
from .parts import name_parts
from .scene_impact import Boulder, boulder_impact
from .deposition import deposit, settle, DepositResult, BoxRegion, CylinderRegion, GrainSizes
from .joins import lace, edge_rope, bag, box_surface
from .module.ids import ModuleIds
from .mass_scaling import scale_node_masses
from .placement import placed

__all__ = [
    "flex_material", "steel", "rope_6x7_8mm",
    "node", "cylinder", "chain", "ring", "helix", "net", "fix", "check_finite",
    "membrane_material", "geotextile", "facet", "triangle_mesh", "sheet", "lining", "read_mesh", "mesh_file",
    "membrane_state",
    "engines", "critical_timestep", "energy_budget", "bond_forces", "contacts_on", "contact_law", "grain_engine",
    "wire_material", "tecco_wire", "chain_link_panel", "chain_link_cylinder", "edge_ring", "rope_around",
    "VtkRecorder", "write_vtk_snapshot", "EnergyRecorder", "read_csv", "plot_timeseries", "plot_energy",
    "view", "snapshot", "scene_box", "color_by_part", "legend", "parts", "name_parts", "Boulder", "boulder_impact",
    "deposit", "settle", "DepositResult", "BoxRegion", "CylinderRegion", "GrainSizes", "lace", "edge_rope", "bag", "box_surface",
    "ModuleIds", "scale_node_masses", "placed", "Unstable", "step_until",
]
