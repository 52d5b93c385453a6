// yade-flex kernel tests: the stop of a hooked knot (GPL-2.0-or-later)
#include "kernel/Hook.hpp"
#include "test_util.hpp"

#include <Eigen/Eigenvalues>
#include <random>

using namespace flex;
using flex::test::close;

namespace {
Quat randomQuat(std::mt19937& g)
{
	std::normal_distribution<double> n;
	Quat                             q(n(g), n(g), n(g), n(g));
	q.normalize();
	return q;
}
Vec3 randomVec(std::mt19937& g, double s)
{
	std::uniform_real_distribution<double> u(-s, s);
	return Vec3(u(g), u(g), u(g));
}
} // namespace

TEST(Hook, FreeAtAndBeyondTheRestGap)
{
	const Vec3 a(1, 0, 0);
	// g = (xi - xj) . n = 3 mm: at the rest gap and beyond it the stop does nothing
	for (double c : { 0.003, 0.002, -0.01 }) {
		const HookForces h = hookForces(Vec3(0.003, 0, -0.003), Vec3::Zero(), Quat::Identity(), a, c, 1e8);
		EXPECT_EQ(h.force, 0);
		EXPECT_EQ(h.energy, 0);
		EXPECT_EQ(h.Fi, Vec3::Zero());
		EXPECT_EQ(h.Mi, Vec3::Zero());
	}
}

TEST(Hook, PushesBackAlongTheAxisOfNodeI)
{
	// node i's frame turned 90 degrees about z: its local x is global y
	const Quat       q(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
	const double     k = 2e8, c = 0.003;
	const HookForces h = hookForces(Vec3(0.5, 0.001, 0.2), Vec3(0.5, 0, 0), q, Vec3::UnitX(), c, k);
	EXPECT_TRUE(close(h.force, k * 0.002, 1e-12));
	EXPECT_LT((h.Fi - h.force * Vec3::UnitY()).norm(), 1e-9 * h.force);
	EXPECT_TRUE(close(h.energy, 0.5 * k * 0.002 * 0.002, 1e-12));
}

TEST(Hook, ForcesAndMomentBalanceAboutAnyPoint)
{
	std::mt19937 g(7);
	for (int t = 0; t < 200; ++t) {
		const Vec3       xi = randomVec(g, 1), xj = randomVec(g, 1), o = randomVec(g, 5);
		const Quat       q = randomQuat(g);
		const Vec3       a = randomVec(g, 1).normalized();
		const HookForces h = hookForces(xi, xj, q, a, 2.0, 1e5); // c = 2 > |xi - xj|: always active
		ASSERT_GT(h.force, 0);
		// node j carries -Fi and no moment
		const Vec3 moment = (xi - o).cross(h.Fi) + (xj - o).cross(-h.Fi) + h.Mi;
		EXPECT_LT(moment.norm(), 1e-12 * h.force * 4);
	}
}

TEST(Hook, ForcesAreTheGradientOfTheEnergy)
{
	// central differences of V in the positions of both nodes and the rotation of node i
	std::mt19937 g(11);
	const double k = 3e6, eps = 1e-7;
	for (int t = 0; t < 100; ++t) {
		const Vec3       xi = randomVec(g, 0.01), xj = randomVec(g, 0.01);
		const Quat       q = randomQuat(g);
		const Vec3       a = randomVec(g, 1).normalized();
		const double     c = (xi - xj).dot(q * a) + 0.004; // active, 4 mm into the stop
		const HookForces h = hookForces(xi, xj, q, a, c, k);
		for (int d = 0; d < 3; ++d) {
			const Vec3   e  = Vec3::Unit(d) * eps;
			const double di = (hookForces(xi + e, xj, q, a, c, k).energy - hookForces(xi - e, xj, q, a, c, k).energy) / (2 * eps);
			const double dj = (hookForces(xi, xj + e, q, a, c, k).energy - hookForces(xi, xj - e, q, a, c, k).energy) / (2 * eps);
			const Quat   qp = Quat(Eigen::AngleAxisd(eps, Vec3::Unit(d))) * q, qm = Quat(Eigen::AngleAxisd(-eps, Vec3::Unit(d))) * q;
			const double dr    = (hookForces(xi, xj, qp, a, c, k).energy - hookForces(xi, xj, qm, a, c, k).energy) / (2 * eps);
			const double scale = h.force * (1 + (xi - xj).norm());
			EXPECT_NEAR(-di, h.Fi[d], 1e-6 * scale);
			EXPECT_NEAR(-dj, -h.Fi[d], 1e-6 * scale);
			EXPECT_NEAR(-dr, h.Mi[d], 1e-6 * scale);
		}
	}
}

TEST(Hook, Omega2IsTheLargestEigenfrequency)
{
	// the stop's stiffness on (xi, xj, rotation of i) is k J^T J with J = [n, -n, n x r]:
	// K v = w^2 M v with lumped masses m, m and inertia I, solved directly
	std::mt19937 g(3);
	for (int t = 0; t < 20; ++t) {
		const Vec3                  n = randomVec(g, 1).normalized(), r = randomVec(g, 0.005);
		const double                k = 3e8, m = 4e-4, I = 2e-10;
		Eigen::Matrix<double, 9, 1> J;
		J << n, -n, n.cross(r);
		const Eigen::Matrix<double, 9, 9> K = k * J * J.transpose();
		Eigen::Matrix<double, 9, 9>       M = Eigen::Matrix<double, 9, 9>::Zero();
		for (int i = 0; i < 9; ++i)
			M(i, i) = i < 6 ? m : I;
		Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(K, M, Eigen::EigenvaluesOnly);
		EXPECT_TRUE(close(hookMaxOmega2(k, n.cross(r).norm(), m, I), es.eigenvalues().maxCoeff(), 1e-10));
	}
}
