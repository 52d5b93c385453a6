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
	const auto near = [&](long i, int j) {
		const double reach = radius[i] + radius[j] + skin_;
		return (pos[j] - pos[i]).squaredNorm() < reach * reach;
	};
	std::vector<int> mine;
	for (long i = 0; i < n; ++i) {
		mine.clear();
		if (cellOf_[i] == cells) { // a large sphere: every sphere after it
			for (long j = i + 1; j < n; ++j)
				if (near(i, (int)j)) mine.push_back((int)j);
			second_.insert(second_.end(), mine.begin(), mine.end());
			first_[i + 1] = (long)second_.size();
			continue;
		}
		for (int j : large_)
			if (j > i && near(i, j)) mine.push_back(j);
		long c[3];
		cellIndex(pos[i], c);
		for (long dx = -1; dx <= 1; ++dx)
			for (long dy = -1; dy <= 1; ++dy)
				for (long dz = -1; dz <= 1; ++dz) {
					const long x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
					if (x < 0 || y < 0 || z < 0 || x >= nc[0] || y >= nc[1] || z >= nc[2]) continue;
					const long cell = (x * nc[1] + y) * nc[2] + z;
					for (long k = cellStart_[cell]; k < cellStart_[cell + 1]; ++k) {
						const int j = sorted_[k];
						if (j > i && near(i, j)) mine.push_back(j);
					}
				}
		std::sort(mine.begin(), mine.end());
		second_.insert(second_.end(), mine.begin(), mine.end());
		first_[i + 1] = (long)second_.size();
	}
}

} // namespace flex
