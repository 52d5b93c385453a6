// yade-flex adapter: the contact rows of FlexTimeStepper's estimate, one pass over the
// interactions (GPL-2.0-or-later). Included by FlexTimeStepper.cpp only; the rows' derivation:
// pkg/kernel/ContactRows.hpp.
#pragma once
#include "../FlexContactSide.hpp"
#include "../FlexElements.hpp"
#include "../FlexGrainEngine.hpp"
#include "../FlexLaws.hpp"
#include "../FlexProtocol.hpp"
#include "../FlexSurfaces.hpp"
#include "FlexTuning.hpp"

#include <kernel/ClosestPoints.hpp>
#include <kernel/ContactRows.hpp>
#include <kernel/TimeStep.hpp>
#include <kernel/Triangle.hpp>

#include <core/InteractionLoop.hpp>
#include <pkg/common/InsertionSortCollider.hpp>
#include <pkg/common/NormShearPhys.hpp>

#include <algorithm>
#include <cmath>
#include <vector>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {
namespace flexa {
	namespace stepper {
		// What the time step needs of one body, gathered once per estimate (dynamic_casts and
		// shared_ptr hops once per body instead of once per interaction side).
		struct StepBody {
			Real            invSqrtMass = 0;  // 1/sqrt(m); 0: no row of its own, infinite mass to others
			Real            Imin        = 0;  // smallest principal inertia of a dynamic body, else 0
			Real            radius      = -1; // contact radius (sphere, cylinder, facet), -1: Ip2 takes the other side's
			Real            kappa       = 0;  // facet: triangle load factor - 1 (see triangleLoadFactor)
			const FrictMat* mat         = nullptr;
			bool            sphere      = false; // a Sphere shape (clump members too)
			bool            facet       = false; // a YADE Facet (a rigid triangle)
			bool            shaped      = false; // the body exists and has a shape
			flexa::Element  el;
		};

		std::vector<StepBody> stepBodies(const Scene* scene)
		{
			const auto&             bodies = *scene->bodies;
			const shared_ptr<Body>* body   = bodies.body.data(); // (BodyContainer::operator[] is an out-of-line call)
			const long              n      = (long)bodies.body.size();
			std::vector<StepBody>   out(n);
			const Material*         lastMat   = nullptr;
			const FrictMat*         lastFrict = nullptr;
			// each body on its own: in parallel on large scenes (the material cache per thread)
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) firstprivate(lastMat, lastFrict) if (n >= flexa::tuning::kStepperBodiesParallelMin)
#endif
			for (long id = 0; id < n; ++id) {
				// the bodies and their states and shapes ahead (the bodies are scattered on the heap:
				// without, the pass waits on each body's state)
				flexa::prefetchBodiesAhead(body, n, id, [](const Body& c) {
					flexa::prefetch(c.state.get(), sizeof(State));
					flexa::prefetch(c.shape.get(), sizeof(Sphere));
				});
				const shared_ptr<Body>& b = body[id];
				if (!b) continue;
				StepBody& s = out[id];
				if (b->isDynamic()) {
					const State& st = *b->state;
					if (st.mass > 0 && st.blockedDOFs != State::DOF_ALL) s.invSqrtMass = 1 / std::sqrt(st.mass);
					s.Imin = st.inertia.minCoeff();
				}
				const Material* m = b->material.get();
				if (m != lastMat) { // bodies share materials: one cast per run of equal materials
					lastMat   = m;
					lastFrict = flexa::fastCast<FrictMat>(m);
				}
				s.mat = lastFrict;
				if (!b->shape) continue;
				s.shaped = true;
				// a node (no element; its contact radius is that of its contacts with rigid surfaces,
				// FlexSurfaces.hpp): told by its exact type first, which a failed cast to Sphere took
				// a dynamic_cast to find (one per node and estimate)
				if (typeid(*b->shape) == typeid(FlexNode)) {
					s.radius = flexa::nodeContactRadius(scene, static_cast<const FlexNode&>(*b->shape));
					if (!(s.radius > 0)) s.radius = -1;
					continue;
				}
				if (const Sphere* sp = flexa::fastCast<Sphere>(b->shape.get())) {
					s.radius = sp->radius;
					s.sphere = true;
				} else if (typeid(*b->shape) == typeid(Facet))
					s.facet = true;
				else {
					s.el = flexa::elementOf(b->shape.get());
					if (s.el.nNodes) s.radius = s.el.radius;
					if (s.el.fac) {
						Vector3r x[3];
						bool     ok = true;
						for (int a = 0; a < 3 && ok; ++a) {
							const State* st = flexa::stateOf(scene, s.el.nodes[a]);
							if ((ok = st != nullptr)) x[a] = st->pos;
						}
						s.kappa = ok ? flex::triangleLoadFactor(x, s.el.radius) - 1 : 0;
					}
				}
			}
			return out;
		}

