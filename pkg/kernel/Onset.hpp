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

} // namespace flex
