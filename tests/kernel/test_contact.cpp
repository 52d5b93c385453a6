// yade-flex kernel tests: contact kinematics on segments and the frictional law (GPL-2.0-or-later)
#include "kernel/Contact.hpp"
#include "test_util.hpp"

using namespace flex;
using flex::test::close;

// ---------------------------------------------------------------- kinematics

TEST(SegmentPointVelocity, ExactForRigidMotion)
{
	test::Rng rng(21);
	for (double len : { 1e-3, 1.0, 1e3 }) {
		for (int k = 0; k < 100; ++k) {
			const Vec3   xA = rng.vec(len), xB = xA + len * rng.unit();
			const double u  = k == 0 ? 0.0 : (k == 1 ? 1.0 : (k == 2 ? 0.5 : rng.uniform(0, 1)));
			const Vec3   p  = xA + u * (xB - xA);
			const Vec3   c  = p + rng.vec(len); // any material point carried by the element
			const Vec3   v0 = rng.vec(), W = rng.vec();
			const Vec3   v     = segmentPointVelocity(u, p, c, v0 + W.cross(xA), W, v0 + W.cross(xB), W);
			const Vec3   exact = v0 + W.cross(c);
			EXPECT_TRUE(close(v, exact, 0, 1e-14 * (v0.norm() + W.norm() * (c.norm() + xA.norm() + xB.norm()))));
		}
	}
}

TEST(SegmentPointVelocity, InterpolatesNodes)
{
	const Vec3 xA(0, 0, 0), xB(2, 0, 0), vA(1, 2, 3), vB(-1, 0, 5), wA(0, 0, 1), wB(0, 1, 0);
	// on the axis, at the nodes: the node velocities
	EXPECT_EQ(segmentPointVelocity(0, xA, xA, vA, wA, vB, wB), vA);
	EXPECT_EQ(segmentPointVelocity(1, xB, xB, vA, wA, vB, wB), vB);
	// off axis at the middle: mean velocity + mean spin x offset
	const Vec3 p(1, 0, 0), c(1, 0.5, 0);
	EXPECT_TRUE(close(segmentPointVelocity(0.5, p, c, vA, wA, vB, wB), Vec3(0.5 * (vA + vB) + Vec3(0, 0.5, 0.5).cross(c - p)), 1e-15));
}

TEST(DistributeToSegment, BalanceAndPower)
{
	test::Rng rng(22);
	for (int k = 0; k < 500; ++k) {
		const double len = std::pow(10.0, rng.uniform(-3, 3));
		const Vec3   xA = rng.vec(len), xB = xA + len * rng.unit();
		const double u = k == 0 ? 0.0 : (k == 1 ? 1.0 : rng.uniform(0, 1));
		const Vec3   p = xA + u * (xB - xA);
		const Vec3   c = p + rng.vec(len), F = rng.vec(100.0);
		NodeLoad     A, B;
		distributeToSegment(u, p, c, F, A, B);
		const double Fs = F.norm(), Ms = F.norm() * (c.norm() + xA.norm() + xB.norm());
		EXPECT_TRUE(close(Vec3(A.F + B.F), F, 0, 1e-15 * Fs));
		EXPECT_TRUE(close(Vec3(xA.cross(A.F) + xB.cross(B.F) + A.M + B.M), Vec3(c.cross(F)), 0, 1e-14 * Ms));
		// no power created: F . v(c) = sum F_k . v_k + M_k . w_k, for any nodal velocities
		const Vec3   vA = rng.vec(), vB = rng.vec(), wA = rng.vec(1.0 / len), wB = rng.vec(1.0 / len);
		const double lhs = F.dot(segmentPointVelocity(u, p, c, vA, wA, vB, wB));
		const double rhs = A.F.dot(vA) + A.M.dot(wA) + B.F.dot(vB) + B.M.dot(wB);
		EXPECT_NEAR(lhs, rhs, 1e-13 * Fs * (vA.norm() + vB.norm() + (c - p).norm() * (wA.norm() + wB.norm())));
	}
}

