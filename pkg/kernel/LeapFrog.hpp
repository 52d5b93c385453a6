// The leap-frog (central-difference) update of one body, with Cundall's non-viscous damping, as
// YADE's NewtonIntegrator does it:
//
//   a = F/m + g,  alpha = M/I                       (free DOFs only; blocked ones stay at 0)
//   a_i <- a_i (1 - c sign(a_i v_i'))               (damped bodies; v' = v + a dt/2, mid-step)
//   v <- v + a dt,  omega <- omega + alpha dt,  x <- x + v dt
//   q <- rot(|omega| dt, omega/|omega|) q, normalised
//
// With dampGravity false, gravity is added after the damping (it is then never damped). The
// update is explicit: stable for omega_max dt < 2 (undamped), 2/sqrt(1 + c) damped (the damping
// factor scales the effective stiffness by up to 1 + c; FlexTimeStepper).
//
// Energy booked per step (the same terms as NewtonIntegrator): kinetic energy before the update,
// work of gravity -m g.v dt, and on free DOFs the damping work c dt sum |v_i| |F_i + m g_i| (+
// the rotational terms). Blocked DOFs are not damped, so nothing is booked there.
//
// Driven DOFs: a blocked DOF keeps the velocity the user or an engine gave it, whatever the
// forces (an indenter, a plate, a pulled edge). Whatever holds it supplies the force that
// cancels the rest, -(F_i + m g_i), and so does the work -(F_i + m g_i) v_i dt on the scene in
// the step (v_i unchanged: the mid-step velocity the position moves with). driveWork books
// minus that work, in gravWork's sign (a stored or lost energy is positive, work put in
// negative), so that the balance of a driven test closes as that of a free impact does.
//
// Degrees of freedom: bit `axis` for translation, bit 3 + axis for rotation (YADE's
// State::axisDOF); kAllDofs: all six blocked.
#pragma once
#include "Types.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace flex {

constexpr unsigned kAllDofs = 63;
constexpr unsigned dofBit(int axis, bool rotational) { return 1u << (axis + (rotational ? 3 : 0)); }

/// Cundall's non-viscous damping factor 1 - c sign(x_i) of each component (x_i = a_i v_i, v at
/// mid-step), picked among 1 - c, 1 + c and 1 (the same values, bit for bit, as computing the
/// sign): a few instructions per component.
struct DampFactors {
	double minus, plus; // 1 - c, 1 + c
	explicit DampFactors(double c)
	        : minus(1 - c)
	        , plus(1 + c)
	{
	}
	double of(double x) const { return x > 0 ? minus : (x < 0 ? plus : 1.0); }
	Vec3   factors(const Vec3& x) const { return Vec3(of(x[0]), of(x[1]), of(x[2])); }
};

/// What the update reads of the scene: the step, gravity, the damping coefficient c.
struct LeapFrogSettings {
	double      dt;
	Vec3        gravity;
	double      damping;     // c, in [0, 1)
	DampFactors damp;        // from c
	bool        dampGravity; // gravity inside the damped acceleration (NewtonIntegrator.dampGravity)
};

/// One body's degrees of freedom, updated in place.
struct BodyDofs {
	Vec3&       pos;
	Vec3&       vel;
	Vec3&       angVel;
	Quat&       ori;
	const Vec3& inertia; // principal moments
	double      mass;
	unsigned    blocked; // dofBit()s of the blocked DOFs
	bool        damped;  // State::isDamped
	bool        turns = true; // its orientation integrated (false: a body whose orientation no force depends on, a sphere)
};

/// Minus the work the drive of the blocked DOFs does this step [J] (0 for a free body or a
/// blocked body at rest): sum over blocked DOFs of (F_i + m g_i) v_i dt + M_i omega_i dt.
inline double driveWork(const Vec3& f, const Vec3& m, const BodyDofs& b, const LeapFrogSettings& s)
{
	double e = 0;
	for (int i = 0; i < 3; ++i) {
		if ((b.blocked & dofBit(i, false)) && b.vel[i] != 0) e += (f[i] + b.mass * s.gravity[i]) * b.vel[i];
		if ((b.blocked & dofBit(i, true)) && b.angVel[i] != 0) e += m[i] * b.angVel[i];
	}
	return e * s.dt;
}

