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
// The law puts the contact force on both sides with applyForce. The time stepper counts every
// contact at the worst weights its sides can have (flex::potentialContactRows), which bound these.
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

		/// Inverse mass [1/kg] of the side's contact point for a force along a direction: the
		/// lumped point the weights make of its nodes, sum w^2 / m (a rigid body: 1 / m; rotation
		/// left out); a node or body that cannot move (not dynamic, or all its translations
		/// blocked) adds nothing.
		Real invMass(const Scene* scene) const
		{
			const auto inv = [&](Body::id_t id) -> Real {
				const Body* b = bodyAt(scene, id);
				if (!b || !b->isDynamic() || (b->state->blockedDOFs & State::DOF_XYZ) == State::DOF_XYZ || !(b->state->mass > 0)) return 0;
				return 1 / b->state->mass;
			};
			if (isFacet()) return bary[0] * bary[0] * inv(tri[0]) + bary[1] * bary[1] * inv(tri[1]) + bary[2] * bary[2] * inv(tri[2]);
			if (isRigid()) return inv(body);
			return (1 - u) * (1 - u) * inv(nodes[0]) + u * u * inv(nodes[1]);
		}
	};
} // namespace flexa
} // namespace yade
