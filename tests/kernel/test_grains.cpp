// yade-flex kernel tests: grains on arrays of their own (GrainNeighbours, GrainContacts)
// (GPL-2.0-or-later). The neighbour list against every pair by brute force; the contact law
// against its closed forms (a spring at rest, Coulomb sliding, rolling's cap), the balance of
// forces and moments, a head-on collision's energy under the leap-frog scheme, and the states
// carried from one list to the next.
#include "kernel/GrainContacts.hpp"
#include "kernel/GrainNeighbours.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace flex;

namespace {
struct Grains {
	std::vector<Vec3>   pos, vel, angVel;
	std::vector<double> radius, invMass;
	GrainMotion         motion() const { return GrainMotion { pos.data(), vel.data(), angVel.data(), radius.data(), invMass.data(), (long)pos.size() }; }
	void                add(const Vec3& x, double r, const Vec3& v = Vec3::Zero(), const Vec3& w = Vec3::Zero(), double invM = 1.0)
	{
		pos.push_back(x);
		vel.push_back(v);
		angVel.push_back(w);
		radius.push_back(r);
		invMass.push_back(invM);
	}
};
// n spheres of radii in [0.03, 0.06] m placed at random in a 0.6 m box, overlapping freely
Grains randomGrains(long n, unsigned seed)
{
	std::mt19937                           gen(seed);
	std::uniform_real_distribution<double> u(0.0, 1.0);
	Grains                                 g;
	for (long i = 0; i < n; ++i)
		g.add(Vec3(0.6 * u(gen), 0.6 * u(gen), 0.6 * u(gen)), 0.03 + 0.03 * u(gen), Vec3(u(gen) - 0.5, u(gen) - 0.5, u(gen) - 0.5),
		        Vec3(u(gen) - 0.5, u(gen) - 0.5, u(gen) - 0.5) * 10, 1 / (1 + u(gen)));
	return g;
}
struct Sums {
	std::vector<Vec3> f, t;
	GrainSums         s;
	explicit Sums(long n)
	        : f(n, Vec3::Zero())
	        , t(n, Vec3::Zero())
	{
		s.force  = f.data();
		s.torque = t.data();
	}
};
GrainLaw law(double tanPhi = 0.5, double rolling = 0)
{
	GrainLaw L;
	L.young            = 1e8;
	L.ksOverKn         = 0.3;
	L.tanPhi           = tanPhi;
	L.rollingStiffness = rolling;
	L.rollingFriction  = rolling > 0 ? 0.1 : 0;
	return L;
}
// Two spheres of radius r overlapping by d along x, sphere 2 spinning at w about z, and their
// contact: frictionless, with rolling resistance (rollingStiffness 1, rollingFriction 0.1)
struct SpinningPair {
	Grains          g;
	GrainNeighbours nb { 0.01 };
	GrainContacts   gc { law(0.0, 1.0) };
	SpinningPair(double r, double d, double w)
	{
		g.add(Vec3(0, 0, 0), r);
		g.add(Vec3(2 * r - d, 0, 0), r, Vec3::Zero(), Vec3(0, 0, w));
		nb.build(g.pos.data(), g.radius.data(), 2);
		gc.follow(nb);
	}
};
} // namespace

TEST(GrainLaw, StiffnessIsIp2sForEqualMaterials)
{
	// Ip2_FrictMat_FrictMat_FrictPhys: kn = 2 E1 r1 E2 r2 / (E1 r1 + E2 r2), ks = the same with
	// E v for E; equal spheres: kn = E r, ks = v E r
	GrainLaw L = law();
	double   kn, ks;
	L.stiffness(0.02, 0.02, kn, ks);
	EXPECT_NEAR(kn, 1e8 * 0.02, 1e-9 * kn);
	EXPECT_NEAR(ks, 0.3 * 1e8 * 0.02, 1e-9 * ks);
	L.stiffness(0.01, 0.03, kn, ks); // 2 E r1 r2 / (r1 + r2)
	EXPECT_NEAR(kn, 2 * 1e8 * 0.01 * 0.03 / 0.04, 1e-9 * kn);
	EXPECT_NEAR(ks / kn, 0.3, 1e-12);
	L.ksOverKn = 0; // 0 / 0 in Ip2's arithmetic: no shear stiffness, not NaN
	L.stiffness(0.01, 0.03, kn, ks);
	EXPECT_EQ(ks, 0.0);
}

