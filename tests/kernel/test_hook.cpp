// yade-flex kernel tests: the stop of a hooked knot (GPL-2.0-or-later)
#include "kernel/Hook.hpp"
#include "test_util.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

using namespace flex;
using flex::test::close;

namespace {
Vec3 randomVec(std::mt19937& g, double s)
{
	std::uniform_real_distribution<double> u(-s, s);
	return Vec3(u(g), u(g), u(g));
}
// A knot as yadeflex.mesh builds it: bend i's apex d right of bend j's and d below it, its legs
// going off to the left to a and b (x across the spirals, y along them)
const double d = 0.003, a = 0.0415, h = 0.0715;
const Vec3   xi(0.5 * d, 0, -0.5 * d), xj(-0.5 * d, 0, 0.5 * d), xa(-a, -h, 0), xb(-a, h, 0);
} // namespace

TEST(Hook, FreeAtAndBeyondTheRestGap)
{
	// n = +x here up to the legs' tilt: g is 3 mm; at that gap and beyond it the stop does nothing
	const double g = (xi - xj).dot((xi - 0.5 * (xa + xb)).normalized());
	for (double c : { g, 0.5 * g, -0.01 }) {
		const HookForces f = hookForces(xi, xj, xa, xb, c, 1e8);
		EXPECT_EQ(f.force, 0);
		EXPECT_EQ(f.energy, 0);
		EXPECT_EQ(f.Fi, Vec3::Zero());
		EXPECT_EQ(f.Fa, Vec3::Zero());
	}
	// r = (d, 0, -d), m = (a + d/2, 0, -d/2): g = d (a + d) / |m|, a little over d
	EXPECT_TRUE(close(g, d * (a + d) / std::hypot(a + 0.5 * d, 0.5 * d), 1e-12));
}

TEST(Hook, PushesBackAlongTheBendsOpening)
{
	// bend i moved 1 mm towards -x, into the stop: f = k (c - g) and F_j = -f n with n the
	// direction from its legs' midpoint to its apex
	const double     k = 2e8, c = d;
	const Vec3       yi = xi - Vec3(0.001, 0, 0);
	const HookForces f  = hookForces(yi, xj, xa, xb, c, k);
	const Vec3       n  = (yi - 0.5 * (xa + xb)).normalized();
	EXPECT_TRUE(close(f.force, k * (c - (yi - xj).dot(n)), 1e-12));
	EXPECT_TRUE(close(f.Fj, -f.force * n, 1e-12));
	EXPECT_TRUE(close(f.energy, 0.5 * f.force * f.force / k, 1e-12));
}

TEST(Hook, LetsGoOfAStraightenedBend)
{
	// the apex within one link length of its legs' midline: no force however deep, released with
	// the energy the stop held there
	const Vec3       flat_i(-a + 0.002, 0, 0);
	const HookForces f = hookForces(flat_i, xj, xa, xb, 1.0, 1e8);
	EXPECT_EQ(f.force, 0);
	EXPECT_EQ(f.energy, 0);
	EXPECT_TRUE(f.released);
	const double g = (flat_i - xj).dot(Vec3::UnitX());
	EXPECT_TRUE(close(f.releasedEnergy, 0.5 * 1e8 * (1.0 - g) * (1.0 - g), 1e-12));
	EXPECT_FALSE(hookForces(xi, xj, xa, xb, 1.0, 1e8).released);
}

TEST(Hook, ForcesAndMomentsBalanceAboutAnyPoint)
{
	std::mt19937 g(7);
	for (int trial = 0; trial < 200; ++trial) {
		const Vec3       yi = xi + randomVec(g, 0.002), yj = xj + randomVec(g, 0.002), ya = xa + randomVec(g, 0.01), yb = xb + randomVec(g, 0.01);
		const Vec3       o = randomVec(g, 5);
		const HookForces f = hookForces(yi, yj, ya, yb, 0.01, 1e5); // c = 10 mm: always active
		ASSERT_GT(f.force, 0);
		EXPECT_LT((f.Fi + f.Fj + 2 * f.Fa).norm(), 1e-12 * f.force);
		const Vec3 moment = (yi - o).cross(f.Fi) + (yj - o).cross(f.Fj) + (ya - o).cross(f.Fa) + (yb - o).cross(f.Fa);
		EXPECT_LT(moment.norm(), 1e-11 * f.force * 5);
	}
}

