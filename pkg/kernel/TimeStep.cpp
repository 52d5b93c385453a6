// Critical time step (GPL-2.0-or-later). See TimeStep.hpp.
#include "TimeStep.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace flex {

double beamMaxOmega2(const BeamSection& s, double L, double mi, double mj, double Ii, double Ij)
{
	const Eigen::Matrix<double, 12, 12> K = beamStiffnessLocal(s, L);
	Eigen::Matrix<double, 12, 1>        d;
	d << mi, mi, mi, Ii, Ii, Ii, mj, mj, mj, Ij, Ij, Ij;
	const Eigen::Matrix<double, 12, 1>  w = d.cwiseSqrt().cwiseInverse();
	const Eigen::Matrix<double, 12, 12> A = w.asDiagonal() * K * w.asDiagonal();
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> es(A, Eigen::EigenvaluesOnly);
	return es.eigenvalues().maxCoeff();
}

double criticalTimeStep(double omega2) { return omega2 > 0 ? 2.0 / std::sqrt(omega2) : std::numeric_limits<double>::infinity(); }

} // namespace flex
