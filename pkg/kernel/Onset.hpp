// The normal spring of a contact with a deformable element: how it starts, and what it holds
// while a wire pierces a facet (GPL-2.0-or-later).
//
// A contact passes from element to element as bodies move (kernel/Ownership.hpp); a clean
// hand-over passes the overlap on. Where a contact starts overlapping without one (its
// predecessor carried less: a fold; or it had none: a cluster that split, a pair found late),
// a spring k d would bring 1/2 k d^2 from nothing. So the contact takes over its predecessor's
// normal force F and no more: the part of its overlap beyond F / k is an offset that carries no
// force,
//     force = k max(0, d - offset),   offset = max(0, d_onset - F / k)   (F = 0: no predecessor),
// and the offset shrinks with the overlap (never above it), so the spring starts with the
// predecessor's energy F^2 / (2 k) and loads and unloads elastically from there.
//
// A wire whose axis pierces a facet: the closest points meet at the piercing point, so the
// overlap is the reach wherever the wire goes while it pierces. A force there would work with
// no change of the spring's energy (energy from nothing, or lost), so the spring carries none
// and holds the energy it had when the wire got there; it gives it back as the wire comes out.
//
// The energy that goes with a hand-over. Leap-frog keeps H = 1/2 v(n-1/2) M v(n+1/2) + U(x_n)
// constant while every force is integrated exactly by the trapezoid rule (kernel/Crossing.hpp).
// A contact that ends at step n+1 while overlapping had force F_n at x_n and none at x_n+1: H
// loses 1/2 F_n d_n+1 (d the overlap beyond the offset), what the contact takes with it. A
// contact that starts at step n+1 by taking over a force F has energy 1/2 F d_n+1 at once, of
// which the trapezoid puts only 1/2 F (d_n+1 - approach dt) into H from the bodies: it brings
// 1/2 F (d_n+1 - approach dt). Booked as they happen, a hand-over nets to F (d_n+1 - d_n), the
// work the successor's force skips by starting where its predecessor stood a step earlier, and
// two contacts merging into one leave the spring of the one that ended: H plus the booked terms
// stays constant.
#pragma once

namespace flex {

/// Offset of a contact that starts at overlap depth [m], taking over a predecessor's normal
/// force taken [N] (0: none), on a spring of stiffness k [N/m].
double onsetOffset(double k, double depth, double taken);

/// The offset after a step at overlap depth [m]: never above the overlap, never below 0.
double shrinkOffset(double offset, double depth);

struct NormalSpring {
	double force  = 0; ///< repulsive normal force [N]
	double energy = 0; ///< energy the spring holds [J]
};
/// The normal spring of stiffness k [N/m] at overlap depth [m] with offset [m]: force
/// k max(0, depth - offset), energy 1/2 k max(0, depth - offset)^2; while pierced, no force
/// and the same energy.
NormalSpring normalSpring(double k, double depth, double offset, bool pierced);

/// Energy [J] a contact takes with it when it ends at overlap beyond its offset d [m] (this
/// step's) after carrying normal force F [N] at its last step: 1/2 F max(0, d).
double releasedEnergy(double force, double d);

/// Energy [J] a contact brings when it starts by taking over its predecessor's force: force F
/// [N] at overlap beyond its offset d [m], approaching at speed approach [m/s] over step dt [s]:
/// 1/2 F max(0, d - approach dt).
double takenOverEnergy(double force, double d, double approach, double dt);

} // namespace flex
