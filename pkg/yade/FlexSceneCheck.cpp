// yade-flex adapter: the scene check (GPL-2.0-or-later). What and why: FlexSceneCheck.hpp.
#include "FlexSceneCheck.hpp"
#include "FlexRefuse.hpp"
#include "FlexSurfaces.hpp"
#include "FlexElements.hpp"
#include "FlexProtocol.hpp"
#include "FlexSceneState.hpp"
#include "speed/FlexTuning.hpp"
#include "FlexUnstable.hpp"
#include "FlexFacet.hpp"
#include "speed/FlexLoop.hpp"

#include <core/InteractionLoop.hpp>
#include <boost/python/detail/wrap_python.hpp>
#include <pkg/common/Sphere.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {
namespace flexa {
	namespace {
		constexpr Real kHuge = kHugeValue;
		bool           finite(Real x) { return std::abs(x) < kHuge; } // (false for NaN and inf too)
		bool           finite(const Vector3r& v) { return finite(v[0]) && finite(v[1]) && finite(v[2]); }
		bool           finite(const Quaternionr& q) { return finite(q.w()) && finite(q.x()) && finite(q.y()) && finite(q.z()); }

		// a motion that is not finite: unstable (flexa::Unstable); any other field: a bad value
		[[noreturn]] void refuse(const Body& b, const std::string& field, const std::string& what)
		{
			std::ostringstream os;
			os << "body #" << b.id << " (" << (b.shape ? b.shape->getClassName() : std::string("no shape")) << "): " << field << " " << what;
			if (field == "state.pos" || field == "state.ori" || field == "state.vel" || field == "state.angVel") throw Unstable(os.str());
			throw std::invalid_argument(os.str());
		}
		template <class V> std::string got(const V& v)
		{
			std::ostringstream os;
			os.precision(6);
			os << "got " << v;
			return os.str();
		}
		std::string got(const Vector3r& v)
		{
			std::ostringstream os;
			os.precision(6);
			os << "got (" << v[0] << ", " << v[1] << ", " << v[2] << ")";
			return os.str();
		}

		void checkNodes(const Scene* scene, const Body& b, const int* ids, int n, const std::vector<char>& isNode)
		{
			const auto&        bodies   = scene->bodies->body;
			static const char* names[3] = { "node1", "node2", "node3" };
			for (int a = 0; a < n; ++a) {
				const int id = ids[a];
				// the node table answers for the bodies that are nodes; only a refusal visits the body
				if (id < 0 || (size_t)id >= bodies.size() || (!isNode[id] && !bodies[id]))
					refuse(b, std::string("shape.") + names[a], "= " + std::to_string(id) + " is not a body of the scene");
				if (!isNode[id]) {
					const Shape* s = bodies[id]->shape.get();
					refuse(b, std::string("shape.") + names[a],
					        "= " + std::to_string(id) + " is not a FlexNode (it is a "
					                + (s ? s->getClassName() : std::string("body without shape")) + ")");
				}
				for (int c = 0; c < a; ++c)
					if (ids[c] == id) refuse(b, std::string("shape.") + names[a], "= " + std::to_string(id) + " repeats " + names[c]);
			}
		}

		void checkRadius(const Body& b, Real r)
		{
			if (!(finite(r) && r > 0)) refuse(b, "shape.radius", "must be finite (below 1e100) and positive, " + got(r));
		}

