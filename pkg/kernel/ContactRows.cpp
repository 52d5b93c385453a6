// Contact rows of the critical time step (GPL-2.0-or-later). Derivation: ContactRows.hpp.
#include "ContactRows.hpp"

#include <algorithm>
#include <cmath>

namespace flex {

void contactRows(const double* w, const double* invSqrtMass, int n, double k, double* rows)
{
	double S = 0;
	for (int a = 0; a < n; ++a)
		S += std::abs(w[a]) * invSqrtMass[a];
	for (int a = 0; a < n; ++a)
		rows[a] = k * std::abs(w[a]) * invSqrtMass[a] * S;
}

void potentialContactRows(const RowSide& a, const RowSide& b, double k, double rowsA[3], double rowsB[3])
{
	const RowSide* side[2] = { &a, &b };
	double*        rows[2] = { rowsA, rowsB };
	double         iMax[2];
	for (int s = 0; s < 2; ++s) {
		iMax[s] = 0;
		for (int j = 0; j < side[s]->n; ++j)
			iMax[s] = std::max(iMax[s], side[s]->invSqrtMass[j]);
	}
	for (int s = 0; s < 2; ++s) {
		const RowSide& me = *side[s];
		const RowSide& ot = *side[1 - s];
		for (int j = 0; j < me.n; ++j) {
			const double i     = me.invSqrtMass[j];
			const double own   = (1 + me.kappa) * i + (me.n - 1) * me.kappa * iMax[s];
			const double other = iMax[1 - s] * (1 + ot.n * ot.kappa);
			rows[s][j]         = k * (1 + me.kappa) * i * (own + other);
		}
	}
}

} // namespace flex
