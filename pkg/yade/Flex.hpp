// yade-flex adapter: YADE classes for deformable elements (GPL-2.0-or-later).
//
// Table of contents
//  - FlexNode            Shape: a node carrying mass, inertia and all DOFs; no bound (the
//                        elements attached to it give the contact surface)
//  - FlexCylinder        Shape: capsule between two FlexNodes (no DOF); it IS the bond
//                        (co-rotational beam, pkg/kernel/Beam.hpp) and the contact surface
//  - FlexMat             Material (FrictMat + beam/bond parameters)
//  - FlexContactGeom     IGeom of a contact touching deformable elements: point, normal,
//                        overlap and, per side, the element nodes and axis parameter
//  - Bo1_FlexCylinder_Aabb                       bound from both nodes
//  - Ig2_Sphere_FlexCylinder_FlexContactGeom     sphere-cylinder
//  - Ig2_FlexCylinder_FlexCylinder_FlexContactGeom  cylinder-cylinder (bonded neighbours never)
//  - Law2_FlexContactGeom_FrictPhys_CundallStrack   frictional contact; forces to nodes
//  - FlexElementEngine   internal forces of all bonds; rupture (element removed, counted)
//  - FlexTimeStepper     critical time step from bonds and contacts
//  - FlexNewtonIntegrator NewtonIntegrator that skips element bodies (no DOF) and tells the
//                        collider when an element moved, from both of its nodes
//
// Ownership (one contact where elements meet): a contact with element E is dropped if an
// element sharing a node with E has the SAME contact with a larger overlap (ties: lower body
// id wins). Same contact: one of the two closest points lies on what the two share (a chain's
// shared node, a facet's shared edge or vertex), where both touch at the same point. Distinct
// contacts on neighbours (a sphere on a net cell touching its four wires, a boulder on the legs
// of a mesh) all count.
// Where two segments clamp to the same node the distances are bit-identical and the tie rule
// picks one. A contact between two elements (a ring on the lining) is decided once per cluster
// of element PAIRS (flexa::ownsPair: every pair's overlap computed the same way by all of them),
// not side by side. When ownership moves from A to its neighbour B, B takes over A's shear
// force; A stays one more step, inactive, so B reads stable data (deterministic, no data race).
#pragma once
#include "FlexPch.hpp"
#include "FlexForces.hpp"
#include "FlexTuning.hpp"

