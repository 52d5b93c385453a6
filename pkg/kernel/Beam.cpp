// Co-rotational beam (GPL-2.0-or-later). Derivation of the nodal forces.
//
// In the chord frame the transverse displacements of both ends vanish by construction, so
// only the end rotations relative to the chord, th_i and th_j, deform the beam in bending.
// The Euler-Bernoulli end moments acting ON the beam are (EI/L)(4 th_i + 2 th_j) and
// (EI/L)(2 th_i + 4 th_j) (e.g. Crisfield, Non-linear FE analysis of solids and structures,
// vol. 1, ch. 7); the nodes receive the opposite. The beam must also be in moment balance:
// M_i + M_j + (x_j - x_i) x F_j = 0 with F_i = -F_j. Because the moments are perpendicular to
// e, F_j = e x (M_i + M_j) / L solves it: L e x (e x M) = -L M for M perpendicular to e.
// The twist moments are +-GJ/L phi e and cancel; the axial pair lies on the chord.
#include "Beam.hpp"

#include <cmath>

namespace flex {

BeamSection BeamSection::circular(double young, double shearModulus, double radius, double bendingFactor)
{
	const double r2 = radius * radius, A = M_PI * r2, I = M_PI * r2 * r2 / 4.0;
	return { young * A, bendingFactor * young * I, bendingFactor * shearModulus * 2.0 * I };
}

AxialResult axialForce(double strain, double EA, double L0, const AxialLaw& law, AxialState& st)
{
	AxialResult  r;
	const double k = EA / L0; // [N/m]
	double       N = EA * (strain - st.plasticStrain);
	if (!law.tensionOnly || N > 0) {
		// return mapping on |N| <= Ny + H alpha, H = hardening * EA (force per unit strain)
		const double H = law.hardening * EA;
		const double f = std::abs(N) - (law.yieldForce + H * st.hardeningVar);
		if (f > 0) {
			const double dgamma = f / (EA + H); // plastic strain increment magnitude
			const double sgn    = N > 0 ? 1.0 : -1.0;
			// work of the plastic strain increment at the mean yield force (exact for linear hardening)
			r.plasticWork = (law.yieldForce + H * (st.hardeningVar + 0.5 * dgamma)) * dgamma * L0;
			N -= sgn * EA * dgamma;
			st.plasticStrain += sgn * dgamma;
			st.hardeningVar += dgamma;
		}
	}
	if (law.tensionOnly && N < 0) N = 0;
	r.N             = N;
	r.elasticEnergy = 0.5 * N * N / k;
	r.rupture       = (N >= law.ruptureForce) || (strain >= law.ruptureStrain);
	return r;
}

BeamRest makeBeamRest(const Vec3& xi, const Vec3& xj, const Quat& oi, const Quat& oj)
{
	BeamRest   r;
	const Vec3 d  = xj - xi;
	r.L0          = d.norm();
	const Quat R0 = Quat::FromTwoVectors(Vec3::UnitX(), d / r.L0);
	r.Qi          = (oi.conjugate() * R0).normalized();
	r.Qj          = (oj.conjugate() * R0).normalized();
	return r;
}

namespace {
	// theta = f(alpha) (e x a) takes unit vector e onto unit vector a (alpha the angle between
	// them, f = alpha / sin alpha); also h = f'(alpha) / sin alpha = (sin alpha - alpha cos
	// alpha) / sin^3 alpha, for the gradient. Bending angles of an element are usually small:
	// below sin^2 = 1e-4 the series f = 1 + s^2/6 + 3 s^4/40 and h = 1/3 + 2 s^2/15 + 31 s^4/315
	// (s = sin alpha) are exact to 5e-14 and need neither atan2 nor sqrt (the hot spots of the
	// element loop).
	struct Rot {
		Vec3   theta;
		double f, h;
	};
	inline Rot rotationBetween(const Vec3& e, const Vec3& a)
	{
		const Vec3   c  = e.cross(a);
		const double s2 = c.squaredNorm(), cs = e.dot(a);
		if (s2 < 1e-4 && cs > 0) {
			const double f = 1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0));
			return { f * c, f, 1.0 / 3.0 + s2 * (2.0 / 15.0 + s2 * (31.0 / 315.0)) };
		}
		const double s = std::sqrt(s2);
		if (s < 1e-300) return { Vec3::Zero(), 1, 1.0 / 3.0 }; // anti-parallel: undefined axis; cannot occur for a bonded element
		const double alpha = std::atan2(s, cs), f = alpha / s;
		return { f * c, f, (s - alpha * cs) / (s2 * s) };
	}
	// 2 atan(x / w) for w > 0; series below |x/w| = 1e-2 (error (x/w)^9/9 < 1e-18)
	inline double twoAtan(double x, double w)
	{
		if (w > 0 && std::abs(x) < 1e-2 * w) {
			const double t = x / w, t2 = t * t;
			return 2.0 * t * (1.0 - t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 / 7.0)));
		}
		return 2.0 * std::atan2(x, w);
	}
	// first column of the rotation matrix of unit quaternion q, i.e. q * (1, 0, 0)
	inline Vec3 xAxis(const Quat& q)
	{
		const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
		return Vec3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y));
	}
} // namespace

