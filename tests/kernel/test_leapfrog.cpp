// yade-flex kernel tests: the leap-frog update against exact discrete solutions
// (GPL-2.0-or-later).
#include "kernel/LeapFrog.hpp"
#include "test_util.hpp"

#include <cmath>

using namespace flex;

namespace {
struct Body {
	Vec3     pos = Vec3::Zero(), vel = Vec3::Zero(), angVel = Vec3::Zero(), inertia = Vec3::Ones();
	Quat     ori     = Quat::Identity();
	double   mass    = 1;
	unsigned blocked = 0;
	bool     damped  = true;
	BodyDofs dofs() { return BodyDofs { pos, vel, angVel, ori, inertia, mass, blocked, damped }; }
};
LeapFrogSettings settings(double dt, const Vec3& g, double c, bool dampGravity = true) { return LeapFrogSettings { dt, g, c, DampFactors(c), dampGravity }; }
} // namespace

// Free fall, velocity first: v_n = v0 + n g dt, x_n = x0 + n v0 dt + g dt^2 n (n + 1) / 2.
TEST(LeapFrog, FreeFallFollowsTheDiscreteSolution)
{
	Body b;
	b.pos = Vec3(0, 0, 10);
	b.vel = Vec3(1, 0, 2);
	const Vec3 g(0, 0, -9.81);
	const auto s = settings(1e-3, g, 0);
	for (int n = 1; n <= 1000; ++n) {
		BodyDofs d = b.dofs();
		leapFrog(Vec3::Zero(), Vec3::Zero(), d, s);
		const Vec3 x = Vec3(0, 0, 10) + n * 1e-3 * Vec3(1, 0, 2) + g * 1e-6 * n * (n + 1) / 2.0;
		ASSERT_LT((b.pos - x).norm(), 1e-12 * n) << "step " << n;
	}
	EXPECT_NEAR(b.vel[2], 2 - 9.81, 1e-12);
}

// A linear spring x'' = -w^2 x: the leap-frog keeps the shadow energy
// 1/2 v_{n-1/2} v_{n+1/2} + 1/2 w^2 x_n^2 exactly (up to round-off), at any w dt < 2.
TEST(LeapFrog, SpringKeepsTheShadowEnergy)
{
	for (double wdt : { 0.1, 1.0, 1.9 }) {
		const double w = 10, dt = wdt / w;
		Body         b;
		b.pos            = Vec3(1, 0, 0);
		const auto s     = settings(dt, Vec3::Zero(), 0);
		double     vPrev = 0; // v_{-1/2} = 0, x_0 = 1: I = w^2 / 2 at every step
		for (int n = 0; n < 2000; ++n) {
			const double x = b.pos[0];
			BodyDofs     d = b.dofs();
			leapFrog(Vec3(-w * w * x, 0, 0), Vec3::Zero(), d, s);
			const double I = 0.5 * vPrev * b.vel[0] + 0.5 * w * w * x * x;
			ASSERT_NEAR(I, 0.5 * w * w, 1e-10 * w * w) << "w dt " << wdt << " step " << n;
			vPrev = b.vel[0];
		}
	}
}

// Cundall's damping scales a decelerating component by 1 + c and an accelerating one by 1 - c,
// on free DOFs only; gravity undamped when dampGravity is false.
TEST(LeapFrog, DampingScalesEachComponentBySign)
{
	Body b;
	b.vel = Vec3(1, -1, 0);
	// a = (+2, +2, +2): x accelerates (a v > 0), y decelerates, z at rest (v' = a dt/2 > 0: accelerates)
	BodyDofs   d = b.dofs();
	const auto s = settings(1e-3, Vec3::Zero(), 0.2);
	leapFrog(Vec3(2, 2, 2), Vec3::Zero(), d, s);
	EXPECT_DOUBLE_EQ(b.vel[0], 1 + 1e-3 * 2 * 0.8);
	EXPECT_DOUBLE_EQ(b.vel[1], -1 + 1e-3 * 2 * 1.2);
	EXPECT_DOUBLE_EQ(b.vel[2], 1e-3 * 2 * 0.8);
	// damping work: c dt sum |v_i| |F_i| over free DOFs, at the velocities before the update
	Body b2;
	b2.vel      = Vec3(1, -1, 3);
	b2.blocked  = dofBit(2, false);
	BodyDofs d2 = b2.dofs();
	EXPECT_DOUBLE_EQ(dampingWork(Vec3(2, 2, 2), Vec3::Zero(), d2, s), 0.2 * 1e-3 * (2 + 2));
	// gravity outside the damping
	Body       b3;
	BodyDofs   d3 = b3.dofs();
	const auto s3 = settings(1e-3, Vec3(0, 0, -10), 0.5, false);
	leapFrog(Vec3(0, 0, 4), Vec3::Zero(), d3, s3);
	EXPECT_DOUBLE_EQ(b3.vel[2], 1e-3 * (4 * 0.5 - 10));
}

