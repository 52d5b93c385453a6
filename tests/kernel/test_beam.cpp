// yade-flex kernel tests: co-rotational beam and axial law (GPL-2.0-or-later)
#include "kernel/Beam.hpp"
#include "test_util.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

using namespace flex;
using flex::test::close;
using flex::test::rotvec;

namespace {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

BeamSection testSection() { return { 100.0, 2.0, 1.5 }; } // EA [N], EI, GJ [N m^2]: moderate ratios

struct Config {
	Vec3 xi, xj;
	Quat oi, oj;
};

BeamForces forcesOf(const Config& c, const BeamRest& rest, const BeamSection& s, const AxialLaw& law = {})
{
	AxialState st;
	return beamForces(beamKinematics(c.xi, c.xj, c.oi, c.oj, rest), rest, s, law, st);
}

Vec12 stack(const BeamForces& f)
{
	Vec12 v;
	v << f.Fi, f.Mi, f.Fj, f.Mj;
	return v;
}

// element along x from the origin, identity orientations, displaced by the 12 DOF u
// (u_i, theta_i, u_j, theta_j); rotations as rotation vectors applied in the global frame
Config displaced(double L, const Vec12& u) { return { u.segment<3>(0), Vec3(L, 0, 0) + u.segment<3>(6), rotvec(u.segment<3>(3)), rotvec(u.segment<3>(9)) }; }

// a random, moderately deformed configuration of a random reference state
void randomDeformed(test::Rng& rng, Config& ref, Config& cur)
{
	ref.xi = rng.vec();
	ref.xj = ref.xi + rng.uniform(0.5, 2.0) * rng.unit();
	ref.oi = rng.quat();
	ref.oj = rng.quat();
	cur.xi = ref.xi + rng.vec(0.05);
	cur.xj = ref.xj + rng.vec(0.05);
	cur.oi = rotvec(rng.vec(0.2)) * ref.oi;
	cur.oj = rotvec(rng.vec(0.2)) * ref.oj;
}

// rigid motion x -> Q x + c, o -> Q o
Config moved(const Config& c, const Quat& Q, const Vec3& t) { return { Q * c.xi + t, Q * c.xj + t, Q * c.oi, Q * c.oj }; }

} // namespace

// ---------------------------------------------------------------- objectivity

TEST(Beam, RigidTranslationAndRotationGiveNoForce)
{
	const BeamSection s = testSection();
	test::Rng         rng(11);
	const double      Fscale = s.EA + s.EI, Mscale = s.EI + s.GJ, Escale = s.EA + s.EI + s.GJ; // L ~ 1
	for (int k = 0; k < 50; ++k) {
		Config ref;
		ref.xi              = rng.vec(10.0);
		ref.xj              = ref.xi + rng.uniform(0.5, 2.0) * rng.unit();
		ref.oi              = rng.quat();
		ref.oj              = rng.quat();
		const BeamRest rest = makeBeamRest(ref.xi, ref.xj, ref.oi, ref.oj);
		EXPECT_NEAR(rest.L0, (ref.xj - ref.xi).norm(), 1e-15 * 20);
		const Quat Q = k == 0 ? Quat(Eigen::AngleAxisd(1.3, Vec3(1, -2, 0.5).normalized())) : rng.quat();
		const Vec3 t = rng.vec(5.0);
		for (const Config& c : { ref, moved(ref, Quat::Identity(), t), moved(ref, Q, Vec3::Zero()), moved(ref, Q, t) }) {
			const BeamKinematics kin = beamKinematics(c.xi, c.xj, c.oi, c.oj, rest);
			EXPECT_NEAR(kin.thetaI.norm(), 0.0, 1e-9);
			EXPECT_NEAR(kin.thetaJ.norm(), 0.0, 1e-9);
			EXPECT_NEAR(kin.twist, 0.0, 1e-9);
			const BeamForces f = forcesOf(c, rest, s);
			EXPECT_LE(f.Fi.norm(), 1e-9 * Fscale);
			EXPECT_LE(f.Fj.norm(), 1e-9 * Fscale);
			EXPECT_LE(f.Mi.norm(), 1e-9 * Mscale);
			EXPECT_LE(f.Mj.norm(), 1e-9 * Mscale);
			EXPECT_LE(std::abs(f.N), 1e-9 * s.EA);
			EXPECT_LE(f.elasticEnergy, 1e-18 * Escale);
		}
	}
}

