// Chain-link wire law (GPL-2.0-or-later). Model and energies: see WireLaw.hpp.
#include "WireLaw.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flex {

namespace {
	constexpr int kMaxPoints = 62; // envelope knots fit in fixed arrays of kMaxPoints + 2
	// A strain computed from node positions carries round-off (~1e-16 / strain): a wire driven
	// exactly to its last point must not break there.
	constexpr double kRuptureRelTol = 1e-9;

	std::string str(double v)
	{
		std::ostringstream os;
		os.precision(6);
		os << v;
		return os.str();
	}

	// Stress s and area W = integral_0^e s on the envelope given by knots (ke, ks)[0..m)
	// (ke[0] = 0); e is clamped to [0, ke[m-1]].
	void envelopeAt(const double* ke, const double* ks, int m, double e, double& s, double& W)
	{
		s = 0;
		W = 0;
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
	}
} // namespace

std::string wireCurveError(const std::vector<double>& strain, const std::vector<double>& stress)
{
	if (strain.size() != stress.size())
		return "wire curve: " + std::to_string(strain.size()) + " strains but " + std::to_string(stress.size()) + " stresses";
	const size_t n = strain.size();
	if (n < 2) return "wire curve: needs at least two points (the origin is implied), got " + std::to_string(n);
	if (n > (size_t)kMaxPoints) return "wire curve: at most " + std::to_string(kMaxPoints) + " points, got " + std::to_string(n);
	for (size_t k = 0; k < n; ++k) {
		if (!std::isfinite(strain[k]) || !std::isfinite(stress[k])) return "wire curve: point " + std::to_string(k) + " is not finite";
		if (strain[k] <= 0) return "wire curve: strain of point " + std::to_string(k) + " must be positive, got " + str(strain[k]);
		if (stress[k] <= 0) return "wire curve: stress of point " + std::to_string(k) + " must be positive, got " + str(stress[k]);
		if (k > 0 && strain[k] <= strain[k - 1])
			return "wire curve: strain must increase strictly, but point " + std::to_string(k) + " (" + str(strain[k]) + ") <= point "
			        + std::to_string(k - 1) + " (" + str(strain[k - 1]) + ")";
	}
	// A segment stiffer than the elastic (unloading) slope would make the dissipation decrease
	// along the envelope (dDp/de = s (1 - s'/Ew) < 0): physically inadmissible.
	const double Ew = stress[0] / strain[0];
	for (size_t k = 1; k < n; ++k) {
		const double slope = (stress[k] - stress[k - 1]) / (strain[k] - strain[k - 1]);
		if (slope > Ew * (1 + 1e-12))
			return "wire curve: segment " + std::to_string(k - 1) + "-" + std::to_string(k) + " has slope " + str(slope)
			        + " Pa, stiffer than the elastic slope stress[0]/strain[0] = " + str(Ew) + " Pa used for unloading";
	}
	return "";
}

std::string wireDistortionError(double slackScale, double forceRatio)
{
	if (!(slackScale >= 0) || !std::isfinite(slackScale)) return "wire slack scale must be >= 0 and finite, got " + str(slackScale);
	if (!(forceRatio > 0 && forceRatio <= 1)) return "wire force ratio must be in (0, 1], got " + str(forceRatio);
	return "";
}

int wireEnvelopeKnots(const WireCurve& c, const WireDistortion& d, double* e, double* s)
{
	int m = 0;
	e[m]  = 0;
	s[m]  = 0;
	++m;
	if (d.slack > 0 && d.forceRatio < 1) {
		e[m] = d.slack + d.forceRatio * c.strain[0];
		s[m] = d.forceRatio * c.stress[0];
		++m;
	}
	for (int k = 0; k < c.n; ++k, ++m) {
		e[m] = d.slack + c.strain[k];
		s[m] = c.stress[k];
	}
	return m;
}

double wireEnvelope(const WireCurve& c, const WireDistortion& d, double e)
{
	double    ke[kMaxPoints + 2], ks[kMaxPoints + 2], s, W;
	const int m = wireEnvelopeKnots(c, d, ke, ks);
	envelopeAt(ke, ks, m, e, s, W);
	return s;
}