		void checkMaterial(const Body& b, const Material* m)
		{
			auto bad = [&](const char* field, Real v, const char* need) {
				std::ostringstream os;
				os << "material";
				if (!m->label.empty()) os << " '" << m->label << "'";
				os << " (" << m->getClassName() << ")." << field;
				refuse(b, os.str(), std::string("must be ") + need + ", " + got(v));
			};
			const FrictMat* f = dynamic_cast<const FrictMat*>(m);
			if (!f) return;
			if (!(std::isfinite(f->young) && f->young > 0)) bad("young", f->young, "finite and positive");
			// (ks/kn: YADE's Ip2_FrictMat_FrictMat_FrictPhys gives two bodies of poisson 0 a shear stiffness of 0 / 0)
			if (!(std::isfinite(f->poisson) && f->poisson > 0)) bad("poisson", f->poisson, "finite and positive (ks/kn of its contacts)");
			if (!(std::isfinite(f->frictionAngle) && f->frictionAngle >= 0)) bad("frictionAngle", f->frictionAngle, "finite and >= 0");
			if (const FlexMat* fm = dynamic_cast<const FlexMat*>(m)) {
				if (!(std::isnan(fm->elementYoung) || (std::isfinite(fm->elementYoung) && fm->elementYoung > 0)))
					bad("elementYoung", fm->elementYoung, "finite and positive (NaN: young)");
				if (!(fm->beamPoisson > -1 && fm->beamPoisson < 0.5)) bad("beamPoisson", fm->beamPoisson, "in (-1, 0.5)");
				if (!(std::isfinite(fm->bendingFactor) && fm->bendingFactor >= 0)) bad("bendingFactor", fm->bendingFactor, "finite and >= 0");
				if (!(fm->yieldStress > 0)) bad("yieldStress", fm->yieldStress, "positive (inf: no yield)");
				if (!(std::isfinite(fm->hardening) && fm->hardening >= 0)) bad("hardening", fm->hardening, "finite and >= 0");
				if (!(fm->tensileStrength > 0)) bad("tensileStrength", fm->tensileStrength, "positive (inf: never breaks)");
				if (!(fm->ruptureStrain > 0)) bad("ruptureStrain", fm->ruptureStrain, "positive (inf: never breaks)");
				if (!(std::isfinite(fm->wireSlackScale) && fm->wireSlackScale >= 0))
					bad("wireSlackScale", fm->wireSlackScale, "finite and >= 0");
				if (!(fm->wireForceRatio > 0 && fm->wireForceRatio <= 1)) bad("wireForceRatio", fm->wireForceRatio, "in (0, 1]");
			}
			if (const FlexMembraneMat* mm = dynamic_cast<const FlexMembraneMat*>(m)) {
				if (!(std::isfinite(mm->stiffness) && mm->stiffness > 0)) bad("stiffness", mm->stiffness, "finite and positive");
				if (!(mm->membranePoisson >= 0 && mm->membranePoisson < 0.5)) bad("membranePoisson", mm->membranePoisson, "in [0, 0.5)");
			}
		}

		// every field checkState refuses, tested without a branch per field (a full check reads
		// every body of the scene); false: checkState finds which
		bool stateValid(const Body& b, bool element)
		{
			const State& s  = *b.state;
			bool         ok = motionValid(s);
			ok &= (s.mass >= 0) & (s.mass < kHuge);
			ok &= (s.inertia[0] >= 0) & (s.inertia[0] < kHuge) & (s.inertia[1] >= 0) & (s.inertia[1] < kHuge) & (s.inertia[2] >= 0)
			        & (s.inertia[2] < kHuge);
			if (!ok || element || b.isClumpMember() || !b.isDynamic()) return ok;
			const unsigned blocked = s.blockedDOFs;
			ok &= !((blocked & State::DOF_XYZ) != State::DOF_XYZ && s.mass == 0);
			ok &= !(!(blocked & State::DOF_RX) && s.inertia[0] == 0) & !(!(blocked & State::DOF_RY) && s.inertia[1] == 0)
			        & !(!(blocked & State::DOF_RZ) && s.inertia[2] == 0);
			return ok;
		}

		// names the first field stateValid refused (throws; returns if there is none)
		void checkState(const Body& b, bool element)
		{
			const State& s = *b.state;
			// (se3, not the references pos and ori: these are read from a line of State the pass
			// does not otherwise need)
			if (!finite(s.se3.position)) refuse(b, "state.pos", "must be finite (below 1e100), " + got(s.se3.position));
			if (!finite(s.se3.orientation)) refuse(b, "state.ori", "must be finite");
			if (!finite(s.vel)) refuse(b, "state.vel", "must be finite (below 1e100), " + got(s.vel));
			if (!finite(s.angVel)) refuse(b, "state.angVel", "must be finite (below 1e100), " + got(s.angVel));
			if (!(finite(s.mass) && s.mass >= 0)) refuse(b, "state.mass", "must be finite (below 1e100) and >= 0, " + got(s.mass));
			if (!(finite(s.inertia) && s.inertia.minCoeff() >= 0))
				refuse(b, "state.inertia", "must be finite (below 1e100) and >= 0, " + got(s.inertia));
			if (element || b.isClumpMember() || !b.isDynamic()) return;
			const unsigned blocked = s.blockedDOFs;
			if ((blocked & State::DOF_XYZ) != State::DOF_XYZ && s.mass == 0)
				refuse(b, "state.mass", "is 0 on a free body (give it a mass, or block its DOFs: state.blockedDOFs = 'xyzXYZ')");
			static const unsigned rot[3] = { State::DOF_RX, State::DOF_RY, State::DOF_RZ };
			for (int k = 0; k < 3; ++k)
				if (!(blocked & rot[k]) && s.inertia[k] == 0)
					refuse(b, "state.inertia",
					        "is 0 about a free rotation axis (" + got(s.inertia) + "; give it an inertia, or block its rotations)");
		}
	} // namespace