TEST(DistributeToSegment, ExactSplitAtNodesAndMiddle)
{
	const Vec3 F(1, 2, 3);
	NodeLoad   A, B;
	distributeToSegment(0, Vec3::Zero(), Vec3::Zero(), F, A, B); // on node A's axis point
	EXPECT_EQ(A.F, F);
	EXPECT_EQ(B.F, Vec3::Zero());
	EXPECT_EQ(A.M, Vec3::Zero());
	EXPECT_EQ(B.M, Vec3::Zero());
	distributeToSegment(0.5, Vec3(1, 0, 0), Vec3(1, 0, 0.5), Vec3(0, 2, 0), A, B); // surface point above the middle
	EXPECT_EQ(A.F, Vec3(0, 1, 0));
	EXPECT_EQ(B.F, Vec3(0, 1, 0));
	EXPECT_EQ(A.M, Vec3(-0.5, 0, 0)); // half of (0,0,0.5) x (0,2,0) = (-1, 0, 0)
	EXPECT_EQ(B.M, Vec3(-0.5, 0, 0));
}

// ---------------------------------------------------------------- shear carried to a new plane

TEST(RotateShear, KeepsMagnitudeInNewPlane)
{
	test::Rng rng(23);
	for (int k = 0; k < 500; ++k) {
		const Vec3 nOld = rng.unit();
		Vec3       s    = rng.vec(10.0);
		s -= s.dot(nOld) * nOld; // a shear in the old plane
		const Vec3 nNew = (nOld + rng.vec(0.3)).normalized();
		const Vec3 r    = rotateShear(s, nNew);
		EXPECT_TRUE(close(r.norm(), s.norm(), 1e-14));
		EXPECT_NEAR(r.dot(nNew), 0.0, 1e-14 * s.norm());
		EXPECT_GT(r.dot(s), 0.0); // turned, not flipped
		// same plane: unchanged (to round-off)
		EXPECT_TRUE(close(rotateShear(s, nOld), s, 1e-14));
	}
	// a shear along the new normal has no image in the new plane
	EXPECT_EQ(rotateShear(Vec3(0, 0, 3), Vec3(0, 0, 1)), Vec3::Zero());
	EXPECT_EQ(rotateShear(Vec3::Zero(), Vec3(0, 0, 1)), Vec3::Zero());
	// explicit: shear x in plane z, new normal tilted 45 deg towards x
	EXPECT_TRUE(close(rotateShear(Vec3(2, 0, 0), Vec3(1, 0, 1).normalized()), Vec3(Vec3(2, 0, -2) / std::sqrt(2.0)), 1e-15));
}

// ---------------------------------------------------------------- frictional law

namespace {
FrictionalContact law() { return { 1e5, 5e4, 0.5 }; } // kn, ks [N/m], tanPhi
} // namespace

TEST(FrictionalStep, Stick)
{
	const FrictionalContact p = law();
	const Vec3              n(0, 0, 1);
	const double            overlap = 1e-3; // Fn = 100 N, max shear 50 N
	{
		const FrictionalResult r = frictionalStep(p, overlap, n, Vec3::Zero(), Vec3(1e-4, -2e-4, 0));
		EXPECT_FALSE(r.sliding);
		EXPECT_TRUE(close(r.normalForce, Vec3(0, 0, 100), 1e-15));
		EXPECT_TRUE(close(r.shearForce, Vec3(-5, 10, 0), 1e-15)); // -ks dus
		EXPECT_EQ(r.frictionWork, 0.0);
		EXPECT_TRUE(close(r.elasticEnergy, 0.5 * 100 * 100 / 1e5 + 0.5 * 125 / 5e4, 1e-15));
	}
	{ // with a carried shear state: increments add
		const FrictionalResult r = frictionalStep(p, overlap, n, Vec3(20, 0, 0), Vec3(-2e-4, 1e-4, 0));
		EXPECT_FALSE(r.sliding);
		EXPECT_TRUE(close(r.shearForce, Vec3(30, -5, 0), 1e-15));
		EXPECT_TRUE(close(r.elasticEnergy, 0.5 * 100 * 100 / 1e5 + 0.5 * (900 + 25) / 5e4, 1e-15));
	}
}

