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
Vec3 rotateShear(const Vec3& shear, const Vec3& nNew);

/// A linear spring with a capped magnitude (Coulomb friction, rolling resistance): the trial
/// value old - k increment is scaled back to |value| <= limit. `dissipated` is consistent with
/// the leap-frog energy identity (see Contact.cpp).
struct CappedSpring {
	Vec3   value      = Vec3::Zero(); ///< new force or moment
	double energy     = 0;            ///< stored |value|^2 / (2 k) [J]
	double dissipated = 0;            ///< this step [J]
	bool   slipping   = false;
};
CappedSpring cappedSpringStep(double k, double limit, const Vec3& old, const Vec3& increment);

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
FrictionalResult frictionalStepWithNormal(const FrictionalContact& p, double Fn, const Vec3& n, const Vec3& shearOld, const Vec3& dus);

} // namespace flex
