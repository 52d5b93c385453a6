// yade-flex adapter: FlexGrainEngine, the contacts between grains (spheres of one material) on
// arrays of their own, through the kernel's GrainNeighbours and GrainContacts
// (GPL-2.0-or-later).
//
// The grains' pairs are kept out of YADE's collider and interaction container: the engine gives
// its grains a groupMask bit that the scene's InsertionSortCollider avoids between them
// (Collider.avoidSelfInteractionMask), takes over the grain-grain interactions the scene has (a
// real one's state goes to the kernel: its shear force, rolling moment and crossing correction)
// and erases them. Each step it reads the grains' states into arrays, rebuilds the neighbour
// list when a grain has moved half the skin, runs the law and adds the forces, torques and
// energy terms to the scene. Grains' contacts with anything else (walls, facets, elements,
// spheres of another material) stay in the interaction loop. It runs between the collider and
// the interaction loop, and FlexTimeStepper counts its pairs as it counts the collider's.
#pragma once
#include "FlexPch.hpp"
#include "speed/FlexTuning.hpp"

#include <kernel/GrainContacts.hpp>
#include <kernel/GrainNeighbours.hpp>

#include <memory>
#include <vector>

namespace yade {

class Law2_FlexContactGeom_FrictPhys_CundallStrack;

class FlexGrainEngine : public GlobalEngine {
	std::unique_ptr<flex::GrainNeighbours>        nb;
	std::unique_ptr<flex::GrainContacts>          gc;
	std::vector<Body::id_t>                       ids;     // grain index -> body id (ascending)
	std::vector<int>                              indexOf; // body id -> grain index, -1: not a grain
	std::vector<flex::Vec3>                       pos, vel, angVel, force, torque;
	std::vector<double>                           radius, invMass;
	std::vector<std::vector<flex::Vec3>>          threadForce, threadTorque; // threads 1.. (thread 0: force, torque)
	size_t                                        bodyCount = 0;
	int                                           elastIx = -1, frictIx = -1, rollIx = -1;
	Law2_FlexContactGeom_FrictPhys_CundallStrack* law = nullptr;

