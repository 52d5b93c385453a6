// yade-flex adapter: the collider and the engine order the engines rely on (GPL-2.0-or-later).
// What and why: FlexProtocol.hpp.
#include "FlexProtocol.hpp"
#include "FlexBoundDispatcher.hpp"
#include "FlexFacet.hpp"
#include "FlexElements.hpp"
#include "FlexGrainEngine.hpp"

#include <kernel/TimeStep.hpp>

#include <core/InteractionLoop.hpp>
#include <pkg/common/InsertionSortCollider.hpp>
#include <pkg/common/ParallelEngine.hpp>
#include <pkg/dem/Ig2_Facet_Sphere_ScGeom.hpp>
#include <pkg/common/PeriodicEngines.hpp>

#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <typeinfo>

namespace yade {
namespace flexa {
	namespace {
		// The engine list is checked against the one seen last (each engine's address and
		// dynamic type, a pointer comparison each) and searched with dynamic_cast only when it
		// changed (a dynamic_cast over the engines costs about 2,200 instructions per call).
		// Returns the scene's memo, `same` whether the list is the one seen last.
		EngineListMemo& engineList(const Scene* s, bool& same)
		{
			EngineListMemo& m       = sceneState(s).engineList;
			const auto&     engines = s->engines;
			same                    = m.filled && m.seen.size() == engines.size();
			for (size_t i = 0; same && i < engines.size(); ++i) {
				const Engine* e = engines[i].get();
				same            = e == m.seen[i].first && (!e || &typeid(*e) == m.seen[i].second);
			}
			if (same) return m;
			m.filled       = true;
			m.collider     = nullptr;
			m.orderChecked = false;
			++m.generation;
			m.seen.clear();
			m.periodic.clear();
			m.parallel.clear();
			for (const auto& e : engines) {
				m.seen.emplace_back(e.get(), e ? &typeid(*e) : nullptr);
				if (dynamic_cast<const InsertionSortCollider*>(e.get())) m.collider = e.get(); // the last one
				if (dynamic_cast<const PeriodicEngine*>(e.get())) m.periodic.push_back(m.seen.size() - 1);
				if (dynamic_cast<const ParallelEngine*>(e.get())) m.parallel.push_back(m.seen.size() - 1);
			}
			return m;
		}
		EngineListMemo& engineList(const Scene* s)
		{
			bool same;
			return engineList(s, same);
		}

		// The place of an engine in the order of FlexProtocol.hpp, -1: not part of it.
		int rank(const Engine* e)
		{
			if (!e) return -1;
			if (dynamic_cast<const InsertionSortCollider*>(e)) return 0;
			if (dynamic_cast<const FlexGrainEngine*>(e)) return 1;
			if (dynamic_cast<const InteractionLoop*>(e)) return 2;
			if (dynamic_cast<const FlexElementEngine*>(e)) return 3;
			if (dynamic_cast<const FlexTimeStepper*>(e)) return 4;
			if (dynamic_cast<const NewtonIntegrator*>(e)) return 5;
			return -1;
		}
		std::string name(const Engine& e, size_t at)
		{
			std::ostringstream s;
			s << e.getClassName();
			if (!e.label.empty()) s << " (label '" << e.label << "')";
			s << " at O.engines[" << at << "]";
			return s.str();
		}
	} // namespace

	long insertionSortColliderRuns(const Scene* scene)
	{
		const EngineListMemo& m = engineList(scene);
		return m.collider ? static_cast<const InsertionSortCollider*>(m.collider)->numAction : -1;
	}
	shared_ptr<Engine> insertionSortCollider(const Scene* scene)
	{
		const EngineListMemo& m = engineList(scene);
		for (const auto& e : scene->engines)
			if (e.get() == m.collider && m.collider) return e;
		return nullptr;
	}

	bool foreignEngineRanSince(const Scene* scene, long iter)
	{
		bool            sameList;
		EngineListMemo& m    = engineList(scene, sameList);
		const bool      same = sameList && m.foreignAsked && m.foreignSeen == m.generation;
		m.foreignAsked       = true;
		m.foreignSeen        = m.generation;
		if (!same) return true;
		const auto& engines = scene->engines; // (the memo's list: the places hold the same engines)
		for (size_t i : m.periodic)
			if (static_cast<const PeriodicEngine*>(engines[i].get())->iterLast >= iter) return true;
		// a ParallelEngine's slaves can be replaced without a change of the list: looked up each time
		std::function<bool(const Engine*)> ran = [&](const Engine* e) {
			if (const PeriodicEngine* p = dynamic_cast<const PeriodicEngine*>(e)) return p->iterLast >= iter;
			if (const ParallelEngine* par = dynamic_cast<const ParallelEngine*>(e))
				for (const auto& group : par->slaves)
					for (const auto& slave : group)
						if (ran(slave.get())) return true;
			return false;
		};
		for (size_t i : m.parallel)
			if (ran(engines[i].get())) return true;
		return false;
	}