		// Gershgorin rows of M^-1/2 K M^-1/2 for all contact springs (flex::contactRows, derivation in
		// pkg/kernel/ContactRows.hpp). Rotations: the shear spring at lever l on inertia I gives
		// k_s l^2 / I per side, doubled for coupling. Potential contacts (bounds overlap, no contact
		// yet) and contacts not carrying force now count too (flex::potentialContactRows), with the
		// stiffness Ip2_FrictMat_FrictMat_FrictPhys will give them (their own, for an existing one)
		// and, for each row, the worst weights over the contact's position: a contact appearing or
		// restarting between two estimates must not find a step already too long for it.
		//
		// Potential pairs that cannot touch before the collider runs again are left out: the collider
		// re-runs once a point leaves the sweep box of its bound, and this estimate is then made again
		// before the integrator uses the step (see flex::cannotTouch). Only with an
		// InsertionSortCollider (the guarantee is its trigger) and for shapes whose points are known:
		// spheres (clump members too), elements and YADE facets that stand still (they go nowhere:
		// the estimate is made again when one moves, still()); everything else counts as before.
		// With `mark`, the pairs left out are also marked for the geometry functors and the loop
		// (flexa::UnreachableMarks, which hold only while those facets stand still).
		//
		// FlexTimeStepper::markBeforeLoop makes the marks alone (markOnly) at the start of the loop
		// on a step the collider ran; its estimate at the end of the step, from the same positions,
		// then runs on that pass (adoptMarks): the same tables of the bodies, a marked pair left out
		// without its test, the others tested and marked as usual.
		class ContactRowsPass {
		public:
			ContactRowsPass(
			        const Scene* s, bool prefetch, bool skipUnreachable, bool mark, std::vector<std::pair<Body::id_t, Body::id_t>>* skippedOut)
			        : scene(s)
			        , sb(stepBodies(s))
			        , nb((Body::id_t)sb.size())
			        , prefetch(prefetch)
			        , canSkip(skipUnreachable && !s->isPeriodic && flexa::insertionSortColliderRuns(s) >= 0) // (the gaps ignore periodic images)
			        , mark(mark)
			        , skippedOut(skippedOut)
			        , marks(flexa::sceneState(s).unreachable)
			        , row(sb.size(), 0)
			        , rowRot(sb.size(), 0)
			{
				findLaw();
				if (mark) {
					marks.set = false;
					marks.still.clear();
					++marks.generation;
					marks.pair.assign(scene->interactions->size(), std::make_pair(Body::id_t(-1), Body::id_t(-1)));
					marks.earlyIter = -1;
				}
			}

