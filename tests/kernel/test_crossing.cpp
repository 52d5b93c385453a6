// yade-flex kernel tests: the energy-consistent onset and release of a penalty contact
// (GPL-2.0-or-later). A mass dropped under gravity onto a one-sided linear spring and bouncing
// on it, integrated by the leap-frog scheme; the energy H = 1/2 m v- v+ + U(x) is compared in
// flight (no overlap at either end of the step) with its value at the start.
#include "kernel/Crossing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace flex;

namespace {
struct Bounce {
	double worst  = 0; // largest |H - H0| in flight, over the drop energy
	long   events = 0; // contacts made
	long   steps  = 0; // steps with a correction applied
	long   samples = 0; // steps in flight at which the energy was compared
};
// Mass 1, stiffness 1 (omega 1), gravity g 1: the static overlap is 1. Drop from h (in static
// overlaps) above the spring; x is the overlap (negative: gap), v its rate. The contact exists
// from its first step with x > 0 until crossingDone after it has separated, as in the plugin.
Bounce bounce(double wdt, double h, bool correct, double periods = 300)
{
	const double k = 1, m = 1, g = 1, dt = wdt;
	double       x = -h, vh = 0;
	const auto   U = [&](double y) { return -m * g * y + crossingSpringEnergy(k, y); };
	bool         alive = false;
	CrossingState st;
	Bounce        b;
	double        H0 = NAN, xprev = x, Fprev = 0;
	const long    n = (long)(periods * 2 * M_PI / wdt);
	for (long i = 0; i < n; ++i) {
		double F = -k * std::max(x, 0.0);
		if (correct && !alive && x > 0) {
			alive = true;
			st    = crossingStart(k, x, vh, dt);
		}
		if (x > 0 && xprev <= 0) ++b.events;
		if (alive) {
			const double c = crossingStep(st, k, x, vh, dt, [&] { return 1 / m; });
			b.steps += c != 0;
			F -= c;
			if (x <= 0 && crossingDone(st)) alive = false;
		}
		const double vn = vh + (F / m + g) * dt;
		const double H  = 0.5 * m * vh * vn + U(x);
		if (std::isnan(H0)) H0 = H;
		if (x < 0 && xprev < 0 && F == 0 && Fprev == 0) {
			b.worst = std::max(b.worst, std::abs(H - H0) / (m * g * h));
			++b.samples;
		}
		Fprev = F;
		vh    = vn;
		xprev = x;
		x += vh * dt;
	}
	return b;
}
} // namespace

// Without the correction a bounce gains or loses up to (omega dt)^2 / 4 of its energy: at the
// default step (omega dt up to 1) a tenth of the drop energy or more within 300 periods. With it,
// a lone contact is exact up to round-off: the energy in flight after every bounce is the energy
// of the drop, at every step and height (from a tenth of the static overlap, a body chattering on
// its contact, where a flight lasts long enough to be seen, to a thousand, a bounce of many
// periods).
TEST(Crossing, BouncesKeepTheirEnergy)
{
	EXPECT_GT(bounce(1.0, 10.0, false).worst, 0.1);
	EXPECT_GT(bounce(0.7, 1000.0, false).worst, 0.1);
	EXPECT_GT(bounce(0.5, 1.0, false).worst, 0.05);
	for (double wdt : { 1.0, 0.7, 0.5, 0.2 })
		for (double h : { 0.1, 1.0, 10.0, 1000.0 }) {
			if (h < 1 && wdt > 0.5) continue; // (flights shorter than two steps: never seen)
			const Bounce b = bounce(wdt, h, true);
			EXPECT_LT(b.worst, 1e-12) << "omega dt " << wdt << ", drop " << h;
			EXPECT_GE(b.events, 20) << "omega dt " << wdt << ", drop " << h;
			EXPECT_GE(b.samples, 10) << "omega dt " << wdt << ", drop " << h;
		}
}

// A contact that never leaves its spring (a body resting on it, oscillating less than its static
// overlap) has nothing to correct: the trapezoid is exact for a linear spring.
TEST(Crossing, SteadyContactIsLeftAlone)
{
	const double  k = 2e6, dt = 1e-5, m = 0.5, g = 9.81;
	double        x = 1.5 * m * g / k, vh = 0;
	CrossingState st = crossingStart(k, x, vh, dt);
	st.prevForce     = k * st.prevDepth; // (resting: no onset)
	for (int i = 0; i < 20000; ++i) {
		const double c = crossingStep(st, k, x, vh, dt, [&] { return 1 / m; });
		ASSERT_EQ(c, 0.0) << "step " << i;
		vh += (-k * x / m + g) * dt;
		x += vh * dt;
		ASSERT_GT(x, 0);
	}
	EXPECT_EQ(st.defect, 0.0);
}

// The first step of a contact that starts from a gap: the defect is the trapezoid's error
// 1/2 k d0 d1 (d0 < 0 < d1), and the extra force cancels it over the two steps it acts in when
// the prediction is exact (a lone contact, no other force).
TEST(Crossing, OnsetDefectIsTheTrapezoidError)
{
	const double  k = 3.0, dt = 0.4, m = 2.0, v = 0.7, d1 = 0.1;
	CrossingState st = crossingStart(k, d1, v, dt);
	EXPECT_DOUBLE_EQ(st.prevDepth, d1 - v * dt);
	EXPECT_EQ(st.prevForce, 0.0);
	const double c  = crossingStep(st, k, d1, v, dt, [&] { return 1 / m; });
	const double S0 = 0.5 * k * (d1 - v * dt) * d1;
	// the next overlap with the corrected force, and the defect left after that step
	const double vnext = v - (k * d1 + c) / m * dt;
	const double d2    = d1 + vnext * dt;
	EXPECT_LT(c, 0); // energy lost on entry: less push
	EXPECT_NEAR(S0 - 0.5 * c * (d2 - (d1 - v * dt)), 0.0, 1e-15);
	crossingStep(st, k, d2, vnext, dt, [&] { return 1 / m; });
	EXPECT_NEAR(st.defect, 0.0, 1e-15);
}

TEST(Crossing, ForceIsCappedAtATurningPoint)
{
	EXPECT_EQ(crossingForce(1.0, 2.0, 0.0, 0.1), 0.0);
	EXPECT_DOUBLE_EQ(crossingForce(1.0, 2.0, 1e-3, 0.0), 2.0 * 1e-3);
	EXPECT_DOUBLE_EQ(crossingForce(1e-9, 2.0, 1e-3, 0.0), 2e-9 / 1e-3);
	EXPECT_EQ(crossingForce(NAN, 2.0, 1.0, 0.0), 0.0);
}
