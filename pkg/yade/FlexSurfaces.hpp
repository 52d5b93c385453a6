// yade-flex adapter: deformable elements against YADE's rigid surfaces, Wall, Box and Facet
// (GPL-2.0-or-later). The geometry and the ownership rule: pkg/kernel/Surface.hpp.
//
// Contents:
//  - Ig2_Wall_FlexNode_FlexContactGeom, Ig2_Box_FlexNode_FlexContactGeom,
//    Ig2_Facet_FlexNode_FlexContactGeom: the contact of a node sphere (the largest radius of the
//    elements on the node, flexa::nodeContactRadius) with the surface;
//  - Ig2_Box_FlexCylinder_FlexContactGeom, Ig2_Facet_FlexCylinder_FlexContactGeom: a cylinder
//    against a box's or a facet's edge or vertex between its nodes;
//  - Ig2_Box_FlexFacet_FlexContactGeom, Ig2_Facet_FlexFacet_FlexContactGeom: a membrane facet
//    against a box's or a facet's edge or vertex between its nodes;
//  - flexa::addSurfaceNodePairs: nodes have no bound, so the collider never pairs them; it pairs
//    their elements with the surfaces. FlexInteractionLoop calls this at the start of each step on
//    which the collider ran or the container changed: for each pair (element, surface) it makes
//    the potential pairs (surface, node) of the element's nodes, and erases the potential
//    (surface, node) pairs no element pair calls for any more. A node and a surface that can
//    neither move (all translations blocked, or not dynamic) get no pair (a net's anchors on the
//    slab carry no contact force);
//  - flexa::checkSurfaceSupport: the scene check's refusal of elements in a scene whose rigid
//    bodies they cannot touch (another shape, or an interaction loop without these functors).
#pragma once
#include "Flex.hpp"
#include "FlexFacet.hpp"

#include <pkg/common/Box.hpp>
#include <pkg/common/Facet.hpp>
#include <pkg/common/Wall.hpp>

namespace yade {

class Ig2_Wall_FlexNode_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Wall_FlexNode_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Wall_FlexNode_FlexContactGeom, IGeomFunctor, "YADE :yref:`Wall` - :yref:`FlexNode` contact: the node as a sphere of the largest radius of the elements on it (the deepest points of capsules and thick triangles against a plane are their nodes, so this is every contact of the elements with the wall, each counted once; pkg/kernel/Surface.hpp). Stiffness as a sphere of that radius on the wall (:yref:`Ip2_FrictMat_FrictMat_FrictPhys` with both radii the node's), the node's material; Wall.sense respected, a two-sided wall pushes towards the side the contact started from.");
	// clang-format on
	FUNCTOR2D(Wall, FlexNode);
	DEFINE_FUNCTOR_ORDER_2D(Wall, FlexNode);
};
REGISTER_SERIALIZABLE(Ig2_Wall_FlexNode_FlexContactGeom);

class Ig2_Box_FlexNode_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Box_FlexNode_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Box_FlexNode_FlexContactGeom, IGeomFunctor, "YADE :yref:`Box` - :yref:`FlexNode` contact: the node as a sphere of the largest radius of the elements on it, against the box's faces, edges and corners (a node inside is pushed out through the nearest face). Elements meet the box at their nodes: an element spanning a box edge between its nodes is not held by that edge.");
	// clang-format on
	FUNCTOR2D(Box, FlexNode);
	DEFINE_FUNCTOR_ORDER_2D(Box, FlexNode);
};
REGISTER_SERIALIZABLE(Ig2_Box_FlexNode_FlexContactGeom);

class Ig2_Box_FlexCylinder_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Box_FlexCylinder_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Box_FlexCylinder_FlexContactGeom, IGeomFunctor, "YADE :yref:`Box` - :yref:`FlexCylinder` contact at a box edge between the cylinder's nodes (a wire draped over a block, a block smaller than a net's cell): where the box's closest point to the cylinder's axis lies on an edge, at an interior point of the axis nearer than both nodes (pkg/kernel/Surface.hpp, segmentOnBoxEdges); the force goes to the two nodes by the shape functions. Everywhere else the cylinder meets the box at its nodes (:yref:`Ig2_Box_FlexNode_FlexContactGeom`), and the contact passes from one to the other at the same overlap.");
	// clang-format on
	FUNCTOR2D(Box, FlexCylinder);
	DEFINE_FUNCTOR_ORDER_2D(Box, FlexCylinder);
};
REGISTER_SERIALIZABLE(Ig2_Box_FlexCylinder_FlexContactGeom);

