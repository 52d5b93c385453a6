// yade-flex adapter: one side of a yade-flex contact, as the contact law and the time stepper
// see it (GPL-2.0-or-later).
//
// A side of a FlexContactGeom is one of
//  - a rigid body (a sphere, a clump member, a box): the force acts on the body, with the moment
//    of its lever about the body's centre (axisPoint);
//  - a point at u on a segment (a cylinder between its two nodes): the force and its moment go to
//    the two nodes (flex::distributeToSegment), weights 1 - u and u;
//  - a point at barycentric weights on a facet (its three nodes): forces only, by the adjoint of
//    the facet point's velocity (flex::distributeToTriangle), each node carrying at most
//    w_a + (load factor - 1) of the force (flex::triangleLoadFactor).
// The law puts the contact force on both sides with applyForce; the time stepper's contact rows
// read the same weights (timeStepEntries), so that the step bounds exactly the force paths the
// law uses.
#pragma once
#include "FlexElements.hpp"
#include "FlexForces.hpp"

#include <kernel/Contact.hpp>
#include <kernel/Triangle.hpp>

namespace yade {
namespace flexa {
	struct ContactSide {
		Body::id_t      body;      // the interaction's body on this side
		const Vector2i& nodes;     // segment: its nodes ([0] < 0: not a segment)
		const Vector3i& tri;       // facet: its nodes ([0] < 0: not a facet)
		Real            u;         // segment: parameter of the contact point
		const Vector3r& bary;      // facet: weights of the contact point
		const Vector3r& axisPoint; // closest point on the axis or midplane (a rigid body: its centre)
		Real            refR;      // contact radius

		/// Side s (1 or 2) of g; body: the interaction's body on that side.
		static ContactSide of(const FlexContactGeom& g, int s, Body::id_t body)
		{
			return s == 1 ? ContactSide { body, g.nodes1, g.tri1, g.u1, g.bary1, g.axis1, g.refR1 }
			              : ContactSide { body, g.nodes2, g.tri2, g.u2, g.bary2, g.axis2, g.refR2 };
		}
		bool isFacet() const { return tri[0] >= 0; }
		bool isRigid() const { return !isFacet() && nodes[0] < 0; }

		/// Puts force F, acting at c, on the side's bodies (through sink, see FlexForces.hpp).
		void applyForce(Scene* scene, const ForceSink* sink, const Vector3r& c, const Vector3r& F) const
		{
			if (isFacet()) {
				Vector3r x[3], f[3];
				for (int k = 0; k < 3; ++k) {
					const State* s = stateOf(scene, tri[k]);
					if (!s) return;
					x[k] = s->pos;
				}
				const double w[3] = { bary[0], bary[1], bary[2] };
				flex::distributeToTriangle(x, w, flex::cappedFacetOffset(x, c - axisPoint), F, f);
				for (int k = 0; k < 3; ++k)
					addForce(scene, sink, tri[k], f[k]);
				return;
			}
			if (isRigid()) {
				addForce(scene, sink, body, F);
				addTorque(scene, sink, body, (c - axisPoint).cross(F));
				return;
			}
			flex::NodeLoad A, B;
			flex::distributeToSegment(u, axisPoint, c, F, A, B);
			addForce(scene, sink, nodes[0], A.F);
			addTorque(scene, sink, nodes[0], A.M);
			addForce(scene, sink, nodes[1], B.F);
			addTorque(scene, sink, nodes[1], B.M);
		}

		/// A body that carries this side in the time step's contact rows: its share of the force
		/// (the bound on it, for a facet) and the lever of the force for its rotational row (0: no
		/// moment reaches it).
		struct Entry {
			Body::id_t id;
			Real       w, lever;
		};
		/// The side's entries into e (at most 3); returns how many.
		int timeStepEntries(const Scene* scene, Entry* e) const
		{
			if (isFacet()) {
				Vector3r x[3];
				bool     ok = true;
				for (int a = 0; a < 3 && ok; ++a) {
					const State* st = stateOf(scene, tri[a]);
					if ((ok = st != nullptr)) x[a] = st->pos;
				}
				const Real extra = ok ? flex::triangleLoadFactor(x, refR) - 1 : 0;
				for (int a = 0; a < 3; ++a)
					e[a] = { tri[a], bary[a] + extra, 0 };
				return 3;
			}
			if (isRigid()) {
				e[0] = { body, 1, refR };
				return 1;
			}
			e[0] = { nodes[0], 1 - u, refR };
			e[1] = { nodes[1], u, refR };
			return 2;
		}
	};
} // namespace flexa
} // namespace yade