namespace yade {

class FlexNode : public Shape {
public:
	virtual ~FlexNode() = default;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(FlexNode, Shape,
		"Node of deformable elements (yade-flex). Carries mass, rotational inertia and all degrees of freedom; its mass and inertia are the sum of the lumped shares of the elements attached to it (see :yref:`FlexCylinder`). Has no bound: contacts are detected on the elements.",
		((Real, radius, NaN, , "Radius for display and output [m]; the contact radius is the element's."))
		((vector<int>, elements, , , "Ids of the elements attached to this node (filled by FlexCylinder.attach).")),
		createIndex();
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexNode, Shape);
};
REGISTER_SERIALIZABLE(FlexNode);

class FlexMat : public FrictMat {
public:
	virtual ~FlexMat() = default;
	/// Whether the axial law is the chain-link wire law (pkg/kernel/WireLaw.hpp).
	bool isWire() const { return !wireStrain.empty() || !wireStress.empty(); }
	/// Empty if the wire parameters are valid (or unused), else what is wrong with them.
	std::string wireError() const;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexMat, FrictMat,
		"Material of deformable elements (yade-flex). ``young`` is Young's modulus of the element and also enters the contact stiffness; ``poisson`` keeps FrictMat's meaning (ks/kn of contacts); the beam's shear modulus uses :yref:`FlexMat.beamPoisson`.",
		((Real, elementYoung, NaN, , "Young's modulus of the element (beam, bar) if it differs from the contact modulus ``young`` [Pa]; NaN: ``young``. A contact modulus below the material's (common DEM practice for steel wires) lengthens the time step without changing the structure's stiffness."))
		((Real, beamPoisson, 0.3, , "Poisson ratio of the element material for G = E/(2(1+nu)) [-]"))
		((Real, bendingFactor, 1.0, , "Scale of bending and torsion stiffness relative to a solid bar [-] (ropes: well below 1; 0: an axial-only bar, no moments, the element loop skips the rotations)"))
		((bool, tensionOnly, false, , "Bonds carry no compression (ropes, wires) [-]"))
		((Real, yieldStress, std::numeric_limits<Real>::infinity(), , "Axial yield stress [Pa]; plastic elongation beyond it"))
		((Real, hardening, 0.0, , "Post-yield axial stiffness as a fraction of EA [-]"))
		((Real, tensileStrength, std::numeric_limits<Real>::infinity(), , "Bond breaks when the axial stress reaches it [Pa]"))
		((Real, ruptureStrain, std::numeric_limits<Real>::infinity(), , "Bond breaks at this total axial strain [-]"))
		((vector<Real>, wireStrain, , , "Chain-link wire law (pkg/kernel/WireLaw.hpp): strains of the stress-strain points, strictly increasing, > 0; the origin is implied [-]. Non-empty: the axial law is the wire law (tension only, elastic unloading with wireStress[0]/wireStrain[0], rupture past the last point); yieldStress, hardening, tensileStrength and ruptureStrain must stay unset. Never modified by the simulation."))
		((vector<Real>, wireStress, , , "Stresses of the stress-strain points of the wire law, > 0 [Pa]"))
		((Real, wireSlackScale, 0.0, , "Scale of the stochastic slack strain of each link: slack = wireSlackScale * xi, xi symmetric triangular on [0, 1] (lambda_u of [Thoeni2013]_) [-]; 0: no distortion"))
		((Real, wireForceRatio, 1.0, , "Force ratio of the soft initial branch of a distorted link, in (0, 1] (lambda_F of [Thoeni2013]_) [-]"))
		((int, wireSeed, 12345, , "Seed of the slack draw; each link's draw is a hash of the seed and its two node ids, so it does not depend on thread count, body order at run time or O.reset() [-]")),
		createIndex();,
		.def("wireError", &FlexMat::wireError, "Empty string if the wire-law parameters are valid (or unused), else what is wrong with them.")
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexMat, FrictMat);
};
REGISTER_SERIALIZABLE(FlexMat);

