// GrainNeighbours (GPL-2.0-or-later): see GrainNeighbours.hpp.
#include "GrainNeighbours.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flex {

GrainNeighbours::GrainNeighbours(double skin)
        : skin_(skin)
{
	if (!(skin > 0) || !std::isfinite(skin)) throw std::invalid_argument("GrainNeighbours: the skin must be finite and positive");
}

bool GrainNeighbours::stale(const Vec3* pos, long n) const
{
	if (builds_ == 0 || n != (long)at_.size()) return true;
	const double limit2 = 0.25 * skin_ * skin_;
	for (long i = 0; i < n; ++i)
		if ((pos[i] - at_[i]).squaredNorm() >= limit2) return true;
	return false;
}

void GrainNeighbours::build(const Vec3* pos, const double* radius, long n)
{
	at_.assign(pos, pos + n);
	first_.assign(n + 1, 0);
	second_.clear();
	++builds_;
	if (n == 0) return;
	// the spheres much larger than the rest (kLargeRatio x the median radius) are paired with
	// every sphere directly; the others go into cells sized by the largest of them
	std::vector<double> r(radius, radius + n);
	std::nth_element(r.begin(), r.begin() + n / 2, r.end());
	const double large = kLargeRatio * r[n / 2];
	large_.clear();
	Vec3   lo = pos[0], hi = pos[0];
	double rMax = 0;
	for (long i = 0; i < n; ++i) {
		lo = lo.cwiseMin(pos[i]);
		hi = hi.cwiseMax(pos[i]);
		if (radius[i] > large)
			large_.push_back((int)i);
		else
			rMax = std::max(rMax, radius[i]);
	}
	// cells of side h >= 2 rMax + skin; no more than about 8 cells per sphere (a sparse set)
	double     h    = 2 * rMax + skin_;
	const Vec3 span = hi - lo;
	long       nc[3];
	for (;;) {
		for (int a = 0; a < 3; ++a)
			nc[a] = (long)std::floor(span[a] / h) + 1;
		if ((double)nc[0] * nc[1] * nc[2] <= 8.0 * n + 27) break;
		h *= 2;
	}
	const long cells     = nc[0] * nc[1] * nc[2];
	auto       cellIndex = [&](const Vec3& x, long c[3]) {
                for (int a = 0; a < 3; ++a)
                        c[a] = std::min(nc[a] - 1, std::max(0L, (long)std::floor((x[a] - lo[a]) / h)));
	};
	cellOf_.resize(n);
	cellStart_.assign(cells + 1, 0);
	for (long i = 0; i < n; ++i) {
		long c[3];
		cellIndex(pos[i], c);
		cellOf_[i] = radius[i] > large ? cells : (c[0] * nc[1] + c[1]) * nc[2] + c[2]; // (large: in no cell)
		if (cellOf_[i] < cells) ++cellStart_[cellOf_[i] + 1];
	}
	for (long c = 0; c < cells; ++c)
		cellStart_[c + 1] += cellStart_[c];
	sorted_.resize(n);
	{
		std::vector<long> fill(cellStart_.begin(), cellStart_.end() - 1);
		for (long i = 0; i < n; ++i)
			if (cellOf_[i] < cells) sorted_[fill[cellOf_[i]]++] = (int)i;
	}
	// the spheres in cell order, centre and radius side by side: a cell's spheres are read as one
	// stream
	const long inCells = cellStart_[cells];
	packed_.resize(inCells);
	for (long k = 0; k < inCells; ++k) {
		const int j = sorted_[k];
		packed_[k]  = Packed { pos[j], radius[j] };
	}
	// every pair is met once: from the sphere earlier in cell order, in its own cell and in the 13
	// cells after its cell (the half of the 26 neighbours whose offset comes first in x, then y,
	// then z). Cells adjacent in z are adjacent in that order, so the 13 cells are 5 runs: the next
	// cell of the column, and the three cells about z of columns (x, y + 1), (x + 1, y - 1 .. y + 1).
	// |x_j - x_i|^2 and r_i + r_j + skin are the same either way round, so the list is that of
	// testing every pair (i, j), i < j.
	found_.clear();
	const auto add  = [&](int p, int q) { found_.push_back(p < q ? std::make_pair(p, q) : std::make_pair(q, p)); };
	const auto near = [&](const Packed& a, const Packed& b) {
		const double reach = a.r + b.r + skin_;
		return (b.x - a.x).squaredNorm() < reach * reach;
	};
	static const int kColumns[4][2] = { { 0, 1 }, { 1, -1 }, { 1, 0 }, { 1, 1 } };
	for (long x = 0; x < nc[0]; ++x)
		for (long y = 0; y < nc[1]; ++y)
			for (long z = 0; z < nc[2]; ++z) {
				const long cell = (x * nc[1] + y) * nc[2] + z, b = cellStart_[cell], e = cellStart_[cell + 1];
				if (b == e) continue;
				long run[4][2];
				int  nRun = 0;
				for (const auto& o : kColumns) {
					const long x2 = x + o[0], y2 = y + o[1];
					if (x2 >= nc[0] || y2 < 0 || y2 >= nc[1]) continue;
					const long c2   = (x2 * nc[1] + y2) * nc[2];
					const long from = cellStart_[c2 + std::max(0L, z - 1)], to = cellStart_[c2 + std::min(nc[2] - 1, z + 1) + 1];
					if (from == to) continue;
					run[nRun][0]   = from;
					run[nRun++][1] = to;
				}
				const long columnEnd = cellStart_[cell + (z + 1 < nc[2] ? 2 : 1)]; // this cell and the next in z
				for (long k = b; k < e; ++k) {
					const Packed& a = packed_[k];
					const int     i = sorted_[k];
					for (long k2 = k + 1; k2 < columnEnd; ++k2)
						if (near(a, packed_[k2])) add(i, sorted_[k2]);
					for (int o = 0; o < nRun; ++o)
						for (long k2 = run[o][0]; k2 < run[o][1]; ++k2)
							if (near(a, packed_[k2])) add(i, sorted_[k2]);
				}
			}
	// the large spheres with every other sphere (two large ones: from the lower id)
	for (int i : large_) {
		const Packed a { pos[i], radius[i] };
		for (long j = 0; j < n; ++j)
			if (j != i && !(cellOf_[j] == cells && j < i) && near(a, Packed { pos[j], radius[j] })) add(i, (int)j);
	}
	// CSR by the first sphere, each row ascending
	for (const auto& p : found_)
		++first_[p.first + 1];
	for (long i = 0; i < n; ++i)
		first_[i + 1] += first_[i];
	second_.resize(found_.size());
	{
		std::vector<long> fill(first_.begin(), first_.end() - 1);
		for (const auto& p : found_)
			second_[fill[p.first]++] = p.second;
	}
	for (long i = 0; i < n; ++i)
		std::sort(second_.begin() + first_[i], second_.begin() + first_[i + 1]);
}

} // namespace flex