TEST(Beam, DeformedStateIsObjective)
{
	// a rigid motion of a deformed state rotates the forces and keeps the energy
	const BeamSection s = testSection();
	test::Rng         rng(12);
	for (int k = 0; k < 50; ++k) {
		Config ref, cur;
		randomDeformed(rng, ref, cur);
		const BeamRest   rest = makeBeamRest(ref.xi, ref.xj, ref.oi, ref.oj);
		const Quat       Q    = k == 0 ? Quat(Eigen::AngleAxisd(1.3, Vec3(0.3, 0.4, -1).normalized())) : rng.quat();
		const BeamForces f = forcesOf(cur, rest, s), g = forcesOf(moved(cur, Q, rng.vec(3.0)), rest, s);
		const double     tol = 1e-9 * stack(f).norm();
		EXPECT_TRUE(close(g.Fi, Vec3(Q * f.Fi), 0, tol));
		EXPECT_TRUE(close(g.Fj, Vec3(Q * f.Fj), 0, tol));
		EXPECT_TRUE(close(g.Mi, Vec3(Q * f.Mi), 0, tol));
		EXPECT_TRUE(close(g.Mj, Vec3(Q * f.Mj), 0, tol));
		EXPECT_TRUE(close(g.elasticEnergy, f.elasticEnergy, 1e-9));
		EXPECT_TRUE(close(g.N, f.N, 1e-9, 1e-12));
	}
}

// ---------------------------------------------------------------- balance

TEST(Beam, ForceAndMomentBalance)
{
	const BeamSection s = testSection();
	test::Rng         rng(13);
	for (int k = 0; k < 200; ++k) {
		Config ref, cur;
		randomDeformed(rng, ref, cur);
		const BeamRest   rest = makeBeamRest(ref.xi, ref.xj, ref.oi, ref.oj);
		const BeamForces f    = forcesOf(cur, rest, s);
		const double     Fmag = f.Fi.norm() + f.Fj.norm(), Mmag = f.Mi.norm() + f.Mj.norm();
		ASSERT_GT(Fmag, 0.0);
		EXPECT_LE((f.Fi + f.Fj).norm(), 1e-15 * Fmag);
		// about the origin and about an arbitrary point (the latter follows from sum F = 0)
		for (const Vec3& o : { Vec3(Vec3::Zero()), rng.vec(10.0) }) {
			const Vec3   Mo = (cur.xi - o).cross(f.Fi) + (cur.xj - o).cross(f.Fj) + f.Mi + f.Mj;
			const double sc = Fmag * ((cur.xi - o).norm() + (cur.xj - o).norm()) + Mmag;
			EXPECT_LE(Mo.norm(), 1e-14 * sc);
		}
		// bending rotations lie perpendicular to the chord, and so does the shear: the chord part
		// of the force is the axial force. (The moments' chord parts are the twist pair only at
		// small angles: the exact gradient at finite bending turns them, see
		// ForcesAreTheGradientOfTheEnergyAtLargeAngles.)
		const BeamKinematics kin = beamKinematics(cur.xi, cur.xj, cur.oi, cur.oj, rest);
		EXPECT_NEAR(kin.thetaI.dot(kin.e), 0.0, 1e-15);
		EXPECT_NEAR(kin.thetaJ.dot(kin.e), 0.0, 1e-15);
		EXPECT_NEAR(f.Fj.dot(kin.e), -f.N, 1e-12 * Fmag);
	}
}

// ---------------------------------------------------------------- small displacements

