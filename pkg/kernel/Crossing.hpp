// Energy-consistent onset and release of a linear penalty contact under the leap-frog scheme
// (GPL-2.0-or-later).
//
// Leap-frog keeps H = 1/2 v(n-1/2) M v(n+1/2) + U(x_n) exactly constant when, over every step,
// the trapezoid rule 1/2 (F_n + F_n+1) . (x_n+1 - x_n) integrates the forces exactly: true for
// linear springs and gravity, false over the one step in which a contact starts or ends (the
// force has a kink at zero overlap). There the contact gains or loses
//   1/2 k d_n d_n+1   (d the overlap, of opposite signs at the two ends of that step),
// up to 1/8 k (v dt)^2, a quarter of (omega dt)^2 of the kinetic energy it meets: 25% of a
// bounce at omega dt = 1, in either direction, so that a body bouncing or chattering on a stiff
// contact random-walks in energy.
//
// The contact here keeps the running defect S (the energy the scheme has put into the bodies
// beyond the change of its potential; exact arithmetic of the trapezoid along the overlap) and
// cancels it with an extra normal force c at the next step, chosen so that its work over the
// two steps it acts in, -1/2 c (d_n+1 - d_n-1), is -S with d_n+1 predicted from the approach
// rate, the contact's own force and the acceleration seen on the last step. In steady contact
// S does not change (the trapezoid is exact for a linear spring), so c is zero; at a crossing it
// is of the order of the spring force times the fraction of the step spent on the wrong side of
// zero. A prediction error leaves a remainder that the next step cancels in turn; the contact
// is kept two steps past its separation to do so. c is an equal and opposite pair of forces
// along the normal at the contact point: momentum is kept.
#pragma once
#include <cmath>
#include <limits>

namespace flex {

/// What a contact remembers between steps for the correction.
struct CrossingState {
	double prevDepth = 0;   // overlap at the last step, negative: gap [m]
	double prevForce = 0;   // normal force applied at the last step, repulsive positive [N]
	double prevRate  = std::numeric_limits<double>::quiet_NaN(); // d(overlap)/dt at the last step [m/s]; NaN: unknown
	double defect    = 0;   // S: energy put into the bodies beyond the potential's change [J]
	int    outSteps  = 0;   // steps since the last step with positive overlap
};

/// The state of a contact first seen (or seen again after an interruption) at overlap depth,
/// approach rate d(overlap)/dt [m/s] and step dt [s], with spring stiffness k [N/m]: the overlap
/// one step earlier is taken as depth - rate dt, carrying its spring force (a contact that
/// starts from a gap starts with no force; one taken over deep starts without a defect).
CrossingState crossingStart(double k, double depth, double rate, double dt);

/// Spring energy 1/2 k d^2 of overlap d (0 for a gap) [J].
inline double crossingSpringEnergy(double k, double d) { return d > 0 ? 0.5 * k * d * d : 0.0; }

/// One step of the correction for a linear spring (base normal force k max(depth, 0)): the extra
/// normal force c, repulsive positive [N], and st updated for the next step. invMass() gives the
/// sum of the inverse masses [1/kg] with which the two sides move along the normal under the
/// contact's force; it is asked for only on the steps that correct something.
template <class InvMass> double crossingStep(CrossingState& st, double k, double depth, double rate, double dt, InvMass&& invMass);

/// Whether a contact with this state may be let go (no defect worth correcting, or two steps
/// out of contact).
inline bool crossingDone(const CrossingState& st) { return st.outSteps >= 2 || st.defect == 0; }

// ---- implementation ----

/// The extra force that cancels defect S: c (d0 - c a) = 2 S, with d0 the predicted d_n+1 - d_n-1
/// without it and a = invMass dt^2 (the root continuous with 2 S / d0 as a -> 0), capped at
/// k |d0| (a prediction near a turning point: the rest is left to the next step).
double crossingForce(double S, double k, double d0, double a);

template <class InvMass> double crossingStep(CrossingState& st, double k, double depth, double rate, double dt, InvMass&& invMass)
{
	const double fb = depth > 0 ? k * depth : 0.0;
	double       S  = st.defect - 0.5 * (st.prevForce + fb) * (depth - st.prevDepth) + crossingSpringEnergy(k, depth) - crossingSpringEnergy(k, st.prevDepth);
	// round-off of steady contact (the trapezoid is exact there): nothing to correct
	const double scale = k * (depth * depth + st.prevDepth * st.prevDepth) + std::abs(st.prevForce * (depth - st.prevDepth));
	if (std::abs(S) <= 1e-12 * scale) S = 0;
	double c = 0;
	if (S != 0) {
		const double im     = invMass();
		const double aOther = std::isnan(st.prevRate) ? 0.0 : (rate - st.prevRate) / dt + st.prevForce * im;
		const double d0     = (depth - st.prevDepth) + (rate + (aOther - fb * im) * dt) * dt;
		c                   = crossingForce(S, k, d0, im * dt * dt);
		S -= 0.5 * c * (depth - st.prevDepth); // (its share of the next step is counted there, in prevForce)
	}
	st.prevForce = fb + c;
	st.prevDepth = depth;
	st.prevRate  = rate;
	st.defect    = S;
	st.outSteps  = depth > 0 ? 0 : st.outSteps + 1;
	return c;
}

} // namespace flex
