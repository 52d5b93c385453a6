// yade-flex adapter: FlexSnapshot, the scene's bodies, elements and contacts as flat arrays for
// output (GPL-2.0-or-later).
//
// Output (yadeflex.output's VTK frames) needs, at every frame, a few values of every body, every
// element and every contact. Read attribute by attribute from Python that is one call per value;
// here it is one pass over the bodies (per method) and one over the interactions. Each method returns a dict
// {name: bytes}, every value the raw native-endian array of one field (float64, or int64 for
// ids, codes and counts), row by row; numpy.frombuffer reads it without a copy.
#pragma once
#include "FlexPch.hpp"

namespace yade {

class FlexSnapshot : public Serializable {
public:
	/// Group codes of FlexSnapshot.bodies()["group"], in the order yadeflex.output's GROUPS
	/// lists the body groups; a body matches the first shape class it is an instance of.
	enum Group : long { kErased = -1, kNoGroup = 0, kNodes, kCylinders, kFacets, kSpheres, kClumps, kBoxes, kRigidFacets, kWalls };
	boost::python::dict bodies() const;
	boost::python::dict contacts() const;
	boost::python::dict elements(long group) const;
	virtual ~FlexSnapshot() = default;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexSnapshot, Serializable,
		"The current scene's bodies and contacts as flat arrays (yadeflex.output's VTK frames read them): each method returns a dict of field name to bytes, the raw array of that field (float64, int64 for ids, codes and counts), for numpy.frombuffer.",
		/* no attributes */,
		/* ctor */,
		.def("bodies", &FlexSnapshot::bodies, "One row per body slot (len(O.bodies)), in id order: 'group' (int64: -1 erased, 0 none of these, 1 FlexNode, 2 FlexCylinder, 3 FlexFacet, 4 Sphere, 5 Clump, 6 Box, 7 Facet, 8 Wall; the first class the shape is an instance of), 'clumped' (int64: 1 for a clump or a clump member), 'pos', 'vel', 'angVel' (3 float64 each), 'mass', 'radius' (float64; the shape's radius for FlexNode and Sphere, else NaN), 'blocked' (int64: number of blocked DOFs).")
		.def("elements", &FlexSnapshot::elements, (boost::python::arg("group")), "The bodies of one element group (2: FlexCylinder, 3: FlexFacet; the group codes of bodies()), one row each, in id order: 'id' (int64), 'nodes' (int64, 2 per cylinder, 3 per facet: node1, node2[, node3]) and one float64 array per shape field: for cylinders radius, axialForce, strain, plasticStrain, maxStrain, hardeningVar, wireSlack, elasticEnergy, L0; for facets radius, n1, n2, e1, e2, elasticEnergy, pressure, area0. Another group raises ValueError.")
		.def("contacts", &FlexSnapshot::contacts, "One row per real interaction whose physics is a NormShearPhys (not a FlexContactGeom handed over to a neighbour: active false), in O.interactions' order, then the contacts of a FlexGrainEngine (as its last step saw them: end1, end2 the grains' centres): 'id1', 'id2' (int64), 'end1', 'end2' (3 float64: the centre of each side: a FlexContactGeom's axis point, else a sphere's centre, else the contact point), 'contactPoint', 'normal', 'normalForce', 'shearForce' (3 float64; NaN where the geometry has no such field), 'penetrationDepth' (float64, NaN where the geometry has none) and 'plasticOverlap' (float64: a FlexContactGeom's crushed overlap, else 0).")
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexSnapshot);

} // namespace yade
