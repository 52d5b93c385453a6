// yade-flex adapter: deformable facets (membranes, geotextile linings) (GPL-2.0-or-later).
//
//  - FlexMembraneMat  Material: FrictMat for contacts + membrane stiffness E t, Poisson ratio,
//                     areal density, tension-only (wrinkling) and strength
//  - FlexFacet        Shape: thick triangle (thickness 2 radius, rounded edges and corners) over
//                     three FlexNodes; constant-strain membrane (pkg/kernel/Membrane.hpp); no DOF
//  - Bo1_FlexFacet_Aabb
//  - Ig2_Sphere_FlexFacet_FlexContactGeom       face, edge and vertex regions; one contact where
//                                               facets meet (ownership, see FlexContactGeom.hpp)
//  - Ig2_FlexCylinder_FlexFacet_FlexContactGeom wire against lining
//  - Ig2_FlexFacet_FlexFacet_FlexContactGeom    switches facet pairs off (neighbours and others:
//                                               no facet-facet contact yet), erased at no cost
// Contact kinematics and the force split to the nodes: pkg/kernel/Triangle.hpp (forces only,
// exact force, moment and power balance; a rigid motion gives no slip).
#pragma once
#include "Flex.hpp"

namespace yade {

class FlexMembraneMat : public FrictMat {
public:
	virtual ~FlexMembraneMat() = default;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(FlexMembraneMat, FrictMat,
		"Material of deformable facets (yade-flex membranes). ``young``, ``poisson`` and ``frictionAngle`` keep FrictMat's meaning for contacts (kn = 2 E1 r1 E2 r2/(E1 r1 + E2 r2) with r the facet's half thickness); the membrane law uses :yref:`FlexMembraneMat.stiffness` (E t) and :yref:`FlexMembraneMat.membranePoisson`. ``density`` is not used: the mass comes from :yref:`FlexMembraneMat.arealDensity`.",
		((Real, stiffness, NaN, , "Membrane tensile stiffness E t [N/m]"))
		((Real, membranePoisson, 0.3, , "Poisson ratio of the membrane, in [0, 0.5) [-]"))
		((Real, arealDensity, NaN, , "Mass per unit area [kg/m2]"))
		((bool, tensionOnly, false, , "Fabric that wrinkles: no compression (tension-field model) [-]"))
		((Real, strength, std::numeric_limits<Real>::infinity(), , "A facet ruptures when its larger principal membrane force per unit rest width (n1) reaches this: folded or wrinkled fabric at low stretch never does [N/m]")),
		createIndex();
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexMembraneMat, FrictMat);
};
REGISTER_SERIALIZABLE(FlexMembraneMat);

class FlexFacet : public Shape {
public:
	virtual ~FlexFacet() = default;
	/// Validate, bind to the nodes, compute the rest state and add the lumped mass shares to
	/// the nodes. Raises ValueError naming the problem.
	void attach(int selfId);
	/// Its largest squared eigenfrequency now, for the time-step bound (FlexTimeStepper): omega2
	/// scaled up by how much its current stretch (e1, e2) stiffens its material mat [1/s2].
	Real stepOmega2(const Material* mat) const;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexFacet, Shape,
		"Deformable facet (yade-flex): a thick triangle (thickness 2 :yref:`FlexFacet.radius`, rounded edges and corners) over three :yref:`FlexNode` bodies, with no DOF of its own. It is both the membrane element (constant-strain triangle, St. Venant-Kirchhoff, plane stress; tension-field wrinkling if the material is tension-only) and the contact surface. Each node receives a third of its mass (arealDensity x area). Create with ``yadeflex.facet`` or the membrane builders.",
		((int, node1, -1, , "Id of the first node"))
		((int, node2, -1, , "Id of the second node"))
		((int, node3, -1, , "Id of the third node"))
		((Real, radius, NaN, , "Half thickness: the contact radius [m]"))
		((Real, pressure, 0, , "Follower pressure along the facet normal (x2-x1)x(x3-x1) [Pa]; its work is booked as 'flexPressureWork'"))
		((bool, attached, false, Attr::readonly, "Bound to its nodes (rest state computed)"))
		((Vector3r, restEdges, Vector3r::Zero(), Attr::readonly, "Rest shape in the facet's own frame: |X2-X1|, and X3-X1 along and across that edge [m]"))
		((Real, area0, NaN, Attr::readonly, "Rest area [m2]"))
		((Real, massShare, 0, Attr::readonly, "Mass given to each node [kg]"))
		((Real, inertiaShare, 0, Attr::readonly, "Rotational inertia given to each node [kg m2] (the membrane puts no moment on its nodes)"))
		((Real, omega2, 0, Attr::readonly, "Largest squared eigenfrequency of the facet at rest with its own mass shares [1/s2]; stepOmega2 scales it up for the current stretch (a stretched membrane is stiffer)"))
		((Real, n1, 0, Attr::readonly, "Larger principal membrane force per unit rest width (nominal: what a strip tensile test reports; finite when the fabric folds) [N/m]"))
		((Real, n2, 0, Attr::readonly, "Smaller principal membrane force per unit rest width [N/m]"))
		((Real, e1, 0, Attr::readonly, "Larger principal Green strain [-]"))
		((Real, e2, 0, Attr::readonly, "Smaller principal Green strain [-]"))
		((Real, elasticEnergy, 0, Attr::readonly, "Stored membrane energy [J]"))
		((Vector3r, boundRef1, Vector3r::Zero(), (Attr::hidden | Attr::noSave), "node positions when the bound was last built [m]"))
		((Vector3r, boundRef2, Vector3r::Zero(), (Attr::hidden | Attr::noSave), ""))
		((Vector3r, boundRef3, Vector3r::Zero(), (Attr::hidden | Attr::noSave), "")),
		createIndex();,
		.def("attach", &FlexFacet::attach, (boost::python::arg("id")), "Bind to the nodes (called by yadeflex.facet).")
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexFacet, Shape);
};
REGISTER_SERIALIZABLE(FlexFacet);

