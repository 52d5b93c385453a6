// yade-flex adapter: FlexInteractionLoop, YADE's InteractionLoop with memory prefetching
// (GPL-2.0-or-later). Measurements behind each part: bench/README.md.
//
// Why: in a granular scene the interaction loop is bound by memory latency, not arithmetic.
// Each interaction is a separate heap object, and so are its two bodies, their states and
// shapes, and the contact's geometry and physics; the loop visits them in the order the collider
// created them, which is not the order they sit in memory.
//
// What: the same loop, the same functor calls, the same results (bit-identical at -j1: the order
// of the calls and of the force sums is unchanged; tests/yade/test_loop.py), but each thread
// takes blocks of consecutive interactions (blockSize) and makes two passes over a block:
//  1. it reads the interaction objects, asking for each one `ahead[0]` objects before it reads
//     it, and lists the interactions left after
//     - those the time stepper marked as unable to touch before the collider runs again
//       (flexa::UnreachableMarks, FlexProtocol.hpp: their functor would return false first thing);
//     - with quickReject, the sphere-sphere pairs without contact whose spheres are apart (the
//       functor would return false before changing anything), judged from a table of the
//       spheres' centres and radii made at the start of the step (32 bytes per body in id order,
//       r = -1 for bodies that are not plain spheres, which sends a pair to its functor); the
//       table is made only on steps after one that had such pairs or new pairs; the same for a
//       sphere without contact beside a YADE Facet or Wall, farther from its plane than its
//       radius, judged from a table of the facets' and walls' planes made with it (a grain in a
//       container of facets, on a floor). The grains of a FlexGrainEngine that ran right before
//       this loop go into the table from that engine's arrays, which hold the same values read
//       from the same bodies at this step;
//     - with rememberSkips, pairs left out on an earlier step: each is remembered (its object's
//       address, its ids, a generation) and left out again from that 24-byte record, read in
//       order, without reading its interaction object. A record holds while the object at its
//       place in the container is the same (the record keeps it alive, so no new object takes its
//       address) and, for a sphere pair apart, while the functors, quickReject, the scene and the
//       container stay the same; for a marked pair, also while marks hold: when they are made
//       again (with nothing else changed), the record is asked against the new marks by its place
//       and ids. Objects are asked for ahead by reads, not by place (most places are left
//       out from their records);
//  2. it runs the functors on the listed ones, asking for their bodies, geom and phys `ahead[1]`
//     listed interactions ahead and for the bodies' states and shapes `ahead[2]` ahead. An
//     existing sphere-sphere contact of the yade-flex law (fuseSpheres) runs as one call,
//     Ig2_Sphere_Sphere_FlexContactGeom::update and the law's apply, on the spheres' centres,
//     radii, velocities, angular velocities and inverse masses (the onset and release correction's)
//     from the table (88 bytes per body): the same arithmetic on the same values, without reading
//     bodies, states and shapes or dispatching.
// Prefetches never fault, and only interactions of the thread's own block are read ahead (no
// data race with the thread that owns the next block).
//
// Every compactEvery steps, at the start of the step, the contacts' geometry and physics objects
// (FlexContactGeom with FrictPhys) are copied into one block of memory in the order of the
// container (on several threads, each thread one contiguous part into a block of its own), which
// pass 2 follows: it reads them as one stream instead of from addresses the allocator scattered
// as contacts came and went. The copies are exact. An object that Python or another interaction
// also holds (use_count > 1) stays where it is, so that a reference held from Python stays the
// live object. Each copy is released on its own; the block with its last.
//
// On several threads, each thread takes one contiguous run of blocks, split so that each
// thread's blocks took about as long on the last step, then blocks left at the back of the other
// threads' runs (flex::BlockShares: a run that takes longer than on the last step is finished by
// the threads that are done); and (threadSums) the yade-flex contact law
// adds its forces to the thread's own per-body sums (flexa::ThreadForceSums), added to the
// ForceContainer once per body after the loop, instead of ForceContainer::addForce per contact,
// whose writes to fields shared by all threads contend. One thread runs exactly as before.
//
// A contact that ends is reset in place at once, as InteractionLoop does, but its geometry and
// physics objects are released only after the loop: on several threads, the functor of a
// neighbouring contact may be reading them (the shear a contact takes over when it is handed
// from one element to the next, flexa::takeOverShear).
//
// Steps the fast path does not cover run InteractionLoop::action unchanged, on one thread (it
// frees an ending contact's objects at once): interaction callbacks, loopOnSortedInteractions,
// and the steps on which the collider asks for unseen interactions to be removed (an exception
// thrown by a functor there still terminates YADE, as in InteractionLoop). On the fast path an exception thrown by a functor stops the threads from
// calling further functors and is rethrown after the parallel loop (InteractionLoop would
// terminate YADE); a pair with no Ip2 or Law2 functor raises a RuntimeError naming the types.
// The skip of marked pairs does not look at the bodies' MPI subdomains: YADE's MPI mode is not
// supported here (nor anywhere in yade-flex). InteractionLoop's warning for a geometry functor
// that returns false on a real interaction is not printed (the interaction is reset all the same).
#pragma once
#include "../FlexPch.hpp"
#include "../FlexForces.hpp"
#include "FlexTuning.hpp"