WireAxial wireAxialEnvelope(double strain, double L0, double area, const WireCurve& c, const WireDistortion& d, WireState& st)
{
	WireAxial    r;
	const double Ew  = c.elasticModulus();
	const double vol = L0 * area; // stress x strain -> energy [J]
	// the envelope's knots (wireEnvelopeKnots) generated on the fly, without copying them
	const bool soft = d.slack > 0 && d.forceRatio < 1;
	const int  m    = c.n + (soft ? 2 : 1);
	auto       knot = [&](int j, double& e, double& s) {
                if (j == 0)
                        e = s = 0;
                else if (soft && j == 1) {
                        e = d.slack + d.forceRatio * c.strain[0];
                        s = d.forceRatio * c.stress[0];
                } else {
                        const int k = j - (soft ? 2 : 1);
                        e           = d.slack + c.strain[k];
                        s           = c.stress[k];
                }
	};
	const double eLast = d.slack + c.strain[c.n - 1];
	r.rupture          = strain > eLast * (1 + kRuptureRelTol);
	// stress s and area W = integral_0^x env at x = maxStrain and at x = e >= maxStrain, in one
	// pass over the segments (the same operations, in the same order, as envelopeAt at each x)
	const double q[2]  = { st.maxStrain, std::min(strain, eLast) };
	double       qs[2] = { 0, 0 }, qw[2] = { 0, 0 };
	int          next = 0;
	while (next < 2 && q[next] <= 0)
		++next;
	double W = 0, e0, s0;
	knot(0, e0, s0);
	for (int j = 1; j < m && next < 2; ++j) {
		double e1, s1;
		knot(j, e1, s1);
		for (; next < 2 && (q[next] <= e1 || j == m - 1); ++next) {
			const double x = std::min(q[next], e1);
			qs[next]       = s0 + (s1 - s0) * (x - e0) / (e1 - e0);
			qw[next]       = W + 0.5 * (s0 + qs[next]) * (x - e0);
		}
		W += 0.5 * (s0 + s1) * (e1 - e0);
		e0 = e1;
		s0 = s1;
	}
	const double e = q[1], s = qs[1], sOld = qs[0];
	// dissipation Dp = W - s^2/(2 Ew): its increment is exact for any step size
	r.plasticWork    = vol * ((qw[1] - 0.5 * s * s / Ew) - (qw[0] - 0.5 * sOld * sOld / Ew));
	st.maxStrain     = e;
	st.plasticStrain = e - s / Ew;
	r.N              = s * area;
	r.elasticEnergy  = 0.5 * vol * s * s / Ew;
	return r;
}

namespace {
	inline std::uint64_t splitmix64(std::uint64_t x)
	{
		x += 0x9e3779b97f4a7c15ULL;
		x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
		x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
		return x ^ (x >> 31);
	}
} // namespace

double wireUniform(std::uint64_t seed, long nodeA, long nodeB, int stream)
{
	const std::uint64_t lo = (std::uint64_t)std::min(nodeA, nodeB), hi = (std::uint64_t)std::max(nodeA, nodeB);
	std::uint64_t       h = splitmix64(seed);
	h                     = splitmix64(h ^ lo);
	h                     = splitmix64(h ^ (hi * 0x632be59bd9b4e019ULL));
	h                     = splitmix64(h ^ (std::uint64_t)stream);
	return (double)(h >> 11) * 0x1.0p-53;
}

double wireSlackDraw(std::uint64_t seed, long nodeA, long nodeB, double slackScale)
{
	const double xi = 0.5 * (wireUniform(seed, nodeA, nodeB, 0) + wireUniform(seed, nodeA, nodeB, 1));
	return slackScale * xi;
}

double wireSlackCdf(double xi)
{
	if (xi <= 0) return 0;
	if (xi <= 0.5) return 2 * xi * xi;
	if (xi < 1) return 1 - 2 * (1 - xi) * (1 - xi);
	return 1;
}

} // namespace flex
