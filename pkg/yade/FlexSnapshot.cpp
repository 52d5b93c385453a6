// yade-flex adapter: FlexSnapshot (GPL-2.0-or-later). What and why: FlexSnapshot.hpp.
#include "FlexSnapshot.hpp"
#include "FlexGrainEngine.hpp"
#include "Flex.hpp"
#include "FlexElements.hpp"
#include "FlexFacet.hpp"

#include <core/Clump.hpp>
#include <lib/factory/ClassFactory.hpp>
#include <pkg/common/Box.hpp>
#include <pkg/common/Facet.hpp>
#include <pkg/common/Wall.hpp>
#include <pkg/dem/ScGeom.hpp>

#include <bitset>
#include <initializer_list>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace yade {

YADE_PLUGIN((FlexSnapshot));

namespace {
	static_assert(sizeof(Real) == sizeof(double), "FlexSnapshot writes float64 arrays");

	boost::python::object bytesOf(const void* data, size_t size)
	{
		PyObject* o = PyBytes_FromStringAndSize(static_cast<const char*>(data), (Py_ssize_t)size);
		if (!o) boost::python::throw_error_already_set();
		return boost::python::object(boost::python::handle<>(o));
	}
	template <class T> using Named = std::initializer_list<std::pair<const char*, const std::vector<T>*>>;
	// the arrays as bytes into d, under their names
	template <class T> void put(boost::python::dict& d, Named<T> arrays)
	{
		for (const auto& a : arrays)
			d[a.first] = bytesOf(a.second->data(), a.second->size() * sizeof(T));
	}
	void push3(std::vector<double>& out, const Vector3r& v)
	{
		out.push_back(v[0]);
		out.push_back(v[1]);
		out.push_back(v[2]);
	}
	void pushNaN3(std::vector<double>& out) { out.insert(out.end(), 3, std::numeric_limits<double>::quiet_NaN()); }

	long groupOf(const Shape* s)
	{
		if (!s) return FlexSnapshot::kNoGroup;
		// the scene's common shapes by their exact type first (a dynamic_cast that fails walks the
		// class hierarchy, for most bodies several times); then any class derived from them
		const std::type_info& t = typeid(*s);
		if (t == typeid(Sphere)) return FlexSnapshot::kSpheres;
		if (t == typeid(FlexNode)) return FlexSnapshot::kNodes;
		if (t == typeid(FlexCylinder)) return FlexSnapshot::kCylinders;
		if (t == typeid(FlexFacet)) return FlexSnapshot::kFacets;
		if (dynamic_cast<const FlexNode*>(s)) return FlexSnapshot::kNodes;
		if (dynamic_cast<const FlexCylinder*>(s)) return FlexSnapshot::kCylinders;
		if (dynamic_cast<const FlexFacet*>(s)) return FlexSnapshot::kFacets;
		if (dynamic_cast<const Sphere*>(s)) return FlexSnapshot::kSpheres;
		if (dynamic_cast<const Clump*>(s)) return FlexSnapshot::kClumps;
		if (dynamic_cast<const Box*>(s)) return FlexSnapshot::kBoxes;
		if (dynamic_cast<const Facet*>(s)) return FlexSnapshot::kRigidFacets;
		if (dynamic_cast<const Wall*>(s)) return FlexSnapshot::kWalls;
		return FlexSnapshot::kNoGroup;
	}
} // namespace

boost::python::dict FlexSnapshot::bodies() const
{
	const Scene*        scene = Omega::instance().getScene().get();
	const auto&         body  = scene->bodies->body;
	const size_t        n     = body.size();
	std::vector<long>   group(n, kErased), clumped(n, 0), blocked(n, 0);
	std::vector<double> pos, vel, angVel, mass(n, 0), radius(n, std::numeric_limits<double>::quiet_NaN());
	pos.reserve(3 * n);
	vel.reserve(3 * n);
	angVel.reserve(3 * n);
	for (size_t id = 0; id < n; ++id) {
		const Body* b = body[id].get();
		if (!b || !b->state) {
			pushNaN3(pos);
			pushNaN3(vel);
			pushNaN3(angVel);
			continue;
		}
		const Shape* sh = b->shape.get();
		group[id]       = groupOf(sh);
		clumped[id]     = b->isClump() || b->isClumpMember();
		const State& st = *b->state;
		push3(pos, st.pos);
		push3(vel, st.vel);
		push3(angVel, st.angVel);
		mass[id]    = st.mass;
		blocked[id] = (long)std::bitset<8 * sizeof(unsigned)>(st.blockedDOFs & State::DOF_ALL).count();
		if (group[id] == kNodes)
			radius[id] = static_cast<const FlexNode*>(sh)->radius;
		else if (group[id] == kSpheres)
			radius[id] = static_cast<const Sphere*>(sh)->radius;
	}
	boost::python::dict d;
	put<long>(d, { { "group", &group }, { "clumped", &clumped }, { "blocked", &blocked } });
	put<double>(d, { { "pos", &pos }, { "vel", &vel }, { "angVel", &angVel }, { "mass", &mass }, { "radius", &radius } });
	return d;
}

