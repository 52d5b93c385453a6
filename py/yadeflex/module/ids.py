"""The body ids of a filled damping-module scene, typed: ModuleIds (the scene's slab, grains and
rope, and one ModuleStructureIds per module: its mesh, rings and lining).

Both read as the dictionaries they are stored as (O.tags['yadeflex_module'], the fill cache):
ids['grains'], ids['modules'][0]['lining'], ids.get('rope', []); the top level also reads the
first module's keys (ids['mesh_nodes'] is the first module's mesh nodes). ModuleIds.bodies(key)
is the set over the whole scene and every module, and KEYS is the one table from a key to the
part of the 3D view, the name of one such body in messages and the kind of a broken element.
"""
import json
from collections.abc import Mapping
from dataclasses import dataclass, field, fields

from ..parts import PART, register_structure_tag

# key -> (part of the VTK series and the 3D view (yadeflex.parts.PARTS), name of one such body in
# messages or None, summary key of such a broken element or None). A body under two keys takes
# the first key's name and part.
KEYS = (
    ("grains", "grain", "grain", None),
    ("mesh_cylinders", "mesh", "wire leg", "broken_wire_legs"),
    ("lining", "lining", "lining facet", "broken_lining_facets"),
    ("mesh_nodes", "mesh", "mesh node", None),
    ("ring_top", "ring", "top ring", "broken_ring_segments"),
    ("ring_bottom", "ring", "bottom ring", "broken_ring_segments"),
    ("rope", "rope", "rope", "broken_rope_segments"),
    ("lining_nodes", "lining", "lining node", None),
    ("rope_nodes", "rope", "rope node", None),
    ("wall", "slab", None, None),
)
BROKEN_KINDS = tuple(dict.fromkeys(k for *_, k in KEYS if k))  # in KEYS order, each once


class _ReadsAsDict(Mapping):
    """Read access by key to the dataclass's fields."""

    def _names(self):
        return [f.name for f in fields(self)]

    def __getitem__(self, key):
        if key in self._names():
            return getattr(self, key)
        raise KeyError(key)

    def __iter__(self):
        return iter(self._names())

    def __len__(self):
        return len(self._names())


def _list(name, value):
    if value is None:
        return []
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise TypeError(f"module ids: {name} must be a list of body ids, got {value!r}")
    return [int(i) for i in value]


@dataclass
class ModuleStructureIds(_ReadsAsDict):
    """One module's bodies: its chain-link mesh (nodes, wire legs), its top and bottom rings,
    its lining (facets, nodes), the nodes on the slab, its centre (x, y) [m] and the mesh's
    parameters (yadeflex.mesh)."""
    center: tuple = (0.0, 0.0)
    mesh_nodes: list = field(default_factory=list)
    mesh_cylinders: list = field(default_factory=list)
    ring_bottom: list = field(default_factory=list)
    ring_top: list = field(default_factory=list)
    lining: list = field(default_factory=list)
    lining_nodes: list = field(default_factory=list)
    base_nodes: list = field(default_factory=list)
    mesh_params: dict = field(default_factory=dict)

    @classmethod
    def from_dict(cls, d):
        known = {f.name for f in fields(cls)}
        kw = {k: (_list(k, v) if k not in ("center", "mesh_params") else v) for k, v in d.items() if k in known}
        if "center" in kw:
            kw["center"] = tuple(float(c) for c in kw["center"])
        return cls(**kw)

    def to_dict(self):
        return {f.name: (list(getattr(self, f.name)) if f.name == "center" else getattr(self, f.name)) for f in fields(self)}


