// yade-flex kernel tests: time-step rows of contacts against exact eigenvalues (GPL-2.0-or-later)
#include "kernel/ContactRows.hpp"
#include "test_util.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

using namespace flex;
using flex::test::close;

namespace {
// Largest eigenvalue of M^-1/2 (k g g^T) M^-1/2 for the force weights g on bodies of 1/sqrt(m) i:
// a rank-one matrix, eigenvalue k sum (g_a i_a)^2 (computed with an eigensolver all the same).
double exactOmega2(const std::vector<double>& g, const std::vector<double>& i, double k)
{
	const int       n = (int)g.size();
	Eigen::VectorXd v(n);
	for (int a = 0; a < n; ++a)
		v[a] = g[a] * i[a];
	const Eigen::MatrixXd A = k * v * v.transpose();
	return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
}
double maxOf(const double* r, int n)
{
	double m = 0;
	for (int a = 0; a < n; ++a)
		m = std::max(m, r[a]);
	return m;
}
} // namespace

TEST(ContactRows, TwoEqualMassesAreExact)
{
	// two free spheres of mass m joined by k: omega^2 = 2 k / m, each row equals it
	const double k = 3e5, m = 0.4, i = 1 / std::sqrt(m);
	const double w[2] = { 1, -1 }, is[2] = { i, i };
	double       rows[2];
	contactRows(w, is, 2, k, rows);
	EXPECT_TRUE(close(rows[0], 2 * k / m, 1e-14));
	EXPECT_TRUE(close(rows[1], 2 * k / m, 1e-14));
}

TEST(ContactRows, AFixedBodyHasNoRowAndAddsNothing)
{
	// a segment's nodes (m1, m2) at u = 0.3 against a fixed sphere: the rows are the exact
	// rank-one entries' sums k w_a i_a (w_1 i_1 + w_2 i_2), the fixed side 0
	const double k = 2e6, i1 = 1 / std::sqrt(0.02), i2 = 1 / std::sqrt(0.05), u = 0.3;
	const double w[3] = { 1 - u, u, -1 }, is[3] = { i1, i2, 0 };
	double       rows[3];
	contactRows(w, is, 3, k, rows);
	const double S = (1 - u) * i1 + u * i2;
	EXPECT_TRUE(close(rows[0], k * (1 - u) * i1 * S, 1e-14));
	EXPECT_TRUE(close(rows[1], k * u * i2 * S, 1e-14));
	EXPECT_EQ(rows[2], 0.0);
	EXPECT_GE(maxOf(rows, 3) * (1 + 1e-12), exactOmega2({ 1 - u, u, -1 }, { i1, i2, 0 }, k));
}

TEST(ContactRows, PotentialSegmentOnAFixedBodyIsItsWorstPosition)
{
	// the worst position of a contact on a segment against a fixed body is on a node: k / m_a;
	// the exact omega^2 at any position u, k ((1-u)^2/m1 + u^2/m2), stays below the larger
	const double k = 9e8, m1 = 0.022, m2 = 0.011;
	RowSide      seg, fixedBody;
	seg.n              = 2;
	seg.invSqrtMass[0] = 1 / std::sqrt(m1);
	seg.invSqrtMass[1] = 1 / std::sqrt(m2);
	double rs[3], rf[3];
	potentialContactRows(seg, fixedBody, k, rs, rf);
	EXPECT_TRUE(close(rs[0], k / m1, 1e-14));
	EXPECT_TRUE(close(rs[1], k / m2, 1e-14));
	EXPECT_EQ(rf[0], 0.0);
	for (double u = 0; u <= 1; u += 0.125)
		EXPECT_GE(maxOf(rs, 2) * (1 + 1e-12), exactOmega2({ 1 - u, u }, { seg.invSqrtMass[0], seg.invSqrtMass[1] }, k));
	EXPECT_TRUE(close(maxOf(rs, 2), exactOmega2({ 0, 1 }, { seg.invSqrtMass[0], seg.invSqrtMass[1] }, k), 1e-12)); // tight at u = 1
}

TEST(ContactRows, PotentialRowsBoundEveryPositionOfEveryPair)
{
	// random pairs of rigid bodies, segments and facets (some bodies fixed), each contact
	// position drawn at random (a facet node's share up to its weight + kappa): the worst-position
	// rows bound the exact omega^2 of the contact there. Dropping the other side's sum, the
	// facet excess or a weight from the bound makes some draw exceed it.
	std::mt19937                           gen(7);
	std::uniform_real_distribution<double> U(0, 1);
	int                                    tight = 0;
	for (int trial = 0; trial < 20000; ++trial) {
		RowSide             side[2];
		std::vector<double> g, is;
		for (int s = 0; s < 2; ++s) {
			RowSide& sd = side[s];
			sd.n        = 1 + (int)(3 * U(gen));
			sd.kappa    = sd.n == 3 ? 0.5 * U(gen) : 0;
			for (int a = 0; a < sd.n; ++a)
				sd.invSqrtMass[a] = U(gen) < 0.15 ? 0 : 1 / std::sqrt(1e-3 + U(gen));
			// weights: 1; (1-u, u); barycentric, each share up to w + kappa
			double w[3] = { 1, 0, 0 };
			// a third of the draws at the extremes: on a node, every facet share at w + kappa,
			// equal masses
			const bool extreme = U(gen) < 0.33;
			if (extreme)
				for (int a = 1; a < sd.n; ++a)
					sd.invSqrtMass[a] = sd.invSqrtMass[0];
			if (sd.n == 2) {
				const double u = extreme ? (U(gen) < 0.5 ? 0 : 1) : U(gen);
				w[0] = 1 - u, w[1] = u;
			} else if (sd.n == 3) {
				double a = U(gen), b = U(gen);
				if (a + b > 1) a = 1 - a, b = 1 - b;
				if (extreme) a = b = 0;
				w[0] = 1 - a - b, w[1] = a, w[2] = b;
				for (int j = 0; j < 3; ++j)
					w[j] += sd.kappa * (extreme ? 1 : U(gen));
			}
			for (int a = 0; a < sd.n; ++a) {
				g.push_back(s ? -w[a] : w[a]);
				is.push_back(sd.invSqrtMass[a]);
			}
		}
		const double k = 1e3 + 1e6 * U(gen);
		double       ra[3], rb[3];
		potentialContactRows(side[0], side[1], k, ra, rb);
		const double bound = std::max(maxOf(ra, side[0].n), maxOf(rb, side[1].n));
		const double exact = exactOmega2(g, is, k);
		ASSERT_GE(bound * (1 + 1e-12), exact) << "trial " << trial;
		tight += exact > 0.9 * bound;
	}
	EXPECT_GT(tight, 50); // the bound is reached closely by some draws, not a loose multiple
}

TEST(ContactRows, ActiveRowsBoundTheExactEigenvalue)
{
	std::mt19937                           gen(11);
	std::uniform_real_distribution<double> U(0, 1);
	for (int trial = 0; trial < 2000; ++trial) {
		const int           n = 2 + (int)(5 * U(gen));
		std::vector<double> w(n), is(n);
		double              rows[6];
		for (int a = 0; a < n; ++a) {
			w[a]  = (a % 2 ? -1 : 1) * U(gen);
			is[a] = U(gen) < 0.2 ? 0 : 1 / std::sqrt(1e-3 + U(gen));
		}
		contactRows(w.data(), is.data(), n, 5e5, rows);
		ASSERT_GE(maxOf(rows, n) * (1 + 1e-12), exactOmega2(w, is, 5e5));
	}
}
