// Contact kinematics on deformable elements and the frictional contact law.
//
// A contact point c touches a cylinder whose axis point is p = (1-u) x_A + u x_B. The
// element carries no DOF: the material point at c moves with the nodes,
//     v(c) = (1-u) v_A + u v_B + w(u) x (c - p),     w(u) = (1-u) w_A + u w_B,
// which is exact for a rigid motion of the element (v_k = v0 + W x x_k, w_k = W gives
// v(c) = v0 + W x c), whatever its length.
// A force F at c on the element goes to the nodes with the same weights (the adjoint map):
//     F_A = (1-u) F,  F_B = u F,  M_A = (1-u) (c - p) x F,  M_B = u (c - p) x F,
// so sum F_k = F and sum (x_k x F_k + M_k) = c x F exactly (force and moment balance), and
// the power F . v(c) equals sum F_k . v_k + M_k . w_k (no energy created by the split).
#pragma once
#include "Types.hpp"

#include <cmath>

namespace flex {

/// Velocity of the material point c of a segment (nodes A, B) at axis parameter u.
Vec3 segmentPointVelocity(double u, const Vec3& axisPoint, const Vec3& c, const Vec3& vA, const Vec3& wA, const Vec3& vB, const Vec3& wB);

struct NodeLoad {
	Vec3 F, M;
};
/// Split a force F acting at point c of a segment (axis point p at parameter u) onto its nodes.
void distributeToSegment(double u, const Vec3& axisPoint, const Vec3& c, const Vec3& F, NodeLoad& A, NodeLoad& B);

/// Carry a shear force from an old contact plane (normal nOld) to the new one (nNew):
/// remove the normal component and restore the magnitude.
inline Vec3 rotateShear(const Vec3& shear, const Vec3& nNew);

/// A linear spring with a capped magnitude (Coulomb friction, rolling resistance): the trial
/// value old - k increment is scaled back to |value| <= limit. `dissipated` is consistent with
/// the leap-frog energy identity (see Contact.cpp).
struct CappedSpring {
	Vec3   value      = Vec3::Zero(); ///< new force or moment
	double energy     = 0;            ///< stored |value|^2 / (2 k) [J]
	double dissipated = 0;            ///< this step [J]
	bool   slipping   = false;
};
inline CappedSpring cappedSpringStep(double k, double limit, const Vec3& old, const Vec3& increment);

/// Linear frictional contact (Cundall & Strack 1979) with Coulomb's limit.
struct FrictionalContact {
	double kn = 0, ks = 0; ///< normal / shear stiffness [N/m]
	double tanPhi = 0;     ///< friction coefficient [-]
};
struct FrictionalResult {
	Vec3   normalForce;       ///< on body 2 (n points from 1 to 2) [N]
	Vec3   shearForce;        ///< on body 2 [N] (also the new shear state)
	double elasticEnergy = 0; ///< [J]
	double frictionWork  = 0; ///< dissipated this step [J]
	bool   sliding       = false;
};
/// overlap > 0 in contact [m]; n unit normal from 1 to 2; shearOld already carried to the new
/// plane; dus = tangential displacement increment of 2 relative to 1 this step [m].
FrictionalResult frictionalStep(const FrictionalContact& p, double overlap, const Vec3& n, const Vec3& shearOld, const Vec3& dus);
/// The same with the normal force magnitude Fn [N] given (a normal spring of its own, e.g. one
/// that yields: Crushing.hpp); the stored energy counts Fn^2 / (2 kn).
inline FrictionalResult frictionalStepWithNormal(const FrictionalContact& p, double Fn, const Vec3& n, const Vec3& shearOld, const Vec3& dus);

// ---- the two steps every contact takes, inline (definitions)

inline Vec3 rotateShear(const Vec3& shear, const Vec3& nNew)
{
	const double mag = shear.norm();
	if (mag == 0) return shear;
	Vec3         t  = shear - nNew.dot(shear) * nNew;
	const double tn = t.norm();
	return tn > 1e-14 * mag ? Vec3(t * (mag / tn)) : Vec3::Zero();
}

// Trial shear Fs* = Fs_old - ks dus (elastic predictor); if |Fs*| > tanPhi |Fn| it is scaled
// back to the cone. Dissipation consistent with the leap-frog energy identity, whose work of
// the contact over a step is the trapezoid W = -(Fs_old + Fs_new).dus / 2: with stored energy
// E = |Fs|^2 / (2 ks) and dus = (Fs_old - Fs*)/ks,
//     D = W - (E_new - E_old) = (Fs* - Fs_new).(Fs_old + Fs_new) / (2 ks).
// Steady sliding: D = Fs_max |slip|; a cone shrinking under a falling normal force with no
// tangential motion: D = the elastic energy released; stick: D = 0. The classical
// (|Fs*| - Fs_max) Fs_max / ks misses (|Fs*| - Fs_max)^2 / (2 ks) in the second case, which
// left 3.4 % of a frictional sphere-wire impact's energy unbooked (measured).
inline CappedSpring cappedSpringStep(double k, double limit, const Vec3& old, const Vec3& increment)
{
	CappedSpring r;
	Vec3         v  = old - k * increment;
	const double v2 = v.squaredNorm();
	if (v2 > limit * limit) {
		const double trial = std::sqrt(v2);
		r.slipping         = true;
		const Vec3 trialV  = v;
		v *= (trial > 0 ? limit / trial : 0.0);
		if (k > 0) r.dissipated = 0.5 * (trialV - v).dot(old + v) / k;
	}
	r.value  = v;
	r.energy = k > 0 ? 0.5 * v.squaredNorm() / k : 0.0;
	return r;
}

inline FrictionalResult frictionalStepWithNormal(const FrictionalContact& p, double Fn, const Vec3& n, const Vec3& shearOld, const Vec3& dus)
{
	FrictionalResult r;
	r.normalForce        = Fn * n;
	const CappedSpring s = cappedSpringStep(p.ks, p.tanPhi * Fn, shearOld, dus);
	r.shearForce         = s.value;
	r.sliding            = s.slipping;
	r.frictionWork       = s.dissipated;
	r.elasticEnergy      = (p.kn > 0 ? 0.5 * Fn * Fn / p.kn : 0.0) + s.energy;
	return r;
}

} // namespace flex