TEST(Beam, SmallDisplacementsMatchLinearStiffness)
{
	const BeamSection s    = testSection();
	const double      L    = 1.3;
	const BeamRest    rest = makeBeamRest(Vec3::Zero(), Vec3(L, 0, 0), Quat::Identity(), Quat::Identity());
	EXPECT_EQ(rest.L0, L);
	const Mat12  K = beamStiffnessLocal(s, L);
	const double h = 1e-7 * L;
	// column by column: each DOF alone (translations h, rotations h/L)
	for (int dof = 0; dof < 12; ++dof) {
		Vec12 u       = Vec12::Zero();
		u[dof]        = (dof % 6) < 3 ? h : h / L;
		const Vec12 f = stack(forcesOf(displaced(L, u), rest, s));
		EXPECT_TRUE(close(f, Vec12(-K * u), 1e-5)) << "DOF " << dof;
	}
	// random combinations
	test::Rng rng(14);
	for (int k = 0; k < 50; ++k) {
		Vec12 u;
		for (int i = 0; i < 12; ++i)
			u[i] = rng.uniform() * ((i % 6) < 3 ? h : h / L);
		const Vec12 f = stack(forcesOf(displaced(L, u), rest, s));
		EXPECT_TRUE(close(f, Vec12(-K * u), 1e-5));
	}
}

TEST(Beam, CantileverSingleElement)
{
	const BeamSection                 s { 50.0, 3.0, 2.0 };
	const double                      L = 1.7, P = 0.8, T = 0.3;
	const Mat12                       K   = beamStiffnessLocal(s, L);
	const Eigen::Matrix<double, 6, 6> Kjj = K.block<6, 6>(6, 6); // node i clamped
	Eigen::Matrix<double, 6, 1>       load;
	// transverse y load
	load << 0, P, 0, 0, 0, 0;
	Eigen::Matrix<double, 6, 1> u = Kjj.fullPivLu().solve(load);
	EXPECT_TRUE(close(u[1], P * L * L * L / (3 * s.EI), 1e-13));
	EXPECT_TRUE(close(u[5], P * L * L / (2 * s.EI), 1e-13));
	EXPECT_NEAR(u[0], 0, 1e-15);
	EXPECT_NEAR(u[2], 0, 1e-15);
	EXPECT_NEAR(u[3], 0, 1e-15);
	EXPECT_NEAR(u[4], 0, 1e-15);
	// transverse z load: rotation about -y
	load << 0, 0, P, 0, 0, 0;
	u = Kjj.fullPivLu().solve(load);
	EXPECT_TRUE(close(u[2], P * L * L * L / (3 * s.EI), 1e-13));
	EXPECT_TRUE(close(u[4], -P * L * L / (2 * s.EI), 1e-13));
	// axial load and torque
	load << P, 0, 0, T, 0, 0;
	u = Kjj.fullPivLu().solve(load);
	EXPECT_TRUE(close(u[0], P * L / s.EA, 1e-13));
	EXPECT_TRUE(close(u[3], T * L / s.GJ, 1e-13));
	// end moment M about z: deflection M L^2/(2EI), rotation M L/EI
	load << 0, 0, 0, 0, 0, T;
	u = Kjj.fullPivLu().solve(load);
	EXPECT_TRUE(close(u[1], T * L * L / (2 * s.EI), 1e-13));
	EXPECT_TRUE(close(u[5], T * L / s.EI, 1e-13));

	// the co-rotational element in that displaced shape holds the load (small P)
	const double p = 1e-7 * s.EI / (L * L); // tip deflection ~ 1e-7 L
	load << 0, p, -0.5 * p, 0, 0, 0;
	u                     = Kjj.fullPivLu().solve(load);
	Vec12 U               = Vec12::Zero();
	U.segment<6>(6)       = u;
	const BeamRest   rest = makeBeamRest(Vec3::Zero(), Vec3(L, 0, 0), Quat::Identity(), Quat::Identity());
	const BeamForces f    = forcesOf(displaced(L, U), rest, s);
	EXPECT_TRUE(close(f.Fj, Vec3(0, -p, 0.5 * p), 1e-5)); // internal force balances the applied load
	EXPECT_LE(f.Mj.norm(), 1e-5 * p * L);                 // no end moment
	EXPECT_TRUE(close(f.Fi, Vec3(0, p, -0.5 * p), 1e-5)); // reaction at the clamp
	// clamp moment from the element's moment balance Mi + (L e_x) x Fj = 0: Mi = L e_x x P_applied
	EXPECT_TRUE(close(f.Mi, Vec3(0, 0.5 * p * L, p * L), 1e-5));
}