	namespace {
		// the engines of the yade-flex order inside a ParallelEngine (which runs its slave groups
		// at the same time): they share the scene's containers and must run one after another
		void refuseParallelSlaves(const Engine& e, size_t at, const Engine& top)
		{
			const ParallelEngine* par = dynamic_cast<const ParallelEngine*>(&e);
			if (!par) return;
			for (const auto& group : par->slaves)
				for (const auto& slave : group) {
					if (rank(slave.get()) >= 0) {
						std::ostringstream s;
						s << "O.engines: " << name(top, at) << " holds " << slave->getClassName()
						  << ", which must run on its own in O.engines: a ParallelEngine runs its slaves at the same time, and the "
						     "yade-flex engines (InsertionSortCollider, FlexGrainEngine, (Flex)InteractionLoop, FlexElementEngine, FlexTimeStepper, "
						     "(Flex)NewtonIntegrator) share the scene's bodies and interactions";
						throw std::invalid_argument(s.str());
					}
					if (slave) refuseParallelSlaves(*slave, at, top);
				}
		}
	} // namespace

	void checkEngineOrder(const Scene* scene)
	{
		bool            same;
		EngineListMemo& m = engineList(scene, same);
		for (size_t i : m.parallel) // (looked at each time: its slaves can change without a change of the list)
			if (scene->engines[i]) refuseParallelSlaves(*scene->engines[i], i, *scene->engines[i]);
		if (same && m.orderChecked) return;
		const auto& engines = scene->engines;
		int         best    = -1;
		size_t      at      = 0;
		for (size_t i = 0; i < engines.size(); ++i) {
			const int r = rank(engines[i].get());
			if (r < 0) continue;
			if (r < best) {
				std::ostringstream s;
				s << "O.engines: " << name(*engines[i], i) << " must come before " << name(*engines[at], at)
				  << ": the yade-flex engines run in the order InsertionSortCollider, FlexGrainEngine, (Flex)InteractionLoop, FlexElementEngine, "
				     "FlexTimeStepper, (Flex)NewtonIntegrator (yadeflex.engines() builds it)";
				throw std::invalid_argument(s.str());
			}
			if (r > best) {
				best = r;
				at   = i;
			}
		}
		m.orderChecked = true;
	}

	bool readsUnreachableMarks(const IGeomFunctor* f)
	{
		if (!f) return false;
		const std::type_info& t = typeid(*f);
		return t == typeid(Ig2_Sphere_Sphere_FlexContactGeom) || t == typeid(Ig2_Sphere_FlexCylinder_FlexContactGeom)
		        || t == typeid(Ig2_FlexCylinder_FlexCylinder_FlexContactGeom) || t == typeid(Ig2_Sphere_FlexFacet_FlexContactGeom)
		        || t == typeid(Ig2_FlexCylinder_FlexFacet_FlexContactGeom);
	}
	bool skipsMarkedAsApart(const IGeomFunctor* f) { return f && typeid(*f) == typeid(Ig2_Facet_Sphere_ScGeom); }
	bool allStandStill(const Scene* scene, const std::vector<Body::id_t>& ids)
	{
		for (Body::id_t id : ids) {
			const Body* b = bodyAt(scene, id);
			if (!b || !standsStill(*b)) return false;
		}
		return true;
	}
	bool marksHold(const Scene* scene)
	{
		const UnreachableMarks& m = sceneState(scene).unreachable;
		return m.valid(scene) && allStandStill(scene, m.still);
	}
} // namespace flexa

YADE_PLUGIN((FlexBoundDispatcher));

void FlexBoundDispatcher::action()
{
	BoundDispatcher::action();
	floored = 0;
	if (!(targetInterv > 0) || !(sweepDist > 0)) return; // every bound has sweepDist, or none a sweep
	const Real minSweep = minSweepDistFactor * sweepDist;
	for (const auto& b : *scene->bodies) {
		if (!b || !b->bound || b->bound->lastUpdateIter != scene->iter || b->bound->sweepLength != 0) continue;
		const State& st     = *b->state;
		const bool   moving = b->isDynamic() || st.vel != Vector3r::Zero() || st.angVel != Vector3r::Zero();
		const Real   sweep  = flex::flooredSweep(0, moving, minSweep);
		if (sweep == 0) continue;
		b->bound->sweepLength = sweep;
		b->bound->min -= Vector3r::Constant(sweep);
		b->bound->max += Vector3r::Constant(sweep);
		++floored;
	}
}

bool FlexBoundDispatcher::install(const Scene* scene, bool on)
{
	const shared_ptr<Engine> e = flexa::insertionSortCollider(scene);
	if (!e) return false;
	auto*                             isc  = static_cast<InsertionSortCollider*>(e.get());
	const shared_ptr<BoundDispatcher> old  = isc->boundDispatcher;
	const bool                        ours = old && dynamic_cast<const FlexBoundDispatcher*>(old.get());
	if (ours == on) return on;
	if (on && old && typeid(*old) != typeid(BoundDispatcher)) return false; // someone's own dispatcher: left alone
	shared_ptr<BoundDispatcher> d = on ? shared_ptr<BoundDispatcher>(boost::make_shared<FlexBoundDispatcher>()) : boost::make_shared<BoundDispatcher>();
	if (old) d->functors_set(old->functors);
	isc->boundDispatcher = d;
	return on;
}

} // namespace yade