TEST(Hook, ForcesAreTheGradientOfTheEnergy)
{
	// central differences of V in the positions of all four nodes
	std::mt19937 g(11);
	const double k = 3e6, eps = 1e-8;
	for (int trial = 0; trial < 100; ++trial) {
		const Vec3       yi = xi + randomVec(g, 0.002), yj = xj + randomVec(g, 0.002), ya = xa + randomVec(g, 0.01), yb = xb + randomVec(g, 0.01);
		const double     c    = (yi - yj).dot((yi - 0.5 * (ya + yb)).normalized()) + 0.001; // 1 mm into the stop
		const HookForces f    = hookForces(yi, yj, ya, yb, c, k);
		const Vec3       F[4] = { f.Fi, f.Fj, f.Fa, f.Fa };
		for (int node = 0; node < 4; ++node)
			for (int dim = 0; dim < 3; ++dim) {
				Vec3 p[4] = { yi, yj, ya, yb }, q[4] = { yi, yj, ya, yb };
				p[node][dim] += eps;
				q[node][dim] -= eps;
				const double dV
				        = (hookForces(p[0], p[1], p[2], p[3], c, k).energy - hookForces(q[0], q[1], q[2], q[3], c, k).energy) / (2 * eps);
				EXPECT_NEAR(-dV, F[node][dim], 1e-5 * f.force) << "node " << node << " dim " << dim;
			}
	}
}

TEST(Hook, Omega2BoundsTheLargestEigenfrequency)
{
	// K = k (grad g)(grad g)^T on the 12 coordinates, equal masses m: its largest eigenvalue over
	// m, from Eigen, against the bound
	std::mt19937 g(3);
	const double k = 3e8, m = 4e-4;
	for (int trial = 0; trial < 20; ++trial) {
		const Vec3       yi = xi + randomVec(g, 0.002), yj = xj + randomVec(g, 0.002), ya = xa + randomVec(g, 0.01), yb = xb + randomVec(g, 0.01);
		const HookForces f = hookForces(yi, yj, ya, yb, 1.0, 1.0); // f = 1 - g: its forces / f are grad g
		Eigen::Matrix<double, 12, 1> J;
		J << f.Fi / f.force, f.Fj / f.force, f.Fa / f.force, f.Fa / f.force;
		Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> es(k / m * J * J.transpose(), Eigen::EigenvaluesOnly);
		const double                                                 w2 = es.eigenvalues().maxCoeff();
		EXPECT_TRUE(close(w2, k / m * J.squaredNorm(), 1e-10));
		EXPECT_LE(w2, hookMaxOmega2(k, m));
		EXPECT_GE(w2, 2 * k / m * (1 - 1e-12)); // the bound is not loose by more than its t terms
	}
	// the bound's own case: |m| = |r| with r across n (|t| = 1): reached
	const Vec3                   ai(0, 0, 0), aj(0, 0, -0.004), aa(-0.004, -0.01, 0), ab(-0.004, 0.01, 0); // m = (0.004, 0, 0), r = (0, 0, 0.004)
	const HookForces             f = hookForces(ai, aj, aa, ab, 1.0, 1.0);
	Eigen::Matrix<double, 12, 1> J;
	J << f.Fi / f.force, f.Fj / f.force, f.Fa / f.force, f.Fa / f.force;
	EXPECT_FALSE(f.released);
	EXPECT_TRUE(close(k / m * J.squaredNorm(), hookMaxOmega2(k, m), 1e-12));
}
