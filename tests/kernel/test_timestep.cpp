// yade-flex kernel tests: element eigenfrequency and critical time step (GPL-2.0-or-later)
#include "kernel/TimeStep.hpp"
#include "test_util.hpp"

#include <Eigen/Eigenvalues>
#include <limits>

using namespace flex;
using flex::test::close;

TEST(TimeStep, AxialElementTwoMassesOneSpring)
{
	// EI = GJ = 0: only the axial spring k = EA/L between masses; omega^2 = k (1/mi + 1/mj)
	const double L = 0.7, k = 3e4, m = 0.2;
	const BeamSection s{ k * L, 0, 0 };
	EXPECT_TRUE(close(beamMaxOmega2(s, L, m, m, 1e-3, 1e-3), 2 * k / m, 1e-13));
	EXPECT_TRUE(close(beamMaxOmega2(s, L, 0.2, 0.6, 1e-3, 2e-3), k * (1 / 0.2 + 1 / 0.6), 1e-13));
	// with weak bending and torsion the axial mode stays the highest and almost unchanged
	const BeamSection w{ k * L, 1e-9, 1e-9 };
	EXPECT_TRUE(close(beamMaxOmega2(w, L, m, m, 1e-3, 1e-3), 2 * k / m, 1e-9));
}

TEST(TimeStep, TorsionElement)
{
	// twist alone: two inertias I joined by GJ/L, omega^2 = 2 GJ / (L I)
	const double L = 0.5, GJ = 4.0, I = 1e-4;
	EXPECT_TRUE(close(beamMaxOmega2(BeamSection{ 0, 0, GJ }, L, 1.0, 1.0, I, I), 2 * GJ / (L * I), 1e-13));
}

TEST(TimeStep, FullElementEqualsGeneralizedEigenproblem)
{
	// a steel wire segment with its own lumped shares: compare with K v = w^2 M v solved directly
	const double      rho = 7850, r = 0.002, L = 0.05;
	const BeamSection s   = BeamSection::circular(2.1e11, 8.1e10, r);
	const NodeShare   sh  = cylinderNodeShare(rho, r, L);
	const double      w2  = beamMaxOmega2(s, L, sh.mass, sh.mass, sh.inertia, sh.inertia);
	Eigen::Matrix<double, 12, 12> M = Eigen::Matrix<double, 12, 12>::Zero();
	for (int i = 0; i < 12; ++i) M(i, i) = (i % 6) < 3 ? sh.mass : sh.inertia;
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
	const double dtc = criticalTimeStep(beamMaxOmega2(BeamSection{ k * L, 0, 0 }, L, m, m, 1, 1));
	auto maxAmplitude = [&](double dt) {
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
