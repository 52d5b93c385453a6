// yade-flex adapter: what FlexInteractionLoop's passes read before the functors: the bodies, the
// pairs left out (unreachable marks, quickReject) or fused (fuseSpheres), and what is asked for
// ahead (GPL-2.0-or-later). Included by FlexLoop.cpp only; why and what: FlexLoop.hpp.
#pragma once
#include "FlexLoop.hpp"
#include "../FlexProtocol.hpp"
#include "FlexTuning.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace yade {
namespace flexa {
	namespace loop {
		using flexa::tuning::kMaxBlock;

		struct Bodies {
			const shared_ptr<Body>* p;
			long                    n;
			Body*                   get(Body::id_t id) const { return (id >= 0 && id < n) ? p[id].get() : nullptr; }
		};

		// What the loop and the contact functors read, whole: the interaction, the bodies (id, flags,
		// shape, state, material, clumpId), their states and shapes, the contact's geom and phys
		// (176, 320, 104, 352 and 104 bytes for Body, State, Sphere, FlexContactGeom, FrictPhys).
		inline void fetchTargets(const Interaction* I, const Bodies& b, bool fused)
		{
			if (!fused) {
				if (Body* b1 = b.get(I->getId1())) flexa::prefetch(b1, sizeof(Body));
				if (Body* b2 = b.get(I->getId2())) flexa::prefetch(b2, sizeof(Body));
			}
			if (const IGeom* g = I->geom.get()) flexa::prefetch(g, sizeof(FlexContactGeom)); // (the largest geom of the module's contacts)
			if (const IPhys* p = I->phys.get()) flexa::prefetch(p, sizeof(FrictPhys));
		}

		// The pairs the time stepper marked as unable to touch before the collider runs again
		// (flexa::UnreachableMarks), for the functors that read these marks: such a pair, while it
		// has no geometry, is skipped here before its bodies are touched, which is exactly what
		// happens inside the functor (it returns false first thing) and after it in the loop
		// (nothing for a pair that was not real). Also for the functors that return false for
		// shapes apart (flexa::skipsMarkedAsApart: a grain beside a YADE facet), where the marks
		// hold (flexa::marksHold: their facets have not started turning).
		struct Marked {
			bool                                     valid   = false;
			const std::vector<const IGeomFunctor*>*  readers = nullptr; // readsUnreachableMarks and skipsMarkedAsApart, of this loop's functors
			const std::pair<Body::id_t, Body::id_t>* pairs   = nullptr; // the marks, by Interaction::linIx
			size_t                                   nPairs  = 0;
			Marked()                                         = default;
			Marked(const Scene* scene, const std::vector<const IGeomFunctor*>* r)
			        : readers(r)
			{
				const flexa::UnreachableMarks& m = flexa::sceneState(scene).unreachable;
				valid                            = flexa::marksHold(scene);
				if (valid) {
					pairs  = m.pair.data();
					nPairs = m.pair.size();
				}
			}
			// whether the marks hold the pair (id1, id2) at index i (either order)
			bool holds(long i, Body::id_t id1, Body::id_t id2) const { return valid && flexa::markMatches(pairs, nPairs, i, id1, id2); }
			// flexa::markedUnreachable and the functor's membership among the readers, inline, the
			// cheap tests first (it runs once per pair, and on a wire net every pair is marked)
			bool operator()(const Interaction& I) const
			{
				if (!valid || I.geom) return false;
				if (!flexa::markMatches(pairs, nPairs, I)) return false;
				const IGeomFunctor* f = I.functorCache.geom.get();
				for (const IGeomFunctor* g : *readers)
					if (g == f) return true;
				return false;
			}
		};