TEST(GrainNeighbours, ListsEveryPairWithinReachOnce)
{
	for (unsigned seed : { 1u, 2u, 3u }) {
		const Grains    g    = randomGrains(600, seed);
		const double    skin = 0.016;
		GrainNeighbours nb(skin);
		nb.build(g.pos.data(), g.radius.data(), (long)g.pos.size());
		std::set<std::pair<int, int>> listed;
		for (long i = 0; i < nb.spheres(); ++i)
			for (long k = nb.first()[i]; k < nb.first()[i + 1]; ++k) {
				EXPECT_GT(nb.second()[k], i);
				if (k > nb.first()[i]) EXPECT_GT(nb.second()[k], nb.second()[k - 1]); // ascending
				listed.insert({ (int)i, nb.second()[k] });
			}
		EXPECT_EQ((long)listed.size(), nb.pairs());
		std::set<std::pair<int, int>> all;
		for (int i = 0; i < (int)g.pos.size(); ++i)
			for (int j = i + 1; j < (int)g.pos.size(); ++j) {
				const double reach = g.radius[i] + g.radius[j] + skin;
				if ((g.pos[j] - g.pos[i]).squaredNorm() < reach * reach) all.insert({ i, j });
			}
		EXPECT_EQ(listed, all) << "seed " << seed;
		EXPECT_GT(all.size(), 1000u);
	}
}

// A boulder among grains (radius over kLargeRatio times the median) is paired directly, not by
// cells: the list is still every pair within reach, and the cells stay sized by the grains.
TEST(GrainNeighbours, LargeSpheresArePairedDirectly)
{
	Grains g = randomGrains(500, 5);
	g.add(Vec3(0.3, 0.3, 0.3), 0.25);                       // (its index last)
	g.pos.insert(g.pos.begin() + 100, Vec3(0.1, 0.5, 0.2)); // one in the middle of the indices
	g.radius.insert(g.radius.begin() + 100, 0.3);
	const long      n = (long)g.pos.size();
	GrainNeighbours nb(0.016);
	nb.build(g.pos.data(), g.radius.data(), n);
	std::set<std::pair<int, int>> listed, all;
	for (long i = 0; i < n; ++i)
		for (long k = nb.first()[i]; k < nb.first()[i + 1]; ++k) {
			if (k > nb.first()[i]) EXPECT_GT(nb.second()[k], nb.second()[k - 1]);
			listed.insert({ (int)i, nb.second()[k] });
		}
	for (int i = 0; i < n; ++i)
		for (int j = i + 1; j < n; ++j) {
			const double reach = g.radius[i] + g.radius[j] + 0.016;
			if ((g.pos[j] - g.pos[i]).squaredNorm() < reach * reach) all.insert({ i, j });
		}
	EXPECT_EQ(listed, all);
	long withLarge = 0;
	for (const auto& p : all)
		withLarge += p.first == 100 || p.second == n - 1;
	EXPECT_GT(withLarge, 50);
}

TEST(GrainNeighbours, StaleOnceASphereMovesHalfTheSkin)
{
	Grains          g = randomGrains(50, 4);
	GrainNeighbours nb(0.02);
	EXPECT_TRUE(nb.stale(g.pos.data(), 50));
	nb.build(g.pos.data(), g.radius.data(), 50);
	EXPECT_FALSE(nb.stale(g.pos.data(), 50));
	g.pos[17] += Vec3(0, 0.0099, 0);
	EXPECT_FALSE(nb.stale(g.pos.data(), 50));
	g.pos[17] += Vec3(0, 0.0001, 0);
	EXPECT_TRUE(nb.stale(g.pos.data(), 50));
	EXPECT_TRUE(nb.stale(g.pos.data(), 49));
	EXPECT_THROW(GrainNeighbours(0.0), std::invalid_argument);
}

