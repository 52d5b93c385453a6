// The neighbour list of a set of spheres (grains): every pair close enough to touch before any
// of them moves more than half the skin (GPL-2.0-or-later).
//
// A pair (i, j), i < j, is listed when |x_j - x_i| < r_i + r_j + skin. The list stays valid
// (no contact missed) while every sphere has moved less than skin / 2 from where it was at the
// build: two spheres then close their gap by less than the skin. The list is built by binning
// the centres into cubic cells of side at least 2 r_max + skin (every listed pair then lies in
// the same or adjacent cells), a counting sort of the spheres by cell (their centres and radii
// copied in that order), and a scan of each cell against itself and the 13 cells after it, which
// meets every pair once. A few spheres much larger than the rest (more than kLargeRatio times
// the median radius: a boulder on a bed) are left out of the cells, which would otherwise be sized
// by them, and paired with every sphere directly (LAMMPS's `multi` does the same by size classes):
// their pairs cost O(n) each per build. Pairs are stored sphere by sphere (CSR: the partners of i are
// second[first[i] .. first[i + 1]), ascending), so that a contact's state kept beside its pair
// can be carried from one list to the next by a merge (GrainContacts::follow).
#pragma once
#include "Types.hpp"

#include <utility>
#include <vector>

namespace flex {

class GrainNeighbours {
public:
	/// A sphere of a radius above this times the median radius is paired directly, not by cells.
	static constexpr double kLargeRatio = 4;
	/// skin > 0 [m]
	explicit GrainNeighbours(double skin);

	/// Whether the list must be built again before the next contact pass: no build yet, another
	/// number of spheres, or a sphere moved skin / 2 or more from its place at the last build.
	bool stale(const Vec3* pos, long n) const;
	/// The list of n spheres at positions pos with radii radius (all finite, radius > 0).
	void build(const Vec3* pos, const double* radius, long n);

	double skin() const { return skin_; }
	long   spheres() const { return (long)first_.size() - 1; }
	long   pairs() const { return (long)second_.size(); }
	long   builds() const { return builds_; }
	/// CSR: partners of i are second()[first()[i] .. first()[i + 1]), ascending, each > i.
	const std::vector<long>& first() const { return first_; }
	const std::vector<int>&  second() const { return second_; }
	/// How far sphere i (at pos[i]) may still move before the list is stale: skin / 2 less its
	/// distance from its place at the last build [m] (after a build of at least i + 1 spheres).
	double reach(const Vec3* pos, long i) const { return 0.5 * skin_ - (pos[i] - at_[i]).norm(); }

private:
	double            skin_;
	long              builds_ = 0;
	std::vector<Vec3> at_; // positions at the last build
	std::vector<long> first_ { 0 };
	std::vector<int>  second_;
	// the binning's work arrays (kept to avoid allocating at each build)
	std::vector<long> cellOf_, cellStart_;
	std::vector<int>  sorted_, large_;
	struct Packed {
		Vec3   x;
		double r;
	};
	std::vector<Packed>              packed_; // the spheres in cell order
	std::vector<std::pair<int, int>> found_;  // the pairs found, (lower, higher) index
};

} // namespace flex