	namespace {
		// YADE's own InteractionLoop with the yade-flex geometry functors, on several threads: it
		// frees the objects of a contact that ends while a neighbouring contact's functor, on
		// another thread, reads them (the shear handed over, flexa::takeOverShear);
		// FlexInteractionLoop keeps them until the end of the loop
		void refuseThreadedPlainLoop(const InteractionLoop& il)
		{
			if (dynamic_cast<const FlexInteractionLoop*>(&il) || !il.geomDispatcher) return;
#ifdef YADE_OPENMP
			const int threads = il.ompThreads > 0 ? std::min(il.ompThreads, omp_get_max_threads()) : omp_get_max_threads();
#else
			const int threads = 1;
#endif
			if (threads <= 1) return;
			for (const auto& f : il.geomDispatcher->functors)
				if (f && f->getClassName().find("FlexContactGeom") != std::string::npos) {
					std::ostringstream os;
					os << il.getClassName();
					if (!il.label.empty()) os << " '" << il.label << "'";
					os << " runs the yade-flex functor " << f->getClassName() << " on " << threads
					   << " threads, where an ending contact's objects are freed while a neighbouring contact reads them: use "
					      "FlexInteractionLoop (yadeflex.engines() builds it), or set ompThreads=1 on this loop";
					throw std::invalid_argument(os.str());
				}
		}

		// the engines' parameters that enter every step's arithmetic
		void checkEngines(const Scene* scene)
		{
			checkEngineOrder(scene);
			for (const auto& e : scene->engines) {
				if (const NewtonIntegrator* nw = dynamic_cast<const NewtonIntegrator*>(e.get())) {
					if (!(nw->damping >= 0 && nw->damping < 1)) refuseAttribute(*nw, "damping", nw->damping, "in [0, 1)");
					for (int k = 0; k < 3; ++k)
						if (!std::isfinite(nw->gravity[k])) refuseAttribute(*nw, "gravity", nw->gravity[k], "finite");
				} else if (const InteractionLoop* il = dynamic_cast<const InteractionLoop*>(e.get())) {
					refuseThreadedPlainLoop(*il);
					for (const auto& f : il->lawDispatcher->functors)
						if (const auto* law = dynamic_cast<const Law2_FlexContactGeom_FrictPhys_CundallStrack*>(f.get())) {
							if (!(std::isfinite(law->rollingStiffness) && law->rollingStiffness >= 0))
								refuseAttribute(*law, "rollingStiffness", law->rollingStiffness, "finite and >= 0");
							if (!(std::isfinite(law->rollingFriction) && law->rollingFriction >= 0))
								refuseAttribute(*law, "rollingFriction", law->rollingFriction, "finite and >= 0");
							if (!(std::isfinite(law->onsetFactor) && law->onsetFactor > 0))
								refuseAttribute(*law, "onsetFactor", law->onsetFactor, "finite and positive");
						}
				}
			}
		}
	} // namespace

	namespace {
		// The materials a pass has checked: each is checked on the first body that has it.
		struct SeenMaterials {
			std::vector<const Material*> list; // (a scene has a handful)
			const Material*              last = nullptr;
		};

		// What the element pass checks of an element, copied while its shape is at hand (the pass
		// then reads this table instead of visiting every element's body and shape again).
		using ElementRecord = SceneCheckMemo::Element;