// Two spheres at rest with overlap d: kn d along the normal, kn = 2 E r1 r2 / (r1 + r2), no
// torque, energy 1/2 kn d^2; the same at every step (the correction leaves a steady contact alone).
TEST(GrainContacts, SpringAtRest)
{
	Grains       g;
	const double r1 = 0.04, r2 = 0.06, d = 1e-4;
	g.add(Vec3(0, 0, 0), r1);
	g.add(Vec3(r1 + r2 - d, 0, 0), r2);
	GrainNeighbours nb(0.01);
	nb.build(g.pos.data(), g.radius.data(), 2);
	GrainContacts gc(law());
	gc.follow(nb);
	const double kn = 2 * 1e8 * r1 * r2 / (r1 + r2);
	for (long it = 0; it < 3; ++it) {
		Sums s(2);
		gc.step(g.motion(), it, 1e-5, s.s);
		EXPECT_NEAR(s.f[1].x(), kn * d, 1e-9 * kn * d);
		EXPECT_NEAR(s.f[1].y(), 0, 1e-12);
		EXPECT_EQ(s.f[0], Vec3(-s.f[1]));
		EXPECT_LT(s.t[0].norm() + s.t[1].norm(), 1e-15);
		EXPECT_NEAR(s.s.elastic, 0.5 * kn * d * d, 1e-9 * kn * d * d);
		EXPECT_EQ(s.s.deepOnsets, it == 0 ? 1 : 0); // (built overlapping: a deep onset)
	}
	EXPECT_EQ(gc.contacts(), 1);
	EXPECT_EQ(gc.active(), 1);
}

// Sphere 2 slides tangentially over sphere 1 at speed v (angular velocities zero): the shear
// grows by ks v dt per step up to tanPhi kn d, then stays there and dissipates tanPhi kn d v dt
// per step (the friction work of steady sliding).
TEST(GrainContacts, CoulombSliding)
{
	Grains       g;
	const double r = 0.05, d = 2e-4, v = 1.0, dt = 1e-5, tanPhi = 0.5;
	g.add(Vec3(0, 0, 0), r);
	g.add(Vec3(2 * r - d, 0, 0), r, Vec3(0, v, 0));
	GrainNeighbours nb(0.01);
	nb.build(g.pos.data(), g.radius.data(), 2);
	GrainContacts gc(law(tanPhi));
	gc.follow(nb);
	const double kn = 1e8 * r, ks = 0.3 * kn, cap = tanPhi * kn * d;
	long         it = 0;
	for (; it < 200; ++it) {
		Sums s(2);
		gc.step(g.motion(), it, dt, s.s);
		const double shear = std::abs(s.f[1].y());
		if (it < 10) EXPECT_NEAR(shear, std::min(cap, ks * v * dt * (it + 1)), 1e-9 * cap) << it;
		if (it > 150) {
			EXPECT_NEAR(shear, cap, 1e-9 * cap);
			EXPECT_NEAR(s.s.friction, cap * v * dt, 1e-6 * cap * v * dt);
		}
		EXPECT_LT(s.f[1].y(), 0); // against the motion
	}
	EXPECT_GT(cap / (ks * v * dt), 10); // (sliding sets in during the run)
	EXPECT_LT(cap / (ks * v * dt), 150);
}

// Sphere 2 turns about an axis in the contact plane: the rolling moment grows by kr w dt and is
// capped at eta R |Fn|, R = r1 r2 / (r1 + r2), kr = rollingStiffness ks R^2.
TEST(GrainContacts, RollingMomentIsCapped)
{
	const double r = 0.05, d = 2e-4, w = 2.0, dt = 1e-5;
	SpinningPair   p(r, d, w);
	Grains&        g  = p.g;
	GrainContacts& gc = p.gc;
	const double kn = 1e8 * r, ks = 0.3 * kn, R = 0.5 * r, kr = ks * R * R, cap = 0.1 * R * kn * d;
	double       last = 0;
	for (long it = 0; it < 3000; ++it) {
		Sums s(2);
		gc.step(g.motion(), it, dt, s.s);
		last = gc.states()[0].roll.norm();
		if (it == 0) EXPECT_NEAR(last, kr * w * dt, 1e-9 * kr * w * dt);
		EXPECT_LE(last, cap * (1 + 1e-12));
	}
	EXPECT_NEAR(last, cap, 1e-9 * cap);
	EXPECT_LT(cap / (kr * w * dt), 3000);
}

