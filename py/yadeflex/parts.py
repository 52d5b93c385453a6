"""Which part of a structure each body is: the part ids of the VTK series (yadeflex.vtk_frames), the
colours of the 3D view (yadeflex.view) and of the ParaView macro (yadeflex/paraview/), the kinds
of contact.

PARTS lists the standard parts; a body's part id is its index there. A structure may name its
bodies in a tag of its own (register_structure_tag: the damping module's ids, mesh, rings, rope,
lining, slab, grains, in O.tags['yadeflex_module']). Any scene names groups of its bodies with name_parts({"panel": ids,
"anchors": ids, ...}) (stored in O.tags['yadeflex_parts']): a standard name keeps its id, other
names get the ids after PARTS, in the order given (part_names() lists them all). scene_parts()
reads both, the named groups last. A body named nowhere is a boulder if it is a clump or a clump
member, a grain if it is a sphere, the slab if it is a wall, else 'other'.
The kind of a contact is 10 * min(a, b) + max(a, b) for the standard parts a and b of its bodies
(a named group's body counts as the standard part its shape gives): two digits naming both
(16: mesh-grain, 66: grain-grain, 67: grain-boulder; contact_kind_name).

PARTS, COLORS and the contact kinds need no YADE: the ParaView macro (run by pvpython) loads
this file by its path; the functions that read the scene import YADE when called.
"""
import json

PARTS = ("other", "mesh", "ring", "rope", "lining", "slab", "grain", "boulder")
PART = {name: k for k, name in enumerate(PARTS)}

# RGB [0-1] of each part, far apart in hue so that a picture tells the parts apart
COLORS = dict(other=(0.85, 0.85, 0.85), mesh=(0.10, 0.30, 0.95), ring=(0.95, 0.08, 0.08), rope=(0.0, 0.70, 0.75),
              lining=(0.10, 0.75, 0.15), slab=(0.55, 0.55, 0.55), grain=(0.80, 0.70, 0.45), boulder=(0.85, 0.10, 0.85))

_STRUCTURE_TAGS = {}  # O.tags key -> function(the tag's text) -> dict body id -> standard part name


def register_structure_tag(key, parts_of):
    """A structure that names its bodies in a tag of its own (the damping module: its ids in
    O.tags['yadeflex_module'], registered by yadeflex.module.ids): parts_of(the tag's text) gives
    dict body id -> standard part name (of PARTS), read by scene_parts."""
    _STRUCTURE_TAGS[key] = parts_of


def structure_parts():
    """dict body id -> standard part id from the registered structures' tags in O.tags."""
    from yade import O
    out, keys = {}, O.tags.keys()
    for key, parts_of in _STRUCTURE_TAGS.items():
        if key in keys:
            out.update({i: PART[name] for i, name in parts_of(O.tags[key]).items()})
    return out


USER_TAG = "yadeflex_parts"
PALETTE = ((1.0, 0.50, 0.05), (0.17, 0.63, 0.17), (0.58, 0.40, 0.74), (0.55, 0.34, 0.29), (0.74, 0.74, 0.13), (0.89, 0.47, 0.76),
           (0.09, 0.75, 0.81), (0.84, 0.15, 0.16), (0.50, 0.50, 0.50), (0.12, 0.47, 0.71))  # colours of named groups, in turn


def name_parts(groups):
    """Names groups of the scene's bodies: groups is a dict name -> body ids (a list, or a dict or
    list of lists of ids as the builders return them). The names replace earlier ones; the VTK
    series (part field, part_names), the 3D view and the impact runner's summaries use them. A
    name is a non-empty word of letters, digits and _; a body in two groups, an id that is no
    body, an empty group: ValueError naming it. Returns the part id of each name."""
    from yade import O
    from .builders import _body_ids
    if not isinstance(groups, dict):
        raise TypeError(f"parts: a dict name -> body ids, got {type(groups).__name__}")
    seen, stored = {}, {}
    for name, ids in groups.items():
        if not (isinstance(name, str) and name.replace("_", "a").isalnum()):
            raise ValueError(f"parts: a part name is a word of letters, digits and _, got {name!r}")
        flat = _body_ids(f"parts[{name!r}]", _flatten(ids))
        if not flat:
            raise ValueError(f"parts[{name!r}] holds no body")
        for i in flat:
            if i in seen and seen[i] != name:
                raise ValueError(f"body #{i} is in two parts, {seen[i]!r} and {name!r}")
            seen[i] = name
        stored[name] = sorted(set(flat))
    O.tags[USER_TAG] = json.dumps(stored)
    names = part_names()
    return {name: names.index(name) for name in stored}


def _flatten(ids):
    """The body ids in ids: an int, a list/tuple/set of them, or dicts and lists of those."""
    if isinstance(ids, dict):
        return [i for v in ids.values() for i in _flatten(v)]
    if isinstance(ids, (list, tuple, set, frozenset)):
        return [i for v in ids for i in _flatten(v)]
    return [ids]


def named_groups():
    """The scene's named groups: dict name -> body ids (name_parts'), {} without any."""
    from yade import O
    return json.loads(O.tags[USER_TAG]) if USER_TAG in O.tags.keys() else {}


def part_names():
    """Every part's name by its id: PARTS, then the named groups' names that are not in PARTS."""
    return list(PARTS) + [n for n in named_groups() if n not in PART]


def color_of(name, names):
    """RGB [0-1] of part `name` among the part names `names` (part_names()): COLORS' for a
    standard part, else the PALETTE's in turn."""
    if name in COLORS:
        return COLORS[name]
    extra = [n for n in names if n not in PART]
    return PALETTE[extra.index(name) % len(PALETTE)] if name in extra else COLORS["other"]


def part_color(name):
    """RGB [0-1] of a part of the scene (color_of among part_names())."""
    return color_of(name, part_names())


def scene_parts(standard_only=False):
    """dict body id -> part id: the registered structures' (structure_parts: a damping module's),
    then the named groups (name_parts); standard_only: the structures' alone (the standard parts
    the contact kinds use)."""
    out = structure_parts()
    if not standard_only:
        names = part_names()
        for name, ids in named_groups().items():
            k = names.index(name)
            out.update(dict.fromkeys(ids, k))
    return out


def part_of(body, table):
    """Part id of a body (not None): table's (a dict from scene_parts), else
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