// Blocked DOFs keep their velocity (a driven node moves at its imposed speed).
TEST(LeapFrog, BlockedDofsKeepTheirVelocity)
{
	Body b;
	b.vel      = Vec3(0.5, 0, 0);
	b.angVel   = Vec3(0, 0, 1);
	b.blocked  = kAllDofs;
	BodyDofs d = b.dofs();
	leapFrog(Vec3(100, 100, 100), Vec3(5, 5, 5), d, settings(0.01, Vec3(0, 0, -9.81), 0.3));
	EXPECT_EQ(b.vel, Vec3(0.5, 0, 0));
	EXPECT_EQ(b.angVel, Vec3(0, 0, 1));
	EXPECT_DOUBLE_EQ(b.pos[0], 0.005);
}

// A blocked body driven at speed v into a spring k (fixed far end): the drive's booked work
// (minus its work, gravWork's sign) and the spring's energy at step N sum to the rectangle rule's
// bias, k v^2 dt^2 N / 2 exactly (the force of the step's start over the step's displacement):
// dt / T of the stored energy, so the balance of a driven test closes as dt -> 0. Gravity on
// the blocked DOF is the drive's too: it books m g v dt, the opposite of gravWork's.
TEST(LeapFrog, DriveWorkClosesTheBalanceOfADrivenSpring)
{
	const double k = 1e4, v = 0.3, dt = 1e-4, m = 2;
	const Vec3   g(0, 0, -9.81);
	Body         b;
	b.mass       = m;
	b.vel        = Vec3(0, 0, v);
	b.blocked    = kAllDofs;
	const auto s = settings(dt, g, 0.3);
	double     booked = 0, grav = 0;
	const int  N      = 5000;
	for (int n = 0; n < N; ++n) {
		const Vec3 f(0, 0, -k * b.pos[2]);
		BodyDofs   d = b.dofs();
		booked += driveWork(f, Vec3::Zero(), d, s);
		grav += -g.dot(b.vel) * m * dt;
		leapFrog(f, Vec3::Zero(), d, s);
	}
	const double x = b.pos[2];
	EXPECT_NEAR(x, N * v * dt, 1e-12);
	EXPECT_NEAR(0.5 * k * x * x + booked + grav, 0.5 * k * v * v * dt * dt * N, 1e-9 * 0.5 * k * x * x);
	// a free body or a blocked one at rest: no drive
	Body free;
	free.vel = Vec3(1, 2, 3);
	BodyDofs df = free.dofs();
	EXPECT_EQ(driveWork(Vec3(5, 5, 5), Vec3(1, 1, 1), df, s), 0.0);
	Body held;
	held.blocked = kAllDofs;
	BodyDofs dh  = held.dofs();
	EXPECT_EQ(driveWork(Vec3(5, 5, 5), Vec3(1, 1, 1), dh, s), 0.0);
}

// A constant spin about z turns the orientation by w dt per step, and it stays a unit quaternion.
TEST(LeapFrog, ConstantSpinTurnsByOmegaDtPerStep)
{
	Body b;
	b.angVel     = Vec3(0, 0, 2.0);
	const auto s = settings(1e-2, Vec3::Zero(), 0);
	for (int n = 0; n < 100; ++n) {
		BodyDofs d = b.dofs();
		leapFrog(Vec3::Zero(), Vec3::Zero(), d, s);
	}
	EXPECT_NEAR(Eigen::AngleAxis<double>(b.ori).angle(), 2.0, 1e-12);
	EXPECT_NEAR(b.ori.norm(), 1, 1e-15);
}

// A body that does not turn (a sphere, whose orientation no force depends on) keeps its
// orientation, and every other DOF moves exactly as that of a body that turns.
TEST(LeapFrog, ABodyThatDoesNotTurnMovesAsOneThatDoes)
{
	Body a, b;
	a.angVel = b.angVel = Vec3(0.3, -2.0, 1.5);
	a.vel = b.vel = Vec3(1.0, 0.5, -0.2);
	a.inertia = b.inertia = Vec3(2.0, 2.0, 2.0);
	const Quat q0(Eigen::AngleAxis<double>(0.7, Vec3(1, 2, 3).normalized()));
	a.ori = b.ori = q0;
	const auto s  = settings(1e-3, Vec3(0, 0, -9.81), 0.2);
	for (int n = 0; n < 200; ++n) {
		const Vec3 f(std::sin(0.1 * n), 2.0, -1.0), m(0.5, std::cos(0.2 * n), -0.3);
		BodyDofs   da = a.dofs(), db = b.dofs();
		db.turns = false;
		leapFrog(f, m, da, s);
		leapFrog(f, m, db, s);
	}
	EXPECT_EQ(a.pos, b.pos);
	EXPECT_EQ(a.vel, b.vel);
	EXPECT_EQ(a.angVel, b.angVel);
	EXPECT_EQ(b.ori.coeffs(), q0.coeffs());
	EXPECT_GT(Eigen::AngleAxis<double>(a.ori * q0.inverse()).angle(), 0.1); // the turning one turned
}
