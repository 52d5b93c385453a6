// yade-flex adapter: FlexGrainEngine (GPL-2.0-or-later). What it does: FlexGrainEngine.hpp.
#include "FlexGrainEngine.hpp"
#include "FlexContactGeom.hpp"
#include "FlexElements.hpp"
#include "FlexForces.hpp"
#include "FlexLaws.hpp"
#include "FlexProtocol.hpp"
#include "FlexRefuse.hpp"

#include <kernel/ContactRows.hpp>
#include <kernel/TimeStep.hpp>

#include <core/InteractionLoop.hpp>
#include <lib/factory/ClassFactory.hpp>
#include <pkg/common/Collider.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

YADE_PLUGIN((FlexGrainEngine));

namespace {
	constexpr int kSavedFields = 20; // id1, id2, shear, roll, normal, kn, ks, the crossing state (5), crossIter, lastActive
	static_assert(std::is_same<flex::Vec3, Vector3r>::value, "the kernel's vectors are YADE's (double)");

	[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("FlexGrainEngine: " + what); }

	Law2_FlexContactGeom_FrictPhys_CundallStrack* findLaw(const Scene* scene)
	{
		for (const auto& e : scene->engines)
			if (const InteractionLoop* il = dynamic_cast<const InteractionLoop*>(e.get()))
				for (const auto& f : il->lawDispatcher->functors)
					if (auto* l = dynamic_cast<Law2_FlexContactGeom_FrictPhys_CundallStrack*>(f.get())) return l;
		return nullptr;
	}
} // namespace

void FlexGrainEngine::validate() const
{
	auto bad = [this](const char* name, Real v, const char* need) { flexa::refuseAttribute(*this, name, v, need); };
	if (material < -1) bad("material", material, "a material id >= 0, or -1 (none)");
	if (grainBit <= 0 || (grainBit & (grainBit - 1)) != 0) bad("grainBit", grainBit, "a power of 2");
	if (!(skin >= 0) || !std::isfinite(skin)) bad("skin", skin, "finite and >= 0 (0: half the smallest grain radius)");
}

flex::GrainLaw FlexGrainEngine::grainLaw() const
{
	const FrictMat* m = static_cast<const FrictMat*>(scene->materials[material].get());
	flex::GrainLaw  L;
	L.young            = m->young;
	L.ksOverKn         = m->poisson;
	L.tanPhi           = std::tan(m->frictionAngle);
	L.rollingStiffness = law->rollingStiffness;
	L.rollingFriction  = law->rollingFriction;
	L.onsetFactor      = law->onsetFactor;
	L.crossing         = law->crossing;
	L.trackEnergy      = scene->trackEnergy;
	return L;
}

bool FlexGrainEngine::gather()
{
	const auto&     bodies = *scene->bodies;
	const Material* mat    = scene->materials[material].get();
	const long      n      = (long)ids.size();
	const bool      pf     = n >= flexa::kPrefetchMin; // (small passes stay in cache)
	// the first grain that is no longer one (the list is then found again) and the first with a
	// bad radius: whichever comes first decides, as in a pass that stops at it
	long firstOther = n, firstBad = n;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (n >= flexa::tuning::kGrainBodiesParallelMin) reduction(min : firstOther, firstBad)
#endif
	for (long k = 0; k < n; ++k) {
		if (pf) flexa::prefetchBodiesAhead(bodies.body.data(), ids.data(), n, k, [](const Body& c) { flexa::prefetchSphereParts<Sphere>(c); });
		const Body*   b = bodies.body[ids[k]].get();
		const Sphere* s = b && b->material.get() == mat && (b->groupMask & grainBit) ? flexa::fastCast<Sphere>(b->shape.get()) : nullptr;
		if (!s) {
			firstOther = std::min(firstOther, k);
			continue;
		}
		const State& st = *b->state;
		pos[k]          = st.pos;
		vel[k]          = st.vel;
		angVel[k]       = st.angVel;
		radius[k]       = s->radius;
		invMass[k]      = (!b->isDynamic() || (st.blockedDOFs & State::DOF_XYZ) == State::DOF_XYZ || !(st.mass > 0)) ? 0.0 : 1 / st.mass;
		if (!(radius[k] > 0) || !std::isfinite(radius[k])) firstBad = std::min(firstBad, k);
	}
	if (firstBad < firstOther) {
		std::ostringstream os;
		os << "grain #" << ids[firstBad] << " has radius " << radius[firstBad] << ": a grain's radius must be finite and > 0";
		refuse(os.str());
	}
	return firstOther == n;
}

