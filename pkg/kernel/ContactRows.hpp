// Contact rows of the critical time step: Gershgorin row sums of M^-1/2 K M^-1/2 for contact
// springs whose force is spread over element nodes.
//
// A contact of stiffness k (k = max(kn, ks), any direction) whose force goes to the DOF bodies
// a with weights w_a (w on one side, -w on the other: linear shape functions on a segment,
// barycentric shares on a facet, 1 for a rigid body) adds K = k g g^T to the stiffness, with
// g_a = w_a in the direction of the force. Scaled by the masses, the entries are
// k (w_a / sqrt(m_a)) (w_b / sqrt(m_b)); Gershgorin bounds omega^2 by the largest row sum,
//     row_a = k |w_a| i_a S,   i_a = 1/sqrt(m_a),   S = sum_b |w_b| i_b,
// summed over the contacts loading a (TimeStep.hpp: the bounds of bonds and contacts add).
// A body of infinite mass (fixed, i = 0) has no row and adds nothing to the others' S.
//
// A pair that may carry a contact before the next estimate (a potential pair, or a contact not
// carrying force now) counts with its worst weights: row_a is largest when the contact sits on
// node a, w_a = 1, and the other side puts its whole weight on its heaviest-loaded node (the
// lightest, largest i). A facet node's share of the force can exceed its barycentric weight
// by kappa = (triangle load factor - 1) (Triangle.hpp), so on a facet side every node carries
// up to w_a + kappa:
//     own_a  = (1 + kappa) i_a + (n - 1) kappa i_max        (its own side's sum)
//     other  = i_max' (1 + n' kappa')                        (the other side's sum)
//     row_a += k (1 + kappa) i_a (own_a + other)
// Reference: Gershgorin's circle theorem; Irons' element bound for the bonds (TimeStep.hpp).
#pragma once

namespace flex {

/// One side of a contact for its time-step rows: the n DOF bodies it loads (1 rigid body,
/// 2 segment nodes, 3 facet nodes), their 1/sqrt(m) [1/sqrt(kg)] (0: infinite mass, no row),
/// and the excess kappa [-] of a node's share over its weight (facets; 0 otherwise).
struct RowSide {
	int    n              = 1;
	double invSqrtMass[3] = { 0, 0, 0 };
	double kappa          = 0;
};

/// Row increments rows[a] [1/s^2] of a contact of stiffness k [N/m] loading the n DOF bodies
/// with weights w[a] [-] (both sides' together) and 1/sqrt(m) invSqrtMass[a].
void contactRows(const double* w, const double* invSqrtMass, int n, double k, double* rows);

/// Row increments [1/s^2] of a pair that may carry a contact of stiffness k [N/m] before the
/// next estimate, each node at its worst position: rowsA[a] for side a's nodes, rowsB for b's.
void potentialContactRows(const RowSide& a, const RowSide& b, double k, double rowsA[3], double rowsB[3]);

} // namespace flex
