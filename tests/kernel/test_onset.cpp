// yade-flex kernel tests: the normal spring of a contact with an element, its onset and the
// piercing wire (GPL-2.0-or-later)
#include "kernel/Onset.hpp"

#include <gtest/gtest.h>

using namespace flex;

TEST(Onset, TakesOverThePredecessorsEnergyAndNoMore)
{
	const double k = 1e6, d = 3e-3, taken = 1e3; // the predecessor's spring: 1 mm
	const double off = onsetOffset(k, d, taken);
	EXPECT_DOUBLE_EQ(off, 2e-3);
	const NormalSpring s = normalSpring(k, d, off, false);
	EXPECT_DOUBLE_EQ(s.force, taken);
	EXPECT_DOUBLE_EQ(s.energy, 0.5 * taken * taken / k);
}

TEST(Onset, WithoutAPredecessorItStartsUnloaded)
{
	const double k = 1e6, d = 3e-3;
	const NormalSpring s = normalSpring(k, d, onsetOffset(k, d, 0), false);
	EXPECT_EQ(s.force, 0.0);
	EXPECT_EQ(s.energy, 0.0);
}

TEST(Onset, ShallowerThanItsPredecessorItKeepsItsOverlap)
{
	// (its energy is then below the predecessor's: a hand-over never brings more)
	const double k = 1e6, d = 0.5e-3, taken = 1e3;
	EXPECT_EQ(onsetOffset(k, d, taken), 0.0);
	EXPECT_LT(normalSpring(k, d, 0, false).energy, 0.5 * taken * taken / k);
}

TEST(Onset, TheOffsetNeverExceedsTheOverlap)
{
	EXPECT_EQ(shrinkOffset(3e-3, 1e-3), 1e-3);
	EXPECT_EQ(shrinkOffset(1e-3, 2e-3), 1e-3);
	EXPECT_EQ(shrinkOffset(1e-3, -1e-4), 0.0);
}

TEST(Onset, TheSpringWorksAsItsEnergySays)
{
	// started unloaded at 3 mm, loaded to 5 mm and back to 3 mm, then on to a gap, in equal steps:
	// the trapezoid work of the force (what the leap-frog scheme does to the bodies) equals the
	// change of the spring's energy at every step where the offset stays, and nothing happens
	// below it
	const double k = 1e6, h = 1e-5;
	double       d = 3e-3, off = onsetOffset(k, d, 0), work = 0;
	NormalSpring s = normalSpring(k, d, off, false);
	auto step = [&](double dn) {
		off                  = shrinkOffset(off, dn);
		const NormalSpring n = normalSpring(k, dn, off, false);
		work += 0.5 * (s.force + n.force) * (dn - d); // work done ON the spring
		d = dn;
		s = n;
	};
	for (int i = 0; i < 200; ++i)
		step(d + h);
	EXPECT_NEAR(work, s.energy, 1e-12 * s.energy);
	EXPECT_NEAR(s.energy, 0.5 * k * 2e-3 * 2e-3, 1e-12);
	for (int i = 0; i < 200; ++i)
		step(d - h);
	EXPECT_NEAR(work, 0.0, 1e-12);
	EXPECT_NEAR(s.energy, 0.0, 1e-15);
	for (int i = 0; i < 400; ++i)
		step(d - h);
	EXPECT_NEAR(work, 0.0, 1e-12);
	EXPECT_EQ(off, 0.0);
}

TEST(Onset, APiercingWireHoldsItsEnergyWithoutForce)
{
	const double       k = 1e6, reach = 2.5e-3;
	const NormalSpring p = normalSpring(k, reach, 0.0, true);
	EXPECT_EQ(p.force, 0.0);
	EXPECT_DOUBLE_EQ(p.energy, 0.5 * k * reach * reach);
	EXPECT_DOUBLE_EQ(p.energy, normalSpring(k, reach, 0.0, false).energy); // the same as just before it pierced
}

namespace {
// One body of mass m on linear springs of stiffness k (overlap x - offset), leap-frog as YADE
// steps it (kernel/LeapFrog.hpp), and its shadow energy H = 1/2 m v(n-1/2) v(n+1/2) + U(x_n),
// which the scheme keeps constant while the springs stay linear.
struct Bouncer {
	double k = 1e6, m = 2.0, dt = 1e-5;
	double x = 1e-4, v = 0.5; // overlap [m], approach speed at n-1/2 [m/s]
	double force(const double* off, int n) const
	{
		double f = 0;
		for (int i = 0; i < n; ++i)
			f += normalSpring(k, x, off[i], false).force;
		return f;
	}
	double energy(const double* off, int n) const
	{
		double e = 0;
		for (int i = 0; i < n; ++i)
			e += normalSpring(k, x, off[i], false).energy;
		return e;
	}
	double shadow(const double* off, int n) const
	{
		const double vNext = v - force(off, n) / m * dt;
		return 0.5 * m * v * vNext + energy(off, n);
	}
	void step(const double* off, int n) // forces at x_n, then v(n+1/2), then x_n+1
	{
		v -= force(off, n) / m * dt;
		x += v * dt;
	}
};
} // namespace

TEST(Onset, AHandOverBooksTheWorkItsSuccessorSkips)
{
	// spring A carries the contact, then B takes it over at its own overlap with A's last force
	// (offset): H plus the booked energies (A's released, B's taken over) stays as it was
	Bouncer b;
	double  offA = 0;
	for (int i = 0; i < 5; ++i)
		b.step(&offA, 1);
	const double h0 = b.shadow(&offA, 1), fA = b.force(&offA, 1);
	b.step(&offA, 1); // A's last force moves the body; now A ends and B starts
	double       offB    = onsetOffset(b.k, b.x, fA);
	const double fB      = normalSpring(b.k, b.x, offB, false).force;
	const double booked  = releasedEnergy(fA, b.x - offA) - takenOverEnergy(fB, b.x - offB, b.v, b.dt);
	EXPECT_DOUBLE_EQ(fB, fA);
	EXPECT_GT(booked, 0.0); // approaching: B starts a step behind, the work it skips is lost
	EXPECT_NEAR(b.shadow(&offB, 1) + booked, h0, 1e-12 * h0);
	for (int i = 0; i < 3; ++i) { // and on (B linear while its offset stays)
		b.step(&offB, 1);
		EXPECT_NEAR(b.shadow(&offB, 1) + booked, h0, 1e-12 * h0);
	}
}

TEST(Onset, AMergeBooksTheSpringOfTheContactThatEnds)
{
	// two springs in parallel, one of which ends while overlapping (no successor)
	Bouncer      b;
	const double off[2] = { 0, 0 };
	for (int i = 0; i < 5; ++i)
		b.step(off, 2);
	const double h0 = b.shadow(off, 2), fEnding = normalSpring(b.k, b.x, off[1], false).force, xLast = b.x;
	b.step(off, 2);
	const double booked = releasedEnergy(fEnding, b.x - off[1]);
	EXPECT_NEAR(b.shadow(off, 1) + booked, h0, 1e-12 * h0);
	// its spring's energy, between the last step's and this step's (approaching)
	EXPECT_GT(booked, 0.5 * b.k * xLast * xLast);
	EXPECT_LT(booked, 0.5 * b.k * b.x * b.x);
}