// The grains found again (at the first step, and when bodies came or went): their masks, the
// collider's, the states carried over by body ids, the scene's grain-grain interactions taken over.
void FlexGrainEngine::scan()
{
	if (scene->isPeriodic) refuse("periodic cells are not supported");
	if (material >= (int)scene->materials.size() || !scene->materials[material]) {
		std::ostringstream os;
		os << "material " << material << " is not in O.materials (" << scene->materials.size() << " materials)";
		refuse(os.str());
	}
	const Material* mat = scene->materials[material].get();
	if (!dynamic_cast<const FrictMat*>(mat)) refuse("material " + std::to_string(material) + " is a " + mat->getClassName() + ", not a FrictMat");
	law = findLaw(scene);
	if (!law) refuse("needs Law2_FlexContactGeom_FrictPhys_CundallStrack in the interaction loop (yadeflex.engines() puts it there)");
	if (law->crushingIs50 > 0) refuse("grains that crush (Law2_FlexContactGeom_FrictPhys_CundallStrack.crushingIs50 > 0) are not supported");
	const shared_ptr<Engine> ce = flexa::insertionSortCollider(scene);
	if (!ce) refuse("needs an InsertionSortCollider in O.engines (it keeps grain pairs out of O.interactions)");
	Collider& collider = static_cast<Collider&>(*ce);

	// the states of the grains' contacts, by body ids
	std::vector<std::tuple<Body::id_t, Body::id_t, flex::GrainContacts::State>> kept;
	if (!gc && savedContacts.size() % kSavedFields != 0) refuse("savedContacts is not a whole number of saved contacts");
	if (!gc)
		for (size_t o = 0; o < savedContacts.size(); o += kSavedFields) { // (a loaded scene's)
			const Real*                r = &savedContacts[o];
			flex::GrainContacts::State c;
			c.exists          = true;
			c.shear           = Vector3r(r[2], r[3], r[4]);
			c.roll            = Vector3r(r[5], r[6], r[7]);
			c.normal          = Vector3r(r[8], r[9], r[10]);
			c.kn              = r[11];
			c.ks              = r[12];
			c.cross.prevDepth = r[13];
			c.cross.prevForce = r[14];
			c.cross.prevRate  = r[15];
			c.cross.defect    = r[16];
			c.cross.outSteps  = (int)r[17];
			c.crossIter       = (long)r[18];
			c.lastActive      = (long)r[19];
			kept.emplace_back((Body::id_t)r[0], (Body::id_t)r[1], c);
		}
	savedContacts.clear();
	forEachState([&](long i, long j, const flex::GrainContacts::State& c) { kept.emplace_back(ids[i], ids[j], c); });

	const auto& bodies = *scene->bodies;
	const long  nb_    = (long)bodies.body.size();
	ids.clear();
	indexOf.assign(nb_, -1);
	mask_t mask = 0;
	for (long id = 0; id < nb_; ++id) {
		Body* b = bodies.body[id].get();
		if (!b || b->material.get() != mat || !b->isStandalone() || !dynamic_cast<const Sphere*>(b->shape.get())) continue;
		b->groupMask |= grainBit;
		if (ids.empty())
			mask = b->groupMask;
		else if (b->groupMask != mask) {
			std::ostringstream os;
			os << "grains #" << ids[0] << " and #" << id << " have different groupMask (" << mask << ", " << b->groupMask
			   << "): the collider keeps grain pairs apart only between equal masks";
			refuse(os.str());
		}
		indexOf[id] = (int)ids.size();
		ids.push_back((Body::id_t)id);
	}
	for (long id = 0; id < nb_ && !ids.empty(); ++id) {
		const Body* b = bodies.body[id].get();
		if (b && indexOf[id] < 0 && b->groupMask == mask) {
			std::ostringstream os;
			os << "body #" << id << " is not a grain but has the grains' groupMask " << mask
			   << ": the collider would never pair it with a grain (give it another mask, or another grainBit)";
			refuse(os.str());
		}
	}
	collider.avoidSelfInteractionMask |= grainBit;
	bodyCount = bodies.body.size();

	const long n = (long)ids.size();
	for (auto* v : { &pos, &vel, &angVel, &force, &torque })
		v->assign(n, flex::Vec3::Zero());
	radius.assign(n, 0);
	invMass.assign(n, 0);
	if (!gather()) refuse("a grain changed while it was being found");
	double rMin = INFINITY;
	for (double r : radius)
		rMin = std::min(rMin, r);
	skinUsed = skin > 0 ? skin : (n ? 0.5 * rMin : 0.0);
	if (!nb || nb->skin() != skinUsed) nb.reset(new flex::GrainNeighbours(skinUsed > 0 ? skinUsed : 1));
	nb->build(pos.data(), radius.data(), n);
	if (!gc) gc.reset(new flex::GrainContacts(grainLaw()));
	gc->restart(*nb);
	for (const auto& [a, b, st] : kept) {
		if (a >= nb_ || b >= nb_ || indexOf[a] < 0 || indexOf[b] < 0) continue;
		if (flex::GrainContacts::State* s = gc->at(indexOf[a], indexOf[b]))
			*s = st;
		else
			++lostContacts;
	}

	// the scene's grain-grain interactions: a real one's state to the list, all erased
	std::vector<std::pair<Body::id_t, Body::id_t>> erase; // (by ids: erasing moves another interaction to the freed index)
	for (const auto& I : *scene->interactions) {
		const Body::id_t a = I->getId1(), b = I->getId2();
		if (a < 0 || b < 0 || a >= nb_ || b >= nb_ || indexOf[a] < 0 || indexOf[b] < 0) continue;
		erase.emplace_back(a, b);
		if (!I->isReal()) continue;
		const FlexContactGeom* g = dynamic_cast<const FlexContactGeom*>(I->geom.get());
		const FrictPhys*       p = dynamic_cast<const FrictPhys*>(I->phys.get());
		if (!g || !p)
			refuse("grains #" + std::to_string(a) + " and #" + std::to_string(b)
			        + " touch through YADE's own sphere contact (ScGeom): the engine takes over yade-flex's sphere contacts only "
			          "(yadeflex.engines(flex_sphere_contacts=True))");
		const bool                 flip = indexOf[a] > indexOf[b]; // the state's forces act on its second grain
		flex::GrainContacts::State s;
		s.exists     = true;
		s.kn         = p->kn;
		s.ks         = p->ks;
		s.shear      = flip ? Vector3r(-p->shearForce) : Vector3r(p->shearForce);
		s.roll       = flip ? Vector3r(-g->rollMoment) : g->rollMoment;
		s.normal     = (flip ? Vector3r(-g->normal) : g->normal);
		s.cross      = flex::CrossingState { g->crossDepth, g->crossForce, g->crossRate, g->crossDefect, g->crossOut };
		s.crossIter  = g->crossIter;
		s.lastActive = g->lastActiveIter;
		if (flex::GrainContacts::State* t = gc->at(std::min(indexOf[a], indexOf[b]), std::max(indexOf[a], indexOf[b]))) {
			*t = s;
			++takenOver;
		} else
			++lostContacts;
	}
	for (const auto& [a, b] : erase)
		if (const shared_ptr<Interaction> I = scene->interactions->find(a, b)) scene->interactions->erase(a, b, I->linIx);
	grains = n;
	pairs  = nb->pairs();
	builds = nb->builds();
}