class FlexCylinder : public Shape {
public:
	virtual ~FlexCylinder() = default;
	/// Validate, bind to the nodes, compute the rest state and add the lumped mass/inertia
	/// shares to the nodes. Raises ValueError naming the problem.
	void attach(int selfId);
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

class FlexContactGeom : public GenericSpheresContact {
public:
	virtual ~FlexContactGeom() = default;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(FlexContactGeom, GenericSpheresContact,
		"Contact touching deformable elements (yade-flex). Per side: the nodes and the axis parameter u of the contact on a cylinder, or the three nodes and barycentric weights on a facet (all -1: the body itself is rigid); axis1/axis2 is the closest point on the axis or midplane. Normal from body 1 to body 2.",
		((Real, penetrationDepth, NaN, , "Overlap [m]"))
		((Vector2i, nodes1, Vector2i(-1, -1), , "Nodes of side 1 (-1: rigid body)"))
		((Vector2i, nodes2, Vector2i(-1, -1), , "Nodes of side 2 (-1: rigid body)"))
		((Real, u1, 0, , "Axis parameter on side 1 [-]"))
		((Real, u2, 0, , "Axis parameter on side 2 [-]"))
		((Vector3i, tri1, Vector3i(-1, -1, -1), , "Facet nodes of side 1 (-1: not a facet)"))
		((Vector3i, tri2, Vector3i(-1, -1, -1), , "Facet nodes of side 2 (-1: not a facet)"))
		((Vector3r, bary1, Vector3r::Zero(), , "Barycentric weights of the facet point of side 1 [-]"))
		((Vector3r, bary2, Vector3r::Zero(), , "Barycentric weights of the facet point of side 2 [-]"))
		((Vector3r, axis1, Vector3r::Zero(), , "Axis point (or centre) of side 1 [m]"))
		((Vector3r, axis2, Vector3r::Zero(), , "Axis point (or centre) of side 2 [m]"))
		((Vector3r, relVel, Vector3r::Zero(), , "Velocity of side 2 relative to side 1 at the contact point [m/s]"))
		((bool, active, true, , "Owned: this interaction carries the contact force"))
		((long, lastActiveIter, -2, , "Last iteration at which it was active"))
		((bool, handover, false, , "Took over the shear force of a neighbour this step"))
		((Vector3r, handoverShear, Vector3r::Zero(), , "Shear force taken over [N]"))
		((Real, handoverNormal, 0, (Attr::noSave | Attr::readonly), "Normal force of the neighbour this contact took over from at this step (0: none; -1: none, and the contact is one of the scene as built, found at its first step) [N]"))
		((Vector3r, rollMoment, Vector3r::Zero(), , "Rolling-resistance moment on body 2 (sphere-sphere contacts) [N m]"))
		((Real, plasticOverlap, 0, , "Part of the overlap that carries no force: the normal force is kn (penetrationDepth - plasticOverlap), at least 0 [m]. A sphere-sphere contact whose grains crushed (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.crushingIs50`): its crushed part, for good. A contact with an element that started deep (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.deepOnsets`): the part of its overlap beyond what its predecessor's force gives (all of it without one), so that it starts with the spring energy it took over and none from nothing; it shrinks with the overlap (never above it)"))
		((bool, pierced, false, (Attr::noSave | Attr::readonly), "A wire's axis passes through the facet's midplane (a cylinder-facet contact over the face): the overlap is the reach, the same wherever the wire goes while it stays pierced, so the contact carries no normal force (a force there would work without changing the spring's energy: energy from nothing); its spring keeps the energy it had when the wire got there (booked in flexContactElastic) and gives it back as the wire comes out. A wire pushed wholly through is pushed back towards the side it came from"))
		((Real, onsetDepth, 0, (Attr::noSave | Attr::readonly), "Overlap this contact (re)started with at this step if that was a deep onset (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.deepOnsets`), else 0 [m]"))
		((long, crossIter, -2, Attr::readonly, "Crossing correction (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack.crossing`): last iteration it was updated at (otherwise it starts again)"))
		((Real, crossDepth, 0, Attr::readonly, "Crossing correction: overlap at that iteration [m]"))
		((Real, crossForce, 0, Attr::readonly, "Crossing correction: normal force applied at that iteration, the spring's and the correction's, repulsive positive [N]"))
		((Real, crossRate, NaN, Attr::readonly, "Crossing correction: rate of the overlap at that iteration (NaN: unknown) [m/s]"))
		((Real, crossDefect, 0, Attr::readonly, "Crossing correction: energy the leap-frog scheme has put into the bodies beyond the spring's potential, still to be cancelled [J]"))
		((int, crossOut, 0, Attr::readonly, "Crossing correction: steps since the last step with positive overlap")),
		createIndex();
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexContactGeom, GenericSpheresContact);
};
REGISTER_SERIALIZABLE(FlexContactGeom);

class Bo1_FlexCylinder_Aabb : public BoundFunctor {
public:
	void go(const shared_ptr<Shape>& sh, shared_ptr<Bound>& bv, const Se3r&, const Body*) override;
	FUNCTOR1D(FlexCylinder);
	// clang-format off
	YADE_CLASS_BASE_DOC(Bo1_FlexCylinder_Aabb, BoundFunctor, "Axis-aligned box of a :yref:`FlexCylinder` from both nodes' current positions (so detection follows both ends).");
	// clang-format on
};
REGISTER_SERIALIZABLE(Bo1_FlexCylinder_Aabb);

class Ig2_Sphere_FlexCylinder_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Sphere_FlexCylinder_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Sphere_FlexCylinder_FlexContactGeom, IGeomFunctor, "Sphere - :yref:`FlexCylinder` contact with node-interpolated kinematics and ownership at shared nodes (one contact, continuous force).");
	// clang-format on
	FUNCTOR2D(Sphere, FlexCylinder);
	DEFINE_FUNCTOR_ORDER_2D(Sphere, FlexCylinder);
};
REGISTER_SERIALIZABLE(Ig2_Sphere_FlexCylinder_FlexContactGeom);

