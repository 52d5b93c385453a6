// Constant-strain-triangle membrane (GPL-2.0-or-later). See Membrane.hpp.
#include "Membrane.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace flex {

MembraneRest makeMembraneRest(const Vec3& x1, const Vec3& x2, const Vec3& x3)
{
	MembraneRest r;
	const Vec3   a = x2 - x1, b = x3 - x1;
	const double la = a.norm();
	const Vec3   N  = a.cross(b);
	if (!(la > 0) || !(N.norm() > 1e-12 * la * b.norm())) return r;
	const Vec3      e1 = a / la, e2 = N.normalized().cross(e1);
	Eigen::Matrix2d Dm;
	Dm << la, b.dot(e1), 0, b.dot(e2);
	r.A0    = 0.5 * la * b.dot(e2);
	r.DmInv = Dm.inverse();
	return r;
}

namespace {
	// eigenvalues (l1 >= l2) and the unit eigenvector of l1 of a symmetric 2x2 matrix
	inline void eig2(const Eigen::Matrix2d& A, double& l1, double& l2, Eigen::Vector2d& v1)
	{
		const double m = 0.5 * (A(0, 0) + A(1, 1)), h = 0.5 * (A(0, 0) - A(1, 1));
		const double r = std::sqrt(h * h + A(0, 1) * A(0, 1));
		l1             = m + r;
		l2             = m - r;
		const double t = 0.5 * std::atan2(A(0, 1), h);
		v1             = Eigen::Vector2d(std::cos(t), std::sin(t));
	}
} // namespace

MembraneResult membraneForces(const Vec3 x[3], const MembraneRest& rest, const MembraneLaw& law)
{
	MembraneResult              res;
	Eigen::Matrix<double, 3, 2> Ds;
	Ds.col(0)                           = x[1] - x[0];
	Ds.col(1)                           = x[2] - x[0];
	const Eigen::Matrix<double, 3, 2> F = Ds * rest.DmInv;
	const Eigen::Matrix2d             C = F.transpose() * F;
	const Eigen::Matrix2d             E = 0.5 * (C - Eigen::Matrix2d::Identity());
	Eigen::Vector2d                   v1;
	eig2(E, res.e1, res.e2, v1);
	Eigen::Matrix2d S;
	double          W;
	if (law.tensionOnly && res.e1 <= 0) {
		S.setZero();
		W = 0;
	} else if (law.tensionOnly && res.e2 < -law.nu * res.e1) {
		S = law.Et * res.e1 * v1 * v1.transpose();
		W = 0.5 * law.Et * res.e1 * res.e1;
	} else {
		const double k = law.Et / (1 - law.nu * law.nu);
		S              = k * ((1 - law.nu) * E + law.nu * E.trace() * Eigen::Matrix2d::Identity());
		W              = 0.5 * (S.cwiseProduct(E)).sum();
	}
	const Eigen::Matrix<double, 3, 2> H = -rest.A0 * F * S * rest.DmInv.transpose();
	res.f[1]                            = H.col(0);
	res.f[2]                            = H.col(1);
	res.f[0]                            = -(res.f[1] + res.f[2]);
	res.energy                          = rest.A0 * W;
	// Principal membrane forces per unit REST width (nominal, first Piola-Kirchhoff P = F S): S
	// is coaxial with E for this isotropic law, so along E's principal directions v_i the force
	// per rest width is lambda_i s_i, lambda_i = sqrt(1 + 2 e_i), s_i = v_i^T S v_i. It is what a
	// strip tensile test reports (force over the strip's initial width), and it stays finite when
	// the fabric folds: the Cauchy force per CURRENT width, lambda_1 s_1 / lambda_2, grows without
	// bound as the folded width lambda_2 goes to zero although the fabric carries no more load.
	const Eigen::Vector2d v2(-v1[1], v1[0]);
	const double          s1 = v1.dot(S * v1), s2 = v2.dot(S * v2);
	res.n1                   = std::sqrt(std::max(0.0, 1 + 2 * res.e1)) * s1;
	res.n2                   = std::sqrt(std::max(0.0, 1 + 2 * res.e2)) * s2;
	if (res.n2 > res.n1) std::swap(res.n1, res.n2);
	res.rupture                = res.n1 >= law.strength;
	return res;
}

double membraneMaxOmega2(const MembraneRest& rest, const MembraneLaw& law, double nodeMass)
{
	if (!(rest.A0 > 0) || !(nodeMass > 0)) return 0;
	// gradients of the shape functions in the rest frame: g2, g3 = rows of Dm^-1, g1 = -(g2 + g3)
	const Eigen::Vector2d g[3]    = { -(rest.DmInv.row(0) + rest.DmInv.row(1)).transpose(), rest.DmInv.row(0).transpose(), rest.DmInv.row(1).transpose() };
	Eigen::Matrix<double, 3, 6> B = Eigen::Matrix<double, 3, 6>::Zero();
	for (int a = 0; a < 3; ++a) {
		B(0, 2 * a)     = g[a][0];
		B(1, 2 * a + 1) = g[a][1];
		B(2, 2 * a)     = g[a][1];
		B(2, 2 * a + 1) = g[a][0];
	}
	const double    k = law.Et / (1 - law.nu * law.nu);
	Eigen::Matrix3d D;
	D << k, k * law.nu, 0, k * law.nu, k, 0, 0, 0, 0.5 * k * (1 - law.nu);
	const Eigen::Matrix<double, 6, 6> K = rest.A0 * B.transpose() * D * B;
	return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(K, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() / nodeMass;
}

double membraneStretchFactor(double e1, double e2, const MembraneLaw& law)
{
	if (!(law.Et > 0)) return 1;
	const double k = law.Et / (1 - law.nu * law.nu);
	double       s1; // larger principal value of S, the same branches as membraneForces
	if (law.tensionOnly && e1 <= 0)
		s1 = 0;
	else if (law.tensionOnly && e2 < -law.nu * e1)
		s1 = law.Et * e1;
	else
		s1 = k * (e1 + law.nu * e2);
	return std::max(1.0, 1 + 2 * e1 + std::max(0.0, s1) / (k * (1 - law.nu)));
}

} // namespace flex