// A contact that separates for one step and touches again starts with no rolling moment, as
// with no shear: the spring's energy was booked as released when it separated, and the spring
// must not come back with it. Sphere 2 spins against sphere 1 (the moment builds up), is lifted
// off for one step (the state is kept that step for the onset and release correction) and put
// back at rest: the moment is then zero, and the stored energy is the normal spring's only.
TEST(GrainContacts, ARollingSpringEndsWithItsContact)
{
	const double   r = 0.05, d = 2e-4, w = 2.0, dt = 1e-5;
	SpinningPair   p(r, d, w);
	Grains&        g  = p.g;
	GrainContacts& gc = p.gc;
	const double   kn = 1e8 * r, ks = 0.3 * kn, R = 0.5 * r, kr = ks * R * R;
	long           it = 0;
	for (; it < 20; ++it) {
		Sums s(2);
		gc.step(g.motion(), it, dt, s.s);
	}
	const double built = gc.states()[0].roll.norm();
	EXPECT_NEAR(built, 20 * kr * w * dt, 1e-9 * built); // (below the cap: elastic all along)
	// lifted off for one step: the spring's energy leaves as released (rolling)
	g.pos[1]    = Vec3(2 * r + d, 0, 0);
	g.angVel[1] = Vec3::Zero();
	{
		Sums s(2);
		gc.step(g.motion(), it++, dt, s.s);
		EXPECT_NEAR(s.s.rolling, 0.5 * built * built / kr, 1e-12 * built * built / kr);
		EXPECT_TRUE(gc.states()[0].exists); // (kept this step)
	}
	// back in contact, at rest
	g.pos[1] = Vec3(2 * r - d, 0, 0);
	Sums s(2);
	gc.step(g.motion(), it++, dt, s.s);
	EXPECT_EQ(gc.states()[0].roll, Vec3::Zero());
	EXPECT_EQ(s.t[1], -s.t[0]);
	EXPECT_NEAR(s.t[1].norm(), 0, 1e-15);
	EXPECT_NEAR(s.s.elastic, 0.5 * kn * d * d, 1e-9 * 0.5 * kn * d * d);
}

// On a random overlapping set with random motion: the forces sum to zero and so do the moments
// about the origin (x x F + T), to round-off; every contact is a listed pair that overlaps.
TEST(GrainContacts, ForcesAndMomentsBalance)
{
	Grains          g = randomGrains(800, 7);
	GrainNeighbours nb(0.016);
	nb.build(g.pos.data(), g.radius.data(), (long)g.pos.size());
	GrainContacts gc(law(0.5, 1.0));
	gc.follow(nb);
	for (long it = 0; it < 3; ++it) {
		Sums s((long)g.pos.size());
		gc.step(g.motion(), it, 1e-5, s.s);
		Vec3   F = Vec3::Zero(), M = Vec3::Zero();
		double scale = 0;
		for (size_t i = 0; i < g.pos.size(); ++i) {
			F += s.f[i];
			M += g.pos[i].cross(s.f[i]) + s.t[i];
			scale += s.f[i].norm();
		}
		EXPECT_GT(gc.active(), 500);
		EXPECT_LT(F.norm(), 1e-12 * scale);
		EXPECT_LT(M.norm(), 1e-12 * scale);
	}
}

// Two frictionless spheres meeting head on, integrated by the leap-frog scheme: the kinetic
// energy after the collision is the energy before to round-off (the onset and release
// correction, Crossing.hpp), and the momentum is kept; without the correction the error is
// of the order of (omega dt)^2.
TEST(GrainContacts, HeadOnCollisionKeepsItsEnergy)
{
	for (bool crossing : { true, false }) {
		Grains       g;
		const double r = 0.05, m1 = 2.0, m2 = 3.0, v = 1.0;
		g.add(Vec3(0, 0, 0), r, Vec3(v, 0, 0), Vec3::Zero(), 1 / m1);
		g.add(Vec3(2 * r + 0.003, 0, 0), r, Vec3(-v, 0, 0), Vec3::Zero(), 1 / m2);
		GrainLaw L = law(0.0);
		L.crossing = crossing;
		GrainContacts   gc(L);
		GrainNeighbours nb(0.02);
		const double    kn = 1e8 * r, omega = std::sqrt(kn * (1 / m1 + 1 / m2)), dt = 0.7 / omega;
		const double    E0 = 0.5 * (m1 + m2) * v * v, P0 = m1 * v - m2 * v;
		long            touched = 0;
		for (long it = 0; it < 400; ++it) {
			if (nb.stale(g.pos.data(), 2)) {
				nb.build(g.pos.data(), g.radius.data(), 2);
				EXPECT_EQ(gc.follow(nb), 0);
			}
			Sums s(2);
			gc.step(g.motion(), it, dt, s.s);
			touched += gc.active() > 0 && gc.states()[0].lastActive == it;
			for (int i = 0; i < 2; ++i) {
				g.vel[i] += s.f[i] * g.invMass[i] * dt;
				g.pos[i] += g.vel[i] * dt;
			}
		}
		EXPECT_GT(touched, 3);
		EXPECT_EQ(gc.contacts(), 0); // (apart, the correction done)
		const double E = 0.5 * (m1 * g.vel[0].squaredNorm() + m2 * g.vel[1].squaredNorm()), P = m1 * g.vel[0].x() + m2 * g.vel[1].x();
		EXPECT_LT(g.vel[0].x(), 0); // bounced
		EXPECT_NEAR(P, P0, 1e-12);
		if (crossing)
			EXPECT_NEAR(E, E0, 1e-10 * E0);
		else
			EXPECT_GT(std::abs(E - E0), 1e-3 * E0);
	}
}