		// One body's own checks (shape radius, state, material), in that order; records whether it
		// is a node or an element (and then the element's nodes and radius) for the element pass
		// that follows.
		void checkBody(const Body& b, char& isNode, char& isElement, ElementRecord& rec, SeenMaterials& seen)
		{
			const Shape* sh      = b.shape.get();
			bool         element = false;
			if (sh) {
				// (by class index: a comparison of type_info across shared libraries compares names)
				const int           k = sh->getClassIndex();
				const FlexCylinder* c = nullptr;
				const FlexFacet*    f = nullptr;
				if (k == FlexNode::getClassIndexStatic())
					isNode = 1;
				else if (k == Sphere::getClassIndexStatic())
					checkRadius(b, static_cast<const Sphere*>(sh)->radius);
				else if (k == FlexCylinder::getClassIndexStatic())
					c = static_cast<const FlexCylinder*>(sh);
				else if (k == FlexFacet::getClassIndexStatic())
					f = static_cast<const FlexFacet*>(sh);
				else if (!(c = dynamic_cast<const FlexCylinder*>(sh)) && !(f = dynamic_cast<const FlexFacet*>(sh)))
					if (const Sphere* sp = dynamic_cast<const Sphere*>(sh)) checkRadius(b, sp->radius);
				if (c) rec = { { c->node1, c->node2, -1 }, 2, c->radius };
				if (f) rec = { { f->node1, f->node2, f->node3 }, 3, f->radius };
				element   = c || f;
				isElement = element;
			}
			if (b.state && !stateValid(b, element)) checkState(b, element);
			const Material* m = b.material.get();
			if (m && m != seen.last) {
				seen.last = m;
				if (std::find(seen.list.begin(), seen.list.end(), m) == seen.list.end()) {
					seen.list.push_back(m);
					checkMaterial(b, m);
				}
			}
		}

		// the body 32 ahead, then what is read of the one 16 ahead (the pass reads every body's
		// state: without, it waits on each)
		void fetchAhead(const shared_ptr<Body>* body, long n, long id)
		{
			using flexa::tuning::kAheadCheckBodies;
			using flexa::tuning::kAheadCheckParts;
			if (id + kAheadCheckBodies < n) flexa::prefetch(body[id + kAheadCheckBodies].get(), sizeof(Body));
			if (id + kAheadCheckParts < n)
				if (const Body* c = body[id + kAheadCheckParts].get()) {
					// the lines of the fields checkState reads, from the position to blockedDOFs (the
					// State's first bytes hold none of them), and the shape up to a Sphere's radius
					if (const State* st = c->state.get()) {
						const char* from = reinterpret_cast<const char*>(&st->se3); // (pos is a reference: reading it would wait)
						const char* to   = reinterpret_cast<const char*>(&st->blockedDOFs + 1);
						flexa::prefetch(from, size_t(to - from));
					}
					flexa::prefetch(c->shape.get(), sizeof(Sphere));
				}
		}

		// scenes with fewer bodies are checked by one thread (a parallel region costs more)
		constexpr long kCheckParallelMin = 2000;
	} // namespace

	namespace {
		thread_local int scriptFreeSteps = 0; // ScriptFreeSteps alive in this thread

		// Whether this step needs the full pass: whenever a script can have run since the last
		// step, or anything but yade-flex's engines can have changed the scene.
		bool fullCheckDue(const Scene* scene, const SceneState& st)
		{
			const SceneCheckMemo& m = st.check;
			if (!m.checked || m.thread != std::this_thread::get_id()) return true; // (O.run's thread is new at each call)
			if (scene->iter != m.iter + 1) return true;                             // (O.resetTime, a loaded scene)
			if (scene->iter - m.fullIter >= tuning::kFullCheckPeriod) return true;
			if (scene->bodies->size() != m.bodies) return true;
			// the states the last step left: vouched for by FlexNewtonIntegrator's fast path, which
			// refuses what it makes non-finite
			if (st.vouched.iter != m.iter) return true;
			// a script: O.step() holds Python's lock while the step runs (O.run's thread does not)
			if (!scriptFreeSteps && PyGILState_Check()) return true;
			// a PyRunner (or another periodic engine) ran since the last step's check
			return foreignEngineRanSince(scene, m.iter);
		}
	} // namespace

	void checkNextStepInFull(const Scene* scene) { sceneState(scene).check.checked = false; }
	ScriptFreeSteps::ScriptFreeSteps() { ++scriptFreeSteps; }
	ScriptFreeSteps::~ScriptFreeSteps() { --scriptFreeSteps; }

