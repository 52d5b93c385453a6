// yade-flex kernel tests: element eigenfrequency and critical time step (GPL-2.0-or-later)
#include "kernel/TimeStep.hpp"
#include "test_util.hpp"

#include <Eigen/Eigenvalues>
#include <limits>
#include <random>

using namespace flex;
using flex::test::close;

TEST(TimeStep, AxialElementTwoMassesOneSpring)
{
	// EI = GJ = 0: only the axial spring k = EA/L between masses; omega^2 = k (1/mi + 1/mj)
	const double      L = 0.7, k = 3e4, m = 0.2;
	const BeamSection s { k * L, 0, 0 };
	EXPECT_TRUE(close(beamMaxOmega2(s, L, m, m, 1e-3, 1e-3), 2 * k / m, 1e-13));
	EXPECT_TRUE(close(beamMaxOmega2(s, L, 0.2, 0.6, 1e-3, 2e-3), k * (1 / 0.2 + 1 / 0.6), 1e-13));
	// with weak bending and torsion the axial mode stays the highest and almost unchanged
	const BeamSection w { k * L, 1e-9, 1e-9 };
	EXPECT_TRUE(close(beamMaxOmega2(w, L, m, m, 1e-3, 1e-3), 2 * k / m, 1e-9));
}

TEST(TimeStep, TorsionElement)
{
	// twist alone: two inertias I joined by GJ/L, omega^2 = 2 GJ / (L I)
	const double L = 0.5, GJ = 4.0, I = 1e-4;
	EXPECT_TRUE(close(beamMaxOmega2(BeamSection { 0, 0, GJ }, L, 1.0, 1.0, I, I), 2 * GJ / (L * I), 1e-13));
}

TEST(TimeStep, FullElementEqualsGeneralizedEigenproblem)
{
	// a steel wire segment with its own lumped shares: compare with K v = w^2 M v solved directly
	const double                  rho = 7850, r = 0.002, L = 0.05;
	const BeamSection             s  = BeamSection::circular(2.1e11, 8.1e10, r);
	const NodeShare               sh = cylinderNodeShare(rho, r, L);
	const double                  w2 = beamMaxOmega2(s, L, sh.mass, sh.mass, sh.inertia, sh.inertia);
	Eigen::Matrix<double, 12, 12> M  = Eigen::Matrix<double, 12, 12>::Zero();
	for (int i = 0; i < 12; ++i)
		M(i, i) = (i % 6) < 3 ? sh.mass : sh.inertia;
	Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> es(beamStiffnessLocal(s, L), M, Eigen::EigenvaluesOnly);
	EXPECT_TRUE(close(w2, es.eigenvalues().maxCoeff(), 1e-12));
	// and it bounds the axial mode from above
	EXPECT_GE(w2, 2 * s.EA / L / sh.mass * (1 - 1e-14));
}

TEST(TimeStep, CriticalTimeStep)
{
	EXPECT_DOUBLE_EQ(criticalTimeStep(4.0), 1.0);
	EXPECT_TRUE(close(criticalTimeStep(2.5e7), 2 / std::sqrt(2.5e7), 1e-15));
	EXPECT_EQ(criticalTimeStep(0.0), std::numeric_limits<double>::infinity());
	EXPECT_EQ(criticalTimeStep(-1.0), std::numeric_limits<double>::infinity());
}

TEST(TimeStep, LeapFrogStabilityLimitIsSharp)
{
	// two masses and a spring integrated by central differences: bounded just below the
	// critical step, growing just above it
	const double L = 0.7, k = 3e4, m = 0.2;
	const double dtc          = criticalTimeStep(beamMaxOmega2(BeamSection { k * L, 0, 0 }, L, m, m, 1, 1));
	auto         maxAmplitude = [&](double dt) {
                double x1 = 0, x2 = 1e-3, v1 = 0, v2 = 0, amax = 0; // displacements from rest
                for (int i = 0; i < 2000; ++i) {
                        const double f = k * (x2 - x1); // on mass 1; -f on mass 2
                        v1 += dt * f / m;
                        v2 -= dt * f / m;
                        x1 += dt * v1;
                        x2 += dt * v2;
                        amax = std::max(amax, std::abs(x2 - x1));
                }
                return amax;
	};
	EXPECT_LT(maxAmplitude(0.99 * dtc), 1e-3 * 20); // bounded (amplitude factor 1/sqrt(1 - (w dt/2)^2) ~ 7)
	EXPECT_GT(maxAmplitude(1.01 * dtc), 1.0);       // exponential growth
}