/// Damping work of this step on the free DOFs [J] (0 for an undamped body or c = 0).
inline double dampingWork(const Vec3& f, const Vec3& m, const BodyDofs& b, const LeapFrogSettings& s)
{
	if (s.damping == 0 || !b.damped || b.blocked == kAllDofs) return 0;
	if (b.blocked == 0) // the common case
		return (b.vel.cwiseAbs().dot((f + b.mass * s.gravity).cwiseAbs()) + b.angVel.cwiseAbs().dot(m.cwiseAbs())) * s.damping * s.dt;
	double e = 0;
	for (int i = 0; i < 3; ++i) {
		if (!(b.blocked & dofBit(i, false))) e += std::abs(b.vel[i]) * std::abs(f[i] + b.mass * s.gravity[i]);
		if (!(b.blocked & dofBit(i, true))) e += std::abs(b.angVel[i]) * std::abs(m[i]);
	}
	return e * s.damping * s.dt;
}

/// The update of velocities (free DOFs), position and (b.turns) orientation from force f and moment m.
inline void leapFrog(const Vec3& f, const Vec3& m, BodyDofs& b, const LeapFrogSettings& s)
{
	const double dt = s.dt;
	if (b.blocked != kAllDofs) {
		Vec3 a, al;
		if (b.blocked == 0) { // the common case, as vectors (the same IEEE operations per component)
			a = s.dampGravity ? Vec3(f / b.mass + s.gravity) : Vec3(f / b.mass);
			// no moment (the nodes of bar and truss links, grains without contact): +-0 / I is
			// +-0 for I > 0, so the quotient is the moment itself, bit for bit, without its
			// three divisions
			if (m[0] == 0 && m[1] == 0 && m[2] == 0 && b.inertia[0] > 0 && b.inertia[1] > 0 && b.inertia[2] > 0)
				al = m;
			else
				al = m.cwiseQuotient(b.inertia);
		} else {
			a = al = Vec3::Zero();
			for (int i = 0; i < 3; ++i) {
				if (!(b.blocked & dofBit(i, false))) a[i] = f[i] / b.mass + (s.dampGravity ? s.gravity[i] : 0);
				if (!(b.blocked & dofBit(i, true))) al[i] = m[i] / b.inertia[i];
			}
		}
		if (b.damped && s.damping != 0) {
			a  = a.cwiseProduct(s.damp.factors(a.cwiseProduct(b.vel + (0.5 * dt) * a)));
			al = al.cwiseProduct(s.damp.factors(al.cwiseProduct(b.angVel + (0.5 * dt) * al)));
		}
		if (!s.dampGravity)
			for (int i = 0; i < 3; ++i)
				if (!(b.blocked & dofBit(i, false))) a[i] += s.gravity[i];
		b.vel += dt * a;
		b.angVel += dt * al;
	}
	b.pos += b.vel * dt;
	if (!b.turns) return;
	const double w2 = b.angVel.squaredNorm();
	if (w2 != 0) {
		const double w = std::sqrt(w2);
		b.ori          = Quat(Eigen::AngleAxis<double>(w * dt, b.angVel / w)) * b.ori;
	}
	// Eigen's normalize() (divide by sqrt(|q|^2) if |q|^2 > 0), written out so that |q|^2 is
	// computed once, and skipped when |q|^2 is exactly 1, where it is the identity (sqrt(1) = 1,
	// x / 1 = x): a node that never turned saves a square root and four divisions
	const double q2 = b.ori.squaredNorm();
	if (q2 != 1 && q2 > 0) b.ori.coeffs() /= std::sqrt(q2);
}

} // namespace flex