BeamKinematics beamKinematics(const Vec3& xi, const Vec3& xj, const Quat& oi, const Quat& oj, const BeamRest& rest)
{
	BeamKinematics k;
	const Chord    ch = chord(xi, xj);
	k.L               = ch.L;
	k.e               = ch.e;
	const Quat Ri = oi * rest.Qi, Rj = oj * rest.Qj;
	k.aI         = xAxis(Ri);
	k.aJ         = xAxis(Rj);
	const Rot ri = rotationBetween(k.e, k.aI), rj = rotationBetween(k.e, k.aJ);
	k.thetaI = ri.theta;
	k.thetaJ = rj.theta;
	k.fI     = ri.f;
	k.hI     = ri.h;
	k.fJ     = rj.f;
	k.hJ     = rj.h;
	// D = conj(Ri) Rj; the twist is 2 atan(Dx / Dw), the rotation of D about the element axis
	double Dw = Ri.w() * Rj.w() + Ri.x() * Rj.x() + Ri.y() * Rj.y() + Ri.z() * Rj.z();
	double Dx = Ri.w() * Rj.x() - Ri.x() * Rj.w() - Ri.y() * Rj.z() + Ri.z() * Rj.y();
	double Dy = Ri.w() * Rj.y() - Ri.y() * Rj.w() - Ri.z() * Rj.x() + Ri.x() * Rj.z();
	double Dz = Ri.w() * Rj.z() - Ri.z() * Rj.w() - Ri.x() * Rj.y() + Ri.y() * Rj.x();
	if (Dw < 0) { // shortest representation
		Dw = -Dw;
		Dx = -Dx;
		Dy = -Dy;
		Dz = -Dz;
	}
	k.twist = twoAtan(Dx, Dw);
	// its gradient: a rotation dphi of node i turns D into exp(-Ri^T dphi) D, of node j into
	// D exp(Rj^T dphi) (body frames); d(2 atan(x/w)) = 2 (w dx - x dw) / (w^2 + x^2)
	const double Q = Dw * Dw + Dx * Dx;
	if (Q > 0) {
		k.twistGradI = Ri * Vec3(-1, -(Dw * Dz + Dx * Dy) / Q, (Dw * Dy - Dx * Dz) / Q);
		k.twistGradJ = Rj * Vec3(1, (Dx * Dy - Dw * Dz) / Q, (Dw * Dy + Dx * Dz) / Q);
	} else { // a half turn about an axis normal to the element: the twist is undefined there
		k.twistGradI = -k.aI;
		k.twistGradJ = k.aJ;
	}
	return k;
}

BeamForces beamForces(const BeamKinematics& k, const BeamRest& rest, const BeamSection& s, const AxialLaw& law, AxialState& st)
{
	return beamForcesWithAxial(k, rest, s, axialForce((k.L - rest.L0) / rest.L0, s.EA, rest.L0, law, st));
}

