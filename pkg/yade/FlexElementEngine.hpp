// yade-flex adapter (GPL-2.0-or-later): the engine of the elements' internal forces: every bond and membrane,
// rupture (element removed, counted).
#pragma once
#include "FlexPch.hpp"
#include "FlexForces.hpp"
#include "speed/FlexTuning.hpp"

namespace yade {

class FlexElementEngine : public GlobalEngine {
	std::vector<Body::id_t> cylinders, facets; // cache of element ids
	// Ruptured element bodies, kept alive: a body created in Python holds a Python reference,
	// and dropping the last one here, in O.run()'s worker thread without the GIL, aborts YADE.
	std::vector<shared_ptr<Body>> rupturedBodies;
	size_t                        cachedBodyCount = 0;
	std::vector<int>              slotOf;     // body id -> index in slotNode (-1: not a cylinder node)
	std::vector<Body::id_t>       slotNode;   // the cylinders' nodes
	std::vector<Vector3r>         accF, accM; // per-node sums of the serial element loop
	// the threads' own sums of the element forces, when an element loop runs on several threads
	// (flexa::ThreadForceSums; empty sinks: add to the ForceContainer)
	flexa::ThreadForceSums        sums;
	std::vector<flexa::ForceSink> sinks;
	// Per cylinder (same order as `cylinders`), what its forces read and write, as pointers: the
	// loop checks them against the bodies (loads whose results only feed a branch) and computes
	// from the pointers, so the chain body -> shape -> node ids -> node bodies -> states is off the
	// forces' critical path (a chain of 8 dependent loads per element before). A pointer that no
	// longer matches (a body, shape, state or material replaced from Python) is looked up again.
	struct Link {
		const Body*     b  = nullptr;                // the element body,
		FlexCylinder*   c  = nullptr;                // its shape,
		const Material* m  = nullptr;                // its material (cast where used: an address may be reused),
		State*          se = nullptr;                // its state (follows the nodes),
		const Body *    bi = nullptr, *bj = nullptr; // the nodes' bodies
		State *         si = nullptr, *sj = nullptr; // and states
	};
	std::vector<Link> links;
	static Link       linkOf(const Scene* scene, const Body* b); // all null if not computable
	void              refresh();
	// the passes of a step (action), in this order; [lo, hi]: the node ids added to the sinks
	void              prepareSinks();
	void              bondForces(std::vector<Body::id_t>& broken, long& lo, long& hi); // cylinders (FlexCylinder)
	void              facetForces(std::vector<Body::id_t>& broken, long& lo, long& hi); // membranes (FlexFacet)
	void              rupture(std::vector<Body::id_t>& broken);
	void              releaseHooks(const FlexCylinder& leg, bool energy); // hooked knots whose bend loses this leg let go

public:
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(FlexElementEngine, GlobalEngine,
		"Internal forces of all :yref:`FlexCylinder` bonds (co-rotational beam, pkg/kernel/Beam.hpp) and :yref:`FlexFacet` membranes (constant-strain triangle, pkg/kernel/Membrane.hpp, and their follower pressure). An element that ruptures is erased with its body (it stops interacting entirely; its nodes keep their mass) and counted. Books 'flexBondElastic', 'flexBondPlastic', 'flexMembraneElastic', 'flexPressureWork' and 'flexRupture' in O.energy.",
		((int, nRuptured, 0, , "Number of bonds ruptured so far [-]"))
		((int, parallelMin, flexa::tuning::kElementParallelMin, , "Run each element loop (cylinders, facets) on several threads only from this many elements on: below, OpenMP's fork and join cost more than they save (bench/README.md, 'Two threads'). On one thread the loop is always the serial one [-]"))
		((vector<int>, rupturedIds, , Attr::readonly, "Ids of ruptured elements, in order"))
		((int, elastIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, plastIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, ruptIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, contactIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, membIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, pressIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexElementEngine);

} // namespace yade