void FlexGrainEngine::action()
{
	if (material < 0) return;
	validate();
	if (gc && !savedContacts.empty()) savedContacts.clear(); // (saved while running on: the states are in gc)
	if (!gc || scene->bodies->body.size() != bodyCount || !gather())
		scan();
	else if (nb->stale(pos.data(), (long)ids.size())) {
		nb->build(pos.data(), radius.data(), (long)ids.size());
		lostContacts += gc->follow(*nb);
		pairs  = nb->pairs();
		builds = nb->builds();
	}
	gc->setLaw(grainLaw());
	const long              n = (long)ids.size();
	const flex::GrainMotion m { pos.data(), vel.data(), angVel.data(), radius.data(), invMass.data(), n };
	int                     threads = 1;
#ifdef YADE_OPENMP
	if (pairs >= parallelMin) threads = omp_get_max_threads();
#endif
	threadsUsed = threads;
	std::vector<flex::GrainSums> part(threads);
	if (threads > 1) {
		threadForce.resize(threads - 1);
		threadTorque.resize(threads - 1);
	}
	const Real ratio0 = law->maxOverlapRatio;
	// each thread zeroes its own force sums and steps its part of the pairs into them; then (once
	// all are done) each adds up a share of the grains' sums, in thread order, into YADE's forces
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(threads)
#endif
	{
#ifdef YADE_OPENMP
		const int t = omp_get_thread_num();
#else
		const int t = 0;
#endif
		std::vector<flex::Vec3>& f = t == 0 ? force : threadForce[t - 1];
		std::vector<flex::Vec3>& q = t == 0 ? torque : threadTorque[t - 1];
		f.assign(n, flex::Vec3::Zero());
		q.assign(n, flex::Vec3::Zero());
		flex::GrainSums& s = part[t];
		s.force            = f.data();
		s.torque           = q.data();
		s.maxOverlapRatio  = ratio0;
		gc->step(m, scene->iter, scene->dt, s, gc->splitAt(t, threads), gc->splitAt(t + 1, threads));
		if (threads == 1) {
			for (long k = 0; k < n; ++k) {
				if (force[k] != flex::Vec3::Zero()) scene->forces.addForce(ids[k], force[k]);
				if (torque[k] != flex::Vec3::Zero()) scene->forces.addTorque(ids[k], torque[k]);
			}
		} else {
			// on several threads, into the container's sums (addForce from several threads
			// writes shared words of the container at every call): they are first brought up to
			// date (sync), as the interaction loop's per-thread sums are (flexa::mergeThreadSums)
#ifdef YADE_OPENMP
#pragma omp barrier
#pragma omp single
#endif
			{
				if (n > 0) scene->forces.addMaxId(*std::max_element(ids.begin(), ids.end()));
				scene->forces.sync();
			}
#ifdef YADE_OPENMP
#pragma omp for schedule(static)
#endif
			for (long k = 0; k < n; ++k) {
				flex::Vec3 fk = force[k], qk = torque[k];
				for (int u = 1; u < threads; ++u) {
					fk += threadForce[u - 1][k];
					qk += threadTorque[u - 1][k];
				}
				if (fk != flex::Vec3::Zero()) scene->forces.addForceUnsynced(ids[k], fk);
				if (qk != flex::Vec3::Zero()) scene->forces.addTorqueUnsynced(ids[k], qk);
			}
		}
	}
	flex::GrainSums sum;
	sum.maxOverlapRatio = ratio0;
	for (int t = 0; t < threads; ++t) {
		const flex::GrainSums& s = part[t];
		sum.elastic += s.elastic;
		sum.friction += s.friction;
		sum.rolling += s.rolling;
		sum.touching += s.touching;
		sum.deepOnsets += s.deepOnsets;
		sum.deepOnsetEnergy += s.deepOnsetEnergy;
		if (s.maxOverlapI >= 0 && s.maxOverlapRatio > sum.maxOverlapRatio) {
			sum.maxOverlapRatio = s.maxOverlapRatio;
			sum.maxOverlapI     = s.maxOverlapI;
			sum.maxOverlapJ     = s.maxOverlapJ;
		}
	}
	contacts = sum.touching;
	lastIter = scene->iter;
	if (sum.deepOnsets) {
		deepOnsets += sum.deepOnsets;
		deepOnsetEnergy += sum.deepOnsetEnergy;
		law->deepOnsets += sum.deepOnsets;
		law->deepOnsetEnergy += sum.deepOnsetEnergy;
	}
	if (sum.maxOverlapI >= 0 && sum.maxOverlapRatio > law->maxOverlapRatio) {
		law->maxOverlapRatio = sum.maxOverlapRatio;
		law->maxOverlapIds   = Vector2i(ids[sum.maxOverlapI], ids[sum.maxOverlapJ]);
	}
	if (scene->trackEnergy) {
		flexa::addEnergy(scene, sum.elastic, "flexContactElastic", elastIx, /*reset every step*/ true);
		flexa::addEnergy(scene, sum.friction, "flexFriction", frictIx, false);
		if (sum.rolling != 0) flexa::addEnergy(scene, sum.rolling, "flexRolling", rollIx, false);
	}
}

