// yade-flex adapter: bodies and elements as the engines and functors read them
// (GPL-2.0-or-later): a body or state by id, an element's nodes and radius from its shape, and
// the scene as the kernel's mesh view (kernel/Ownership.hpp).
#pragma once
#include "Flex.hpp"
#include "FlexFacet.hpp"

#include <kernel/Ownership.hpp>

#include <type_traits>
#include <typeinfo>
#include <vector>

namespace yade {
static_assert(std::is_same<Vector3r, flex::Vec3>::value, "yade-flex expects YADE_REAL_BIT=64 (Real = double)");
static_assert(std::is_same<Quaternionr, flex::Quat>::value, "yade-flex expects YADE_REAL_BIT=64 (Real = double)");
static_assert(std::is_same<Body::id_t, int>::value, "the kernel's element ids are Body::id_t");

namespace flexa {
	/// Body `id` of the scene, or null (no such id, or erased). Reads the container's vector
	/// directly: BodyContainer::size, operator[] and Body::byId are out-of-line calls into
	/// libyade, two per lookup, made for every neighbour an ownership search probes.
	inline const Body* bodyAt(const Scene* scene, Body::id_t id)
	{
		const std::vector<shared_ptr<Body>>& v = scene->bodies->body;
		return (id < 0 || (size_t)id >= v.size()) ? nullptr : v[id].get();
	}
	inline const State* stateOf(const Scene* scene, Body::id_t id)
	{
		const Body* b = bodyAt(scene, id);
		return b ? b->state.get() : nullptr;
	}
	/// dynamic_cast with a fast path for the exact type: one type_info comparison (a pointer
	/// comparison when both sides use the same type_info object) instead of a walk of the
	/// hierarchy with string comparisons.
	template <class T, class B> inline const T* fastCast(const B* p)
	{
		if (!p) return nullptr;
		if (typeid(*p) == typeid(T)) return static_cast<const T*>(p);
		return dynamic_cast<const T*>(p);
	}
	using flex::shareNode;
	inline bool shareNode(const FlexCylinder& a, const FlexCylinder& b)
	{
		return a.node1 == b.node1 || a.node1 == b.node2 || a.node2 == b.node1 || a.node2 == b.node2;
	}

	/// A deformable element seen generically: its nodes and contact radius (the kernel's view),
	/// and its shape.
	struct Element : flex::ElementNodes {
		const FlexCylinder* cyl = nullptr;
		const FlexFacet*    fac = nullptr;
	};
	// from the static type: no dynamic_cast (the contact functors know their shapes' types)
	inline Element elementOf(const FlexCylinder* c)
	{
		Element e;
		e.cyl      = c;
		e.nodes[0] = c->node1;
		e.nodes[1] = c->node2;
		e.nNodes   = 2;
		e.radius   = c->radius;
		return e;
	}
	inline Element elementOf(const FlexFacet* f)
	{
		Element e;
		e.fac      = f;
		e.nodes[0] = f->node1;
		e.nodes[1] = f->node2;
		e.nodes[2] = f->node3;
		e.nNodes   = 3;
		e.radius   = f->radius;
		return e;
	}
	inline Element elementOf(const Shape* sh)
	{
		Element e;
		if (!sh) return e;
		const std::type_info& t = typeid(*sh);
		// the common types by the address of their type_info first: type_info's == compares the
		// names (a string comparison) whenever the addresses differ, i.e. for every type but one
		if (&t == &typeid(Sphere) || &t == &typeid(FlexNode)) return e;
		if (&t == &typeid(FlexCylinder)) return elementOf(static_cast<const FlexCylinder*>(sh));
		if (&t == &typeid(FlexFacet)) return elementOf(static_cast<const FlexFacet*>(sh));
		if (t == typeid(FlexCylinder)) return elementOf(static_cast<const FlexCylinder*>(sh));
		if (t == typeid(FlexFacet)) return elementOf(static_cast<const FlexFacet*>(sh));
		if (t == typeid(Sphere) || t == typeid(FlexNode)) return e; // the common non-elements
		if (const FlexCylinder* c = dynamic_cast<const FlexCylinder*>(sh)) return elementOf(c);
		if (const FlexFacet* f = dynamic_cast<const FlexFacet*>(sh)) return elementOf(f);
		return e;
	}
	inline Element elementOf(const Scene* scene, Body::id_t id)
	{
		const Body* b = bodyAt(scene, id);
		return b ? elementOf(b->shape.get()) : Element();
	}

	/// The scene as the kernel's mesh (kernel/Ownership.hpp): node positions, the elements on a
	/// node (FlexNode::elements), an element's nodes.
	struct SceneMesh {
		const Scene*    scene;
		const Vector3r* pos(int id) const
		{
			const State* s = stateOf(scene, id);
			return s ? &s->pos : nullptr;
		}
		flex::IdRange elementsAt(int id) const
		{
			const Body*     nb   = bodyAt(scene, id);
			const FlexNode* node = nb ? fastCast<FlexNode>(nb->shape.get()) : nullptr;
			return flex::idRange(node ? &node->elements : nullptr);
		}
		flex::ElementNodes element(int id) const { return elementOf(scene, id); }
	};
} // namespace flexa
} // namespace yade