#include <core/InteractionLoop.hpp>

namespace yade {

class FlexInteractionLoop : public InteractionLoop {
public:
	/// a body's centre and radius for quickReject (r < 0: not a plain Sphere)
	struct SpherePoint {
		Real x, y, z, r;
	};
	/// a body's velocity, angular velocity and inverse mass (0: it cannot move, as
	/// flexa::ContactSide::invMass has it), beside its SpherePoint (fuseSpheres)
	struct SphereMotion {
		Vector3r vel, angVel;
		Real     invMass;
	};
	/// a YADE Facet's or Wall's side for quickReject: kind 1, a Facet: its centre x and its
	/// normal n = R * Facet::normal (R its orientation's matrix), `scale` = sum |R_ij| x sum
	/// |normal_j| (the margin's factor); kind 2, a Wall: x and `axis`; kind 0: neither this step
	struct SidePoint {
		Real x[3], n[3], scale;
		int  kind, axis;
	};

private:
	// the geometry functors of the last step (address and dynamic type), and those among them
	// that read the unreachable marks (flexa::readsUnreachableMarks; found again only when the list changes)
	std::vector<std::pair<const IGeomFunctor*, const std::type_info*>> seenFunctors;
	std::vector<const IGeomFunctor*>                                   markReaders;
	// the sphere-sphere functors among them (Ig2_Sphere_Sphere_FlexContactGeom), and this step's
	// centres and radii of the bodies that are plain Spheres (r < 0: any other body), by id
	std::vector<const IGeomFunctor*> sphereReaders;
	std::vector<SpherePoint>         spherePoints;
	std::vector<SphereMotion>        sphereMotion;
	// the ids of the bodies that were plain Spheres when the body container last changed size (or
	// the scene changed): the table is filled from these bodies only, every other entry keeps
	// r = -1 (a body made a Sphere since then takes the full path, as any non-sphere)
	std::vector<Body::id_t> sphereIds;
	std::vector<char>       isSphereId;     // by id: 1 for the bodies in sphereIds
	std::vector<Body::id_t> otherSphereIds; // this step's sphereIds that a FlexGrainEngine did not read (the table's)
	// YADE's facet-sphere and wall-sphere functors among the geometry functors
	// (Ig2_Facet_Sphere_ScGeom, Ig2_Wall_Sphere_ScGeom, exactly), the bodies that were a Facet or a
	// Wall when sphereIds was made, their index in sideIds by id (-1: none) and this step's sides
	std::vector<const IGeomFunctor*> sideReaders;
	std::vector<Body::id_t>          sideIds;
	std::vector<int>                 sideIx;
	std::vector<SidePoint>           sidePoints;
	const Scene*            sphereIdsScene  = nullptr;
	long                    sphereIdsBodies = -1;
	// contacts the fused path could take on the last step (fuseSpheres; -1: not counted yet):
	// the table is made when this or lastCandidates is not 0
	long lastFusable = -1;
	// pairs that quickReject could have judged on the last step (no contact, and the sphere-sphere
	// functor, or none cached yet between two bodies of sphereIds, or a side's functor with a
	// sphere); -1: not counted yet. The table is made only when this is not 0
	// (a net of wires has no sphere pairs: a table made for nothing would be a sizeable share of its short step)
	long lastCandidates = -1;
	// the threads' own sums of the contact forces (threadSums, several threads)
	flexa::ThreadForceSums sums;
	// the work of each block of interactions on the last step, for the split among threads
	std::vector<Real> blockWeight;
	// rememberSkips: by index in the interaction container, what pass 1 found out about the pair
	// there while it did not touch it (kind 1: marked unreachable; kind 2: a sphere pair without
	// contact for quickReject; kind 3: a sphere beside a facet or wall, the same; 0: nothing), valid while the object there is still `ptr` and `gen`
	// is its kind's current generation (genMarked, genQuick; FlexLoop.cpp). `held` keeps each
	// remembered object alive, so that no other interaction can take its address while the record
	// names it.
	struct Remembered {
		const Interaction* ptr = nullptr;
		Body::id_t         id1 = -1, id2 = -1;
		unsigned           gen  = 0;
		unsigned char      kind = 0;
	};
	std::vector<Remembered>              remembered;
	std::vector<shared_ptr<Interaction>> held;
	unsigned                             recGen = 0, genMarked = 0, genQuick = 0; // (records start at gen 0, kind 0)
	// the generation of the marked records (kind 1) before the marks were last made again, when
	// nothing else changed and marks held before and after (0: none): such a record still leaves
	// its pair out if the new marks hold its pair at its place (Step::markedBefore)
	unsigned genMarkedBefore = 0;
	// what the records were made against (a change starts a new generation)
	const Scene*                recScene       = nullptr;
	const InteractionContainer* recContainer   = nullptr;
	unsigned long               recMarks       = 0;
	long                        recColliderRun = 0;
	bool                        recMarksValid = false, recQuick = false;
	// compactEvery: the step of the last copy
	long lastCompact = 0;