			// the rows of every interaction, summed; returns the largest row and its body
			Real run(Body::id_t& stiffest, long& skippedCount)
			{
				InteractionContainer& ic = *scene->interactions;
				nI                       = (long)ic.size();
				intrs                    = nI ? &ic[0] : nullptr;
				// In parallel on large scenes (a serial engine's pass over every interaction, run at
				// each collider run): each thread sums its interactions into its own rows, added up in
				// thread order afterwards (one thread: the serial sums, bit for bit); the bodies' Sides
				// are all computed first, so that the threads only read them. A list of the skipped
				// pairs (unreachablePairs) is made serially, in order.
				int nThreads = 1;
#ifdef YADE_OPENMP
				if (!skippedOut && nI >= flexa::tuning::kStepperParallelMin) nThreads = omp_get_max_threads();
#endif
				std::vector<std::vector<Real>> moreRows(2 * (nThreads - 1), std::vector<Real>(sb.size(), 0));
				if (canSkip && !sidesMade) computeSides(nThreads);
				long skipped = 0;
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(nThreads) reduction(+ : skipped)
#endif
				{
#ifdef YADE_OPENMP
					const int thread = omp_get_thread_num();
#else
					const int thread = 0;
#endif
					Real* const myRow = thread == 0 ? row.data() : moreRows[2 * (thread - 1)].data();
					Real* const myRot = thread == 0 ? rowRot.data() : moreRows[2 * (thread - 1) + 1].data();
#ifdef YADE_OPENMP
#pragma omp for schedule(static)
#endif
					for (long li = 0; li < nI; ++li) {
						if (prefetch) fetchAhead(li);
						const Interaction& I = *intrs[li];
						if (I.isReal())
							realContactRows(I, myRow, myRot);
						else
							skipped += potentialPairRows(I, myRow, myRot);
					}
				} // omp parallel
				for (int t = 1; t < nThreads; ++t)
					for (size_t i = 0; i < sb.size(); ++i) {
						row[i] += moreRows[2 * (t - 1)][i];
						rowRot[i] += moreRows[2 * (t - 1) + 1][i];
					}
				skippedCount = skipped;
				// the grains' pairs, which FlexGrainEngine keeps out of the interactions
				if (!sb.empty())
					flexa::forEachGrainEngine(scene, [&](const FlexGrainEngine& ge) {
						auto column = [&](const Real& first) {
							return FlexGrainEngine::BodyColumn { reinterpret_cast<const unsigned char*>(&first), sizeof(StepBody),
								sb.size() };
						};
						ge.addStepRows(row.data(), rowRot.data(), column(sb[0].invSqrtMass), column(sb[0].Imin));
					});
				if (mark && canSkip) finishMarks();
				Real w2  = 0;
				stiffest = -1;
				for (size_t i = 0; i < row.size(); ++i)
					if (std::max(row[i], rowRot[i]) > w2) {
						w2       = std::max(row[i], rowRot[i]);
						stiffest = (Body::id_t)i;
					}
				return w2;
			}
			/// The marks alone, without rows (FlexTimeStepper::markBeforeLoop, for the loop at place
			/// loopIx in the engine list), made as run() makes them.
			void markOnly(size_t loopIx)
			{
				if (!mark || !canSkip) return; // (no marks: marks.set stays false)
				InteractionContainer& ic = *scene->interactions;
				nI                       = (long)ic.size();
				intrs                    = nI ? &ic[0] : nullptr;
				int nThreads             = 1;
#ifdef YADE_OPENMP
				if (nI >= flexa::tuning::kStepperParallelMin) nThreads = omp_get_max_threads();
#endif
				computeSides(nThreads);
				sidesMade = true;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(nThreads)
#endif
				for (long li = 0; li < nI; ++li) {
					if (prefetch) fetchAhead(li);
					const Interaction& I = *intrs[li];
					Real               r1, r2;
					if (!I.isReal()) screen(I, r1, r2);
				}
				finishMarks();
				marks.earlyIter     = scene->iter;
				marks.earlyLoopIx   = loopIx;
				marks.earlyErasures = flexa::sceneState(scene).elementErasures;
			}
			/// After markOnly, for the estimate of the same step (FlexTimeStepper::earlyMarksHold):
			/// the marks made are taken as this pass's own.
			void adoptMarks()
			{
				reuse = mark && canSkip && marks.valid(scene);
				if (reuse && marks.pair.size() < scene->interactions->size()) // (interactions added since: no mark yet)
					marks.pair.resize(scene->interactions->size(), std::make_pair(Body::id_t(-1), Body::id_t(-1)));
			}
			/// the bodies as the estimate saw them (id order)
			const std::vector<StepBody>& bodies() const { return sb; }
			/// the facets the estimate took as standing still (their pairs may have been left out)
			std::vector<Body::id_t> still() const
			{
				std::vector<Body::id_t> out;
				for (Body::id_t id = 0; id < (Body::id_t)sides.size(); ++id)
					if (sb[id].facet && sides[id].state == 1) out.push_back(id);
				return out;
			}

