// yade-flex adapter: drawing in YADE's 3D view (GPL-2.0-or-later).
//
//  - Gl1_FlexNode      FlexNode: a sphere of the node's radius, off by default (nodes sit
//                      inside their elements)
//  - Gl1_FlexCylinder  FlexCylinder: the capsule (tube + spherical caps) of its radius between
//                      its two nodes; wire mode: the axis; optional colour by axial force
//  - Gl1_FlexFacet     FlexFacet: the mid-surface triangle over its three nodes; wire mode:
//                      its outline; optional colour by the larger principal membrane force n1
//
// YADE's renderer (OpenGLRenderer::renderShape) translates to the body's displayed position
// and rotates by its orientation before calling a shape functor. Element bodies carry no DOF
// (their state->pos is the mean of their nodes, their ori the identity), so the element
// functors undo that transform and draw from the nodes' current positions. Consequence:
// OpenGLRenderer.dispScale and rotScale do not magnify element deformation.
#pragma once
#include "FlexFacet.hpp" // Flex.hpp too: RENDERS needs the complete shape types
#include <pkg/common/GLDrawFunctors.hpp>

namespace yade {

class Gl1_FlexNode : public GlShapeFunctor {
public:
	void go(const shared_ptr<Shape>&, const shared_ptr<State>&, bool wire, const GLViewInfo&) override;
	// clang-format off
	YADE_CLASS_BASE_DOC_STATICATTRS(Gl1_FlexNode, GlShapeFunctor,
		"Renders :yref:`FlexNode` as a sphere of its radius, only if :yref:`Gl1_FlexNode.show` (nodes lie inside the capsules and facets drawn by :yref:`Gl1_FlexCylinder` and :yref:`Gl1_FlexFacet`).",
		((bool, show, false, , "Draw the nodes [-]"))
		((int, slices, 8, , "Slices (and half as many stacks) of the sphere [-]"))
	);
	// clang-format on
	RENDERS(FlexNode);
};
REGISTER_SERIALIZABLE(Gl1_FlexNode);

class Gl1_FlexCylinder : public GlShapeFunctor {
public:
	void go(const shared_ptr<Shape>&, const shared_ptr<State>&, bool wire, const GLViewInfo&) override;
	// clang-format off
	YADE_CLASS_BASE_DOC_STATICATTRS(Gl1_FlexCylinder, GlShapeFunctor,
		"Renders :yref:`FlexCylinder` as the capsule used for contacts: a tube of its radius between its nodes' current positions, with spherical caps. In wire mode (``wire`` of the renderer or of the shape) only the axis is drawn, as a line. Colour: ``shape.color``, or the axial force if :yref:`Gl1_FlexCylinder.colorByForce` (blue: compression, grey: zero, red: tension).",
		((bool, colorByForce, false, , "Colour by :yref:`FlexCylinder.axialForce` instead of ``shape.color`` [-]"))
		((Vector2r, forceRange, Vector2r::Zero(), , "Axial force drawn fully blue (first) and fully red (second), grey midway [N]. Empty range (first >= second): symmetric about zero, +- the largest absolute axial force in the scene, found at the start of each frame."))
		((Vector2r, lastRange, Vector2r::Zero(), (Attr::noSave | Attr::readonly), "Range used for the last frame drawn with colorByForce [N]"))
		((bool, caps, true, , "Draw the spherical caps (they close the joints between segments of a chain) [-]"))
		((int, slices, 8, , "Slices around the tube (and caps) [-]"))
	);
	// clang-format on
	RENDERS(FlexCylinder);
};
REGISTER_SERIALIZABLE(Gl1_FlexCylinder);

class Gl1_FlexFacet : public GlShapeFunctor {
public:
	void go(const shared_ptr<Shape>&, const shared_ptr<State>&, bool wire, const GLViewInfo&) override;
	// clang-format off
	YADE_CLASS_BASE_DOC_STATICATTRS(Gl1_FlexFacet, GlShapeFunctor,
		"Renders :yref:`FlexFacet` as its mid-surface: the triangle over its three nodes' current positions, lit on both sides (the thickness 2 radius is not drawn). In wire mode only its outline. Colour: ``shape.color``, or the larger principal membrane force if :yref:`Gl1_FlexFacet.colorByForce` (same scale as :yref:`Gl1_FlexCylinder`).",
		((bool, colorByForce, false, , "Colour by :yref:`FlexFacet.n1` instead of ``shape.color`` [-]"))
		((Vector2r, forceRange, Vector2r::Zero(), , "n1 drawn fully blue (first) and fully red (second), grey midway [N/m]. Empty range (first >= second): +- the largest absolute n1 in the scene, found at the start of each frame."))
		((Vector2r, lastRange, Vector2r::Zero(), (Attr::noSave | Attr::readonly), "Range used for the last frame drawn with colorByForce [N/m]"))
	);
	// clang-format on
	RENDERS(FlexFacet);
};
REGISTER_SERIALIZABLE(Gl1_FlexFacet);

} // namespace yade
