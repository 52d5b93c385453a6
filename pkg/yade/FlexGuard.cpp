// yade-flex adapter: FlexGuard (GPL-2.0-or-later). Definitions: FlexGuard.hpp.
#include "FlexGuard.hpp"
#include "FlexRefuse.hpp"
#include "FlexUnstable.hpp"
#include "FlexFacet.hpp"

#include <core/EnergyTracker.hpp>
#include <lib/factory/ClassFactory.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace yade {

YADE_PLUGIN((FlexGuard));

namespace {
	bool finite3(const Vector3r& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

	std::string fmt(const Vector3r& v)
	{
		std::ostringstream os;
		os.precision(6);
		os << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
		return os.str();
	}
} // namespace

void FlexGuard::validate() const
{
	auto bad = [this](const char* name, Real v, const char* need) { flexa::refuseAttribute(*this, name, v, need); };
	if (interval < 1) bad("interval", interval, ">= 1");
	if (!(maxStepFraction > 0)) bad("maxStepFraction", maxStepFraction, "> 0 (inf: off)");
	if (!(maxSpeed > 0)) bad("maxSpeed", maxSpeed, "> 0 (inf: off)");
	if (!(energyTolerance > 0)) bad("energyTolerance", energyTolerance, "> 0 (inf: off)");
	if (!(maxKineticRatio > 0)) bad("maxKineticRatio", maxKineticRatio, "> 0 (inf: off)");
	if (!(rawEnergyTolerance > 0)) bad("rawEnergyTolerance", rawEnergyTolerance, "> 0 (inf: off)");
}

void FlexGuard::resetPy()
{
	message.clear();
	bodies.clear();
	detectedIter      = -1;
	energyStart       = NaN;
	rawEnergyStart    = NaN;
	rawEnergyResidual = 0;
	energyScale       = 0;
	energyResidual    = 0;
	externalWork      = 0;
	maxStepSeen       = 0;
	energyInput       = 0;
	kineticSeen       = 0;
	lastWorkIter      = -1;
	lastEnergyCount   = 0;
}

void FlexGuard::refresh()
{
	auto& bs = *scene->bodies;
	contactRadius.assign(bs.size(), std::numeric_limits<Real>::infinity());
	for (const auto& b : bs) {
		if (!b || !b->shape) continue;
		if (const auto* s = dynamic_cast<const Sphere*>(b->shape.get()))
			contactRadius[b->id] = s->radius;
		else if (const auto* n = dynamic_cast<const FlexNode*>(b->shape.get())) {
			Real r = std::numeric_limits<Real>::infinity();
			for (int e : n->elements) {
				if (e < 0 || e >= (int)bs.size() || !bs[e]) continue;
				if (const auto* c = dynamic_cast<const FlexCylinder*>(bs[e]->shape.get()))
					r = std::min(r, c->radius);
				else if (const auto* f = dynamic_cast<const FlexFacet*>(bs[e]->shape.get()))
					r = std::min(r, f->radius);
			}
			contactRadius[b->id] = r;
		}
	}
	cachedBodyCount = bs.size();
}

// External work of permanent forces during the step that has just ended. Driven DOFs (blocked
// DOFs that move) are booked by the integrator itself, as 'driveWork' in O.energy (minus the
// work the drive does, kernel/LeapFrog.hpp): they are in O.energy.total() already.
void FlexGuard::addExternalWork()
{
	if (scene->iter == lastWorkIter) return; // once per step
	lastWorkIter = scene->iter;
	if (scene->iter == 0) return; // no step has been taken yet
	Real dW = 0;
	scene->forces.sync();
	// Permanent forces (O.forces.setPermF) are external loads: their work over the last step,
	// F.(x_{n+1} - x_n) = F.v_{n+1/2} dt, with the velocity the step has just produced. On a
	// blocked DOF the drive absorbs it: driveWork counts it with the opposite sign.
	if (scene->forces.getPermForceUsed())
		for (Body::id_t id : loaded) {
			const auto& b = Body::byId(id, scene);
			if (!b) continue;
			dW += scene->forces.getPermForce(id).dot(b->state->vel) + scene->forces.getPermTorque(id).dot(b->state->angVel);
		}
	lastWorkIncrement = dW * scene->dt;
	externalWork += lastWorkIncrement;
}

// The balance is taken at the level of the last step's positions x_n, where the elements and
// contacts booked their energies. YADE books the kinetic energy 1/2 m v_{n-1/2}^2, before the
// velocity update; the leap-frog scheme conserves exactly (linear forces, constant loads)
// 1/2 m v_{n-1/2}.v_{n+1/2} + U(x_n), whose change per step is the work F.(x_{n+1} - x_n) of
// constant loads. The difference, 1/2 m v_{n-1/2}.(v_{n+1/2} - v_{n-1/2}), is first order in dt
// and large where a load is suddenly applied near the stable step (an undamped bar under a
// permanent force: 14% of its energy at safety 0.5). The guard adds it (translations and
// rotations, bodies the integrator moves), and counts the external work up to x_n: the
// increment of the step just taken (x_n -> x_{n+1}) enters the next balance.
void FlexGuard::storeVelocities()
{
	auto& bs = *scene->bodies;
	prevVel.resize(bs.size());
	prevAngVel.resize(bs.size());
	for (const auto& b : bs)
		if (b) {
			prevVel[b->id]    = b->state->vel;
			prevAngVel[b->id] = b->state->angVel;
		}
	prevVelIter = scene->iter;
	prevDrive   = driveWork();
}

Real FlexGuard::driveWork() const
{
	const auto it = scene->energy->names.find("driveWork");
	return it == scene->energy->names.end() ? Real(0) : Real(scene->energy->energies.get(it->second));
}

Real FlexGuard::kineticCorrection() const
{
	if (prevVelIter != scene->iter - 1) return 0;
	auto& bs = *scene->bodies; // (BodyContainer has no const iteration)
	Real  c  = 0;
	for (const auto& b : bs) {
		if (!b || b->isClumpMember() || (size_t)b->id >= prevVel.size()) continue;
		const State& st = *b->state;
		c += 0.5 * st.mass * prevVel[b->id].dot(st.vel - prevVel[b->id])
		        + 0.5 * prevAngVel[b->id].dot(st.inertia.cwiseProduct(st.angVel - prevAngVel[b->id]));
	}
	return c;
}

void FlexGuard::fail(const std::string& what, const std::vector<Body::id_t>& ids)
{
	bodies.assign(ids.begin(), ids.end());
	detectedIter = scene->iter;
	std::ostringstream os;
	os << "FlexGuard: instability at iter " << scene->iter << " (t = " << scene->time << " s, dt = " << scene->dt << " s): " << what;
	message = os.str();
	// Leave the scene as the previous step left it: nothing of this step has run (the guard is
	// first), and subStep back to "between steps" so that a later O.step() starts a full step.
	scene->subStep = -1;
	throw flexa::Unstable(message);
}

void FlexGuard::action()
{
	validate();
	if (scene->trackEnergy) addExternalWork();
	// the next check needs the velocities of the step before it
	const bool storeNow = scene->trackEnergy && std::isfinite(energyTolerance) && (scene->iter + 1) % interval == 0;
	if (scene->iter % interval != 0) {
		if (storeNow) storeVelocities();
		return;
	}
	if (scene->bodies->size() != cachedBodyCount) refresh();
	loaded.clear();
	scene->forces.sync();
	checkBodies();
	if (scene->trackEnergy && std::isfinite(energyTolerance)) checkEnergy(storeNow);
}

void FlexGuard::checkBodies()
{
	auto&      bs       = *scene->bodies;
	const bool permUsed = scene->forces.getPermForceUsed();

	// 1-3: one pass over the bodies; the worst offender of each kind is reported first.
	struct Worst {
		Real                    value = 0;
		std::vector<Body::id_t> ids;
		Body::id_t              first = -1;
		void                    add(Body::id_t id, Real v)
		{
			ids.push_back(id);
			if (first < 0 || v > value) {
				value = v;
				first = id;
			}
		}
	} nonFinite, longStep, fast;
	std::string nonFiniteWhat;
	const Real  dt       = scene->dt;
	Real        maxRatio = 0;
	for (const auto& b : bs) {
		if (!b) continue;
		const Body::id_t id = b->id;
		const State&     st = *b->state;
		if (permUsed && (scene->forces.getPermForce(id) != Vector3r::Zero() || scene->forces.getPermTorque(id) != Vector3r::Zero()))
			loaded.push_back(id);
		const Vector3r& F = scene->forces.getForce(id);
		const Vector3r& T = scene->forces.getTorque(id);
		if (!(finite3(st.pos) && finite3(st.vel) && finite3(st.angVel) && finite3(F) && finite3(T))) {
			if (nonFinite.ids.empty()) {
				std::ostringstream os;
				os << "body #" << id << " has a non-finite";
				if (!finite3(st.pos)) os << " position " << fmt(st.pos);
				if (!finite3(st.vel)) os << " velocity " << fmt(st.vel);
				if (!finite3(st.angVel)) os << " angular velocity " << fmt(st.angVel);
				if (!finite3(F)) os << " force " << fmt(F);
				if (!finite3(T)) os << " torque " << fmt(T);
				nonFiniteWhat = os.str();
			}
			nonFinite.ids.push_back(id);
			continue;
		}
		const Real v = st.vel.norm();
		if (v > maxSpeed) fast.add(id, v);
		const Real r = contactRadius[id];
		if (std::isfinite(r) && r > 0) {
			const Real ratio = v * dt / r;
			maxRatio         = std::max(maxRatio, ratio);
			if (ratio > maxStepFraction) longStep.add(id, ratio);
		}
	}
	maxStepSeen = maxRatio;
	// the worst body first, then the others in id order
	auto ordered = [](const Worst& w) {
		std::vector<Body::id_t> out { w.first };
		for (Body::id_t id : w.ids)
			if (id != w.first) out.push_back(id);
		return out;
	};
	auto more = [](const Worst& w) { return w.ids.size() > 1 ? " (" + std::to_string(w.ids.size()) + " bodies in all)" : std::string(); };
	if (!nonFinite.ids.empty()) {
		const std::string extra = nonFinite.ids.size() > 1 ? " (" + std::to_string(nonFinite.ids.size()) + " bodies in all)" : std::string();
		fail(nonFiniteWhat + extra, nonFinite.ids);
	}
	if (!longStep.ids.empty()) {
		const auto&        b = Body::byId(longStep.first, scene);
		std::ostringstream os;
		os << "body #" << longStep.first << " moves " << longStep.value << " x its contact radius " << contactRadius[longStep.first]
		   << " m in one step (|v| = " << b->state->vel.norm() << " m/s; limit maxStepFraction = " << maxStepFraction << ")" << more(longStep)
		   << "; the time step is too long for a contact or element acting on it";
		fail(os.str(), ordered(longStep));
	}
	if (!fast.ids.empty()) {
		std::ostringstream os;
		os << "body #" << fast.first << " moves at " << fast.value << " m/s > maxSpeed = " << maxSpeed << " m/s" << more(fast);
		fail(os.str(), ordered(fast));
	}
}

// 4: energy created without external work
void FlexGuard::checkEnergy(bool storeNow)
{
	const EnergyTracker& en    = *scene->energy;
	// the integrator books a driven DOF's work when it moves it, x_n -> x_{n+1}: the step just
	// taken's share is past the level x_n of the balance, taken back as the external work's is
	const Real lastDrive = prevVelIter == scene->iter - 1 ? driveWork() - prevDrive : 0;
	const Real total     = en.total() + kineticCorrection() - lastDrive;
	if (storeNow) storeVelocities();
	if (!std::isfinite(total)) fail("O.energy.total() is not finite", {});
	// O.energy.clear() (or a fresh tracker): start a new balance once a step has booked energy
	if (en.energies.size() < lastEnergyCount) energyStart = NaN;
	lastEnergyCount = en.energies.size();
	if (lastEnergyCount == 0) return;
	if (std::isnan(energyStart)) {
		energyScale    = 0;
		energyInput    = 0;
		energyStart    = total;
		rawEnergyStart = en.total();
		externalWork   = 0;
		startIncrement = lastWorkIncrement;
	}
	// 4a: kinetic energy far above the energy put in (a linear blow-up, which keeps the leap-frog
	// balance of 4b constant while every term grows)
	auto term = [&](const char* name) {
		const auto it = en.names.find(name);
		return it == en.names.end() ? Real(0) : std::abs(en.energies.get(it->second));
	};
	// both as booked by the integrator in the step just taken (the same half step: the gravity
	// work that brought the current velocities is booked only in the next step)
	energyInput = std::max(energyInput, std::abs(energyStart) + std::abs(externalWork) + term("gravWork") + term("driveWork") + term("flexPressureWork"));
	kineticSeen = term("kinetic") + term("kinTrans") + term("kinRot");
	if (energyInput > 0 && kineticSeen > maxKineticRatio * energyInput) {
		std::ostringstream os;
		os << "kinetic energy " << kineticSeen << " J > maxKineticRatio = " << maxKineticRatio << " x the energy put in " << energyInput
		   << " J (start, external work, gravity, pressure): the time step is too long for some element or contact";
		const std::vector<Body::id_t> ids = largestKinetic(os);
		fail(os.str(), ids);
	}
	Real sumAbs = std::abs(externalWork);
	for (size_t i = 0; i < en.energies.size(); i++)
		sumAbs += std::abs(en.energies.get(i));
	energyScale    = std::max(energyScale, sumAbs);
	energyResidual = (total - energyStart) - (externalWork - lastWorkIncrement + startIncrement);
	// 4c: the balance as booked (kinetic energy 1/2 m v^2 at the half step, no leap-frog
	// correction). Above the critical step the corrected form stays constant while the
	// velocities alternate in sign and grow (1/2 m v-.v+ turns negative), so the booked form
	// runs away from it. In a stable run the two differ by 1/2 m v+.(v+ - v-): for a mode at
	// omega dt = 2 s (s the fraction of its critical step) the booked kinetic energy is at most
	// 1/(1 - s^2) times the invariant, so the difference stays below (1/(1 - s^2) - 1) x the
	// energy put in: 0.33 at s = 0.5, 1.78 at s = 0.8. Measured against the energy put in (the
	// scale of 4b grows with the blow-up's own terms).
	rawEnergyResidual = (en.total() - rawEnergyStart) - externalWork;
	if (energyScale > 0 && energyResidual > energyTolerance * energyScale) {
		std::ostringstream os;
		os << "energy created without external work: (total - start) - externalWork = " << energyResidual
		   << " J > energyTolerance = " << energyTolerance << " x energy scale " << energyScale << " J";
		const std::vector<Body::id_t> ids = largestKinetic(os);
		fail(os.str(), ids);
	}
	if (energyInput > 0 && rawEnergyResidual > rawEnergyTolerance * energyInput) {
		std::ostringstream os;
		os << "energy created without external work, as booked (no leap-frog correction): (O.energy.total() - start) - externalWork = "
		   << rawEnergyResidual << " J > rawEnergyTolerance = " << rawEnergyTolerance << " x the energy put in " << energyInput
		   << " J: the time step is too long for some element or contact";
		const std::vector<Body::id_t> ids = largestKinetic(os);
		fail(os.str(), ids);
	}
}

// the bodies carrying the most kinetic energy: where created energy shows
std::vector<Body::id_t> FlexGuard::largestKinetic(std::ostringstream& os) const
{
	std::vector<std::pair<Real, Body::id_t>> kin;
	for (const auto& b : *scene->bodies)
		if (b && b->state->mass > 0) kin.emplace_back(0.5 * b->state->mass * b->state->vel.squaredNorm(), b->id);
	const size_t nShow = std::min<size_t>(5, kin.size());
	std::partial_sort(kin.begin(), kin.begin() + nShow, kin.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
	std::vector<Body::id_t> ids;
	os << "; largest kinetic energy:";
	for (size_t i = 0; i < nShow; i++) {
		ids.push_back(kin[i].second);
		os << " #" << kin[i].second << " " << kin[i].first << " J" << (i + 1 < nShow ? "," : "");
	}
	return ids;
}

} // namespace yade