		private:
			// the defining points of a body (sphere centre, element nodes), how far they may still
			// travel before the collider runs, and the size of their coordinates (for the round-off
			// margin); once per body and estimate
			struct Side {
				signed char state = 0; // 0: not computed yet, 1: known, -1: unknown (no bound yet, another shape)
				int         n     = 0;
				Real        reach = 0, size = 0;
				Vector3r    x[3];
			};

			const Scene* const                                    scene;
			const std::vector<StepBody>                           sb;
			const Body::id_t                                      nb;
			const bool                                            prefetch, canSkip, mark;
			std::vector<std::pair<Body::id_t, Body::id_t>>* const skippedOut;
			flexa::UnreachableMarks&                              marks;
			bool                                                  reuse     = false; // adoptMarks
			bool                                                  sidesMade = false; // markOnly made them
			std::vector<Real>                                     row, rowRot;
			std::vector<Side>                                     sides;
			// the contact law, for rolling resistance between spheres (a rotational spring kr)
			const Law2_FlexContactGeom_FrictPhys_CundallStrack* law   = nullptr;
			long                                                nI    = 0;
			const shared_ptr<Interaction>*                      intrs = nullptr;

			void findLaw()
			{
				for (const auto& e : scene->engines)
					if (const InteractionLoop* il = dynamic_cast<const InteractionLoop*>(e.get()))
						for (const auto& f : il->lawDispatcher->functors)
							if (!law) law = dynamic_cast<const Law2_FlexContactGeom_FrictPhys_CundallStrack*>(f.get());
			}
			Real invSqrtMass(Body::id_t id) const { return (id < 0 || id >= nb) ? 0 : sb[id].invSqrtMass; }
			void addRot(Real* rot, Body::id_t id, Real ks, Real w, Real lever) const
			{
				const Real Imin = sb[id].Imin;
				if (Imin > 0 && std::isfinite(lever)) rot[id] += 2 * ks * std::abs(w) * lever * lever / Imin;
			}

			// the interactions ahead, and what they point to (FlexTuning.hpp)
			void fetchAhead(long li) const
			{
				using flexa::tuning::kAheadStepperObjects;
				using flexa::tuning::kAheadStepperTargets;
				if (li + kAheadStepperObjects < nI) flexa::prefetch(intrs[li + kAheadStepperObjects].get(), sizeof(Interaction));
				if (li + kAheadStepperTargets < nI) {
					const Interaction* J = intrs[li + kAheadStepperTargets].get();
					if (J->geom) flexa::prefetch(J->geom.get(), sizeof(FlexContactGeom));
					if (J->phys)
						flexa::prefetch(J->phys.get(), sizeof(FrictPhys));
					else { // a potential pair: what is read of its two bodies (tables in id order)
						for (Body::id_t id : { J->getId1(), J->getId2() })
							if (id >= 0 && id < nb) {
								flexa::prefetch(&sb[id], sizeof(StepBody));
								if (canSkip) flexa::prefetch(&sides[id], sizeof(Side));
							}
					}
				}
			}