TEST(Beam, StiffnessSymmetricWithSixRigidModes)
{
	const BeamSection s = testSection();
	const double      L = 1.3;
	const Mat12       K = beamStiffnessLocal(s, L);
	EXPECT_EQ(K, Mat12(K.transpose()));
	Eigen::SelfAdjointEigenSolver<Mat12> es(K);
	const auto&                          ev   = es.eigenvalues(); // ascending
	const double                         lmax = ev.maxCoeff();
	for (int i = 0; i < 6; ++i)
		EXPECT_LE(std::abs(ev[i]), 1e-13 * lmax) << i;
	for (int i = 6; i < 12; ++i)
		EXPECT_GT(ev[i], 1e-3 * lmax) << i;
	// the axial and the twist modes are eigenvalues 2 EA/L and 2 GJ/L
	auto has = [&](double v) {
		for (int i = 0; i < 12; ++i)
			if (std::abs(ev[i] - v) <= 1e-12 * lmax) return true;
		return false;
	};
	EXPECT_TRUE(has(2 * s.EA / L));
	EXPECT_TRUE(has(2 * s.GJ / L));
	// the rigid modes: translations and small rotations about node i
	for (int a = 0; a < 3; ++a) {
		Vec12 tr = Vec12::Zero(), rot = Vec12::Zero();
		tr[a] = tr[6 + a] = 1;
		const Vec3 w      = Vec3::Unit(a);
		rot.segment<3>(3) = w;
		rot.segment<3>(9) = w;
		rot.segment<3>(6) = w.cross(Vec3(L, 0, 0));
		EXPECT_LE((K * tr).norm(), 1e-13 * lmax);
		EXPECT_LE((K * rot).norm(), 1e-13 * lmax);
	}
}

TEST(Beam, PureBendingAndTwistEnergyIsQuadraticForm)
{
	const BeamSection s    = testSection();
	const double      L    = 1.3;
	const Mat12       K    = beamStiffnessLocal(s, L);
	const BeamRest    rest = makeBeamRest(Vec3::Zero(), Vec3(L, 0, 0), Quat::Identity(), Quat::Identity());
	test::Rng         rng(15);
	for (int k = 0; k < 50; ++k) {
		// finite end rotations about one axis a: perpendicular to the chord (pure bending in the
		// plane normal to a; both ends in the same plane, else the frames also twist) or along it
		const bool   twist = k % 2;
		const double ang   = rng.uniform(-M_PI, M_PI);
		const Vec3   a     = twist ? Vec3(1, 0, 0) : Vec3(0, std::cos(ang), std::sin(ang));
		Vec12        u     = Vec12::Zero();
		u.segment<3>(3)    = rng.uniform(-0.5, 0.5) * a;
		u.segment<3>(9)    = rng.uniform(-0.5, 0.5) * a;
		const BeamForces f = forcesOf(displaced(L, u), rest, s);
		EXPECT_TRUE(close(f.elasticEnergy, 0.5 * u.dot(K * u), 1e-13));
		if (twist) { // moments are exactly -K u (about the fixed chord), no shear force
			EXPECT_TRUE(close(stack(f), Vec12(-K * u), 1e-13, 1e-15));
		} else { // bending moments are -K u restricted to the rotations
			EXPECT_TRUE(close(f.Mi, Vec3((-K * u).segment<3>(3)), 1e-13));
			EXPECT_TRUE(close(f.Mj, Vec3((-K * u).segment<3>(9)), 1e-13));
			EXPECT_TRUE(close(f.Fj, Vec3((-K * u).segment<3>(6)), 1e-13));
		}
		EXPECT_EQ(f.N, 0.0);
	}
}