BeamForces beamForcesWithAxial(const BeamKinematics& k, const BeamRest& rest, const BeamSection& s, const AxialResult& ax)
{
	BeamForces f;
	f.N             = ax.N;
	f.plasticWork   = ax.plasticWork;
	f.rupture       = ax.rupture;
	const double kb = s.EI / rest.L0, kt = s.GJ / rest.L0;
	// U = kb (2 thI.thI + 2 thI.thJ + 2 thJ.thJ) + kt tw^2 / 2; g = dU/dtheta at each end.
	// theta = f (e x a): with c = e x a, d theta = f (de x a + e x da) - h c (a.de + e.da), so
	// g.d theta = ve.de + va.da with ve = f (a x g) - h (g.c) a and va = f (g x e) - h (g.c) e.
	// A rotation dphi of the node moves its axis by da = dphi x a: its moment is -a x va; a
	// move of the nodes turns the chord by de = (I - e e^T)(dxj - dxi) / L. Small angles (f = 1,
	// a = e, g normal to e): M = -g, Fj = -e x (gI + gJ) / L, the linear beam.
	const Vec3   gI = kb * (4 * k.thetaI + 2 * k.thetaJ), gJ = kb * (2 * k.thetaI + 4 * k.thetaJ);
	const Vec3   cI = k.e.cross(k.aI), cJ = k.e.cross(k.aJ);
	const double gcI = gI.dot(cI), gcJ = gJ.dot(cJ);
	const Vec3   vaI = k.fI * gI.cross(k.e) - k.hI * gcI * k.e, vaJ = k.fJ * gJ.cross(k.e) - k.hJ * gcJ * k.e;
	const Vec3   ve = k.fI * k.aI.cross(gI) - k.hI * gcI * k.aI + k.fJ * k.aJ.cross(gJ) - k.hJ * gcJ * k.aJ;
	const Vec3   V  = -(ve - k.e.dot(ve) * k.e) / k.L;
	f.Fj            = -f.N * k.e + V;
	f.Fi            = -f.Fj;
	f.Mi            = -k.aI.cross(vaI) - kt * k.twist * k.twistGradI;
	f.Mj            = -k.aJ.cross(vaJ) - kt * k.twist * k.twistGradJ;
	f.elasticEnergy
	        = ax.elasticEnergy + kb * (2 * k.thetaI.squaredNorm() + 2 * k.thetaI.dot(k.thetaJ) + 2 * k.thetaJ.squaredNorm()) + 0.5 * kt * k.twist * k.twist;
	return f;
}

Eigen::Matrix<double, 12, 12> beamStiffnessLocal(const BeamSection& s, double L)
{
	Eigen::Matrix<double, 12, 12> K    = Eigen::Matrix<double, 12, 12>::Zero();
	auto                          pair = [&](int a, int b, double v) {
                K(a, a) += v;
                K(b, b) += v;
                K(a, b) -= v;
                K(b, a) -= v;
	};
	pair(0, 6, s.EA / L); // axial
	pair(3, 9, s.GJ / L); // twist
	const double k12 = 12 * s.EI / (L * L * L), k6 = 6 * s.EI / (L * L), k4 = 4 * s.EI / L, k2 = 2 * s.EI / L;
	// bending in the x-y plane: (v_i, rz_i, v_j, rz_j) = (1, 5, 7, 11), sign +1;
	// bending in the x-z plane: (w_i, ry_i, w_j, ry_j) = (2, 4, 8, 10), sign -1
	for (int plane = 0; plane < 2; ++plane) {
		const int    v1 = plane ? 2 : 1, r1 = plane ? 4 : 5, v2 = v1 + 6, r2 = r1 + 6;
		const double sg     = plane ? -1 : 1;
		const int    idx[4] = { v1, r1, v2, r2 };
		const double m[4][4]
		        = { { k12, sg * k6, -k12, sg * k6 }, { sg * k6, k4, -sg * k6, k2 }, { -k12, -sg * k6, k12, -sg * k6 }, { sg * k6, k2, -sg * k6, k4 } };
		for (int a = 0; a < 4; ++a)
			for (int b = 0; b < 4; ++b)
				K(idx[a], idx[b]) += m[a][b];
	}
	return K;
}

NodeShare cylinderNodeShare(double rho, double radius, double length)
{
	const double mh = 0.5 * rho * M_PI * radius * radius * length;
	return { mh, mh * (radius * radius / 4.0 + length * length / 12.0) };
}

} // namespace flex