			// all Sides at once, in id order with the bodies' bounds and states asked for ahead
			void computeSides(int nThreads)
			{
				sides.assign(sb.size(), Side());
				const shared_ptr<Body>* body = scene->bodies->body.data();
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(nThreads)
#endif
				for (long id = 0; id < (long)nb; ++id) {
					flexa::prefetchBodiesAhead(body, (long)nb, id, [](const Body& c) {
						flexa::prefetch(c.bound.get(), sizeof(Aabb));
						if (const State* st = c.state.get())
							flexa::prefetch(&st->se3.position, sizeof(Vector3r)); // (pos is a reference: reading it would wait)
					});
					sideOf((Body::id_t)id);
				}
			}
			const Side& sideOf(Body::id_t id)
			{
				Side& sd = sides[id];
				if (sd.state) return sd;
				sd.state      = -1;
				const Body* b = scene->bodies->body[id].get();
				if (!b || !b->bound) return sd;
				const Real            sweep = b->bound->sweepLength;
				const flexa::Element& el    = sb[id].el;
				if (el.nNodes) {
					const Vector3r* ref[3] { nullptr, nullptr, nullptr };
					if (el.cyl) {
						ref[0] = &el.cyl->boundRef1;
						ref[1] = &el.cyl->boundRef2;
					} else {
						ref[0] = &el.fac->boundRef1;
						ref[1] = &el.fac->boundRef2;
						ref[2] = &el.fac->boundRef3;
					}
					for (int a = 0; a < el.nNodes; ++a) {
						const State* st = flexa::stateOf(scene, el.nodes[a]);
						if (!st) return sd;
						sd.x[a]  = st->se3.position; // (not pos, a reference: one line more to wait for)
						sd.reach = std::max(sd.reach, flex::reachableDistance(sd.x[a], *ref[a], sweep));
						sd.size  = std::max(sd.size, sd.x[a].cwiseAbs().maxCoeff());
					}
					sd.n = el.nNodes;
				} else if (sb[id].sphere) {
					sd.x[0]  = b->state->se3.position;
					sd.reach = flex::reachableDistance(sd.x[0], b->bound->refPos, sweep);
					sd.size  = sd.x[0].cwiseAbs().maxCoeff();
					sd.n     = 1;
				} else if (sb[id].facet) {
					// a rigid triangle that stands still (not dynamic, no velocity: a container's
					// side) goes nowhere; the loop holds the marks only while it still stands
					// (flexa::marksHold; FlexTimeStepper estimates again when one moves). A moving
					// one is not known (its sweep does not bound its turning).
					const State& st = *b->state;
					if (!flexa::standsStill(*b)) return sd;
					const Facet& f = static_cast<const Facet&>(*b->shape);
					if (f.vertices.size() != 3) return sd;
					for (int a = 0; a < 3; ++a) {
						sd.x[a] = st.se3.position + st.se3.orientation * f.vertices[a];
						sd.size = std::max(sd.size, sd.x[a].cwiseAbs().maxCoeff());
					}
					sd.reach = 0;
					sd.n     = 3;
				} else
					return sd;
				sd.state = 1;
				return sd;
			}
			bool cannotTouchBeforeCollider(Body::id_t i1, Body::id_t i2) const
			{
				const Side &s1 = sides[i1], &s2 = sides[i2]; // (all computed before the pass)
				if (s1.state < 0 || s2.state < 0) return false;
				const int       n1 = s1.n, n2 = s2.n;
				const Vector3r *x1 = s1.x, *x2 = s2.x;
				const Real      reach1 = s1.reach, reach2 = s2.reach, size = std::max(s1.size, s2.size);
				// cheap first: the points' boxes farther apart than both radii and both reaches
				Vector3r p[6];
				for (int a = 0; a < n1; ++a)
					p[a] = x1[a];
				for (int a = 0; a < n2; ++a)
					p[n1 + a] = x2[a];
				const Real r1 = std::max(Real(0), sb[i1].radius), r2 = std::max(Real(0), sb[i2].radius); // (a facet's -1: no thickness)
				const Real reachAll = r1 + r2 + reach1 + reach2;
				if (flex::boxesApart(p, n1, n2, flex::searchReach(p, n1 + n2, reachAll))) return true;
				// a point or segment and a triangle: the plane test next (a wire or grain beside a
				// lining), before the exact distance
				if (n2 == 3 && n1 < 3 && flex::segmentTriangleApart(x1[0], x1[n1 - 1], x2[0], x2[1], x2[2], reachAll)) return true;
				if (n1 == 3 && n2 < 3 && flex::segmentTriangleApart(x2[0], x2[n2 - 1], x1[0], x1[1], x1[2], reachAll)) return true;
				const Real gap = flex::primitiveGap(x1, n1, r1, x2, n2, r2);
				return flex::cannotTouch(gap, reach1, reach2, size);
			}