class Ig2_FlexCylinder_FlexCylinder_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>& s1, const shared_ptr<Shape>& s2, const State& st1, const State& st2, const Vector3r& sh, const bool& f,
	        const shared_ptr<Interaction>& I) override
	{
		throw std::logic_error("Ig2_FlexCylinder_FlexCylinder_FlexContactGeom::goReverse called.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_FlexCylinder_FlexCylinder_FlexContactGeom, IGeomFunctor, "Contact between :yref:`FlexCylinder` elements of different chains (parallel, crossing and intersecting axes handled). Elements sharing a node never interact: their collider pair is switched off and then erased by FlexElementEngine, so it costs nothing per step.");
	// clang-format on
	FUNCTOR2D(FlexCylinder, FlexCylinder);
	DEFINE_FUNCTOR_ORDER_2D(FlexCylinder, FlexCylinder);
};
REGISTER_SERIALIZABLE(Ig2_FlexCylinder_FlexCylinder_FlexContactGeom);

class Ig2_Sphere_Sphere_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>& s1, const shared_ptr<Shape>& s2, const State& st1, const State& st2, const Vector3r& sh, const bool& f,
	        const shared_ptr<Interaction>& I) override
	{
		return go(s1, s2, st1, st2, sh, f, I);
	}
	/// What go() does to a contact's geometry from the two spheres' radii, centres (x2 with the
	/// periodic shift added) and velocities, once it has decided the contact goes on (isNew: g was
	/// just made). FlexInteractionLoop calls it directly for existing contacts, from its table of
	/// the spheres' centres and motion, without reading their bodies, states and shapes.
	static void update(Scene* scene, FlexContactGeom& g, bool isNew, Real R1, Real R2, const Vector3r& x1, const Vector3r& x2, const Vector3r& vel1,
	        const Vector3r& angVel1, const Vector3r& vel2, const Vector3r& angVel2);
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Sphere_Sphere_FlexContactGeom, IGeomFunctor, "Sphere - sphere contact as a :yref:`FlexContactGeom` (both sides rigid), so that granular fill uses the same frictional law and energy booking as the element contacts (:yref:`Law2_FlexContactGeom_FrictPhys_CundallStrack`: friction dissipation consistent with the leap-frog, shear energy released at separation booked). Periodic cells are not supported.");
	// clang-format on
	FUNCTOR2D(Sphere, Sphere);
	DEFINE_FUNCTOR_ORDER_2D(Sphere, Sphere);
};
REGISTER_SERIALIZABLE(Ig2_Sphere_Sphere_FlexContactGeom);

