// yade-flex adapter (GPL-2.0-or-later): the geometry of a contact touching deformable elements: point, normal,
// overlap and, per side, the element nodes and axis parameter or barycentric weights.
//
// Ownership (one contact where elements meet): a contact with element E is dropped if an
// element sharing a node with E has the SAME contact with a larger overlap (ties: lower body
// id wins). Same contact: one of the two closest points lies on what the two share (a chain's
// shared node, a facet's shared edge or vertex), where both touch at the same point. Distinct
// contacts on neighbours (a sphere on a net cell touching its four wires, a boulder on the legs
// of a mesh) all count.
// Where two segments clamp to the same node the distances are bit-identical and the tie rule
// picks one. A contact between two elements (a ring on the lining) is decided once per cluster
// of element PAIRS (flexa::ownsPair: every pair's overlap computed the same way by all of them),
// not side by side. When ownership moves from A to its neighbour B, B takes over A's shear
// force; A stays one more step, inactive, so B reads stable data (deterministic, no data race).
#pragma once
#include "FlexPch.hpp"

namespace yade {

class FlexContactGeom : public GenericSpheresContact {
public:
	virtual ~FlexContactGeom() = default;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(FlexContactGeom, GenericSpheresContact,
		"Contact touching deformable elements (yade-flex). Per side: the nodes and the axis parameter u of the contact on a cylinder, or the three nodes and barycentric weights on a facet (all -1: the body itself is rigid); axis1/axis2 is the closest point on the axis or midplane. Normal from body 1 to body 2.",
		((Real, penetrationDepth, NaN, , "Overlap [m]"))
		((Vector2i, nodes1, Vector2i(-1, -1), , "Nodes of side 1 (-1: rigid body)"))
		((Vector2i, nodes2, Vector2i(-1, -1), , "Nodes of side 2 (-1: rigid body)"))
		((Real, u1, 0, , "Axis parameter on side 1 [-]"))
		((Real, u2, 0, , "Axis parameter on side 2 [-]"))
		((Vector3i, tri1, Vector3i(-1, -1, -1), , "Facet nodes of side 1 (-1: not a facet)"))
		((Vector3i, tri2, Vector3i(-1, -1, -1), , "Facet nodes of side 2 (-1: not a facet)"))
		((Vector3r, bary1, Vector3r::Zero(), , "Barycentric weights of the facet point of side 1 [-]"))
		((Vector3r, bary2, Vector3r::Zero(), , "Barycentric weights of the facet point of side 2 [-]"))
		((Vector3r, axis1, Vector3r::Zero(), , "Axis point (or centre) of side 1 [m]"))
		((Vector3r, axis2, Vector3r::Zero(), , "Axis point (or centre) of side 2 [m]"))
		((Vector3r, relVel, Vector3r::Zero(), , "Velocity of side 2 relative to side 1 at the contact point [m/s]"))
		((bool, active, true, , "Owned: this interaction carries the contact force"))
		((long, lastActiveIter, -2, , "Last iteration at which it was active"))
		((bool, handover, false, , "Took over the shear force of a neighbour this step"))
		((Vector3r, handoverShear, Vector3r::Zero(), , "Shear force taken over [N]"))
		((Real, handoverNormal, 0, (Attr::noSave | Attr::readonly), "Normal force of the neighbour this contact took over from at this step (0: none; -1: none, and the contact is one of the scene as built, found at its first step) [N]"))
		((Vector3r, rollMoment, Vector3r::Zero(), , "Rolling-resistance moment on body 2 (sphere-sphere contacts) [N m]"))
		((Real, plasticOverlap, 0, , "Part of the overlap that carries no force: the normal force is kn (penetrationDepth - plasticOverlap), at least 0 [m]. A sphere-sphere contact whose grains crushed (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.crushingIs50`): its crushed part, for good. A contact with an element that started deep (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.deepOnsets`): the part of its overlap beyond what its predecessor's force gives (all of it without one), so that it starts with the spring energy it took over and none from nothing; it shrinks with the overlap (never above it)"))
		((bool, pierced, false, (Attr::noSave | Attr::readonly), "A wire's axis passes through the facet's midplane (a cylinder-facet contact over the face): the overlap is the reach, the same wherever the wire goes while it stays pierced, so the contact carries no normal force (a force there would work without changing the spring's energy: energy from nothing); its spring keeps the energy it had when the wire got there (booked in flexContactElastic) and gives it back as the wire comes out. A wire pushed wholly through is pushed back towards the side it came from"))
		((Real, onsetDepth, 0, (Attr::noSave | Attr::readonly), "Overlap this contact (re)started with at this step if that was a deep onset (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.deepOnsets`), else 0 [m]"))
		((long, crossIter, -2, Attr::readonly, "Crossing correction (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.crossing`): last iteration it was updated at (otherwise it starts again)"))
		((Real, crossDepth, 0, Attr::readonly, "Crossing correction: overlap at that iteration [m]"))
		((Real, crossForce, 0, Attr::readonly, "Crossing correction: normal force applied at that iteration, the spring's and the correction's, repulsive positive [N]"))
		((Real, crossRate, NaN, Attr::readonly, "Crossing correction: rate of the overlap at that iteration (NaN: unknown) [m/s]"))
		((Real, crossDefect, 0, Attr::readonly, "Crossing correction: energy the leap-frog scheme has put into the bodies beyond the spring's potential, still to be cancelled [J]"))
		((int, crossOut, 0, Attr::readonly, "Crossing correction: steps since the last step with positive overlap")),
		createIndex();
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexContactGeom, GenericSpheresContact);
};
REGISTER_SERIALIZABLE(FlexContactGeom);

} // namespace yade
