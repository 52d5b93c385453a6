// yade-flex adapter: shapes, material, geometry, bound (GPL-2.0-or-later).
#include "FlexElements.hpp"
#include "FlexLaws.hpp"
#include <kernel/Hook.hpp>
#include <kernel/Membrane.hpp>
#include <kernel/TimeStep.hpp>

#include <kernel/WireLaw.hpp>

#include <lib/factory/ClassFactory.hpp>

#include <sstream>

namespace yade {

YADE_PLUGIN((FlexNode)(FlexMat)(FlexCylinder)(FlexContactGeom)(Bo1_FlexCylinder_Aabb)(FlexMembraneMat)(FlexFacet)(Bo1_FlexFacet_Aabb));

namespace {
	[[noreturn]] void bad(int id, const std::string& what, const char* cls = "FlexCylinder")
	{
		std::ostringstream os;
		os << cls << " #" << id << ": " << what;
		throw std::invalid_argument(os.str());
	}
	bool finite(const Vector3r& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
} // namespace

std::string FlexMat::wireError() const
{
	if (!isWire()) return "";
	std::string e = flex::wireCurveError(wireStrain, wireStress);
	if (e.empty()) e = flex::wireDistortionError(wireSlackScale, wireForceRatio);
	if (e.empty() && (std::isfinite(yieldStress) || hardening != 0 || std::isfinite(tensileStrength) || std::isfinite(ruptureStrain)))
		e = "wire law: the curve defines yield and rupture; leave yieldStress, hardening, tensileStrength and ruptureStrain unset";
	return e;
}

void FlexCylinder::attach(int selfId)
{
	Scene* scene = Omega::instance().getScene().get();
	if (selfId < 0 || selfId >= (int)scene->bodies->size() || !(*scene->bodies)[selfId]) bad(selfId, "no such body");
	const shared_ptr<Body>& self = (*scene->bodies)[selfId];
	if (self->shape.get() != this) bad(selfId, "the body with this id does not hold this shape");
	if (attached) bad(selfId, "already attached");
	if (!(radius > 0) || !std::isfinite(radius)) bad(selfId, "radius must be positive and finite, got " + std::to_string(radius));
	if (node1 == node2) bad(selfId, "both ends are the same node #" + std::to_string(node1));
	const int ids[2] = { node1, node2 };
	for (int id : ids) {
		if (id < 0 || id >= (int)scene->bodies->size() || !(*scene->bodies)[id]) bad(selfId, "end node #" + std::to_string(id) + " does not exist");
		const shared_ptr<Body>& n = (*scene->bodies)[id];
		if (!n->shape || !dynamic_cast<FlexNode*>(n->shape.get()))
			bad(selfId,
			        "end body #" + std::to_string(id) + " is a " + (n->shape ? n->shape->getClassName() : std::string("body without shape"))
			                + ", not a FlexNode");
		if (!finite(n->state->pos)) bad(selfId, "end node #" + std::to_string(id) + " has a non-finite position");
	}
	const FlexMat* mat = dynamic_cast<const FlexMat*>(self->material.get());
	if (!mat) bad(selfId, "material must be a FlexMat, got " + (self->material ? self->material->getClassName() : std::string("none")));
	if (!(mat->density > 0) || !std::isfinite(mat->density)) bad(selfId, "material density must be positive and finite");
	if (!(mat->young > 0) || !std::isfinite(mat->young)) bad(selfId, "material young must be positive and finite");
	if (!std::isnan(mat->elementYoung) && !(mat->elementYoung > 0 && std::isfinite(mat->elementYoung)))
		bad(selfId, "material elementYoung must be positive and finite (or NaN: young)");
	if (!(mat->bendingFactor >= 0)) bad(selfId, "material bendingFactor must be >= 0");
	const std::string wireErr = mat->wireError();
	if (!wireErr.empty()) bad(selfId, "material '" + mat->label + "': " + wireErr);
	State&         s1 = *(*scene->bodies)[node1]->state;
	State&         s2 = *(*scene->bodies)[node2]->state;
	const Vector3r d  = s2.pos - s1.pos;
	if (!(d.norm() > 1e-9 * radius)) bad(selfId, "nodes #" + std::to_string(node1) + " and #" + std::to_string(node2) + " coincide (zero length)");

	const flex::BeamRest rest = flex::makeBeamRest(s1.pos, s2.pos, s1.ori, s2.ori);
	L0                        = rest.L0;
	Q1                        = rest.Qi;
	Q2                        = rest.Qj;
	const flex::NodeShare sh  = flex::cylinderNodeShare(mat->density, radius, L0);
	massShare                 = sh.mass;
	inertiaShare              = sh.inertia;
	flex::BeamSection sec     = flexa::section(*mat, radius);
	if (mat->isWire()) { // the wire's elastic slope may exceed young: the time step must see it
		sec.EA        = std::max(sec.EA, M_PI * radius * radius * mat->wireStress[0] / mat->wireStrain[0]);
		maxStrain     = 0;
		plasticStrain = 0;
		wireSlack     = flex::wireSlackDraw((std::uint64_t)(std::int64_t)mat->wireSeed, node1, node2, mat->wireSlackScale);
	}
	omega2        = flex::beamMaxOmega2(sec, L0, sh.mass, sh.mass, sh.inertia, sh.inertia);
	hookNodes     = Vector2i(-1, -1);
	hookGap       = 0;
	hookStiffness = 0;
	hookForce     = 0;
	if (hookLegs != Vector2i(-1, -1)) {
		for (int k = 0; k < 2; ++k) {
			const int id = hookLegs[k];
			if (id < 0 || id >= (int)scene->bodies->size() || !(*scene->bodies)[id] || !dynamic_cast<FlexNode*>((*scene->bodies)[id]->shape.get()))
				bad(selfId, "hookLegs: #" + std::to_string(id) + " is not a FlexNode");
			if (id == node1 || id == node2) bad(selfId, "hookLegs: #" + std::to_string(id) + " is an end of the knot link itself");
			if (!finite((*scene->bodies)[id]->state->pos)) bad(selfId, "hookLegs: node #" + std::to_string(id) + " has a non-finite position");
		}
		if (hookLegs[0] == hookLegs[1]) bad(selfId, "hookLegs: both legs end at node #" + std::to_string(hookLegs[0]));
		const Vector3r m = s1.pos - 0.5 * ((*scene->bodies)[hookLegs[0]]->state->pos + (*scene->bodies)[hookLegs[1]]->state->pos);
		if (!(m.norm() >= d.norm()))
			bad(selfId, "hookLegs: node1's bend is straight (its apex is within one link length of its legs' midline), it cannot hook");
		hookNodes     = hookLegs;
		hookGap       = (s1.pos - s2.pos).dot(m.normalized());
		hookStiffness = sec.EA / L0;
		// the stop's mode added to the bond's (the largest eigenvalue of a sum is at most the sum of
		// theirs), with the link's own mass share at each of the stop's four nodes
		omega2 += flex::hookMaxOmega2(hookStiffness, sh.mass);
	}
	for (State* s : { &s1, &s2 }) {
		s->mass += sh.mass;
		s->inertia += Vector3r::Constant(sh.inertia);
	}
	for (int id : ids)
		static_cast<FlexNode*>((*scene->bodies)[id]->shape.get())->elements.push_back(selfId);
	self->setDynamic(false);
	self->state->pos = 0.5 * (s1.pos + s2.pos);
	attached         = true;
}

void Bo1_FlexCylinder_Aabb::go(const shared_ptr<Shape>& sh, shared_ptr<Bound>& bv, const Se3r&, const Body*)
{
	if (scene->isPeriodic) throw std::runtime_error("Bo1_FlexCylinder_Aabb: periodic scenes are not supported by yade-flex yet.");
	FlexCylinder& c  = static_cast<FlexCylinder&>(*sh);
	const State*  s1 = flexa::stateOf(scene, c.node1);
	const State*  s2 = flexa::stateOf(scene, c.node2);
	if (!s1 || !s2) return; // a node was erased: no bound, no new contact
	if (!bv) bv = shared_ptr<Bound>(new Aabb);
	Aabb*          aabb = static_cast<Aabb*>(bv.get());
	const Vector3r r    = Vector3r::Constant(c.radius);
	aabb->min           = s1->pos.cwiseMin(s2->pos) - r;
	aabb->max           = s1->pos.cwiseMax(s2->pos) + r;
	c.boundRef1         = s1->pos; // FlexNewtonIntegrator measures the nodes' motion from here
	c.boundRef2         = s2->pos;
}

void FlexFacet::attach(int selfId)
{
	auto   fail  = [selfId](const std::string& what) { bad(selfId, what, "FlexFacet"); };
	Scene* scene = Omega::instance().getScene().get();
	if (selfId < 0 || selfId >= (int)scene->bodies->size() || !(*scene->bodies)[selfId]) fail("no such body");
	const shared_ptr<Body>& self = (*scene->bodies)[selfId];
	if (self->shape.get() != this) fail("the body with this id does not hold this shape");
	if (attached) fail("already attached");
	if (!(radius > 0) || !std::isfinite(radius)) fail("radius (half thickness) must be positive and finite, got " + std::to_string(radius));
	const int ids[3] = { node1, node2, node3 };
	if (node1 == node2 || node2 == node3 || node1 == node3) fail("two corners are the same node");
	for (int id : ids) {
		if (id < 0 || id >= (int)scene->bodies->size() || !(*scene->bodies)[id]) fail("corner node #" + std::to_string(id) + " does not exist");
		const shared_ptr<Body>& n = (*scene->bodies)[id];
		if (!n->shape || !dynamic_cast<FlexNode*>(n->shape.get()))
			fail("corner body #" + std::to_string(id) + " is a " + (n->shape ? n->shape->getClassName() : std::string("body without shape"))
			        + ", not a FlexNode");
		if (!finite(n->state->pos)) fail("corner node #" + std::to_string(id) + " has a non-finite position");
	}
	const FlexMembraneMat* mat = dynamic_cast<const FlexMembraneMat*>(self->material.get());
	if (!mat) fail("material must be a FlexMembraneMat, got " + (self->material ? self->material->getClassName() : std::string("none")));
	if (!(mat->stiffness > 0) || !std::isfinite(mat->stiffness)) fail("material stiffness (E t) must be positive and finite");
	if (!(mat->arealDensity > 0) || !std::isfinite(mat->arealDensity)) fail("material arealDensity must be positive and finite");
	if (!(mat->membranePoisson >= 0 && mat->membranePoisson < 0.5))
		fail("material membranePoisson must be in [0, 0.5) (the time step's stretch bound is not valid for auxetic membranes)");
	if (!(mat->young > 0) || !std::isfinite(mat->young)) fail("material young (contact modulus) must be positive and finite");
	State* s[3];
	for (int k = 0; k < 3; ++k)
		s[k] = (*scene->bodies)[ids[k]]->state.get();
	const flex::MembraneRest rest = flex::makeMembraneRest(s[0]->pos, s[1]->pos, s[2]->pos);
	if (!(rest.A0 > 0))
		fail("nodes #" + std::to_string(node1) + ", #" + std::to_string(node2) + ", #" + std::to_string(node3)
		        + " are collinear or coincident (zero area)");
	// Dm is upper triangular: store its entries (|a|, b.e1, b.e2)
	restEdges = Vector3r(1 / rest.DmInv(0, 0), -rest.DmInv(0, 1) / (rest.DmInv(0, 0) * rest.DmInv(1, 1)), 1 / rest.DmInv(1, 1));
	area0     = rest.A0;
	massShare = mat->arealDensity * area0 / 3;
	// any positive inertia will do (facets put no moment on their nodes): that of the node's
	// share spread over its third of the facet
	inertiaShare = massShare * area0 / 18;
	omega2       = flex::membraneMaxOmega2(rest, flexa::membraneLaw(*mat), massShare);
	for (State* st : s) {
		st->mass += massShare;
		st->inertia += Vector3r::Constant(inertiaShare);
	}
	for (int id : ids)
		static_cast<FlexNode*>((*scene->bodies)[id]->shape.get())->elements.push_back(selfId);
	self->setDynamic(false);
	self->state->pos = (s[0]->pos + s[1]->pos + s[2]->pos) / 3;
	attached         = true;
}

void Bo1_FlexFacet_Aabb::go(const shared_ptr<Shape>& sh, shared_ptr<Bound>& bv, const Se3r&, const Body*)
{
	if (scene->isPeriodic) throw std::runtime_error("Bo1_FlexFacet_Aabb: periodic scenes are not supported by yade-flex yet.");
	FlexFacet&   f  = static_cast<FlexFacet&>(*sh);
	const State* s1 = flexa::stateOf(scene, f.node1);
	const State* s2 = flexa::stateOf(scene, f.node2);
	const State* s3 = flexa::stateOf(scene, f.node3);
	if (!s1 || !s2 || !s3) return;
	if (!bv) bv = shared_ptr<Bound>(new Aabb);
	Aabb*          aabb = static_cast<Aabb*>(bv.get());
	const Vector3r r    = Vector3r::Constant(f.radius);
	aabb->min           = s1->pos.cwiseMin(s2->pos).cwiseMin(s3->pos) - r;
	aabb->max           = s1->pos.cwiseMax(s2->pos).cwiseMax(s3->pos) + r;
	f.boundRef1         = s1->pos;
	f.boundRef2         = s2->pos;
	f.boundRef3         = s3->pos;
}

Real FlexFacet::stepOmega2(const Material* mat) const
{
	const FlexMembraneMat* m = mat ? flexa::fastCast<FlexMembraneMat>(mat) : nullptr;
	return m ? omega2 * flex::membraneStretchFactor(e1, e2, flexa::membraneLaw(*m)) : omega2;
}

} // namespace yade
