// Chain-link wire law: tension-only, piecewise-linear, with stochastic distortion (GPL-2.0-or-later).
//
// Input: the wire's stress-strain points (e_1, s_1) ... (e_n, s_n), e_k > 0 strictly increasing,
// s_k > 0; the origin is implied. The elastic modulus is the first secant Ew = s_1 / e_1.
// Forces are stresses times the wire area A; strains are elongations / L0.
//
// Distortion (Thoeni et al. 2013, Computers and Geotechnics 49:158-169, "type 2"): a real mesh
// wire is not straight, so a link first straightens (soft) before the wire itself is loaded.
// A link gets a slack strain d (drawn once, see wireSlackDraw) and a force ratio lf in (0, 1].
// Its envelope is the input curve shifted by d, reached through a soft initial branch:
//   (0, 0) -> A = (d + lf e_1, lf s_1) -> (d + e_1, s_1) -> (d + e_2, s_2) -> ... -> (d + e_n, s_n)
// (A is omitted when lf = 1: one soft segment from the origin to the shifted first knot). The
// segment from A to the first knot has the elastic slope Ew. With d = 0 the envelope is the input.
//
// Loading and unloading (state: maxStrain, the largest strain reached; plasticStrain):
//   e >= maxStrain : on the envelope, s = env(e); maxStrain = e; plasticStrain = e - s / Ew
//   e <  maxStrain : elastic, s = max(0, Ew (e - plasticStrain)); tension only
// so unloading and reloading follow the initial elastic slope Ew and rejoin the envelope at
// maxStrain, where they left it. Rupture: e > (d + e_n)(1 + 1e-9) (past the last point; the
// margin absorbs the round-off of a strain computed from positions). The link carries the
// last point's force at the step it breaks, and then stops interacting.
//
// Energy (per link, L0 A times the stress-strain quantities):
//   elastic (recoverable)  Ue = L0 A s^2 / (2 Ew)
//   dissipated             Dp(maxStrain) = L0 A [ W(maxStrain) - env(maxStrain)^2 / (2 Ew) ],
//                          W(e) = integral_0^e env: the area between the envelope and the
//                          unloading line. It grows only on the envelope; its increment is
//                          exact (piecewise-linear integral), so a load-unload cycle dissipates
//                          exactly the area the cycle encloses.
//   rupture                the elastic energy held at the last point, released when it breaks.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace flex {

/// Non-owning view of a validated stress-strain curve (the material's arrays, never modified).
struct WireCurve {
	const double* strain = nullptr; ///< e_1..e_n [-], strictly increasing, > 0
	const double* stress = nullptr; ///< s_1..s_n [Pa], > 0
	int           n      = 0;
	double        Ew     = 0; ///< stress[0] / strain[0] if the caller computed it once for many links, else 0
	double        elasticModulus() const { return Ew > 0 ? Ew : stress[0] / strain[0]; } ///< Ew [Pa]
};

/// Empty string if the curve is valid, else what is wrong with it (for a ValueError).
std::string wireCurveError(const std::vector<double>& strain, const std::vector<double>& stress);
/// Empty string if the distortion parameters are valid (slackScale >= 0, 0 < forceRatio <= 1).
std::string wireDistortionError(double slackScale, double forceRatio);

/// Per-link distortion (drawn once at creation).
struct WireDistortion {
	double slack      = 0; ///< d [-], slack strain
	double forceRatio = 1; ///< lf [-], force ratio of the soft branch's end point
};

/// What a wire link remembers.
struct WireState {
	double maxStrain     = 0; ///< [-] largest strain reached (on the envelope)
	double plasticStrain = 0; ///< [-] strain at zero force on the current unloading line
};

/// Knots of the distorted envelope, origin included (at most n + 2 points). Returns the count.
int wireEnvelopeKnots(const WireCurve& c, const WireDistortion& d, double* e, double* s);
/// Envelope stress at strain e [Pa] (the last point's stress beyond it).
double wireEnvelope(const WireCurve& c, const WireDistortion& d, double e);

/// Axial response of one link: strain = (L - L0)/L0, L0 [m], wire area [m^2]. Updates state.
struct WireAxial {
	double N             = 0;     ///< axial force [N]
	double elasticEnergy = 0;     ///< [J]
	double plasticWork   = 0;     ///< [J] this step
	bool   rupture       = false; ///< broke this step
};
/// On the envelope (strain > st.maxStrain): out of line.
WireAxial        wireAxialEnvelope(double strain, double L0, double area, const WireCurve& c, const WireDistortion& d, WireState& st);
inline WireAxial wireAxial(double strain, double L0, double area, const WireCurve& c, const WireDistortion& d, WireState& st)
{
	if (strain > st.maxStrain) return wireAxialEnvelope(strain, L0, area, c, d, st);
	// unloading or reloading below the largest strain reached: the elastic line, no envelope
	const double Ew = c.elasticModulus();
	const double s  = std::max(0.0, Ew * (strain - st.plasticStrain));
	WireAxial    r;
	r.N             = s * area;
	r.elasticEnergy = 0.5 * (L0 * area) * s * s / Ew;
	return r;
}

/// Uniform number in [0, 1) from a seed and a link's two node ids (order-independent):
/// a pure function, so the draw does not depend on threads, body order or O.reset().
double wireUniform(std::uint64_t seed, long nodeA, long nodeB, int stream);
/// Slack strain of a link: slackScale x xi, xi = (u1 + u2)/2 symmetric triangular on [0, 1]
/// with mode 1/2 (the distribution of Thoeni et al. 2013).
double wireSlackDraw(std::uint64_t seed, long nodeA, long nodeB, double slackScale);
/// CDF of xi (for tests and for checking samples).
double wireSlackCdf(double xi);

} // namespace flex
