// yade-flex kernel tests: chain-link wire law (GPL-2.0-or-later)
#include "kernel/WireLaw.hpp"
#include "test_util.hpp"

#include <algorithm>
#include <vector>

using namespace flex;
using flex::test::close;

namespace {

// a high-tensile wire curve: elastic to 1400 MPa, hardening to 1770 MPa (values for the tests only)
const std::vector<double> kStrain = { 0.007, 0.012, 0.025, 0.04 };
const std::vector<double> kStress = { 1.40e9, 1.60e9, 1.72e9, 1.77e9 };
constexpr double          kArea   = 7.0685834705770345e-6; // d = 3 mm [m^2]
constexpr double          kL0     = 0.05;                  // [m]

WireCurve curve() { return { kStrain.data(), kStress.data(), (int)kStrain.size() }; }

// drive a link through the strains in path; returns the forces and sums the dissipation
std::vector<double> drive(const std::vector<double>& path, const WireDistortion& d, WireState& st, double& dissipated, bool& broke)
{
	std::vector<double> N;
	dissipated = 0;
	broke      = false;
	for (double e : path) {
		const WireAxial a = wireAxial(e, kL0, kArea, curve(), d, st);
		N.push_back(a.N);
		dissipated += a.plasticWork;
		broke = broke || a.rupture;
	}
	return N;
}

std::vector<double> ramp(double from, double to, int steps)
{
	std::vector<double> p;
	for (int k = 1; k <= steps; ++k)
		p.push_back(from + (to - from) * k / steps);
	return p;
}

} // namespace

TEST(WireCurve, RejectsBadCurvesNamingTheProblem)
{
	EXPECT_EQ(wireCurveError(kStrain, kStress), "");
	auto err = [](std::vector<double> e, std::vector<double> s) { return wireCurveError(e, s); };
	EXPECT_NE(err({ 0.01 }, { 1e9 }).find("at least two points"), std::string::npos);
	EXPECT_NE(err({ 0.01, 0.02 }, { 1e9 }).find("2 strains but 1 stresses"), std::string::npos);
	EXPECT_NE(err({ 0.01, 0.01 }, { 1e9, 1.1e9 }).find("strain must increase strictly"), std::string::npos);
	EXPECT_NE(err({ 0.02, 0.01 }, { 1e9, 1.1e9 }).find("point 1"), std::string::npos);
	EXPECT_NE(err({ -0.01, 0.02 }, { 1e9, 1.1e9 }).find("strain of point 0 must be positive"), std::string::npos);
	EXPECT_NE(err({ 0.01, 0.02 }, { 1e9, -1.0 }).find("stress of point 1 must be positive"), std::string::npos);
	EXPECT_NE(err({ 0.01, 0.02 }, { 1e9, NAN }).find("not finite"), std::string::npos);
	// second segment stiffer than the elastic slope: unloading would cross the envelope
	EXPECT_NE(err({ 0.01, 0.02 }, { 1e9, 2.5e9 }).find("stiffer than the elastic slope"), std::string::npos);
	EXPECT_EQ(wireDistortionError(0.02, 0.5), "");
	EXPECT_NE(wireDistortionError(-0.1, 0.5), "");
	EXPECT_NE(wireDistortionError(0.02, 0.0), "");
	EXPECT_NE(wireDistortionError(0.02, 1.5), "");
}

TEST(WireLaw, MonotonicLoadingPassesThroughEveryKnot)
{
	WireState st;
	for (size_t k = 0; k < kStrain.size(); ++k) {
		const WireAxial a = wireAxial(kStrain[k], kL0, kArea, curve(), {}, st);
		EXPECT_TRUE(close(a.N, kStress[k] * kArea, 1e-14)) << "knot " << k;
		EXPECT_FALSE(a.rupture);
	}
	// between knots: linear interpolation
	WireState    st2;
	const double e = 0.5 * (kStrain[1] + kStrain[2]);
	EXPECT_TRUE(close(wireAxial(e, kL0, kArea, curve(), {}, st2).N, 0.5 * (kStress[1] + kStress[2]) * kArea, 1e-14));
}

TEST(WireLaw, TensionOnlyAndElasticBelowFirstKnot)
{
	WireState st;
	EXPECT_EQ(wireAxial(-0.01, kL0, kArea, curve(), {}, st).N, 0.0);
	const double Ew = kStress[0] / kStrain[0];
	EXPECT_TRUE(close(wireAxial(0.003, kL0, kArea, curve(), {}, st).N, Ew * 0.003 * kArea, 1e-14));
	EXPECT_EQ(st.plasticStrain, 0.0); // elastic range: no permanent strain
	EXPECT_EQ(wireAxial(-0.001, kL0, kArea, curve(), {}, st).N, 0.0);
}