			// The rows of a pair that may carry a contact before the next estimate (a potential pair,
			// or a contact not carrying force now), at its worst position (flex::potentialContactRows):
			// each side's DOF bodies are an element's nodes, else the body itself.
			void potentialRows(Real* rowOut, Real* rotOut, Body::id_t i1, Body::id_t i2, Real kn, Real ks) const
			{
				const StepBody* bs[2] = { &sb[i1], &sb[i2] };
				Real            r[2]  = { bs[0]->radius, bs[1]->radius };
				if (r[0] <= 0) r[0] = r[1];
				if (r[1] <= 0) r[1] = r[0];
				Body::id_t       ids[2][3];
				flex::RowSide    side[2];
				const Body::id_t self[2] = { i1, i2 };
				for (int s = 0; s < 2; ++s) {
					const flexa::Element& el = bs[s]->el;
					side[s].kappa            = el.fac ? bs[s]->kappa : 0;
					side[s].n                = el.nNodes ? el.nNodes : 1;
					for (int a = 0; a < side[s].n; ++a) {
						ids[s][a]              = el.nNodes ? el.nodes[a] : self[s];
						side[s].invSqrtMass[a] = invSqrtMass(ids[s][a]);
					}
				}
				Real rows[2][3];
				flex::potentialContactRows(side[0], side[1], std::max(kn, ks), rows[0], rows[1]);
				for (int s = 0; s < 2; ++s)
					for (int a = 0; a < side[s].n; ++a) {
						if (side[s].invSqrtMass[a] == 0) continue;
						rowOut[ids[s][a]] += rows[s][a];
						if (!bs[s]->el.fac) addRot(rotOut, ids[s][a], ks, 1, r[s]);
					}
			}

			// A real contact: its own stiffness on the bodies that carry its two sides (ContactSide),
			// rolling resistance, and a contact not carrying force counted as a potential pair.
			void realContactRows(const Interaction& I, Real* myRow, Real* myRot) const
			{
				const IPhys*         ip = I.phys.get();
				const FrictPhys*     fp = flexa::fastCast<FrictPhys>(ip);
				const NormShearPhys* ph = fp ? fp : dynamic_cast<const NormShearPhys*>(ip);
				if (!ph) return;
				const FlexContactGeom* fg = flexa::fastCast<FlexContactGeom>(I.geom.get());
				if (law && law->rollingStiffness > 0)
					if (const FlexContactGeom* g = fg)
						if (fp) {
							const Real kr = law->rollingK(*g, *fp);
							if (kr > 0) { // 2 kr / I on each side (Gershgorin row of the coupled pair)
								addRot(myRot, I.getId1(), kr, 1, 1);
								addRot(myRot, I.getId2(), kr, 1, 1);
							}
						}
				if (fg) {
					// a yade-flex contact counts with the worst weights of a potential pair, carrying
					// force or not: one that is not (it separated this step, or another contact of its
					// cluster owns the force) can carry it again at the next step, before the next
					// estimate; and one that is counts the same, so that the step does not change as
					// contacts come and go (the leap-frog update v += a dt with a step that changes
					// while a contact carries force F puts F v (dt - dt_before) / 2 into the bodies: a
					// body chattering on a stiff contact gained energy at every change)
					const Body::id_t i1 = I.getId1(), i2 = I.getId2();
					if (i1 >= 0 && i2 >= 0 && i1 < nb && i2 < nb) potentialRows(myRow, myRot, i1, i2, ph->kn, ph->ks);
					return;
				}
				// YADE's own contacts between two bodies (a grain on the slab): weight 1 on each
				const GenericSpheresContact* g = dynamic_cast<const GenericSpheresContact*>(I.geom.get());
				if (!g) return;
				const Body::id_t id[2]    = { I.getId1(), I.getId2() };
				const Real       lever[2] = { g->refR1, g->refR2 };
				Real             w[2]     = { 1, 1 }, ia[2], rows[2];
				for (int a = 0; a < 2; ++a)
					ia[a] = invSqrtMass(id[a]);
				flex::contactRows(w, ia, 2, std::max(ph->kn, ph->ks), rows);
				for (int a = 0; a < 2; ++a) {
					if (ia[a] == 0) continue;
					myRow[id[a]] += rows[a];
					addRot(myRot, id[a], ph->ks, w[a], lever[a]);
				}
			}