@dataclass
class ModuleIds(_ReadsAsDict):
    """The bodies of a filled damping-module scene (yadeflex.module.filled_module returns one):
    the slab (wall), the grains, the rope around the modules (rope: its segments, rope_nodes),
    the nodes on the slab of every module (base_nodes) and one ModuleStructureIds per module."""
    wall: int = -1
    grains: list = field(default_factory=list)
    modules: list = field(default_factory=list)
    rope: list = field(default_factory=list)
    rope_nodes: list = field(default_factory=list)
    base_nodes: list = field(default_factory=list)

    def _names(self):
        own = [f.name for f in fields(self)]
        first = [f.name for f in fields(ModuleStructureIds) if f.name not in own] if self.modules else []
        return first + own

    def __getitem__(self, key):
        if key in (f.name for f in fields(self)):
            return getattr(self, key)
        if self.modules and key in self.modules[0]:
            return self.modules[0][key]
        raise KeyError(key)

    @classmethod
    def of(cls, ids):
        """ids as ModuleIds: itself, or made from the stored dictionary (missing keys empty)."""
        if isinstance(ids, cls):
            return ids
        if not isinstance(ids, Mapping):
            raise TypeError(f"module ids: expected the ids of a filled module (yadeflex.module.filled_module), got {type(ids).__name__}")
        mods = ids.get("modules")
        if mods is None:
            raise TypeError("module ids: no 'modules' key: expected the ids of a filled module (yadeflex.module.filled_module), "
                            f"got a mapping of {sorted(ids)}")
        wall = ids.get("wall", -1)
        return cls(wall=int(wall) if wall is not None else -1, grains=_list("grains", ids.get("grains")),
                   modules=[m if isinstance(m, ModuleStructureIds) else ModuleStructureIds.from_dict(m) for m in mods],
                   rope=_list("rope", ids.get("rope")), rope_nodes=_list("rope_nodes", ids.get("rope_nodes")),
                   base_nodes=_list("base_nodes", ids.get("base_nodes")))

    @classmethod
    def from_json(cls, text):
        return cls.of(json.loads(text))

    def to_dict(self):
        """The stored form: the first module's keys, then the scene's (as O.tags holds it)."""
        d = dict(self.modules[0].to_dict()) if self.modules else {}
        d.update(wall=self.wall, grains=self.grains, modules=[m.to_dict() for m in self.modules], rope=self.rope,
                 rope_nodes=self.rope_nodes, base_nodes=self.base_nodes)
        return d

    def to_json(self):
        return json.dumps(self.to_dict())

    def bodies(self, key):
        """Set of the body ids under key over the whole scene and every module."""
        if key not in {k for k, *_ in KEYS} | {f.name for f in fields(ModuleStructureIds)} | {f.name for f in fields(self)}:
            raise KeyError(f"module ids have no key {key!r}")
        out = set()
        own = getattr(self, key, None) if key in (f.name for f in fields(self)) else None
        if isinstance(own, int):
            out.add(own)
        elif own is not None and key != "modules":
            out.update(own)
        for m in self.modules:
            if key in m:
                out.update(m[key] if isinstance(m[key], list) else ())
        out.discard(-1)
        return out

    def _by_body(self, column):
        out = {}
        for row in reversed(KEYS):  # the first key wins
            if row[column] is not None:
                out.update(dict.fromkeys(self.bodies(row[0]), row[column]))
        return out

    def parts(self):
        """dict body id -> part name ('grain', 'mesh', 'ring', 'rope', 'lining', 'slab')."""
        return self._by_body(1)

    def names(self):
        """dict body id -> name of the body in messages ('grain', 'wire leg', 'lining facet', ...)."""
        return self._by_body(2)

    def broken_kinds(self):
        """dict element id -> summary key of such a broken element ('broken_wire_legs', ...)."""
        return self._by_body(3)


def module_parts(ids):
    """dict body id -> part id (yadeflex.parts) from the module's ids (a ModuleIds or its stored
    dictionary): every module's mesh, rings and lining, and the scene's grains, slab and rope; a
    ring's nodes are mesh nodes."""
    return {i: PART[name] for i, name in ModuleIds.of(ids).parts().items()}


# the parts of a scene with a damping module (yadeflex.parts.scene_parts): its ids in O.tags
register_structure_tag("yadeflex_module", lambda text: ModuleIds.from_json(text).parts())