// A list built again (the spheres moved less than half the skin) carries every contact's state:
// the run gives the same forces, bit for bit, as the run on the first list.
TEST(GrainContacts, StatesFollowANewList)
{
	Grains          g = randomGrains(400, 9), h = g;
	GrainNeighbours nb1(0.016), nb2(0.016);
	nb1.build(g.pos.data(), g.radius.data(), (long)g.pos.size());
	nb2.build(g.pos.data(), g.radius.data(), (long)g.pos.size());
	GrainContacts a(law(0.5, 1.0)), b(law(0.5, 1.0));
	a.follow(nb1);
	b.follow(nb2);
	for (long it = 0; it < 6; ++it) {
		if (it == 3) { // move everyone a little (less than half the skin), rebuild b's list only
			std::mt19937                           gen(11);
			std::uniform_real_distribution<double> u(-0.004, 0.004);
			for (size_t i = 0; i < g.pos.size(); ++i) {
				g.pos[i] += Vec3(u(gen), u(gen), u(gen));
				h.pos[i] = g.pos[i];
			}
			EXPECT_FALSE(nb1.stale(g.pos.data(), (long)g.pos.size()));
			nb2.build(h.pos.data(), h.radius.data(), (long)h.pos.size());
			EXPECT_EQ(b.follow(nb2), 0);
		}
		Sums sa((long)g.pos.size()), sb((long)g.pos.size());
		a.step(g.motion(), it, 1e-5, sa.s);
		b.step(h.motion(), it, 1e-5, sb.s);
		EXPECT_EQ(sa.f, sb.f);
		EXPECT_EQ(sa.t, sb.t);
		EXPECT_EQ(sa.s.elastic, sb.s.elastic);
	}
	EXPECT_NE(nb1.second(), nb2.second()); // (the lists differ)
	EXPECT_EQ(a.contacts(), b.contacts());
	EXPECT_GT(a.contacts(), 100);
}

TEST(GrainContacts, RefusesBadSettings)
{
	GrainLaw L = law();
	L.young    = 0;
	EXPECT_THROW(GrainContacts { L }, std::invalid_argument);
	L        = law();
	L.tanPhi = NAN;
	EXPECT_THROW(GrainContacts { L }, std::invalid_argument);
	GrainContacts   gc(law());
	GrainNeighbours nb(0.01);
	Grains          g = randomGrains(5, 1);
	nb.build(g.pos.data(), g.radius.data(), 5);
	gc.follow(nb);
	Grains h = randomGrains(6, 1);
	Sums   s(6);
	EXPECT_THROW(gc.step(h.motion(), 0, 1e-5, s.s), std::invalid_argument);
}

