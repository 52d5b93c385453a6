// yade-flex adapter (GPL-2.0-or-later): the cylinder element: a capsule between two FlexNodes (no DOF); it IS the
// bond (co-rotational beam, pkg/kernel/Beam.hpp) and the contact surface; its bound from both nodes.
#pragma once
#include "FlexPch.hpp"

namespace yade {

class FlexCylinder : public Shape {
public:
	virtual ~FlexCylinder() = default;
	/// Validate, bind to the nodes, compute the rest state and add the lumped mass/inertia
	/// shares to the nodes. Raises ValueError naming the problem.
	void attach(int selfId);
	/// Its largest squared eigenfrequency, for the time-step bound (FlexTimeStepper) [1/s2].
	Real stepOmega2() const { return omega2; }
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexCylinder, Shape,
		"Deformable cylinder (yade-flex): a capsule of :yref:`FlexCylinder.radius` between two :yref:`FlexNode` bodies, with no DOF of its own. It is both the bond (co-rotational Euler-Bernoulli beam: EA/L, 12EI/L^3, EI/L, GJ/L, J = 2I) and the contact surface. Lumped shares given to each node: mass rho*pi*r^2*L/2 (the cylinder only; the spherical caps overlap the neighbour in a continuous wire and are not counted) and isotropic inertia m_h(r^2/4 + L^2/12). Create with ``yadeflex.cylinder``.",
		((int, node1, -1, , "Id of the first node"))
		((int, node2, -1, , "Id of the second node"))
		((Real, radius, NaN, , "Radius [m]"))
		((bool, attached, false, Attr::readonly, "Bound to its nodes (rest state computed)"))
		((Vector3r, boundRef1, Vector3r::Zero(), (Attr::hidden | Attr::noSave), "node1 position when the bound was last built [m]"))
		((Vector3r, boundRef2, Vector3r::Zero(), (Attr::hidden | Attr::noSave), "node2 position when the bound was last built [m]"))
		((Real, L0, NaN, Attr::readonly, "Rest length [m]"))
		((Quaternionr, Q1, Quaternionr::Identity(), Attr::readonly, "Element frame in node1's frame at rest"))
		((Quaternionr, Q2, Quaternionr::Identity(), Attr::readonly, "Element frame in node2's frame at rest"))
		((Real, massShare, 0, Attr::readonly, "Mass given to each node [kg]"))
		((Real, inertiaShare, 0, Attr::readonly, "Rotational inertia given to each node [kg m^2]"))
		((Real, omega2, 0, Attr::readonly, "Largest squared eigenfrequency of the element with its own mass shares [1/s^2]"))
		((Real, plasticStrain, 0, Attr::readonly, "Permanent axial strain [-]"))
		((Real, hardeningVar, 0, Attr::readonly, "Accumulated plastic strain [-]"))
		((Real, axialForce, 0, Attr::readonly, "Axial force, tension positive [N]"))
		((Real, strain, 0, Attr::readonly, "Axial strain (L-L0)/L0 [-]"))
		((Real, elasticEnergy, 0, Attr::readonly, "Stored elastic energy [J]"))
		((Real, maxStrain, 0, Attr::readonly, "Wire law: largest axial strain reached on the curve [-]"))
		((Real, wireSlack, 0, Attr::readonly, "Wire law: slack strain of this link, drawn once at attach from FlexMat.wireSeed and the node ids [-]"))
		((Vector2i, hookLegs, Vector2i(-1, -1), , "Hooked knot: set before attach to make this link the knot of two hooked wire bends (node1's and node2's), which turn about each other but cannot pass through each other: the far nodes of node1's two legs. node1 stays on its side of node2 along the direction from their midpoint to node1 (the way node1's bend opens), at least at the gap of the rest state (pkg/kernel/Hook.hpp). (-1, -1): no stop. Read at attach. The stop lets go for good when a leg of node1 ruptures or its bend is pulled straight. The time step bound counts the stop's mode with this link's mass share at the legs' far nodes too: they must be at least as heavy (a leg's share makes them so)."))
		((Vector2i, hookNodes, Vector2i(-1, -1), Attr::readonly, "Hooked knot: hookLegs as validated at attach, the nodes the stop uses (later changes of hookLegs are ignored) [-]"))
		((Real, hookGap, 0, Attr::readonly, "Hooked knot: the gap (x1 - x2) . n at rest, the stop [m]"))
		((Real, hookStiffness, 0, Attr::readonly, "Hooked knot: the stop's stiffness, the link's EA/L0 [N/m]; 0: no stop (or let go)"))
		((Real, hookForce, 0, Attr::readonly, "Hooked knot: the stop's force this step, >= 0 [N]")),
		createIndex();,
		.def("attach", &FlexCylinder::attach, (boost::python::arg("id")), "Bind to the nodes (called by yadeflex.cylinder).")
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexCylinder, Shape);
};
REGISTER_SERIALIZABLE(FlexCylinder);

class Bo1_FlexCylinder_Aabb : public BoundFunctor {
public:
	void go(const shared_ptr<Shape>& sh, shared_ptr<Bound>& bv, const Se3r&, const Body*) override;
	FUNCTOR1D(FlexCylinder);
	// clang-format off
	YADE_CLASS_BASE_DOC(Bo1_FlexCylinder_Aabb, BoundFunctor, "Axis-aligned box of a :yref:`FlexCylinder` from both nodes' current positions (so detection follows both ends).");
	// clang-format on
};
REGISTER_SERIALIZABLE(Bo1_FlexCylinder_Aabb);

} // namespace yade
