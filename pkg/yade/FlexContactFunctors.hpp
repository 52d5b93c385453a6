// yade-flex adapter (GPL-2.0-or-later): the contact geometry functors of spheres and cylinders: sphere-cylinder,
// cylinder-cylinder (bonded neighbours never), sphere-sphere.
#pragma once
#include "FlexContactGeom.hpp"
#include "FlexCylinder.hpp"

namespace yade {

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

} // namespace yade