// ---- which potential contacts can start before the next collider run --------------------

namespace {
Vec3 boxCorner(const Vec3& ref, double sweep, int k) { return ref + sweep * Vec3((k & 1) ? 1 : -1, (k & 2) ? 1 : -1, (k & 4) ? 1 : -1); }
// a random point of the primitive spanned by p[0..n) (random barycentric weights)
Vec3 randomPointOf(const Vec3* p, int n, std::mt19937_64& g)
{
	std::uniform_real_distribution<double> u(0, 1);
	double                                 w[3] = { u(g), n > 1 ? u(g) : 0, n > 2 ? u(g) : 0 }, s = w[0] + w[1] + w[2];
	if (g() % 4 == 0) { // edges and corners too
		for (int a = 0; a < n; ++a)
			w[a] = 0;
		w[g() % n] = s = 1;
	}
	Vec3 x = Vec3::Zero();
	for (int a = 0; a < n; ++a)
		x += w[a] / s * p[a];
	return x;
}
} // namespace

TEST(TimeStep, ReachableDistanceIsTheFarthestCornerOfTheSweepBox)
{
	std::mt19937_64                        g(21);
	std::uniform_real_distribution<double> u(-1, 1);
	for (int k = 0; k < 1000; ++k) {
		const Vec3   ref = 10 * Vec3(u(g), u(g), u(g)), x = ref + 0.3 * Vec3(u(g), u(g), u(g));
		const double s   = 0.5 * (1 + u(g));
		double       far = 0;
		for (int c = 0; c < 8; ++c)
			far = std::max(far, (boxCorner(ref, s, c) - x).norm());
		EXPECT_TRUE(close(reachableDistance(x, ref, s), far, 1e-14));
	}
	EXPECT_EQ(reachableDistance(Vec3(1, 2, 3), Vec3(1, 2, 3), 0), 0);
}

TEST(TimeStep, PrimitiveGapIsTheDistanceOfTheClosestPoints)
{
	// never above the distance of any two points of the primitives (it would let a contact
	// through), and attained: the smallest sampled distance comes down to it
	std::mt19937_64                        g(22);
	std::uniform_real_distribution<double> u(-1, 1);
	for (int k = 0; k < 3000; ++k) {
		const int na = 1 + (int)(g() % 3), nb = 1 + (int)(g() % 3);
		Vec3      a[3], b[3];
		for (int i = 0; i < 3; ++i) {
			a[i] = Vec3(u(g), u(g), u(g));
			b[i] = Vec3(u(g), u(g), u(g)) + Vec3(1.5, 0, 0);
		}
		const double ra = 0.01 * (1 + u(g)), rb = 0.02 * (1 + u(g));
		const double gap = primitiveGap(a, na, ra, b, nb, rb);
		if (na == 3 && nb == 3) {
			EXPECT_EQ(gap, -std::numeric_limits<double>::infinity());
			continue;
		}
		EXPECT_NEAR(gap, primitiveGap(b, nb, rb, a, na, ra), 1e-14) << "symmetric up to round-off";
		double dmin = std::numeric_limits<double>::infinity();
		for (int s = 0; s < 400; ++s) {
			const double d = (randomPointOf(a, na, g) - randomPointOf(b, nb, g)).norm() - ra - rb;
			ASSERT_GE(d, gap - 1e-13) << "pair " << k;
			dmin = std::min(dmin, d);
		}
		if (na == 1 && nb == 1) EXPECT_TRUE(close(dmin, gap, 1e-13));
	}
}

