// yade-flex kernel tests: the point-load failure load and the normal spring that yields at it
// (GPL-2.0-or-later)
#include "kernel/Crushing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace flex;

TEST(PointLoadFailure, IsTheIndexTimesTheSizeSquaredWithIsrmSizeCorrection)
{
	EXPECT_DOUBLE_EQ(pointLoadFailure(0.05, 4e6), 4e6 * 0.05 * 0.05); // the reference size: no correction
	EXPECT_NEAR(pointLoadFailure(0.1, 4e6) / pointLoadFailure(0.05, 4e6), std::pow(2.0, 1.55), 1e-14);
	const double d = 0.032; // Is = P / d^2, Is50 = (d / 50 mm)^0.45 Is
	EXPECT_NEAR(std::pow(d / 0.05, 0.45) * pointLoadFailure(d, 1.5e6) / (d * d), 1.5e6, 1.5e6 * 1e-14);
}

TEST(YieldingNormalStep, ElasticBelowTheLimit)
{
	const NormalYield r = yieldingNormalStep(1e6, 100.0, 5e-5, 0.0, 20.0);
	EXPECT_DOUBLE_EQ(r.force, 50.0);
	EXPECT_EQ(r.plastic, 0.0);
	EXPECT_EQ(r.dissipated, 0.0);
	EXPECT_FALSE(r.yielding);
}

TEST(YieldingNormalStep, CapsTheForceAndMovesThePlasticOverlap)
{
	const double      kn = 1e6, limit = 100.0;
	const NormalYield r = yieldingNormalStep(kn, limit, 3e-4, 0.0, 90.0);
	EXPECT_EQ(r.force, limit);
	EXPECT_TRUE(r.yielding);
	EXPECT_NEAR(r.plastic, 3e-4 - limit / kn, 1e-18);
	EXPECT_NEAR(r.dissipated, 0.5 * (90.0 + limit) * (3e-4 - limit / kn), 1e-15);
	// unloading from there is elastic with the full stiffness, and ends at the plastic overlap
	const NormalYield u = yieldingNormalStep(kn, limit, 2.5e-4, r.plastic, r.force);
	EXPECT_NEAR(u.force, kn * (2.5e-4 - r.plastic), 1e-9);
	EXPECT_EQ(u.plastic, r.plastic);
	EXPECT_EQ(u.dissipated, 0.0);
	const NormalYield off = yieldingNormalStep(kn, limit, 0.5 * r.plastic, r.plastic, u.force);
	EXPECT_EQ(off.force, 0.0); // no tension
	EXPECT_EQ(off.plastic, r.plastic);
}

// Over a load-unload-reload path the trapezoid work of each step is the change of the stored
// energy plus the dissipation, to round-off, wherever the force follows kn (overlap - plastic);
// over the whole path the dissipation is the limit times the final plastic overlap plus the
// first yielding step's trapezoid correction.
TEST(YieldingNormalStep, WorkSplitsIntoStoredEnergyAndDissipation)
{
	const double        kn = 2e6, limit = 150.0;
	std::vector<double> path;
	for (int k = 0; k <= 60; ++k)
		path.push_back(4e-6 * k); // load past the limit (75 um)
	for (int k = 1; k <= 20; ++k)
		path.push_back(path[60] - 2e-6 * k); // unload elastically
	for (int k = 1; k <= 40; ++k)
		path.push_back(path[80] + 3e-6 * k); // reload past the limit
	double f = 0, p = 0, work = 0, dissipated = 0;
	for (size_t k = 1; k < path.size(); ++k) {
		const NormalYield r    = yieldingNormalStep(kn, limit, path[k], p, f);
		const double      step = 0.5 * (f + r.force) * (path[k] - path[k - 1]);
		const double      dE   = 0.5 * (r.force * r.force - f * f) / kn;
		EXPECT_NEAR(step, dE + r.dissipated, 1e-12 * limit * 1e-4) << "step " << k;
		work += step;
		dissipated += r.dissipated;
		f = r.force;
		p = r.plastic;
	}
	EXPECT_NEAR(work, 0.5 * f * f / kn + dissipated, 1e-12);
	EXPECT_EQ(f, limit);
	// the dissipation is the limit's work on the plastic overlap, short by the two steps in which
	// the force reached the limit from below (the trapezoid of those steps)
	EXPECT_GT(dissipated, 0.0);
	EXPECT_LE(dissipated, limit * p);
	EXPECT_GT(dissipated, limit * p - limit * 2 * 4e-6);
}

// Unloading past the plastic overlap (the grains part inside the crushed zone) and back: no force
// and no change of the plastic overlap while the overlap is below it; the trapezoid work of a
// step in which the force reaches or leaves zero differs from the stored energy's change by at
// most half the force times the step's overlap increment (as a plain linear contact's first and
// last steps), and by round-off in every other step.
TEST(YieldingNormalStep, PartsInsideTheCrushedZoneAndReloads)
{
	const double        kn = 1e6, limit = 50.0, h = 5e-6;
	std::vector<double> path;
	for (int k = 0; k <= 30; ++k)
		path.push_back(h * k); // load to 150 um, yield past 50 um
	for (int k = 1; k <= 30; ++k)
		path.push_back(path[30] - h * k); // unload to 0, through the plastic overlap
	for (int k = 1; k <= 30; ++k)
		path.push_back(path[60] + h * k); // reload to 150 um
	double f = 0, p = 0;
	int    zeroSteps = 0, edges = 0;
	for (size_t k = 1; k < path.size(); ++k) {
		const NormalYield r    = yieldingNormalStep(kn, limit, path[k], p, f);
		const double      step = 0.5 * (f + r.force) * (path[k] - path[k - 1]);
		const double      dE   = 0.5 * (r.force * r.force - f * f) / kn;
		if (path[k] < p) {
			EXPECT_EQ(r.force, 0.0) << "step " << k;
			EXPECT_EQ(r.plastic, p) << "step " << k;
			++zeroSteps;
		}
		const bool edge = (f > 0) != (r.force > 0);
		edges += edge;
		EXPECT_NEAR(step, dE + r.dissipated, edge ? 0.5 * std::max(f, r.force) * h : 1e-12 * limit * h) << "step " << k;
		f = r.force;
		p = r.plastic;
	}
	EXPECT_NEAR(p, 150e-6 - limit / kn, 1e-18); // the second loading yields from where the first left off
	EXPECT_GT(zeroSteps, 0);
	EXPECT_EQ(edges, 3); // the force leaves 0, returns to 0 and leaves it again
}