// The forces and moments are the exact gradient of the booked energy, also at large bending
// and twist angles: -dU/dx and -dU/dphi by central differences (rotations phi applied in the
// global frame, as the integrator applies them). A force field that is not a gradient does work
// around closed loops: dangling wire ends swinging through 20-180 degrees of bending created
// 1.5 kJ in a 30 m/s impact (bench/STABILITY.md, finding 5) while the moments were taken as
// -dU/dtheta, exact only for small angles.
TEST(Beam, ForcesAreTheGradientOfTheEnergyAtLargeAngles)
{
	const BeamSection s = testSection();
	test::Rng         rng(23);
	for (int k = 0; k < 200; ++k) {
		Config ref, cur;
		randomDeformed(rng, ref, cur);
		// large end rotations: up to 1.2 or 2.5 rad about random axes (bending and twist)
		const double big      = k < 100 ? 1.2 : 2.5;
		cur.oi                = rotvec(rng.vec(big)) * cur.oi;
		cur.oj                = rotvec(rng.vec(big)) * cur.oj;
		const BeamRest   rest = makeBeamRest(ref.xi, ref.xj, ref.oi, ref.oj);
		const BeamForces f    = forcesOf(cur, rest, s);
		auto             U    = [&](const Config& c) { return forcesOf(c, rest, s).elasticEnergy; };
		const double     h    = 1e-6;
		Vec12            grad;
		for (int d = 0; d < 12; ++d) {
			Config    p = cur, m = cur;
			const int a = d % 3;
			Vec3      e = Vec3::Zero();
			e[a]        = h;
			switch (d / 3) {
			case 0:
				p.xi += e, m.xi -= e;
				break;
			case 1:
				p.oi = rotvec(e) * cur.oi, m.oi = rotvec(-e) * cur.oi;
				break;
			case 2:
				p.xj += e, m.xj -= e;
				break;
			default:
				p.oj = rotvec(e) * cur.oj, m.oj = rotvec(-e) * cur.oj;
				break;
			}
			grad[d] = -(U(p) - U(m)) / (2 * h);
		}
		// central differences with h = 1e-6: truncation ~ h^2 times the third derivative and
		// round-off ~ 1e-16 U / h, both far below 1e-6 of the gradient here
		EXPECT_TRUE(close(stack(f), grad, 1e-6, 1e-9 * grad.norm())) << "configuration " << k;
	}
}

// ---------------------------------------------------------------- bar (axial-only) bonds

// A bar is the beam with EI = GJ = 0 minus the rotations: the same forces and energy bit for bit
// in any deformed state (elastic, plastic, tension-only, slack), and no moments.
TEST(Bar, EqualsTheBeamWithoutBendingStiffnessBitForBit)
{
	test::Rng   rng(20261123);
	BeamSection s { 250.0, 0.0, 0.0 };
	AxialLaw    law;
	law.tensionOnly = true;
	law.yieldForce  = 3.0;
	law.hardening   = 0.05;
	int loaded = 0, slack = 0, plastic = 0;
	for (int n = 0; n < 2000; ++n) {
		Config ref, cur;
		randomDeformed(rng, ref, cur);
		const BeamRest   rest = makeBeamRest(ref.xi, ref.xj, ref.oi, ref.oj);
		AxialState       stBeam, stBar;
		const double     L  = (cur.xj - cur.xi).norm();
		const double     st = (L - rest.L0) / rest.L0;
		const BeamForces b  = beamForces(beamKinematics(cur.xi, cur.xj, cur.oi, cur.oj, rest), rest, s, law, stBeam);
		const Chord      c  = chord(cur.xi, cur.xj);
		const BeamForces a  = barForces(c, axialForce((c.L - rest.L0) / rest.L0, s.EA, rest.L0, law, stBar));
		ASSERT_EQ(c.L, L);
		for (int k = 0; k < 3; ++k) { // == also holds for +0 against -0
			ASSERT_EQ(a.Fi[k], b.Fi[k]);
			ASSERT_EQ(a.Fj[k], b.Fj[k]);
			ASSERT_EQ(b.Mi[k], 0.0);
			ASSERT_EQ(b.Mj[k], 0.0);
		}
		EXPECT_TRUE(a.Mi.isZero(0) && a.Mj.isZero(0));
		ASSERT_EQ(a.N, b.N);
		ASSERT_EQ(a.elasticEnergy, b.elasticEnergy);
		ASSERT_EQ(a.plasticWork, b.plasticWork);
		ASSERT_EQ(stBar.plasticStrain, stBeam.plasticStrain);
		loaded += a.N > 0;
		slack += st < 0;
		plastic += a.plasticWork > 0;
	}
	// the random states cover every branch of the law
	EXPECT_GT(loaded, 100);
	EXPECT_GT(slack, 100);
	EXPECT_GT(plastic, 10);
}

