"""Which part of a structure each body is: the part ids of the VTK series (yadeflex.vtk_frames), the
colours of the 3D view (yadeflex.view) and of the ParaView macro (yadeflex/paraview/), the kinds
of contact.

PARTS lists the parts; a body's part id is its index there. A scene built by
yadeflex.module.build_filled names its bodies in O.tags['yadeflex_module'] (mesh, rings, rope,
lining, slab, grains); scene_parts() reads that. A body named nowhere is a boulder if it is a
clump or a clump member, a grain if it is a sphere, the slab if it is a wall, else 'other'.
The kind of a contact between parts a and b is 10 * min(a, b) + max(a, b): two digits naming
both parts (16: mesh-grain, 66: grain-grain, 67: grain-boulder; contact_kind_name).

PARTS, COLORS and the contact kinds need no YADE: the ParaView macro (run by pvpython) loads
this file by its path; the functions that read the scene import YADE when called.
"""
import json

PARTS = ("other", "mesh", "ring", "rope", "lining", "slab", "grain", "boulder")
PART = {name: k for k, name in enumerate(PARTS)}

# RGB [0-1] of each part, far apart in hue so that a picture tells the parts apart
COLORS = dict(other=(0.85, 0.85, 0.85), mesh=(0.10, 0.30, 0.95), ring=(0.95, 0.08, 0.08), rope=(0.0, 0.70, 0.75),
              lining=(0.10, 0.75, 0.15), slab=(0.55, 0.55, 0.55), grain=(0.80, 0.70, 0.45), boulder=(0.85, 0.10, 0.85))

def module_parts(ids):
    """dict body id -> part id from the module's ids (yadeflex.module_ids.ModuleIds or its stored
    dictionary): every module's mesh, rings and lining, and the scene's grains, slab and rope; a
    ring's nodes are mesh nodes."""
    from .module_ids import ModuleIds
    return {i: PART[name] for i, name in ModuleIds.of(ids).parts().items()}


def scene_parts():
    """module_parts of the scene's module (O.tags['yadeflex_module']), or {} without one."""
    from yade import O
    if "yadeflex_module" not in O.tags.keys():
        return {}
    return module_parts(json.loads(O.tags["yadeflex_module"]))


def part_of(body, table):
    """Part id of a body (not None): table's (a dict from scene_parts or module_parts), else
    from its shape (see the module docstring)."""
    from yade.wrapper import Sphere, Wall
    p = table.get(body.id)
    if p is not None:
        return p
    if body.isClump or body.isClumpMember:
        return PART["boulder"]
    if isinstance(body.shape, Sphere):
        return PART["grain"]
    if isinstance(body.shape, Wall):
        return PART["slab"]
    return PART["other"]


def contact_kind(a, b):
    """Kind of a contact between parts a and b (part ids): 10 * min + max."""
    return 10 * min(a, b) + max(a, b)


def contact_kind_name(kind):
    """'grain-boulder', 'mesh-grain', ... of a contact kind."""
    if not (isinstance(kind, int) and 0 <= kind // 10 <= kind % 10 < len(PARTS)):
        raise ValueError(f"a contact kind is 10 * a + b for part ids 0 <= a <= b < {len(PARTS)}, got {kind!r}")
    return f"{PARTS[kind // 10]}-{PARTS[kind % 10]}"