		// Whether a pair is left out by FlexInteractionLoop.quickReject: no contact yet, the
		// sphere-sphere functor, two plain spheres that are apart. The functor returns false for it
		// first thing (R1 + R2 - |x2 - x1| <= 0 for a new contact), changing nothing; the test here
		// asks for more, |x2 - x1|^2 > (R1 + R2)^2 (1 + 1e-12), so that round-off can never make the
		// two disagree (the pairs in between go to the functor).
		// The same for a plain sphere (body 2) beside a YADE Facet or Wall (body 1, the functor's
		// order) with no contact yet:
		// - Ig2_Facet_Sphere_ScGeom returns false first thing when |normal . (R^T (x2 - x1))| > r,
		//   which is (R normal) . (x2 - x1) for any R; computed in the other order its round-off is
		//   below 1e-15 of sum |R_ij| sum |normal_j| sum |x2 - x1|, and the test here asks for r
		//   plus 1e-12 of that;
		// - Ig2_Wall_Sphere_ScGeom returns false when |x2[axis] - x1[axis]| > r, the same
		//   arithmetic here.
		struct Apart {
			const std::vector<const IGeomFunctor*>* readers = nullptr; // the sphere-sphere functors (null: quickReject off)
			const std::vector<const IGeomFunctor*>* sides   = nullptr; // the facet- and wall-sphere functors (null: quickReject off)
			const FlexInteractionLoop::SpherePoint* p       = nullptr; // this step's table (null: not made)
			long                                    n       = 0;
			const char*                             sphere  = nullptr; // by id: a body of the loop's list of spheres
			long                                    nIds    = 0;
			const int*                              sideIx  = nullptr; // by id: the index of its SidePoint (-1: none)
			long                                    nSideIx = 0;
			const FlexInteractionLoop::SidePoint*   side    = nullptr; // this step's sides (null: not made)
			bool                                    on() const { return readers || sides; }
			// 0: not a candidate; 1: a candidate the tables do not leave out (or no table); 2: a
			// sphere pair left out; 3: a sphere beside a facet or wall left out. A candidate: no
			// contact and the sphere-sphere functor, or no functor cached yet between two listed
			// spheres (a new pair, or a contact that ended: the pair may become one; a grain's
			// contact with a wall that ends does not make the table on the next step), or a side's
			// functor.
			int operator()(const Interaction& I) const
			{
				if (!on() || I.geom || !I.functorCache.geomExists) return 0;
				const IGeomFunctor* f = I.functorCache.geom.get();
				if (!f) return readers && listed(I.getId1()) && listed(I.getId2()) ? 1 : 0;
				if (readers && std::find(readers->begin(), readers->end(), f) != readers->end()) return byIds(I.getId1(), I.getId2());
				if (sides && std::find(sides->begin(), sides->end(), f) != sides->end()) return sideByIds(I.getId1(), I.getId2());
				return 0;
			}
			bool listed(Body::id_t id) const { return id >= 0 && id < nIds && sphere[id]; }
			// the table's part: 1 or 2 as above, for a candidate of these ids
			int byIds(Body::id_t i1, Body::id_t i2) const
			{
				if (!p) return 1;
				if (i1 < 0 || i2 < 0 || i1 >= n || i2 >= n) return 1;
				const FlexInteractionLoop::SpherePoint &a = p[i1], &b = p[i2];
				if (a.r < 0 || b.r < 0) return 1;
				const Real dx = b.x - a.x, dy = b.y - a.y, dz = b.z - a.z, s = a.r + b.r;
				return dx * dx + dy * dy + dz * dz > s * s * (1 + 1e-12) ? 2 : 1;
			}
			// the tables' part: 1 or 3 as above, for a side's candidate of these ids (i1 the side)
			int sideByIds(Body::id_t i1, Body::id_t i2) const
			{
				if (!p || !side) return 1;
				if (i1 < 0 || i2 < 0 || i1 >= nSideIx || i2 >= n || sideIx[i1] < 0) return 1;
				const FlexInteractionLoop::SidePoint&   f = side[sideIx[i1]];
				const FlexInteractionLoop::SpherePoint& b = p[i2];
				if (b.r < 0) return 1;
				const Real d[3] = { b.x - f.x[0], b.y - f.x[1], b.z - f.x[2] };
				if (f.kind == 1) {
					const Real L      = f.n[0] * d[0] + f.n[1] * d[1] + f.n[2] * d[2];
					const Real margin = 1e-12 * f.scale * (std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]));
					return std::abs(L) > b.r + margin ? 3 : 1;
				}
				if (f.kind == 2) return std::abs(d[f.axis]) > b.r ? 3 : 1;
				return 1;
			}
		};

		// Whether a contact takes the fused path (fuseSpheres): it exists (geom and phys), and its cached
		// functors are the sphere-sphere geometry, Ip2_FrictMat_FrictMat_FrictPhys (which returns at
		// once when the physics exists) and the yade-flex law, each of exactly that class (a subclass
		// could override go); its bodies are plain spheres in this step's table. The generic path would
		// then call exactly Ig2_Sphere_Sphere_FlexContactGeom::update and the law's apply, on the same
		// values read from the bodies' states and shapes instead of the table.
		struct Fusable {
			const std::vector<const IGeomFunctor*>* geoms = nullptr; // the sphere-sphere functors (null: fuseSpheres off)
			const IPhysFunctor*                     phys  = nullptr;
			const LawFunctor*                       law   = nullptr;
			const FlexInteractionLoop::SpherePoint* p     = nullptr; // this step's table (null: not made)
			long                                    n     = 0;
			// 0: not fusable; 1: fusable but not on this step (no table, or a body not a plain sphere); 2: fused
			int operator()(const Interaction& I) const
			{
				if (!geoms || !law || !phys || !I.geom || !I.phys) return 0;
				const auto& c = I.functorCache;
				if (!c.geomExists || c.constLaw.get() != law || c.phys.get() != phys) return 0;
				if (std::find(geoms->begin(), geoms->end(), c.geom.get()) == geoms->end()) return 0;
				if (!p) return 1;
				const Body::id_t i1 = I.getId1(), i2 = I.getId2();
				if (i1 < 0 || i2 < 0 || i1 >= n || i2 >= n || p[i1].r < 0 || p[i2].r < 0) return 1;
				return 2;
			}
		};

		inline void fetchStates(const Interaction* I, const Bodies& b)
		{
			for (Body::id_t id : { I->getId1(), I->getId2() })
				if (const Body* body = b.get(id)) {
					if (const State* s = body->state.get()) flexa::prefetch(s, sizeof(State));
					if (const Shape* sh = body->shape.get()) flexa::prefetch(sh, sizeof(Sphere)); // (the radius is its last field)
				}
		}
	} // namespace loop
} // namespace flexa
} // namespace yade