class Ig2_Facet_FlexNode_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Facet_FlexNode_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Facet_FlexNode_FlexContactGeom, IGeomFunctor, "YADE :yref:`Facet` - :yref:`FlexNode` contact: the node as a sphere of the largest radius of the elements on it, against the facet's face (pushed back towards the side the contact started from), edges and vertices. On a surface of several facets, a node over an edge or vertex the facets share carries one contact, the deepest (pkg/kernel/Surface.hpp); a node in a valley touches both faces. Between its nodes a cylinder meets a facet at an edge or vertex (:yref:`Ig2_Facet_FlexCylinder_FlexContactGeom`).");
	// clang-format on
	FUNCTOR2D(Facet, FlexNode);
	DEFINE_FUNCTOR_ORDER_2D(Facet, FlexNode);
};
REGISTER_SERIALIZABLE(Ig2_Facet_FlexNode_FlexContactGeom);

class Ig2_Facet_FlexCylinder_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Facet_FlexCylinder_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Facet_FlexCylinder_FlexContactGeom, IGeomFunctor, "YADE :yref:`Facet` - :yref:`FlexCylinder` contact at a facet edge or vertex between the cylinder's nodes (a wire over a ridge or the rim of a surface of facets): where the facet's closest point to the cylinder's axis lies on an edge or vertex, at an interior point of the axis nearer than both nodes (pkg/kernel/Surface.hpp, segmentOnTriangleEdges); the force goes to the two nodes by the shape functions. Over an edge or vertex that several facets share, one of them carries the contact (the deepest; ties: the lower id). Everywhere else the cylinder meets the facet at its nodes (:yref:`Ig2_Facet_FlexNode_FlexContactGeom`), and the contact passes from one to the other at the same overlap.");
	// clang-format on
	FUNCTOR2D(Facet, FlexCylinder);
	DEFINE_FUNCTOR_ORDER_2D(Facet, FlexCylinder);
};
REGISTER_SERIALIZABLE(Ig2_Facet_FlexCylinder_FlexContactGeom);

class Ig2_Box_FlexFacet_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Box_FlexFacet_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Box_FlexFacet_FlexContactGeom, IGeomFunctor, "YADE :yref:`Box` - :yref:`FlexFacet` contact at a box edge or corner pressed into a membrane between its nodes (a block on a sheet, a sheet draped over a block): where the box's closest point to the membrane's midplane lies on an edge or corner, nearer than the facet's three nodes (pkg/kernel/Surface.hpp, boxEdgesOnTriangle); the force goes to the three nodes by the barycentric weights. Over a face the box meets the membrane at its nodes (:yref:`Ig2_Box_FlexNode_FlexContactGeom`), and the contact passes from one to the other at the same overlap. At an edge two facets of a sheet share, one of them carries the contact. An edge pushed through the midplane carries no normal force until it comes out (:yref:`FlexContactGeom.pierced`); one pushed wholly through is pushed back towards the side it came from.");
	// clang-format on
	FUNCTOR2D(Box, FlexFacet);
	DEFINE_FUNCTOR_ORDER_2D(Box, FlexFacet);
};
REGISTER_SERIALIZABLE(Ig2_Box_FlexFacet_FlexContactGeom);

class Ig2_Facet_FlexFacet_FlexContactGeom : public IGeomFunctor {
public:
	bool go(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override;
	bool goReverse(const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&,
	        const shared_ptr<Interaction>&) override
	{
		throw std::logic_error("Ig2_Facet_FlexFacet_FlexContactGeom::goReverse called: the dispatcher should swap the bodies.");
	}
	// clang-format off
	YADE_CLASS_BASE_DOC(Ig2_Facet_FlexFacet_FlexContactGeom, IGeomFunctor, "YADE :yref:`Facet` - :yref:`FlexFacet` contact at a facet's edge or vertex pressed into a membrane between its nodes (a sheet over a ridge or the rim of a surface of facets): where the facet's closest point to the membrane's midplane lies on an edge or vertex, nearer than the membrane facet's three nodes (pkg/kernel/Surface.hpp, triangleEdgesOnTriangle); the force goes to the three nodes by the barycentric weights. Over an edge or vertex that several facets share, one of them carries the contact (the deepest; ties: the lower id), and at an edge two membrane facets share, one of those. Over a face the facet meets the membrane at its nodes (:yref:`Ig2_Facet_FlexNode_FlexContactGeom`). An edge pushed through the midplane carries no normal force until it comes out (:yref:`FlexContactGeom.pierced`).");
	// clang-format on
	FUNCTOR2D(Facet, FlexFacet);
	DEFINE_FUNCTOR_ORDER_2D(Facet, FlexFacet);
};
REGISTER_SERIALIZABLE(Ig2_Facet_FlexFacet_FlexContactGeom);

namespace flexa {
	/// Contact radius of a node: the largest radius of the elements on it that still exist (0:
	/// none, no contact).
	Real nodeContactRadius(const Scene* scene, const FlexNode& node);
	/// See the top of this file; returns the number of pairs made.
	long addSurfaceNodePairs(Scene* scene);
	/// Throws std::invalid_argument if the scene has elements and a rigid body they cannot touch:
	/// a shape other than Sphere, Wall, Box and Facet, or one of those three without its
	/// functors (above) in the interaction loop.
	void checkSurfaceSupport(const Scene* scene);
} // namespace flexa
} // namespace yade