boost::python::dict FlexSnapshot::elements(long group) const
{
	if (group != kCylinders && group != kFacets)
		throw std::invalid_argument("FlexSnapshot.elements: group must be 2 (FlexCylinder) or 3 (FlexFacet), got " + std::to_string(group));
	static const std::vector<const char*> cylinderFields { "radius", "axialForce", "strain", "plasticStrain", "maxStrain", "hardeningVar", "wireSlack",
		"elasticEnergy", "L0" };
	static const std::vector<const char*> facetFields { "radius", "n1", "n2", "e1", "e2", "elasticEnergy", "pressure", "area0" };
	const bool                            cyl   = group == kCylinders;
	const std::vector<const char*>&       names = cyl ? cylinderFields : facetFields;
	const auto&                           body  = Omega::instance().getScene()->bodies->body;
	std::vector<long>                     ids, nodes;
	std::vector<std::vector<double>>      fields(names.size());
	for (size_t id = 0; id < body.size(); ++id) {
		const Body* b = body[id].get();
		if (!b || !b->state || groupOf(b->shape.get()) != group) continue;
		ids.push_back((long)id);
		if (cyl) {
			const FlexCylinder& c = static_cast<const FlexCylinder&>(*b->shape);
			nodes.insert(nodes.end(), { (long)c.node1, (long)c.node2 });
			const double v[]
			        = { c.radius, c.axialForce, c.strain, c.plasticStrain, c.maxStrain, c.hardeningVar, c.wireSlack, c.elasticEnergy, c.L0 };
			for (size_t k = 0; k < fields.size(); ++k)
				fields[k].push_back(v[k]);
		} else {
			const FlexFacet& f = static_cast<const FlexFacet&>(*b->shape);
			nodes.insert(nodes.end(), { (long)f.node1, (long)f.node2, (long)f.node3 });
			const double v[] = { f.radius, f.n1, f.n2, f.e1, f.e2, f.elasticEnergy, f.pressure, f.area0 };
			for (size_t k = 0; k < fields.size(); ++k)
				fields[k].push_back(v[k]);
		}
	}
	boost::python::dict d;
	put<long>(d, { { "id", &ids }, { "nodes", &nodes } });
	for (size_t k = 0; k < names.size(); ++k)
		d[names[k]] = bytesOf(fields[k].data(), fields[k].size() * sizeof(double));
	return d;
}

boost::python::dict FlexSnapshot::contacts() const
{
	const Scene*        scene  = Omega::instance().getScene().get();
	const auto&         bodies = scene->bodies->body;
	std::vector<long>   id1, id2;
	std::vector<double> end1, end2, point, normal, fn, fs, depth, plastic;
	// the centre of one side without an axis point: a sphere's centre, else the contact point
	auto centre = [&](Body::id_t id, const GenericSpheresContact* g, std::vector<double>& out) {
		const Body* b = (id >= 0 && (size_t)id < bodies.size()) ? bodies[id].get() : nullptr;
		if (b && b->state && flexa::fastCast<Sphere>(b->shape.get()))
			push3(out, b->state->pos);
		else if (g)
			push3(out, g->contactPoint);
		else
			pushNaN3(out);
	};
	for (const auto& I : *scene->interactions) {
		if (!I->isReal()) continue;
		// (the common classes by their exact type first: flexa::fastCast)
		const FrictPhys*     fp = flexa::fastCast<FrictPhys>(I->phys.get());
		const NormShearPhys* ph = fp ? fp : flexa::fastCast<NormShearPhys>(I->phys.get());
		if (!ph) continue;
		const FlexContactGeom* fg = flexa::fastCast<FlexContactGeom>(I->geom.get());
		if (fg && !fg->active) continue;
		const ScGeom*                sg = fg ? nullptr : flexa::fastCast<ScGeom>(I->geom.get());
		const GenericSpheresContact* g  = fg ? fg : sg ? sg : flexa::fastCast<GenericSpheresContact>(I->geom.get());
		id1.push_back(I->getId1());
		id2.push_back(I->getId2());
		if (fg) {
			push3(end1, fg->axis1);
			push3(end2, fg->axis2);
		} else {
			centre(I->getId1(), g, end1);
			centre(I->getId2(), g, end2);
		}
		if (g) {
			push3(point, g->contactPoint);
			push3(normal, g->normal);
		} else {
			pushNaN3(point);
			pushNaN3(normal);
		}
		push3(fn, ph->normalForce);
		push3(fs, ph->shearForce);
		plastic.push_back(fg ? fg->plasticOverlap : 0.0);
		if (fg)
			depth.push_back(fg->penetrationDepth);
		else if (sg)
			depth.push_back(sg->penetrationDepth);
		else
			depth.push_back(std::numeric_limits<double>::quiet_NaN());
	}
	// the grains' contacts that a FlexGrainEngine keeps out of the interactions (as their step saw them)
	flexa::forEachGrainEngine(scene, [&](const FlexGrainEngine& ge) {
		ge.forEachContact([&](const FlexGrainEngine::ContactRow& r) {
			id1.push_back(r.id1);
			id2.push_back(r.id2);
			push3(end1, r.x1);
			push3(end2, r.x2);
			push3(point, r.point);
			push3(normal, r.normal);
			push3(fn, r.normalForce);
			push3(fs, r.shearForce);
			depth.push_back(r.depth);
			plastic.push_back(0.0);
		});
	});
	boost::python::dict d;
	put<long>(d, { { "id1", &id1 }, { "id2", &id2 } });
	put<double>(d,
	        { { "end1", &end1 }, { "end2", &end2 }, { "contactPoint", &point }, { "normal", &normal }, { "normalForce", &fn }, { "shearForce", &fs },
	                { "penetrationDepth", &depth }, { "plasticOverlap", &plastic } });
	return d;
}

} // namespace yade