// Parts of the spheres run one after the other, each with sums of its own, give every sphere
// the forces of the whole step (up to the order of the sums); the parts hold about equal
// numbers of pairs.
TEST(GrainContacts, PartsMakeTheWholeStep)
{
	const Grains    g = randomGrains(600, 13);
	const long      n = (long)g.pos.size();
	GrainNeighbours nb(0.016);
	nb.build(g.pos.data(), g.radius.data(), n);
	GrainContacts whole(law(0.5, 1.0)), parts(law(0.5, 1.0));
	whole.follow(nb);
	parts.follow(nb);
	for (long it = 0; it < 4; ++it) {
		Sums w(n);
		whole.step(g.motion(), it, 1e-5, w.s);
		Sums  p0(n), p1(n), p2(n);
		Sums* ps[3] = { &p0, &p1, &p2 };
		for (int k = 0; k < 3; ++k)
			parts.step(g.motion(), it, 1e-5, ps[k]->s, parts.splitAt(k, 3), parts.splitAt(k + 1, 3));
		double scale = 0;
		for (long i = 0; i < n; ++i)
			scale = std::max(scale, w.f[i].norm());
		for (long i = 0; i < n; ++i) {
			EXPECT_LT((p0.f[i] + p1.f[i] + p2.f[i] - w.f[i]).norm(), 1e-13 * scale) << i;
			EXPECT_LT((p0.t[i] + p1.t[i] + p2.t[i] - w.t[i]).norm(), 1e-13 * scale) << i;
		}
		EXPECT_NEAR(p0.s.elastic + p1.s.elastic + p2.s.elastic, w.s.elastic, 1e-12 * w.s.elastic);
	}
	for (int k = 0; k < 3; ++k) {
		const long pairs = nb.first()[parts.splitAt(k + 1, 3)] - nb.first()[parts.splitAt(k, 3)];
		EXPECT_NEAR((double)pairs, nb.pairs() / 3.0, 0.05 * nb.pairs()) << k;
	}
	EXPECT_EQ(parts.splitAt(0, 3), 0);
	EXPECT_EQ(parts.splitAt(3, 3), n);
	Sums s(n);
	EXPECT_THROW(parts.step(g.motion(), 4, 1e-5, s.s, 5, 2), std::invalid_argument);
}

// A list restarted empty and its states put back pair by pair with at() (what an adapter does
// when the spheres change) steps exactly as the list that kept them; the pass counts the
// touching contacts and names the deepest one; reach() is skin / 2 less the distance moved.
TEST(GrainContacts, StatesPutBackByPairStepTheSame)
{
	Grains          g = randomGrains(300, 4);
	const long      n = (long)g.pos.size();
	GrainNeighbours nb(0.016);
	nb.build(g.pos.data(), g.radius.data(), n);
	GrainContacts a(law(0.5, 1.0)), b(law(0.5, 1.0));
	a.follow(nb);
	for (long it = 0; it < 3; ++it) {
		Sums s(n);
		a.step(g.motion(), it, 1e-5, s.s);
	}
	b.restart(nb);
	EXPECT_EQ(b.contacts(), 0);
	long put = 0;
	for (long i = 0; i < n; ++i)
		for (long k = a.first()[i]; k < a.first()[i + 1]; ++k)
			if (a.states()[k].exists) {
				GrainContacts::State* s = b.at(i, a.second()[k]);
				ASSERT_NE(s, nullptr);
				*s = a.states()[k];
				++put;
			}
	EXPECT_GT(put, 50);
	EXPECT_EQ(b.at(0, 0), nullptr); // (a sphere is not its own partner)
	EXPECT_EQ(b.at(n, 1), nullptr); // (no such sphere)
	EXPECT_EQ(b.contacts(), a.contacts());
	Sums sa(n), sb(n);
	a.step(g.motion(), 3, 1e-5, sa.s);
	b.step(g.motion(), 3, 1e-5, sb.s);
	EXPECT_EQ(sa.f, sb.f);
	EXPECT_EQ(sa.t, sb.t);
	EXPECT_EQ(sa.s.elastic, sb.s.elastic);
	// the touching contacts and the deepest: brute force over the pairs
	long   touching = 0;
	double deepest  = 0;
	long   di = -1, dj = -1;
	for (long i = 0; i < n; ++i)
		for (long j = i + 1; j < n; ++j) {
			const double ratio = (g.radius[i] + g.radius[j] - (g.pos[j] - g.pos[i]).norm()) / (g.radius[i] + g.radius[j]);
			if (ratio <= 0) continue;
			++touching;
			if (ratio > deepest) {
				deepest = ratio;
				di      = i;
				dj      = j;
			}
		}
	EXPECT_EQ(sa.s.touching, touching);
	EXPECT_EQ(sa.s.maxOverlapRatio, deepest);
	EXPECT_EQ(sa.s.maxOverlapI, di);
	EXPECT_EQ(sa.s.maxOverlapJ, dj);
	std::vector<Vec3> moved = g.pos;
	moved[7] += Vec3(0.003, 0.004, 0);
	EXPECT_NEAR(nb.reach(moved.data(), 7), 0.008 - 0.005, 1e-15);
	EXPECT_EQ(nb.reach(moved.data(), 8), 0.008);
}