FlexGrainEngine::Gathered FlexGrainEngine::gatheredAt(long iter) const
{
	Gathered g;
	if (material < 0 || lastIter != iter || !gc) return g;
	g.ids     = ids.data();
	g.pos     = pos.data();
	g.vel     = vel.data();
	g.angVel  = angVel.data();
	g.radius  = radius.data();
	g.invMass = invMass.data();
	g.indexOf = indexOf.data();
	g.n       = (long)ids.size();
	g.nIds    = (long)indexOf.size();
	return g;
}

void FlexGrainEngine::addStepRows(Real* row, Real* rowRot, BodyColumn invSqrtMass, BodyColumn Imin) const
{
	if (!gc || !nb || material < 0) return;
	const FrictMat* mat = dynamic_cast<const FrictMat*>(scene->materials[material].get());
	if (!mat) return;
	const auto&    bodies = *scene->bodies;
	const long     n      = (long)ids.size();
	const auto&    f      = gc->first();
	const auto&    sec    = gc->second();
	const auto&    st     = gc->states();
	flex::GrainLaw L;
	L.young    = mat->young;
	L.ksOverKn = mat->poisson;
	// the grains where they are now (the engine's arrays hold them as of its last step)
	std::vector<flex::Vec3>& x     = stepPos;
	std::vector<double>&     reach = stepReach;
	x.resize(n);
	reach.resize(n);
	for (long k = 0; k < n; ++k) {
		const Body* b = ids[k] < (Body::id_t)bodies.body.size() ? bodies.body[ids[k]].get() : nullptr;
		x[k]          = b ? b->state->pos : pos[k];
		reach[k]      = (long)f.size() == n + 1 ? nb->reach(x.data(), k) : 0;
	}
	auto addRot = [&](Body::id_t id, double k, double lever2) {
		if (Imin[id] > 0 && std::isfinite(lever2)) rowRot[id] += 2 * k * lever2 / Imin[id];
	};
	for (long i = 0; i + 1 < (long)f.size() && i < n; ++i)
		for (long k = f[i]; k < f[i + 1]; ++k) {
			const int        j  = sec[k];
			const double     R1 = radius[i], R2 = radius[j];
			const double     gap = (x[j] - x[i]).norm() - R1 - R2;
			const Body::id_t a = ids[i], b = ids[j];
			const auto&      s = st[k];
			if (!s.exists
			        && flex::cannotTouch(gap, std::max(0.0, reach[i]), std::max(0.0, reach[j]),
			                std::max(x[i].cwiseAbs().maxCoeff(), x[j].cwiseAbs().maxCoeff())))
				continue;
			// the stiffness it has, or the one Ip2_FrictMat_FrictMat_FrictPhys will give it
			double kn = s.kn, ks = s.ks;
			if (!s.exists) L.stiffness(R1, R2, kn, ks);
			flex::RowSide sa, sb;
			sa.invSqrtMass[0] = invSqrtMass[a];
			sb.invSqrtMass[0] = invSqrtMass[b];
			double ra[3], rb[3];
			flex::potentialContactRows(sa, sb, std::max(kn, ks), ra, rb);
			if (sa.invSqrtMass[0] != 0) {
				row[a] += ra[0];
				addRot(a, ks, R1 * R1);
			}
			if (sb.invSqrtMass[0] != 0) {
				row[b] += rb[0];
				addRot(b, ks, R2 * R2);
			}
			if (s.exists && law && law->rollingStiffness > 0) {
				const double Reff = R1 * R2 / (R1 + R2), kr = law->rollingStiffness * ks * Reff * Reff;
				if (kr > 0) {
					addRot(a, kr, 1);
					addRot(b, kr, 1);
				}
			}
		}
}

boost::python::list FlexGrainEngine::contactList() const
{
	boost::python::list out;
	forEachContact([&](const ContactRow& r) { out.append(boost::python::make_tuple(r.id1, r.id2, r.normalForce, r.shearForce)); });
	return out;
}

void FlexGrainEngine::preSave(FlexGrainEngine&)
{
	savedContacts.clear();
	forEachState([&](long i, long j, const flex::GrainContacts::State& c) {
		const Real row[kSavedFields] = { Real(ids[i]), Real(ids[j]), c.shear[0], c.shear[1], c.shear[2], c.roll[0], c.roll[1], c.roll[2], c.normal[0],
			c.normal[1], c.normal[2], c.kn, c.ks, c.cross.prevDepth, c.cross.prevForce, c.cross.prevRate, c.cross.defect, Real(c.cross.outSteps),
			Real(c.crossIter), Real(c.lastActive) };
		savedContacts.insert(savedContacts.end(), row, row + kSavedFields);
	});
}

} // namespace yade
