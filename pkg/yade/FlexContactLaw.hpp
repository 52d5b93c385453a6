// yade-flex adapter (GPL-2.0-or-later): the frictional contact law of every FlexContactGeom; forces to the nodes.
#pragma once
#include "FlexContactGeom.hpp"

namespace yade {

class Law2_FlexContactGeom_FrictPhys_CundallStrack : public LawFunctor {
public:
	bool go(shared_ptr<IGeom>&, shared_ptr<IPhys>&, Interaction*) override;
	/// What a caller already knows of the two bodies of a contact between two plain spheres
	/// (FlexInteractionLoop's table of sphere motion): their angular velocities (rolling
	/// resistance) and inverse masses (the crossing correction: 1 / mass, 0 for a body that
	/// cannot move, as flexa::ContactSide::invMass gives them)
	struct KnownSpheres {
		const Vector3r *angVel1, *angVel2;
		Real            invMass1, invMass2;
	};
	/// go() on the contact's geometry and physics between bodies id1 and id2 (the interaction's,
	/// in its order); known: what the caller knows of the two bodies (two plain spheres), else
	/// null (read from the bodies' states where needed)
	bool apply(FlexContactGeom& g, FrictPhys& p, Body::id_t id1, Body::id_t id2, const KnownSpheres* known);
	/// Rolling stiffness kr of this contact (0: none; only sphere-sphere contacts roll) [N m].
	Real rollingK(const FlexContactGeom& g, const FrictPhys& p) const;
	/// maxOverlapRatio and maxOverlapIds (several threads: a lock only when the maximum grows)
	void noteOverlap(Real ratio, Body::id_t id1, Body::id_t id2);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(Law2_FlexContactGeom_FrictPhys_CundallStrack, LawFunctor,
		"Linear frictional contact [CundallStrack1979]_ on :yref:`FlexContactGeom`; forces and moments go to the element nodes by the shape functions (exact force and moment balance). Optional rolling resistance between spheres (angular grains): an elastic-plastic moment of stiffness kr = rollingStiffness ks R^2 capped at rollingFriction R |Fn|, R = R1 R2/(R1 + R2). Optional grain crushing between spheres: the normal force never exceeds the point-load failure load of the smaller sphere (crushingIs50); past it the contact yields. Books 'flexContactElastic', 'flexFriction', 'flexRolling', 'flexCrushing' and 'flexHandover' in O.energy.",
		((Real, rollingStiffness, 0, , "Rolling stiffness of sphere-sphere contacts as kr / (ks R^2) [-]; 0: no rolling resistance"))
		((Real, rollingFriction, 0, , "Rolling friction coefficient eta: the rolling moment is capped at eta R |Fn| [-]"))
		((Real, crushingIs50, 0, , "Point-load strength index Is(50) of the spheres' rock [Pa]; 0: spheres do not crush. Else the normal force of a sphere-sphere contact is capped at the failure load Is50 d^2 (0.05 m / d)^0.45 of the smaller sphere (diameter d; ISRM 1985); a step past it adds to the contact's plasticOverlap instead, and the work is booked as 'flexCrushing'"))
		((long, deepOnsets, 0, , "Contacts that started with an overlap larger than onsetFactor x (their approach speed x dt): taken over from a neighbour element (a hand-over, see deepEndings), detected late (missed by the collider, or held back by a cluster's ownership rule) or in a scene built overlapping [-]"))
		((Real, deepOnsetEnergy, 0, , "Sum of 1/2 kn (d - plasticOverlap)^2 over the deep onsets: normal spring energy that came with them (contacts with an element: what they took over from their predecessor, see FlexContactGeom.plasticOverlap) [J]"))
		((long, deepEndings, 0, , "Contacts that ended while still overlapping: handed over to a neighbour element, which then starts deep (see deepOnsets) [-]"))
		((Real, deepEndingEnergy, 0, , "Sum of 1/2 kn (d - plasticOverlap)^2 over the deep endings: normal spring energy that went with them [J]. deepOnsetEnergy - deepEndingEnergy is the energy the hand-overs created: a hand-over passes the spring on (a contact with an element that starts deep takes over its predecessor's force and no more, see FlexContactGeom.plasticOverlap), so its onset and ending cancel; negative where two contacts merge into one and the spring of the one that ends goes with it; positive from the contacts of a scene built overlapping. O.energy['flexHandover'] books these springs as they go, in the scheme's own energy (pkg/kernel/Onset.hpp): a contact that ends while overlapping books what its spring takes with it, the contact that takes its force over books back what it brings, so a hand-over nets to the work its successor skips and a merge to the spring of the contact that ended"))
		((bool, crossing, true, , "Energy-consistent onset and release (pkg/kernel/Crossing.hpp): over the step in which a contact starts or ends, the leap-frog scheme gains or loses up to 1/2 kn d0 d1 (the overlaps at the step's ends, of opposite signs), up to a quarter of (omega dt)^2 of the energy of a bounce; each contact keeps that defect and cancels it with an extra normal force on the next steps (kept two steps past its separation to do so). False: the plain penalty contact"))
		((Real, onsetFactor, 2, , "An onset counts as deep when its overlap exceeds onsetFactor x the approach speed x dt (the overlap one step of approach gives; 2 leaves room for the change of speed within the step) [-]"))
		((Real, maxOverlapRatio, 0, , "Largest overlap / (refR1 + refR2) (the contact's reach) of an active contact at any step since it was last set to 0 (set it to 0 to start again) [-]"))
		((Vector2i, maxOverlapIds, Vector2i(-1, -1), , "The two bodies of the contact of maxOverlapRatio [-]"))
		((int, rollIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, elastIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, frictIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, crushIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, handIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
	);
	// clang-format on
	FUNCTOR2D(FlexContactGeom, FrictPhys);
};
REGISTER_SERIALIZABLE(Law2_FlexContactGeom_FrictPhys_CundallStrack);

} // namespace yade