TEST(TimeStep, PairsCalledUnableToTouchStayApartWhereverTheSweepLetsThemGo)
{
	// each defining point may go anywhere in its sweep box; the adversary pushes every point of
	// both primitives towards the other (box corners) and at random. A pair called "cannot
	// touch" must keep a positive gap in all these configurations; and the rule does call most
	// well-separated pairs apart (it is not vacuous)
	std::mt19937_64                        g(23);
	std::uniform_real_distribution<double> u(-1, 1), lg(-9, -1);
	int                                    called = 0, n = 20000;
	for (int k = 0; k < n; ++k) {
		const int    na = 1 + (int)(g() % 2), nb = 1 + (int)(g() % 3); // (triangle-triangle excluded)
		Vec3         a[3], b[3], refA[3], refB[3];
		const double sweep = 0.05 * (1 + u(g)), sep = 0.2 + 0.3 * u(g);
		for (int i = 0; i < 3; ++i) {
			refA[i] = 0.3 * Vec3(u(g), u(g), u(g));
			refB[i] = 0.3 * Vec3(u(g), u(g), u(g)) + Vec3(sep + 0.6, 0, 0);
			a[i]    = refA[i] + sweep * Vec3(u(g), u(g), u(g)); // now: somewhere in the box
			b[i]    = refB[i] + sweep * Vec3(u(g), u(g), u(g));
		}
		const double ra = 0.01, rb = 0.02;
		double       reachA = 0, reachB = 0;
		for (int i = 0; i < na; ++i)
			reachA = std::max(reachA, reachableDistance(a[i], refA[i], sweep));
		for (int i = 0; i < nb; ++i)
			reachB = std::max(reachB, reachableDistance(b[i], refB[i], sweep));
		const double gap = primitiveGap(a, na, ra, b, nb, rb);
		if (!cannotTouch(gap, reachA, reachB, 1.0)) continue;
		++called;
		for (int trial = 0; trial < 30; ++trial) {
			Vec3 a2[3], b2[3];
			for (int i = 0; i < 3; ++i) {
				a2[i] = trial < 8 ? boxCorner(refA[i], sweep, trial) : refA[i] + sweep * Vec3(u(g), u(g), u(g));
				b2[i] = trial < 8 ? boxCorner(refB[i], sweep, 7 - trial) : refB[i] + sweep * Vec3(u(g), u(g), u(g));
			}
			ASSERT_GT(primitiveGap(a2, na, ra, b2, nb, rb), 0) << "pair " << k << " trial " << trial;
		}
	}
	EXPECT_GT(called, n / 10);
}

TEST(TimeStep, CannotTouchKeepsAMarginForRoundOff)
{
	EXPECT_FALSE(cannotTouch(0.3, 0.1, 0.2, 1.0));               // equal: may touch
	EXPECT_FALSE(cannotTouch(0.3 * (1 + 1e-12), 0.1, 0.2, 1.0)); // within round-off of equal
	EXPECT_TRUE(cannotTouch(0.3 * (1 + 1e-6), 0.1, 0.2, 1.0));
	EXPECT_FALSE(cannotTouch(-0.1, 0, 0, 1.0)); // overlapping
	EXPECT_FALSE(cannotTouch(std::numeric_limits<double>::quiet_NaN(), 0, 0, 1.0));
	EXPECT_FALSE(cannotTouch(-std::numeric_limits<double>::infinity(), 0, 0, 1.0));
}

TEST(TimeStep, AMovingBodyNeverKeepsAZeroSweep)
{
	const double minSweep = 0.1 * 8e-3; // YADE's minSweepDistFactor x verletDist
	// a grain that did not move between two bound updates: YADE gives it 0, which any round-off
	// motion of its centre leaves (the collider's trigger: d != 0 and d >= sweep)
	EXPECT_EQ(flooredSweep(0.0, true, minSweep), minSweep);
	EXPECT_LT(3.5e-18, flooredSweep(0.0, true, minSweep)); // round-off stays inside the floored one
	EXPECT_EQ(flooredSweep(0.0, false, minSweep), 0.0);                  // a wall or a fixed facet
	EXPECT_EQ(flooredSweep(2.5e-3, true, minSweep), 2.5e-3);             // YADE's own sweeps stay
	EXPECT_EQ(flooredSweep(minSweep, true, minSweep), minSweep);
	EXPECT_EQ(flooredSweep(0.0, true, 0.0), 0.0);                        // no verlet distance: no sweep
}