TEST(Bar, ForcesAreAxialAndBalanced)
{
	const Vec3  xi(0.1, -0.2, 0.3), xj(1.1, 0.8, 0.3);
	const Chord c = chord(xi, xj);
	EXPECT_DOUBLE_EQ(c.L, std::sqrt(2.0));
	AxialResult ax;
	ax.N               = 7.0;
	ax.elasticEnergy   = 0.25;
	const BeamForces f = barForces(c, ax);
	EXPECT_TRUE(close(f.Fi, Vec3(7.0 * (xj - xi) / std::sqrt(2.0)), 1e-15)); // tension pulls i towards j
	EXPECT_TRUE(close(f.Fi + f.Fj, Vec3::Zero(), 0, 0));
	EXPECT_NEAR(f.Fi.cross(c.e).norm(), 0.0, 1e-15);
	EXPECT_EQ(f.elasticEnergy, 0.25);
}

// ---------------------------------------------------------------- axial law

TEST(AxialLaw, Elastic)
{
	const double EA = 1000, L0 = 2;
	AxialState   st;
	for (double eps : { 1e-3, -2e-3, 0.0 }) {
		const AxialResult r = axialForce(eps, EA, L0, AxialLaw {}, st);
		EXPECT_DOUBLE_EQ(r.N, EA * eps);
		EXPECT_TRUE(close(r.elasticEnergy, 0.5 * EA * eps * eps * L0, 1e-14));
		EXPECT_EQ(r.plasticWork, 0.0);
		EXPECT_FALSE(r.rupture);
		EXPECT_EQ(st.plasticStrain, 0.0);
		EXPECT_EQ(st.hardeningVar, 0.0);
	}
}

TEST(AxialLaw, TensionOnly)
{
	AxialLaw law;
	law.tensionOnly = true;
	AxialState        st;
	const AxialResult c = axialForce(-1e-3, 1000, 2, law, st);
	EXPECT_EQ(c.N, 0.0);
	EXPECT_EQ(c.elasticEnergy, 0.0);
	EXPECT_EQ(c.plasticWork, 0.0);
	const AxialResult t = axialForce(1e-3, 1000, 2, law, st);
	EXPECT_DOUBLE_EQ(t.N, 1.0);
	// a slack yielded rope: no force until the permanent elongation is taken up, no compression yield
	law.yieldForce = 0.5;
	AxialState   y;
	const double ep = (axialForce(2e-3, 1000, 2, law, y), y.plasticStrain);
	EXPECT_NEAR(ep, 1.5e-3, 1e-15);
	EXPECT_EQ(axialForce(1e-3, 1000, 2, law, y).N, 0.0);
	EXPECT_EQ(axialForce(-5e-3, 1000, 2, law, y).N, 0.0);
	EXPECT_EQ(y.plasticStrain, ep);
}