TEST(WireLaw, UnloadReloadFollowsElasticSlopeAndRejoinsTheCurve)
{
	const double Ew = kStress[0] / kStrain[0];
	WireState    st;
	const double eA = 0.02; // on segment 1-2
	const double FA = wireAxial(eA, kL0, kArea, curve(), {}, st).N;
	const double ep = eA - FA / (kArea * Ew);
	EXPECT_TRUE(close(st.plasticStrain, ep, 1e-14));
	// unloading: slope Ew
	const double eB = eA - 0.002;
	EXPECT_TRUE(close(wireAxial(eB, kL0, kArea, curve(), {}, st).N, FA - Ew * kArea * 0.002, 1e-13));
	// below the plastic strain: slack, zero force
	EXPECT_EQ(wireAxial(ep - 1e-4, kL0, kArea, curve(), {}, st).N, 0.0);
	// reloading: same line, no dissipation, back on the curve at eA
	const WireAxial back = wireAxial(eA, kL0, kArea, curve(), {}, st);
	EXPECT_TRUE(close(back.N, FA, 1e-13));
	EXPECT_EQ(back.plasticWork, 0.0);
	// and beyond: the curve again (knot 2)
	EXPECT_TRUE(close(wireAxial(kStrain[2], kL0, kArea, curve(), {}, st).N, kStress[2] * kArea, 1e-14));
}

TEST(WireLaw, CycleDissipationEqualsEnclosedArea)
{
	// load to eA, unload to zero force, reload to eA: the loop (0 -> curve -> eA -> unloading line
	// -> ep -> axis -> 0) encloses the area W(eA) - s(eA)^2 / (2 Ew)
	std::vector<double> path = ramp(0, 0.02, 4000), down = ramp(0.02, 0.0, 4000), up = ramp(0.0, 0.02, 4000);
	path.insert(path.end(), down.begin(), down.end());
	path.insert(path.end(), up.begin(), up.end());
	WireState                 st;
	double                    dissipated;
	bool                      broke;
	const std::vector<double> N = drive(path, {}, st, dissipated, broke);
	// closed loop: loading and unloading (the reload retraces the unloading line, no dissipation)
	double area = 0; // integral of N du (trapezoids)
	for (size_t k = 1; k < 8000; ++k)
		area += 0.5 * (N[k] + N[k - 1]) * (path[k] - path[k - 1]) * kL0;
	EXPECT_FALSE(broke);
	EXPECT_GT(dissipated, 0);
	EXPECT_TRUE(close(dissipated, area, 1e-4)); // trapezoids over a kink: O(h)
	// exact value from the curve
	const double Ew = kStress[0] / kStrain[0];
	const double sA = kStress[1] + (0.02 - kStrain[1]) * (kStress[2] - kStress[1]) / (kStrain[2] - kStrain[1]);
	const double W
	        = 0.5 * kStress[0] * kStrain[0] + 0.5 * (kStress[0] + kStress[1]) * (kStrain[1] - kStrain[0]) + 0.5 * (kStress[1] + sA) * (0.02 - kStrain[1]);
	EXPECT_TRUE(close(dissipated, kL0 * kArea * (W - 0.5 * sA * sA / Ew), 1e-12));
}

TEST(WireLaw, WorkIsElasticPlusDissipatedOnAnyPath)
{
	// loading in large, irregular steps (crossing knots within a step): work = area under the curve
	WireState                 st;
	double                    dissipated = 0;
	const std::vector<double> path       = { 0.004, 0.0135, 0.013, 0.026, 0.031 };
	WireAxial                 last;
	for (double e : path) {
		last = wireAxial(e, kL0, kArea, curve(), {}, st);
		dissipated += last.plasticWork;
	}
	double    ke[8], ks[8];
	const int m = wireEnvelopeKnots(curve(), {}, ke, ks);
	double    W = 0;
	for (int k = 1; k < m && ke[k - 1] < 0.031; ++k) {
		const double x = std::min(ke[k], 0.031), sx = ks[k - 1] + (ks[k] - ks[k - 1]) * (x - ke[k - 1]) / (ke[k] - ke[k - 1]);
		W += 0.5 * (ks[k - 1] + sx) * (x - ke[k - 1]);
	}
	EXPECT_TRUE(close(dissipated + last.elasticEnergy, kL0 * kArea * W, 1e-12));
}

