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