class Law2_FlexContactGeom_FrictPhys_CundallStrack : public LawFunctor {
public:
	bool go(shared_ptr<IGeom>&, shared_ptr<IPhys>&, Interaction*) override;
	/// go() on the contact's geometry and physics; angVel1/angVel2: the angular velocities of
	/// the two bodies if the caller has them (FlexInteractionLoop's table of sphere motion), else
	/// null (read from the bodies' states; only rolling resistance reads them)
	bool apply(FlexContactGeom& g, FrictPhys& p, Interaction* I, const Vector3r* angVel1, const Vector3r* angVel2);
	/// Rolling stiffness kr of this contact (0: none; only sphere-sphere contacts roll) [N m].
	Real rollingK(const FlexContactGeom& g, const FrictPhys& p) const;
	/// maxOverlapRatio and maxOverlapIds (several threads: a lock only when the maximum grows)
	void noteOverlap(Real ratio, const Interaction* I);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(Law2_FlexContactGeom_FrictPhys_CundallStrack, LawFunctor,
		"Linear frictional contact [CundallStrack1979]_ on :yref:`FlexContactGeom`; forces and moments go to the element nodes by the shape functions (exact force and moment balance). Optional rolling resistance between spheres (angular grains): an elastic-plastic moment of stiffness kr = rollingStiffness ks R^2 capped at rollingFriction R |Fn|, R = R1 R2/(R1 + R2). Optional grain crushing between spheres: the normal force never exceeds the point-load failure load of the smaller sphere (crushingIs50); past it the contact yields. Books 'flexContactElastic', 'flexFriction', 'flexRolling' and 'flexCrushing' in O.energy.",
		((Real, rollingStiffness, 0, , "Rolling stiffness of sphere-sphere contacts as kr / (ks R^2) [-]; 0: no rolling resistance"))
		((Real, rollingFriction, 0, , "Rolling friction coefficient eta: the rolling moment is capped at eta R |Fn| [-]"))
		((Real, crushingIs50, 0, , "Point-load strength index Is(50) of the spheres' rock [Pa]; 0: spheres do not crush. Else the normal force of a sphere-sphere contact is capped at the failure load Is50 d^2 (0.05 m / d)^0.45 of the smaller sphere (diameter d; ISRM 1985); a step past it adds to the contact's plasticOverlap instead, and the work is booked as 'flexCrushing'"))
		((long, deepOnsets, 0, , "Contacts that started with an overlap larger than onsetFactor x (their approach speed x dt): taken over from a neighbour element (a hand-over, see deepEndings), detected late (missed by the collider, or held back by a cluster's ownership rule) or in a scene built overlapping [-]"))
		((Real, deepOnsetEnergy, 0, , "Sum of 1/2 kn (d - plasticOverlap)^2 over the deep onsets: normal spring energy that came with them (contacts with an element: what they took over from their predecessor, see FlexContactGeom.plasticOverlap) [J]"))
		((long, deepEndings, 0, , "Contacts that ended while still overlapping: handed over to a neighbour element, which then starts deep (see deepOnsets) [-]"))
		((Real, deepEndingEnergy, 0, , "Sum of 1/2 kn (d - plasticOverlap)^2 over the deep endings: normal spring energy that went with them [J]. deepOnsetEnergy - deepEndingEnergy is the energy the hand-overs created: a hand-over passes the spring on (a contact with an element that starts deep takes over its predecessor's force and no more, see FlexContactGeom.plasticOverlap), so its onset and ending cancel; negative where two contacts merge into one and the spring of the one that ends goes with it; positive from the contacts of a scene built overlapping"))
		((bool, crossing, true, , "Energy-consistent onset and release (pkg/kernel/Crossing.hpp): over the step in which a contact starts or ends, the leap-frog scheme gains or loses up to 1/2 kn d0 d1 (the overlaps at the step's ends, of opposite signs), up to a quarter of (omega dt)^2 of the energy of a bounce; each contact keeps that defect and cancels it with an extra normal force on the next steps (kept two steps past its separation to do so). False: the plain penalty contact"))
		((Real, onsetFactor, 2, , "An onset counts as deep when its overlap exceeds onsetFactor x the approach speed x dt (the overlap one step of approach gives; 2 leaves room for the change of speed within the step) [-]"))
		((Real, maxOverlapRatio, 0, , "Largest overlap / (refR1 + refR2) (the contact's reach) of an active contact at any step since it was last set to 0 (set it to 0 to start again) [-]"))
		((Vector2i, maxOverlapIds, Vector2i(-1, -1), , "The two bodies of the contact of maxOverlapRatio [-]"))
		((int, rollIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, elastIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, frictIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
		((int, crushIx, -1, (Attr::hidden | Attr::noSave), "energy index"))
	);
	// clang-format on
	FUNCTOR2D(FlexContactGeom, FrictPhys);
};
REGISTER_SERIALIZABLE(Law2_FlexContactGeom_FrictPhys_CundallStrack);

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
	void              facetForces(std::vector<Body::id_t>& broken, long& lo, long& hi); // membranes (FlexFacet); [lo, hi]: the node ids added to the sinks
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

namespace flexa {
	/// FlexTimeStepper.safety's default, and yadeflex.engines()' (which reads it from the class).
	constexpr Real kDefaultTimeStepSafety = 0.5;
} // namespace flexa

class FlexTimeStepper : public GlobalEngine {
	size_t lastInteractionCount = 0;
	long   lastColliderRuns     = -1;
	// where the last bounds came from (const estimates record them)
	mutable Body::id_t stiffestBondBody = -1, stiffestContactBody = -1, stiffestCache = -1;
	mutable long       skippedCache = 0;

public:
	/// Largest omega^2 of bonds and of contacts (see pkg/kernel/TimeStep.hpp) [1/s^2].
	Real omega2Bonds() const;
	Real omega2Contacts() const;
	// skippedOut: collects the pairs left out; mark: also mark them for the geometry functors
	// (flexa::UnreachableMarks; only from action(), the engine's own serial run)
	Real omega2ContactsImpl(std::vector<std::pair<Body::id_t, Body::id_t>>* skippedOut, bool mark) const;
	Real criticalImpl(bool mark) const;
	/// the potential pairs the estimate leaves out now (see skipUnreachable), for tests
	boost::python::list unreachablePairs() const;
	Real                critical() const;
	void                action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexTimeStepper, GlobalEngine,
		"Sets O.dt to safety x the critical step of the central-difference integrator, bounded from the bonds (element eigenvalue inequality) and from all contacts with NormShearPhys (Gershgorin row sums with the node weights), translational and rotational, including potential contacts found by the collider (with the stiffness FrictMat contacts will have) that could start before the collider runs again (see skipUnreachable), so that a contact never starts with a step too long for it, and divided by sqrt(1 + NewtonIntegrator.damping) (Cundall's damping scales accelerations by up to 1 + damping). Runs every :yref:`FlexTimeStepper.interval` steps and whenever the collider ran (it alone adds interactions; without an InsertionSortCollider: whenever the number of interactions changes).",
		((Real, safety, flexa::kDefaultTimeStepSafety, , "Fraction of the critical step, in (0, 1]; yadeflex.engines() uses the same default [-]"))
		((int, interval, 50, , "Recompute every this many steps [-]"))
		((Real, dtCritical, NaN, Attr::readonly, "Last critical step [s]"))
		((Body::id_t, stiffestBody, -1, Attr::readonly, "Body that set the last critical step: the element with the largest bond omega^2, or the body (node, sphere) with the largest contact row, whichever bound is larger [-]"))
		((bool, skipUnreachable, true, , "Leave out potential contacts that cannot start before the collider runs again (their gap exceeds how far both sides can still travel inside the sweep of their bounds; needs an InsertionSortCollider before this engine; not in periodic scenes). The yade-flex geometry functors then also skip those pairs until the collider runs again, instead of computing their distance at every step. False: count every potential contact (for comparisons)."))
		((bool, markUnreachable, true, , "With skipUnreachable: also let the yade-flex geometry functors skip the pairs left out, until the collider runs again (they cannot touch before then, so results are the same bit for bit; see bench/README.md). A body moved by assigning its position (not by the integrator) is seen by the collider one step late; a skipped pair may then miss that one step of contact, as YADE's collider misses a pair it never listed."))
		((bool, prefetch, true, , "Ask for the interactions' data a few iterations ahead in the loop over interactions (same results; False: for comparisons)"))
		((long, skippedPairs, 0, Attr::readonly, "Potential contacts left out of the last estimate by :yref:`FlexTimeStepper.skipUnreachable` [-]"))
		((Real, minDtFraction, 0, , "Stop the run (yadeflex.Unstable, naming the stiffest body) when the critical step falls below this fraction of dtReference: a collapsed step (a crushed facet, a light node under a stiff contact) would run on for ever at a vanishing step; 0: never [-]"))
		((Real, dtReference, 0, , "The critical step minDtFraction compares with; 0: the next estimate sets it (set it to 0 to start again, e.g. at an impact) [s]")),
		,
		.def("critical", &FlexTimeStepper::critical, "Critical step of the current scene [s] (no change to O.dt)")
		.def("omega2Bonds", &FlexTimeStepper::omega2Bonds, "Bound of the largest omega^2 from bonds [1/s^2]")
		.def("omega2Contacts", &FlexTimeStepper::omega2Contacts, "Bound of the largest omega^2 from contacts [1/s^2]")
		.def("unreachablePairs", &FlexTimeStepper::unreachablePairs, "Potential contacts (id1, id2) that the estimate leaves out in the current state: they cannot start before the collider runs again (see skipUnreachable)")
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexTimeStepper);

class FlexNewtonIntegrator : public NewtonIntegrator {
	std::vector<Body::id_t> movers, elements, facets; // bodies with DOFs / cylinder and facet bodies (cached)
	size_t                  cachedBodyCount = 0;
	bool                    simple          = false; // no clump, no aspherical body: the fast path applies
	void                    refresh();
	void                    flagElements(); // collider trigger from element nodes (both paths)
	// the same trigger per node on the fast path (see buildNodeTable in FlexNewtonIntegrator.cpp)
	std::vector<char>     isMover;
	std::vector<Real>     nodeSweep;       // smallest sweep of the bounds of the node's elements, -1: none
	std::vector<Vector3r> nodeRef;         // node position when those bounds were built
	Real                  nodeBase    = 0; // 0.5 if some element has a bound (flagElements' "inside")
	bool                  nodeTableOk = false;
	long                  tableRuns = -2, tableErasures = -1;
	bool                  buildNodeTable();
	Real                  dampingOnBlockedDofs(); // what NewtonIntegrator books on blocked DOFs this step [J]
	Real                  driveWork();            // booked for the driven DOFs this step (flex::driveWork) [J]
	int                   driveWorkIx = -1;

public:
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(FlexNewtonIntegrator, NewtonIntegrator,
		"NewtonIntegrator for scenes with yade-flex elements. Element bodies (:yref:`FlexCylinder`) carry no DOF: they are skipped (FlexElementEngine keeps their position), and the collider is told to run when either NODE of an element left its bound's sweep (NewtonIntegrator only sees the element's midpoint, which moves half as far as the free end of a swinging element). Same leap-frog, damping and energy terms as NewtonIntegrator (except that local damping is booked in nonviscDamp on free DOFs only: NewtonIntegrator also books |v||F| c dt on blocked, driven DOFs, where no damping acts; on its fallback to NewtonIntegrator's loop this class takes that share back), clumps included (members' forces summed about the clump's centre, members moved with it). The work done by prescribed motion (a blocked DOF moving at the velocity the user or an engine gave it: an indenter, a plate, a pulled edge) is booked as 'driveWork' in O.energy, in gravWork's sign (minus the work put in), so that the energy balance of a driven test closes as that of a free impact (kernel/LeapFrog.hpp); scenes with periodic cells, aspherical bodies (a clump whose inertia is not isotropic is flagged aspherical by YADE), masks or density scaling use NewtonIntegrator's own loop.",
		((bool, usedFastPath, false, Attr::readonly, "Whether the last step used the fast path"))
		((bool, prefetch, true, , "On the fast path, ask for the bodies' data a few bodies ahead, when at least 512 bodies move (fewer stay in cache between steps); same results; False: for comparisons"))
		((int, parallelMin, flexa::tuning::kIntegratorParallelMin, , "Integrate on several threads only from this many bodies on (see FlexElementEngine.parallelMin) [-]"))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexNewtonIntegrator);

} // namespace yade