class Bo1_FlexFacet_Aabb : public BoundFunctor {
public:
	void go(const shared_ptr<Shape>& sh, shared_ptr<Bound>& bv, const Se3r&, const Body*) override;
	FUNCTOR1D(FlexFacet);
	// clang-format off
	YADE_CLASS_BASE_DOC(Bo1_FlexFacet_Aabb, BoundFunctor, "Axis-aligned box of a :yref:`FlexFacet` from its three nodes' current positions, grown by its radius.");
	// clang-format on
};
REGISTER_SERIALIZABLE(Bo1_FlexFacet_Aabb);

class Ig2_Sphere_FlexFacet_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Sphere_FlexFacet_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Sphere_FlexFacet_FlexContactGeom, IGeomFunctor, "Sphere - :yref:`FlexFacet` contact in the face, edge and vertex regions of the thick triangle; one contact where facets meet (the facet with the larger overlap of the same contact owns it). In the face region the side the sphere came from is kept, so a sphere pushed through a thin membrane is pushed back, not pulled through.");
	// clang-format on
	FUNCTOR2D(Sphere, FlexFacet);
	DEFINE_FUNCTOR_ORDER_2D(Sphere, FlexFacet);
};
REGISTER_SERIALIZABLE(Ig2_Sphere_FlexFacet_FlexContactGeom);

class Ig2_FlexCylinder_FlexFacet_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_FlexCylinder_FlexFacet_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_FlexCylinder_FlexFacet_FlexContactGeom, IGeomFunctor, ":yref:`FlexCylinder` - :yref:`FlexFacet` contact (a wire against a membrane), with ownership on both sides. Elements sharing a node never interact.");
	// clang-format on
	FUNCTOR2D(FlexCylinder, FlexFacet);
	DEFINE_FUNCTOR_ORDER_2D(FlexCylinder, FlexFacet);
};
REGISTER_SERIALIZABLE(Ig2_FlexCylinder_FlexFacet_FlexContactGeom);

class Ig2_FlexFacet_FlexFacet_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_FlexFacet_FlexFacet_FlexContactGeom::goReverse called.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_FlexFacet_FlexFacet_FlexContactGeom, IGeomFunctor, "Pairs of :yref:`FlexFacet`: switched off and erased by FlexElementEngine after the loop, so the permanent overlap of neighbouring facets costs nothing per step. Facet-facet contact (a membrane folding onto itself) is not modelled yet.");
	// clang-format on
	FUNCTOR2D(FlexFacet, FlexFacet);
	DEFINE_FUNCTOR_ORDER_2D(FlexFacet, FlexFacet);
};
REGISTER_SERIALIZABLE(Ig2_FlexFacet_FlexFacet_FlexContactGeom);

} // namespace yade
