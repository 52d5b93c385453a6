// yade-flex adapter: what every contact geometry functor of a deformable element shares
// (GPL-2.0-or-later): a facet's node states, its contact normal, and the steps of an element Ig2.
// Included by FlexFunctors.cpp (elements against spheres and elements) and FlexSurfaces.cpp
// (elements against YADE's rigid surfaces).
#pragma once
#include "FlexElements.hpp"
#include "FlexFacet.hpp"
#include "FlexProtocol.hpp"
#include <kernel/Triangle.hpp>

namespace yade {
namespace flexa {
	// Facet side of a contact: node states and current positions, or false if a node is gone.
	struct FacetNodes {
		const State* s[3];
		Vector3r     x[3], v[3];
		bool         load(const Scene* scene, const FlexFacet& f, const Vector3r& shift)
		{
			const int ids[3] = { f.node1, f.node2, f.node3 };
			for (int k = 0; k < 3; ++k) {
				if (!(s[k] = flexa::stateOf(scene, ids[k]))) return false;
				x[k] = s[k]->pos + shift;
				v[k] = s[k]->vel;
			}
			return true;
		}
		Vector3r normal() const { return (x[1] - x[0]).cross(x[2] - x[0]).normalized(); }
	};

	// Contact normal (from the other body towards the facet) for a probe point P whose closest
	// point on the facet is pt. Face region: the facet normal, on the side the contact started
	// from (kept while the contact lasts, so a probe pushed through the thin membrane is pushed
	// back); the overlap is measured from that side. Edges and vertices: from P to the closest
	// point (continuous with the face normal at the region boundary).
	inline Vector3r facetNormal(
	        const FacetNodes& fn, const flex::PointTriangle& pt, const Vector3r& P, const Vector3r& side, bool isNew, const Vector3r& prev, Real& dist)
	{
		const Vector3r d  = pt.point - P; // from P to the facet
		const Vector3r nf = fn.normal();
		if (pt.support == 7) {
			Real           s = isNew ? (d.dot(nf) != 0 ? d.dot(nf) : (pt.point - side).dot(nf)) : prev.dot(nf);
			const Vector3r n = s >= 0 ? nf : Vector3r(-nf);
			dist             = d.dot(n);
			return n;
		}
		dist = d.norm();
		if (dist > 0) return d / dist;
		return isNew ? ((pt.point - side).dot(nf) >= 0 ? nf : Vector3r(-nf)) : prev;
	}

	// The steps every element Ig2 takes, in this order (each pair type supplies bonded, load, apart, closest, owns, fill, finish):
	//  1. a potential pair marked unreachable by the time stepper: nothing (FlexProtocol.hpp);
	//  2. bonded neighbours (elements sharing a node): switched off and reported for erasure;
	//  3. the nodes' states: a node gone ends a new pair, or makes an existing contact inactive;
	//  4. a new pair: a cheap conservative separation test, then the closest points and the
	//     overlap (with the same arithmetic as the ownership search's probes);
	//  5. ownership of the contact among the elements or element pairs of its cluster
	//     (kernel/Ownership.hpp): a new pair that does not own it is not created;
	//  6. the geometry: normal, depth, contact point, both sides, relative velocity;
	//  7. activity bookkeeping and the shear hand-over (flexa::finishGeom).
	template <class Pair> bool elementGeom(Scene* scene, const shared_ptr<Interaction>& I, bool force, Pair& p)
	{
		if (!I->geom && !force && flexa::markedUnreachable(scene, *I)) return false; // cannot touch before the collider runs again
		if (p.bonded()) {
			// bonded neighbours: switch the pair off now (InteractionLoop skips it at the cost of a
			// flag test) and have FlexElementEngine erase it after the loop (no cost at all)
			I->functorCache.geomExists = false;
			flexa::reportNeighbourPair(scene, I->getId1(), I->getId2());
			return false;
		}
		const bool isNew = !I->geom;
		if (!p.load()) {
			if (isNew) return false;
			static_cast<FlexContactGeom&>(*I->geom).active = false;
			return true;
		}
		if (isNew && !force && p.apart()) return false;
		const Real overlap = p.closest();
		if (isNew && overlap <= 0 && !force) return false;
		const bool own = overlap > 0 && p.owns(overlap);
		if (isNew && !own) return false;
		if (isNew) I->geom = shared_ptr<FlexContactGeom>(new FlexContactGeom);
		FlexContactGeom& g = static_cast<FlexContactGeom&>(*I->geom);
		p.fill(g, isNew);
		p.finish(g, own);
		return true;
	}
} // namespace flexa
} // namespace yade