TEST(AxialLaw, YieldHardeningUnloadingAndReverseYield)
{
	const double EA = 1000, L0 = 2, Ny = 2, h = 0.1, H = h * EA;
	AxialLaw     law;
	law.yieldForce = Ny;
	law.hardening  = h;
	// monotonic loading in many steps to eps_max
	const double eps_max = 0.01;
	AxialState   st;
	double       work = 0;
	AxialResult  r;
	const int    n = 1000;
	for (int i = 1; i <= n; ++i) {
		r = axialForce(eps_max * i / n, EA, L0, law, st);
		work += r.plasticWork;
		EXPECT_LE(r.N, Ny + H * st.hardeningVar + 1e-12); // never outside the yield surface
	}
	// analytic: N = EA (eps - ep) = Ny + H ep
	const double ep = (EA * eps_max - Ny) / (EA + H);
	EXPECT_TRUE(close(st.plasticStrain, ep, 1e-13));
	EXPECT_TRUE(close(st.hardeningVar, ep, 1e-13));
	EXPECT_TRUE(close(r.N, Ny + H * ep, 1e-13));
	EXPECT_TRUE(close(r.elasticEnergy, 0.5 * r.N * r.N * L0 / EA, 1e-13));
	// plastic work = area under N(ep) * L0 = (Ny ep + H ep^2 / 2) L0, whatever the step size
	EXPECT_TRUE(close(work, (Ny * ep + 0.5 * H * ep * ep) * L0, 1e-12));
	{
		AxialState  one;
		AxialResult r1 = axialForce(eps_max, EA, L0, law, one);
		EXPECT_TRUE(close(r1.plasticWork, (Ny * ep + 0.5 * H * ep * ep) * L0, 1e-13));
		EXPECT_TRUE(close(r1.N, r.N, 1e-13));
	}
	// unloading follows the initial stiffness, leaves the permanent strain ep
	const double Nmax = r.N;
	r                 = axialForce(eps_max - 0.001, EA, L0, law, st);
	EXPECT_TRUE(close(r.N, Nmax - EA * 0.001, 1e-13));
	EXPECT_EQ(r.plasticWork, 0.0);
	r = axialForce(ep, EA, L0, law, st);
	EXPECT_NEAR(r.N, 0.0, 1e-12);
	EXPECT_NEAR(r.elasticEnergy, 0.0, 1e-15);
	EXPECT_TRUE(close(st.plasticStrain, ep, 1e-13));
	// reloading is elastic up to the hardened yield force
	r = axialForce(eps_max, EA, L0, law, st);
	EXPECT_TRUE(close(r.N, Nmax, 1e-12));
	EXPECT_NEAR(r.plasticWork, 0.0, 1e-15); // at most round-off on the yield surface
	// compression: isotropic hardening, reverse yield at -(Ny + H alpha)
	const double alpha = st.hardeningVar;
	r                  = axialForce(ep - (Ny + H * alpha) / EA + 1e-6, EA, L0, law, st);
	EXPECT_EQ(r.plasticWork, 0.0);
	const double eps_c = -0.01;
	r                  = axialForce(eps_c, EA, L0, law, st);
	// N = EA (eps_c - ep') = -(Ny + H (alpha + ep - ep'))
	const double ep2 = (EA * eps_c + Ny + H * (alpha + ep)) / (EA + H);
	EXPECT_TRUE(close(st.plasticStrain, ep2, 1e-12));
	EXPECT_TRUE(close(r.N, -(Ny + H * (alpha + ep - ep2)), 1e-12));
	EXPECT_TRUE(close(st.hardeningVar, alpha + ep - ep2, 1e-12));
	const double a0 = alpha, a1 = st.hardeningVar;
	EXPECT_TRUE(close(r.plasticWork, (Ny * (a1 - a0) + 0.5 * H * (a1 * a1 - a0 * a0)) * L0, 1e-12));
}

TEST(AxialLaw, PerfectPlasticity)
{
	AxialLaw law;
	law.yieldForce = 3; // EA = 100: yield strain 0.03
	AxialState        st;
	const AxialResult r = axialForce(0.02, 100, 1.5, law, st);
	EXPECT_DOUBLE_EQ(r.N, 2);
	EXPECT_EQ(st.plasticStrain, 0.0);
	EXPECT_EQ(r.plasticWork, 0.0);
	const AxialResult r2 = axialForce(0.05, 100, 1.5, law, st);
	EXPECT_TRUE(close(r2.N, 3.0, 1e-14));
	EXPECT_TRUE(close(st.plasticStrain, 0.05 - 0.03, 1e-13));
	EXPECT_TRUE(close(r2.plasticWork, 3 * 0.02 * 1.5, 1e-13));
	EXPECT_TRUE(close(r2.elasticEnergy, 0.5 * 3 * 0.03 * 1.5, 1e-13));
}