	void checkScene(const Scene* scene, const void* caller)
	{
		SceneState&     st   = sceneState(scene);
		SceneCheckMemo& memo = st.check;
		if (memo.checked && scene->iter == memo.iter && caller != memo.checker && memo.thread == std::this_thread::get_id())
			return; // (checked for this step by an engine before)
		if (!fullCheckDue(scene, st)) {
			memo.iter    = scene->iter;
			memo.checker = caller;
			return;
		}
		std::vector<char>&          isNode    = memo.isNode;
		std::vector<char>&          isElement = memo.isElement;
		std::vector<ElementRecord>& elements  = memo.elements;
		checkEngines(scene);
		// one pass over the bodies in id order; the elements' nodes are then checked against the
		// table of node ids, not by visiting the node bodies again
		const shared_ptr<Body>* body = scene->bodies->body.data();
		const long              n    = (long)scene->bodies->body.size();
		isNode.assign(n, 0);
		isElement.assign(n, 0);
		elements.resize(n);
		int nThreads = 1;
#ifdef YADE_OPENMP
		if (n >= kCheckParallelMin) nThreads = omp_get_max_threads();
#endif
		if (nThreads == 1) {
			SeenMaterials seen;
			for (long id = 0; id < n; ++id) {
				fetchAhead(body, n, id);
				if (body[id]) checkBody(*body[id], isNode[id], isElement[id], elements[id], seen);
			}
		} else {
			// Each thread checks a contiguous, ascending range of ids and stops at its first refusal
			// (its materials each checked at their first body in the range). The smallest refused id
			// is then the one a serial pass would stop at (a bad material first seen at a body of
			// another range makes that body refused there, if it comes first), and checking it again
			// alone gives the serial pass's message.
			long firstBad = n;
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(nThreads)
#endif
			{
				SeenMaterials seen;
				long          mine = n;
#ifdef YADE_OPENMP
#pragma omp for schedule(static)
#endif
				for (long id = 0; id < n; ++id) {
					if (mine < n) continue;
					fetchAhead(body, n, id);
					if (!body[id]) continue;
					try {
						checkBody(*body[id], isNode[id], isElement[id], elements[id], seen);
					} catch (const std::invalid_argument&) {
						mine = id;
					}
				}
#ifdef YADE_OPENMP
#pragma omp critical(flexSceneCheck)
#endif
				firstBad = std::min(firstBad, mine);
			}
			if (firstBad < n) {
				SeenMaterials fresh;
				char          node = 0, element = 0;
				ElementRecord rec;
				checkBody(*body[firstBad], node, element, rec, fresh); // (throws)
			}
		}
		for (long id = 0; id < n; ++id) {
			if (!isElement[id]) continue;
			const ElementRecord& e = elements[id];
			checkNodes(scene, *body[id], e.nodes, e.nNodes, isNode);
			checkRadius(*body[id], e.radius);
		}
		checkSurfaceSupport(scene);
		memo.checked   = true;
		memo.thread    = std::this_thread::get_id();
		memo.iter      = scene->iter;
		memo.checker   = caller;
		memo.fullIter  = scene->iter;
		memo.bodies    = scene->bodies->size();
	}

	void refuseIntegrated(const Scene* scene, Body::id_t id, const Vector3r& force, const Vector3r& torque)
	{
		const Body&  b = *scene->bodies->body[id];
		const State& s = *b.state;
		const char*  field;
		if (!finite(s.vel))
			field = "state.vel";
		else if (!finite(s.angVel))
			field = "state.angVel";
		else if (!finite(s.se3.position))
			field = "state.pos";
		else
			field = "state.ori";
		std::ostringstream os;
		os.precision(6);
		os << "became non-finite (or above 1e100) in the step from iteration " << scene->iter << ": the force on the body was (" << force[0] << ", "
		   << force[1] << ", " << force[2] << "), the torque (" << torque[0] << ", " << torque[1] << ", " << torque[2] << "), its mass " << s.mass
		   << "; look at the engines, forces and values acting on it";
		refuse(b, field, os.str());
	}

	void checkTimeStep(const Scene* scene)
	{
		if (!(std::isfinite(scene->dt) && scene->dt > 0)) {
			std::ostringstream os;
			os << "O.dt must be finite and positive, got " << scene->dt;
			throw std::invalid_argument(os.str());
		}
	}
} // namespace flexa
} // namespace yade