TEST(WireLaw, RupturePastTheLastPoint)
{
	WireState st;
	EXPECT_FALSE(wireAxial(kStrain.back(), kL0, kArea, curve(), {}, st).rupture);
	EXPECT_FALSE(wireAxial(kStrain.back() * (1 + 1e-12), kL0, kArea, curve(), {}, st).rupture); // round-off
	const WireAxial a = wireAxial(kStrain.back() * (1 + 1e-8), kL0, kArea, curve(), {}, st);
	EXPECT_TRUE(a.rupture);
	EXPECT_TRUE(close(a.N, kStress.back() * kArea, 1e-14)); // the last point's force at the breaking step
	const double Ew = kStress[0] / kStrain[0];
	EXPECT_TRUE(close(a.elasticEnergy, 0.5 * kL0 * kArea * kStress.back() * kStress.back() / Ew, 1e-14));
}

TEST(WireLaw, DistortionShiftsTheCurveBehindASoftBranch)
{
	const double   Ew = kStress[0] / kStrain[0];
	WireDistortion d { 0.01, 0.4 };
	// knots of the input curve, shifted by the slack
	for (size_t k = 0; k < kStrain.size(); ++k)
		EXPECT_TRUE(close(wireEnvelope(curve(), d, d.slack + kStrain[k]), kStress[k], 1e-14)) << "knot " << k;
	// soft first branch to A = (d + lf e1, lf s1), then the elastic slope to the first knot
	const double eA = d.slack + d.forceRatio * kStrain[0];
	EXPECT_TRUE(close(wireEnvelope(curve(), d, 0.5 * eA), 0.5 * d.forceRatio * kStress[0], 1e-14));
	const double slopeAB = (wireEnvelope(curve(), d, d.slack + kStrain[0]) - wireEnvelope(curve(), d, eA)) / (d.slack + kStrain[0] - eA);
	EXPECT_TRUE(close(slopeAB, Ew, 1e-9));
	// lf = 1: one soft segment from the origin to the shifted first knot
	WireDistortion d1 { 0.01, 1.0 };
	const double   e1 = d1.slack + kStrain[0];
	EXPECT_TRUE(close(wireEnvelope(curve(), d1, 0.3 * e1), 0.3 * kStress[0], 1e-14));
	// straightening the slack is permanent: unloading from A goes down with Ew
	WireState st;
	wireAxial(eA, kL0, kArea, curve(), d, st);
	EXPECT_TRUE(close(st.plasticStrain, eA - d.forceRatio * kStress[0] / Ew, 1e-14));
	EXPECT_GT(st.plasticStrain, 0.0);
	// rupture past the shifted last point only
	WireState st2;
	EXPECT_FALSE(wireAxial(d.slack + kStrain.back(), kL0, kArea, curve(), d, st2).rupture);
	EXPECT_TRUE(wireAxial((d.slack + kStrain.back()) * (1 + 1e-8), kL0, kArea, curve(), d, st2).rupture);
}

// The envelope branch evaluated from wireEnvelopeKnots' arrays, twice (at maxStrain and at the
// new strain), as it was before the single pass over implicit knots: the reference that pass must
// reproduce bit for bit.
WireAxial envelopeReference(double strain, const WireDistortion& d, WireState& st)
{
	double    ke[70], ks[70];
	const int m  = wireEnvelopeKnots(curve(), d, ke, ks);
	auto      at = [&](double e, double& s, double& W) {
                s = W = 0;
                if (e <= 0) return;
                for (int k = 1; k < m; ++k) {
                        const double e0 = ke[k - 1], e1 = ke[k], s0 = ks[k - 1], s1 = ks[k];
                        if (e <= e1 || k == m - 1) {
                                const double x = std::min(e, e1);
                                s              = s0 + (s1 - s0) * (x - e0) / (e1 - e0);
                                W += 0.5 * (s0 + s) * (x - e0);
                                return;
                        }
                        W += 0.5 * (s0 + s1) * (e1 - e0);
                }
	};
	const double Ew = curve().elasticModulus(), vol = kL0 * kArea, eLast = ke[m - 1];
	WireAxial    r;
	r.rupture      = strain > eLast * (1 + 1e-9);
	const double e = std::min(strain, eLast);
	double       s, sOld, wOld, wNew;
	at(st.maxStrain, sOld, wOld);
	at(e, s, wNew);
	r.plasticWork    = vol * ((wNew - 0.5 * s * s / Ew) - (wOld - 0.5 * sOld * sOld / Ew));
	st.maxStrain     = e;
	st.plasticStrain = e - s / Ew;
	r.N              = s * kArea;
	r.elasticEnergy  = 0.5 * vol * s * s / Ew;
	return r;
}