TEST(FrictionalStep, Slip)
{
	const FrictionalContact p = law();
	const Vec3              n(0, 0, 1);
	const double            overlap = 1e-3, Fn = 100, maxFs = 50;
	test::Rng               rng(24);
	for (int k = 0; k < 100; ++k) {
		Vec3 dus                     = rng.vec(5e-3);
		dus.z()                      = 0;
		const Vec3             old   = Vec3(rng.uniform(-30, 30), rng.uniform(-30, 30), 0);
		const Vec3             trial = old - p.ks * dus;
		const FrictionalResult r     = frictionalStep(p, overlap, n, old, dus);
		if (trial.norm() <= maxFs) {
			EXPECT_FALSE(r.sliding);
			EXPECT_TRUE(close(r.shearForce, trial, 1e-14));
			EXPECT_EQ(r.frictionWork, 0.0);
			continue;
		}
		EXPECT_TRUE(r.sliding);
		EXPECT_TRUE(close(r.shearForce.norm(), p.tanPhi * Fn, 1e-14));             // on the cone
		EXPECT_TRUE(close(r.shearForce, Vec3(trial.normalized() * maxFs), 1e-14)); // along the trial
		// D = (Fs* - Fs_new).(Fs_old + Fs_new)/(2 ks), the trapezoid work minus the stored change
		const double D = 0.5 * (trial - r.shearForce).dot(old + r.shearForce) / p.ks;
		EXPECT_TRUE(close(r.frictionWork, D, 1e-13));
		const double W = -0.5 * (old + r.shearForce).dot(dus), dE = 0.5 * (r.shearForce.squaredNorm() - old.squaredNorm()) / p.ks;
		EXPECT_TRUE(close(r.frictionWork, W - dE, 1e-12, 1e-18));
		EXPECT_TRUE(close(r.elasticEnergy, 0.5 * Fn * Fn / p.kn + 0.5 * maxFs * maxFs / p.ks, 1e-14));
	}
	// one explicit case: from 0, trial 80 N along -x, capped at 50 N: D = 30 * 50 / (2 ks)
	const FrictionalResult r = frictionalStep(p, overlap, n, Vec3::Zero(), Vec3(80.0 / 5e4, 0, 0));
	EXPECT_TRUE(r.sliding);
	EXPECT_TRUE(close(r.shearForce, Vec3(-50, 0, 0), 1e-15));
	EXPECT_TRUE(close(r.frictionWork, 0.5 * 30.0 * 50.0 / 5e4, 1e-15));
	// the cone shrinks (normal force halves) with no tangential motion: the released elastic
	// energy is dissipated, (50^2 - 25^2)/(2 ks)
	const FrictionalResult u = frictionalStep(p, 0.5e-3, n, Vec3(-50, 0, 0), Vec3::Zero());
	EXPECT_TRUE(close(u.shearForce, Vec3(-25, 0, 0), 1e-15));
	EXPECT_TRUE(close(u.frictionWork, 0.5 * (2500.0 - 625.0) / 5e4, 1e-15));
	// frictionless: no shear at all, no dissipation
	const FrictionalResult z = frictionalStep({ 1e5, 5e4, 0 }, overlap, n, Vec3::Zero(), Vec3(1e-4, 0, 0));
	EXPECT_EQ(z.shearForce, Vec3::Zero());
	EXPECT_EQ(z.frictionWork, 0.0);
}

TEST(FrictionalStep, EnergyBalanceOverLoadingPath)
{
	// monotonic tangential displacement with constant normal force: the work of the shear force
	// on the contact equals the stored shear energy plus the friction dissipation.
	const FrictionalContact p = law();
	const Vec3              n(0, 0, 1);
	const double            overlap = 1e-3, Fn = 100;
	Vec3                    shear = Vec3::Zero();
	const Vec3              dus(1e-5, 0.5e-5, 0);
	double                  work = 0, dissipated = 0, stored = 0;
	for (int i = 0; i < 1000; ++i) {
		const Vec3             before = shear;
		const FrictionalResult r      = frictionalStep(p, overlap, n, shear, dus);
		shear                         = r.shearForce;
		// work done on body 2 by the external agent against -shear: trapezoid exact for linear stick steps,
		// and the sliding steps are at constant |shear|
		work -= 0.5 * (before + shear).dot(dus);
		dissipated += r.frictionWork;
		stored = r.elasticEnergy - 0.5 * Fn * Fn / p.kn;
		if (r.sliding && before.norm() >= p.tanPhi * Fn * (1 - 1e-12)) {
			EXPECT_TRUE(close(r.frictionWork, shear.norm() * dus.norm(), 1e-9));
		}
	}
	EXPECT_TRUE(close(shear.norm(), p.tanPhi * Fn, 1e-14));
	// exact at the step where sliding starts: energy work = stored + dissipated (to the trapezoid
	// error of that single step, which is below (ks |dus|)^2 / ks)
	EXPECT_NEAR(work, stored + dissipated, 2 * p.ks * dus.squaredNorm());
}