	class Step; // one step of the loop: FlexLoop.cpp
	friend class Step;
	bool fallBack();

public:
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(FlexInteractionLoop, InteractionLoop,
		"InteractionLoop that prefetches the interactions, bodies, states, shapes, geometries and physics a few iterations ahead (yade-flex). Same constructor (3 lists of functors) and same results; see pkg/yade/speed/FlexLoop.hpp.",
		((bool, prefetch, true, , "Use the prefetching loop; False runs InteractionLoop.action (for comparisons)"))
		((int, blockSize, flexa::tuning::kBlockSize, , "Interactions per block (prefetching stays inside a block); on several threads each thread takes one contiguous run of blocks, so that its interactions, mostly of bodies near each other, stay in its core's cache, then blocks left at the end of the other threads' runs [-]"))
		((Vector3i, ahead, Vector3i(flexa::tuning::kAheadObjects, flexa::tuning::kAheadTargets, flexa::tuning::kAheadStates), , "Prefetch distances [iterations]: interaction objects (pass 1, counted in objects read: those left out from rememberSkips' records do not count), their bodies, geom and phys, the bodies' states and shapes (pass 2, counted in interactions left after the unreachable ones); ahead[0] >= 1, ahead[0] >= ahead[1] >= ahead[2] >= 1"))
		((bool, quickReject, true, , "On the prefetching loop, leave out a sphere-sphere pair that has no contact and whose spheres are apart (Ig2_Sphere_Sphere_FlexContactGeom would return false at once), and a sphere without contact farther than its radius from the plane of a YADE Facet (Ig2_Facet_Sphere_ScGeom) or a Wall (Ig2_Wall_Sphere_ScGeom) that would equally return false at once, judged from a table of the spheres' centres and radii and the facets' and walls' planes made at the start of the step, before its bodies are read; False: every such pair goes to its functor (for comparisons). Same results either way."))
		((bool, fuseSpheres, true, , "On the prefetching loop, run an existing sphere-sphere contact (Ig2_Sphere_Sphere_FlexContactGeom, Ip2_FrictMat_FrictMat_FrictPhys, Law2_FlexContactGeom_FrictPhys_CundallStrack, two plain spheres) as one call from a table of the spheres' centres, radii, velocities and angular velocities made at the start of the step, without reading their bodies, states and shapes or calling the three functors through the dispatch; False: through the functors (for comparisons). Same results bit for bit."))
		((bool, threadSums, true, , "On the prefetching loop with several threads and at least threadSumsMin interactions, each thread sums the forces of the yade-flex contact law in its own arrays, added to O.forces once per body after the loop (flexa::ThreadForceSums: ForceContainer.addForce from two threads at once contends for shared cache lines); False: addForce per contact (for comparisons). Same forces up to round-off; one thread never uses them."))
		((long, threadSumsMin, flexa::tuning::kThreadSumsMin, , "Fewest interactions for threadSums: below, the few addForce calls contend little and adding the sums (a pass over every body, on every thread) costs more (bench/profile_wire.py) [-]"))
		((bool, rememberSkips, true, , "On the prefetching loop, remember for each pair left out without its bodies (marked unreachable, or a sphere pair of quickReject) that it was, and on the next steps, while the marks and the interaction at that place in the container stay the same, leave it out (or judge it from the table of centres) without reading its interaction object; False: every interaction object is read on every step (for comparisons). Same results bit for bit. Assumes that nothing but this loop (or InteractionLoop's own loop when this one falls back to it, after which the records start again) gives such a potential pair a geometry or physics: the container's insert, erase and clear are seen, and a pair reset in place by O.interactions.erase is still left out from its record, with the same results (tests/yade/test_loop.py)."))
		((long, compactEvery, flexa::tuning::kCompactEvery, , "On the prefetching loop, every this many steps, copy the geometry and physics of the contacts (FlexContactGeom with FrictPhys) into one block of memory (one per thread, each a contiguous part of the container), side by side in the order the loop visits them, so that it reads them as one stream instead of from scattered places on the heap; 0: never. The copies are exact (same results bit for bit); an object that anything else holds too (a Python reference, another interaction) is left where it is [steps]"))
		((long, compactedContacts, 0, Attr::readonly, "Contacts copied by the last compaction (compactEvery) [-]"))
		((long, compactedBlocks, 0, Attr::readonly, "Blocks of memory the last compaction filled: one per thread that had contacts to copy in its part of the container [-]"))
		((long, recalledSkips, 0, Attr::readonly, "Pairs left out on the last step from rememberSkips' records, without reading their interaction objects [-]"))
		((long, markedSkips, 0, Attr::readonly, "Pairs left out on the last step because FlexTimeStepper marked them as unable to touch before the collider runs again (see FlexTimeStepper.markUnreachable, marksBeforeLoop) [-]"))
		((bool, usedFastPath, false, Attr::readonly, "Whether the last step used the prefetching loop"))
		((bool, usedThreadSums, false, Attr::readonly, "Whether the last step summed the yade-flex contact forces per thread (threadSums, several threads)"))
		((long, quickRejected, 0, Attr::readonly, "Pairs left out by quickReject on the last step (with rememberSkips, also pairs apart that are marked unreachable, when remembered from a step without marks) [-]"))
		((long, fusedContacts, 0, Attr::readonly, "Sphere-sphere contacts run by the fused path (fuseSpheres) on the last step [-]"))
		((long, quickCandidates, 0, Attr::readonly, "Pairs quickReject could judge on the last step: no contact, and Ig2_Sphere_Sphere_FlexContactGeom or no functor yet between two spheres, or a sphere and Ig2_Facet_Sphere_ScGeom or Ig2_Wall_Sphere_ScGeom (the table of centres is made on the next step only if this is not 0) [-]"))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexInteractionLoop);

} // namespace yade