			// valid until the collider runs (else none: marks.set stays false)
			void finishMarks()
			{
				const shared_ptr<Engine> collider = flexa::insertionSortCollider(scene);
				marks.collider                    = collider;
				marks.runs                        = &static_cast<const InsertionSortCollider&>(*collider).numAction;
				marks.runsAtMarking               = *marks.runs;
				marks.colliderIx                  = std::find(scene->engines.begin(), scene->engines.end(), collider) - scene->engines.begin();
				marks.still                       = still();
				marks.set                         = true;
			}

			// A potential pair: -1 if it never counts (no contact possible, no body, no radius), 1 if
			// it cannot touch before the collider runs again (left out, and marked with `mark`), else
			// 0 (it counts, with contact radii r1, r2).
			int screen(const Interaction& I, Real& r1, Real& r2)
			{
				if (!I.functorCache.geomExists) return -1; // bonded neighbours: never a contact
				const Body::id_t i1 = I.getId1(), i2 = I.getId2();
				if (i1 < 0 || i2 < 0 || i1 >= nb || i2 >= nb) return -1;
				const StepBody* bs[2] = { &sb[i1], &sb[i2] };
				if (!bs[0]->mat || !bs[1]->mat || !bs[0]->shaped || !bs[1]->shaped) return -1; // (no body: no material, no shape)
				r1 = bs[0]->radius;
				r2 = bs[1]->radius;
				if (r1 <= 0) r1 = r2;
				if (r2 <= 0) r2 = r1;
				if (!(r1 > 0)) return -1;
				if (!canSkip) return 0;
				if (reuse && flexa::markMatches(marks.pair.data(), marks.pair.size(), I)) {
					if (skippedOut) skippedOut->emplace_back(i1, i2);
					return 1;
				}
				if (!cannotTouchBeforeCollider(i1, i2)) return 0;
				if (skippedOut) skippedOut->emplace_back(i1, i2);
				if (mark && I.linIx >= 0 && (size_t)I.linIx < marks.pair.size()) marks.pair[I.linIx] = std::make_pair(i1, i2);
				return 1;
			}

			// A potential pair: the stiffness Ip2_FrictMat_FrictMat_FrictPhys will give it, unless it
			// cannot touch before the collider runs again. Returns 1 if it was left out, else 0.
			long potentialPairRows(const Interaction& I, Real* myRow, Real* myRot)
			{
				Real      r1 = 0, r2 = 0;
				const int s = screen(I, r1, r2);
				if (s) return s > 0;
				const Body::id_t i1 = I.getId1(), i2 = I.getId2();
				const FrictMat * m1 = sb[i1].mat, *m2 = sb[i2].mat;
				const Real      k1 = m1->young * r1, k2 = m2->young * r2, kn = 2 * k1 * k2 / (k1 + k2);
				const Real      s1 = k1 * m1->poisson, s2 = k2 * m2->poisson, ks = (s1 + s2 > 0) ? 2 * s1 * s2 / (s1 + s2) : 0;
				potentialRows(myRow, myRot, i1, i2, kn, ks);
				return 0;
			}
		};
	} // namespace stepper
} // namespace flexa
} // namespace yade