	mutable std::vector<flex::Vec3> stepPos; // (addStepRows' scratch)
	mutable std::vector<double>     stepReach;
	long                            lastIter = -2; // the iteration of the last step
	flex::GrainLaw                  grainLaw() const;
	bool                            gather(); // false: a grain is gone or changed (scan again)
	void                            scan();

public:
	/// Throws std::invalid_argument naming the first bad setting.
	void validate() const;
	void postLoad(FlexGrainEngine&) { validate(); }
	void action() override;
	/// One Real per body id read from a table of structs (the field of body 0 at `first`, the
	/// next `stride` bytes on; `n` bodies), 0 for an id past the table.
	struct BodyColumn {
		const unsigned char* first;
		size_t               stride, n;
		Real operator[](Body::id_t id) const { return id >= 0 && (size_t)id < n ? *reinterpret_cast<const Real*>(first + (size_t)id * stride) : 0; }
	};
	/// Adds the time-step rows of the grains' pairs (see FlexStepperContacts.hpp): every listed
	/// pair that can touch before the list is built again, with the stiffness its contact has
	/// or will have, and the rolling springs of the contacts. invSqrtMass and Imin by body id.
	void addStepRows(Real* row, Real* rowRot, BodyColumn invSqrtMass, BodyColumn Imin) const;
	/// A contact carrying force at the last step, as the step saw it (positions before the
	/// integrator moved them): forces on id2, normal from id1 to id2.
	struct ContactRow {
		Body::id_t id1, id2;
		Vector3r   x1, x2, point, normal, normalForce, shearForce;
		Real       depth;
	};
	/// The grains as this engine read them from their bodies at its step of iteration `iter`
	/// (null ids if it did not run at `iter`): by grain index, body ids (ascending), centres,
	/// velocities, angular velocities, radii and inverse masses (0: cannot move); the grain index of
	/// each body id below nIds (-1: not a grain). The values stay those of the bodies until an
	/// engine after this one changes a body.
	struct Gathered {
		const Body::id_t* ids = nullptr;
		const Vector3r *  pos = nullptr, *vel = nullptr, *angVel = nullptr;
		const Real *      radius = nullptr, *invMass = nullptr;
		const int*        indexOf = nullptr;
		long              n = 0, nIds = 0;
	};
	Gathered gatheredAt(long iter) const;
	/// f(i, j, state) for each contact state (grain indices i < j), in pair order.
	template <class F> void forEachState(F f) const;
	/// f(row) for each contact carrying force at the last step, in pair order.
	template <class F> void forEachContact(F f) const;
	/// The contacts carrying force at the last step: (id1, id2, normal force, shear force on id2) each
	boost::python::list contactList() const;
	/// Saving: the contacts' states go into savedContacts, which a loaded engine takes back.
	void preSave(FlexGrainEngine&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexGrainEngine, GlobalEngine,
		"The contacts between grains (yade-flex): standalone spheres of material :yref:`FlexGrainEngine.material` contact each other through a neighbour list and contact states of this engine's own (pkg/kernel/GrainContacts.hpp: the same law as Law2_FlexContactGeom_FrictPhys_CundallStrack between two spheres, with its rolling resistance, crossing correction and onset factor read from that functor each step), not through O.interactions. Put it between the InsertionSortCollider and the interaction loop (yadeflex.engines(grains=...) does). It gives its grains the groupMask bit :yref:`FlexGrainEngine.grainBit` and sets it in the collider's avoidSelfInteractionMask, takes over and erases the grain-grain interactions of the scene (a real one's shear force, rolling moment and crossing state carry over); contacts of grains with anything else stay in O.interactions. Energy terms as the law's ('flexContactElastic', 'flexFriction', 'flexRolling'); deep onsets and the largest overlap also go to the law's ledger. Not with crushing (Law2...crushingIs50 > 0) or periodic cells. Grain contacts are not in O.interactions, in VTK contact frames or in saved scenes (a reloaded scene starts its grain contacts anew); see :yref:`FlexGrainEngine.contactList`.",
		((int, material, -1, Attr::triggerPostLoad, "Id of the grains' material in O.materials (a FrictMat); -1: none (the engine does nothing) [-]"))
		((int, grainBit, 1 << 14, Attr::triggerPostLoad, "The groupMask bit (a power of 2) that marks the grains [-]"))
		((long, parallelMin, flexa::tuning::kThreadSumsMin, , "Listed pairs from which a step runs on every OpenMP thread, each on a part of the pairs with force sums of its own, added in thread order [-]"))
		((int, threadsUsed, 1, Attr::readonly, "Threads the last step ran on [-]"))
		((Real, skin, 0, Attr::triggerPostLoad, "Neighbour distance: pairs closer than r1 + r2 + skin are listed; the list is built again when a grain has moved skin / 2. 0: half the smallest grain radius (as yadeflex.engines()' collider sweep) [m]"))
		((long, grains, 0, Attr::readonly, "Grains at the last step [-]"))
		((long, pairs, 0, Attr::readonly, "Listed pairs [-]"))
		((long, contacts, 0, Attr::readonly, "Contacts carrying force at the last step [-]"))
		((long, builds, 0, Attr::readonly, "Neighbour lists built so far [-]"))
		((long, takenOver, 0, Attr::readonly, "Real grain-grain interactions taken over from O.interactions [-]"))
		((long, lostContacts, 0, Attr::readonly, "Contacts not found in a rebuilt list (0 unless a grain moved more than skin / 2 in one step) [-]"))
		((long, deepOnsets, 0, Attr::readonly, "Grain contacts that started deeper than the law's onsetFactor x approach x dt [-]"))
		((Real, deepOnsetEnergy, 0, Attr::readonly, "Their normal springs' energy [J]"))
		((Real, skinUsed, 0, Attr::readonly, "The skin of the current list [m]"))
		((vector<Real>, savedContacts, , (Attr::hidden | Attr::readonly), "The contacts' states as saved with the scene (filled when the scene is saved, taken back at the first step after loading it)")),
		,
		.def("contactList", &FlexGrainEngine::contactList, "The grain contacts carrying force at the last step: a list of (id1, id2, normalForce, shearForce), forces on id2 [N]")
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexGrainEngine);

template <class F> void FlexGrainEngine::forEachState(F f) const
{
	if (!gc) return;
	const auto& first = gc->first();
	const auto& sec   = gc->second();
	const auto& st    = gc->states();
	for (long i = 0; i + 1 < (long)first.size() && i < (long)ids.size(); ++i)
		for (long k = first[i]; k < first[i + 1]; ++k)
			if (st[k].exists) f(i, (long)sec[k], st[k]);
}

template <class F> void FlexGrainEngine::forEachContact(F f) const
{
	forEachState([&](long i, long j, const flex::GrainContacts::State& c) {
		if (c.lastActive != lastIter) return;
		ContactRow r;
		r.id1         = ids[i];
		r.id2         = ids[j];
		r.x1          = pos[i];
		r.x2          = pos[j];
		r.depth       = radius[i] + radius[j] - (pos[j] - pos[i]).norm();
		r.normal      = c.normal;
		r.point       = pos[i] + (radius[i] - 0.5 * r.depth) * c.normal;
		r.normalForce = c.kn * r.depth * c.normal;
		r.shearForce  = c.shear;
		f(r);
	});
}

namespace flexa {
	/// f(engine) for each FlexGrainEngine of the scene, in O.engines' order.
	template <class F> void forEachGrainEngine(const Scene* scene, F f)
	{
		for (const auto& e : scene->engines)
			if (const FlexGrainEngine* ge = dynamic_cast<const FlexGrainEngine*>(e.get())) f(*ge);
	}
} // namespace flexa

} // namespace yade
