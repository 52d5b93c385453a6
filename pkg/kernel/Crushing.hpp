// A contact that yields at the load that splits a grain (GPL-2.0-or-later).
//
// A rock lump of size D pressed between two points splits at the point-load test's failure load
//     P = Is50 D^2 (D50 / D)^0.45,     D50 = 50 mm
// (ISRM 1985, "Suggested method for determining point load strength": the index Is = P / D^2,
// reduced to the size 50 mm by Is50 = (D / 50 mm)^0.45 Is).
//
// The normal spring of a grain contact stands in for the crushing of its grains: its force
// kn (overlap - plastic) never exceeds the limit P of the smaller grain; a step that would pass
// it moves the plastic overlap instead (the crushed material), so unloading and reloading are
// elastic from there. No tension: past the plastic overlap the force is 0.
// The work of the force over a step, by the leap-frog energy identity the trapezoid
// W = (F_old + F_new) (overlap_new - overlap_old) / 2, splits exactly into the change of the
// stored energy F^2 / (2 kn) and the dissipation
//     D = (F_old + F_new) (plastic_new - plastic_old) / 2,
// while the force follows F = kn (overlap - plastic) at both ends of the step.
#pragma once

namespace flex {

/// Point-load failure force [N] of a grain of diameter d [m] of rock of index is50 [Pa].
double pointLoadFailure(double d, double is50);

struct NormalYield {
	double force      = 0;     ///< new normal force magnitude [N], in [0, limit]
	double plastic    = 0;     ///< new plastic overlap [m]
	double dissipated = 0;     ///< this step [J]
	bool   yielding   = false; ///< the limit cut the force this step
};
/// One step of the normal spring of stiffness kn [N/m] that yields at limit [N]: overlap [m]
/// this step, plasticOld [m] and forceOld [N] of the step before (0, 0 for a new contact).
NormalYield yieldingNormalStep(double kn, double limit, double overlap, double plasticOld, double forceOld);

} // namespace flex
