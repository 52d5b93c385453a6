// yade-flex adapter (GPL-2.0-or-later): the node shape: a FlexNode carries mass, inertia and all DOFs; no bound (the
// elements attached to it give the contact surface).
#pragma once
#include "FlexPch.hpp"

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

} // namespace yade