TEST(AxialLaw, Rupture)
{
	const double EA = 1000, L0 = 2;
	{
		AxialLaw law;
		law.ruptureForce = 5;
		AxialState st;
		EXPECT_FALSE(axialForce(4.999e-3, EA, L0, law, st).rupture);
		EXPECT_TRUE(axialForce(5.001e-3, EA, L0, law, st).rupture);
		EXPECT_TRUE(axialForce(6e-3, EA, L0, law, st).rupture);
		EXPECT_FALSE(axialForce(-6e-3, EA, L0, law, st).rupture); // compression never breaks by force
	}
	{
		AxialLaw law;
		law.ruptureStrain = 0.02;
		law.yieldForce    = 1; // yielded bar: the force stays low, the strain criterion still fires
		AxialState st;
		EXPECT_FALSE(axialForce(0.0199, EA, L0, law, st).rupture);
		EXPECT_TRUE(axialForce(0.02, EA, L0, law, st).rupture);
	}
	{ // beamForces reports the rupture of its axial law
		AxialLaw law;
		law.ruptureForce      = 5;
		const BeamRest   rest = makeBeamRest(Vec3::Zero(), Vec3(2, 0, 0), Quat::Identity(), Quat::Identity());
		AxialState       st;
		const BeamForces f = beamForces(
		        beamKinematics(Vec3::Zero(), Vec3(2.02, 0, 0), Quat::Identity(), Quat::Identity(), rest), rest, BeamSection { EA, 1, 1 }, law, st);
		EXPECT_TRUE(f.rupture);
		EXPECT_TRUE(close(f.N, 10.0, 1e-13));
		EXPECT_TRUE(close(f.Fj, Vec3(-10, 0, 0), 1e-13)); // tension pulls j back towards i
		EXPECT_TRUE(close(f.Fi, Vec3(10, 0, 0), 1e-13));
	}
}

// ---------------------------------------------------------------- section and masses

TEST(BeamSection, Circular)
{
	const double      E = 2e11, G = 8e10, r = 0.005;
	const double      A = M_PI * r * r, I = M_PI * r * r * r * r / 4;
	const BeamSection s = BeamSection::circular(E, G, r);
	EXPECT_TRUE(close(s.EA, E * A, 1e-15));
	EXPECT_TRUE(close(s.EI, E * I, 1e-15));
	EXPECT_TRUE(close(s.GJ, G * 2 * I, 1e-15));
	EXPECT_TRUE(close(s.EA, 15707963.267948966, 1e-15)); // 2e11 * pi * 25e-6
	const BeamSection w = BeamSection::circular(E, G, r, 0.1);
	EXPECT_EQ(w.EA, s.EA);
	EXPECT_TRUE(close(w.EI, 0.1 * E * I, 1e-15));
	EXPECT_TRUE(close(w.GJ, 0.1 * G * 2 * I, 1e-15));
}

TEST(CylinderNodeShare, Values)
{
	const double    rho = 7800, r = 0.01, L = 0.5;
	const NodeShare sh = cylinderNodeShare(rho, r, L);
	const double    m  = rho * M_PI * r * r * L;
	EXPECT_TRUE(close(2 * sh.mass, m, 1e-15));
	EXPECT_TRUE(close(sh.mass, 0.6126105674500097, 1e-15)); // 0.5 * 7800 * pi * 1e-4 * 0.5
	// half cylinder (length L/2) about a transverse axis through its end: parallel axis theorem
	const double mh = m / 2, Lh = L / 2;
	EXPECT_TRUE(close(sh.inertia, mh * (r * r / 4 + Lh * Lh / 12) + mh * (Lh / 2) * (Lh / 2), 1e-14));
}