TEST(WireLaw, EnvelopeBranchMatchesTheKnotArraysBitForBit)
{
	test::Rng rng(2026);
	int       soft = 0, straight = 0, fromZero = 0, broken = 0, sameSegment = 0;
	for (int trial = 0; trial < 20000; ++trial) {
		// slack 0, straight (lf = 1) and soft (lf < 1) links; from rest or already on the envelope
		const int      kind = trial % 3;
		WireDistortion d { kind == 0 ? 0.0 : rng.uniform(0, 0.05), kind == 2 ? rng.uniform(0.05, 1.0) : 1.0 };
		const double   eEnd = d.slack + kStrain.back();
		WireState      a;
		a.maxStrain          = trial % 5 == 0 ? 0.0 : rng.uniform(0, eEnd);
		a.plasticStrain      = a.maxStrain - wireEnvelope(curve(), d, a.maxStrain) / curve().elasticModulus();
		WireState       b    = a;
		const double    next = a.maxStrain + (trial % 4 == 0 ? rng.uniform(0, 1e-5) : rng.uniform(0, 1.1 * eEnd));
		const WireAxial x    = wireAxialEnvelope(next, kL0, kArea, curve(), d, a);
		const WireAxial y    = envelopeReference(next, d, b);
		ASSERT_EQ(x.N, y.N) << "trial " << trial;
		ASSERT_EQ(x.plasticWork, y.plasticWork) << "trial " << trial;
		ASSERT_EQ(x.elasticEnergy, y.elasticEnergy) << "trial " << trial;
		ASSERT_EQ(x.rupture, y.rupture) << "trial " << trial;
		ASSERT_EQ(a.maxStrain, b.maxStrain) << "trial " << trial;
		ASSERT_EQ(a.plasticStrain, b.plasticStrain) << "trial " << trial;
		soft += d.slack > 0 && d.forceRatio < 1;
		straight += d.forceRatio == 1;
		fromZero += b.maxStrain > 0 && trial % 5 == 0;
		broken += x.rupture;
		sameSegment += trial % 4 == 0;
	}
	// every branch was taken
	EXPECT_GT(soft, 1000);
	EXPECT_GT(straight, 1000);
	EXPECT_GT(fromZero, 1000);
	EXPECT_GT(broken, 100);
	EXPECT_GT(sameSegment, 1000);
}

TEST(WireSlack, DeterministicOrderFreeAndSeedDependent)
{
	EXPECT_EQ(wireSlackDraw(7, 10, 11, 0.1), wireSlackDraw(7, 10, 11, 0.1));
	EXPECT_EQ(wireSlackDraw(7, 10, 11, 0.1), wireSlackDraw(7, 11, 10, 0.1)); // a link, not an ordered pair
	EXPECT_NE(wireSlackDraw(7, 10, 11, 0.1), wireSlackDraw(8, 10, 11, 0.1));
	EXPECT_NE(wireSlackDraw(7, 10, 11, 0.1), wireSlackDraw(7, 10, 12, 0.1));
	EXPECT_EQ(wireSlackDraw(7, 10, 11, 0.0), 0.0);
}

TEST(WireSlack, SamplesFollowTheSymmetricTriangularDistribution)
{
	// links of a chain-like numbering (neighbouring ids, the hardest case for a weak hash)
	const int           n = 20000;
	std::vector<double> xi;
	for (int k = 0; k < n; ++k)
		xi.push_back(wireSlackDraw(12345, k, k + 1, 1.0));
	std::sort(xi.begin(), xi.end());
	double D = 0, mean = 0, var = 0;
	for (int k = 0; k < n; ++k) {
		const double F = wireSlackCdf(xi[k]);
		D              = std::max({ D, std::abs(F - (double)k / n), std::abs(F - (double)(k + 1) / n) });
		mean += xi[k] / n;
	}
	for (double x : xi)
		var += (x - mean) * (x - mean) / (n - 1);
	EXPECT_GE(xi.front(), 0.0);
	EXPECT_LT(xi.back(), 1.0);
	// Kolmogorov-Smirnov at the 1% level: D < 1.628 / sqrt(n)
	EXPECT_LT(D, 1.628 / std::sqrt((double)n)) << "KS statistic";
	// mean 1/2, variance 1/24 of the triangular law; 4 standard errors
	EXPECT_NEAR(mean, 0.5, 4 * std::sqrt(1.0 / 24 / n));
	EXPECT_NEAR(var, 1.0 / 24, 4 * std::sqrt(2.0 / (n - 1)) / 24 * 1.3);
	// and a uniform distribution would fail the same test (the test can fail)
	double Du = 0;
	for (int k = 0; k < n; ++k)
		Du = std::max(Du, std::abs(wireSlackCdf((k + 0.5) / n) - (k + 0.5) / n));
	EXPECT_GT(Du, 1.628 / std::sqrt((double)n));
}
