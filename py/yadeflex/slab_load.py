"""The load on a slab as a field: vertical point forces on the slab (contact points, supports)
binned into a pressure map on a square grid, record by record; its peak, the load's centre, the
loaded radius and a radial profile. YADE-free (numpy; scipy for the filter):
yadeflex.module.impact feeds it the slab's forces at each record.

Definitions (DEFINITIONS gives them in words, as summary.json states them):

- Force on the slab: the vertical component, positive downward (onto the slab) [N]; negative
  where a support pulls up (a pinned node lifted by the structure).
- Grid: square cells of side `cell` [m], half-open: cell (i, j) holds the points with
  x0 + i cell <= x < x0 + (i + 1) cell and y0 + j cell <= y < y0 + (j + 1) cell (a point on an
  edge belongs to the cell to its right or above). Maps are arrays [i, j]: i along x, j along y.
- Cell pressure [Pa]: the forces of the points in the cell summed, divided by the cell's area.
- Points outside the grid are counted, not binned and not refused: their force is `outside`
  [N] of the record, so that a map's force plus `outside` is the record's whole force.
- Peak pressure: the largest cell pressure at any record; its cell's centre and its time.
- Load centre: the point of application of the resultant vertical force (the force-weighted
  mean of the points' positions) [m].
- Loaded radius: the smallest radius about the load centre within which the point forces sum to
  at least FRACTION (90%) of their total, for the point forces of the record where the total is
  largest (the slab force's peak) [m]. A single point force gives 0; a uniform pressure on a
  disc of radius R gives sqrt(0.9) R.
- Filtered maps: each cell's pressure over time through the force filter of the reported peaks
  (yadeflex.force_filter), so that a filtered map sums to the filtered total force.

- cell_size(grain_max): the cell side for a granular fill; Grid: the cells, and the points
  binned into them; Grid.covering: a grid over circular footprints with a margin.
- PressureSeries: the maps of successive records and what is taken from them (results).
- load_centre, cumulative_share, loaded_radius, radial_profile: of one record's point forces.
"""
import dataclasses
import math

import numpy as np

FRACTION = 0.9  # share of the slab force the loaded radius holds
CELL_GRAINS = 1.5  # cell side in largest grain diameters
CELL_STEP = 0.01  # [m] cell sides are whole multiples of this

DEFINITIONS = dict(
    slab_pressure="cell pressure: the vertical forces on the slab in a square cell (grain contacts at their contact points, the "
                  "supports of the structure's pinned nodes at the nodes; downward > 0) summed and divided by the cell's area [Pa]",
    slab_pressure_peak="the largest cell pressure at any record (raw records) [Pa]; slab_pressure_peak_at: its cell's centre [m], "
                       "slab_pressure_peak_time: its record's t (timeseries.csv's clock) [s]",
    slab_pressure_peak_filtered="the largest cell pressure after each cell's pressure over time is low-pass filtered with the "
                                "reported forces' filter (force_filter) [Pa]",
    slab_loaded_radius=f"the smallest radius about the load centre (the point of application of the resultant vertical force) "
                       f"within which the point forces on the slab sum to at least {100 * FRACTION:g}% of the slab force, at the "
                       f"record of the slab force's peak (slab_force_peak_time) [m]",
    slab_load_centre="the point of application of the resultant vertical force on the slab at the slab force's peak (x, y) [m]",
    slab_force_peak_time="the t of the record of the slab force's peak (timeseries.csv's clock) [s]: the record of the loaded "
                         "radius and of slab_pressure.csv's pressure_at_slab_peak",
    slab_pressure_cell="the cells' side [m]: 1.5 x the largest grain diameter, rounded up to whole centimetres (about two mean "
                       "grains: a cell holds a few grain contacts; a finer grid maps single contacts)",
    slab_force_outside_grid_max="the largest force on the slab outside the map's grid at any record [N] (counted, not mapped)",
)


def cell_size(grain_max, grains=CELL_GRAINS, step=CELL_STEP):
    """The cell side [m] for a fill whose largest grain is grain_max [m]: grains x grain_max
    rounded up to a whole multiple of step [m] (gravel 32-63 mm: 0.10 m; 60-80 mm: 0.12 m)."""
    if not (grain_max > 0 and math.isfinite(grain_max)):
        raise ValueError(f"cell_size: the largest grain must be a positive length [m], got {grain_max!r}")
    n = grains * grain_max / step
    return step * math.ceil(n - 1e-9 * max(1.0, n))  # (1.5 x 0.06 is 0.09, not 0.1, after round-off)


@dataclasses.dataclass(frozen=True)
class Grid:
    """nx x ny square cells of side cell [m], the lower left corner at (x0, y0) [m]."""
    x0: float
    y0: float
    cell: float
    nx: int
    ny: int

    def __post_init__(self):
        if not (self.cell > 0 and math.isfinite(self.cell)):
            raise ValueError(f"Grid: the cell side must be a positive length [m], got {self.cell!r}")
        if self.nx < 1 or self.ny < 1:
            raise ValueError(f"Grid: at least one cell each way, got {self.nx} x {self.ny}")

    @classmethod
    def covering(cls, centres, radius, cell, margin):
        """The grid over the discs of radius `radius` [m] about centres ((x, y) [m], at least one)
        widened by margin [m] each way, the first centre at a cell's centre."""
        c = np.asarray(centres, dtype=float).reshape(-1, 2)
        if len(c) == 0:
            raise ValueError("Grid.covering: no centre")
        lo, hi = c.min(axis=0) - radius - margin, c.max(axis=0) + radius + margin
        # cell edges at c0 + (k - 1/2) cell: the first centre in the middle of a cell
        # (an edge within round-off of the covered range's end: no further cell)
        k_lo = np.floor((lo - c[0]) / cell + 0.5 + 1e-9)
        k_hi = np.ceil((hi - c[0]) / cell + 0.5 - 1e-9)
        x0, y0 = np.round(c[0] + (k_lo - 0.5) * cell, 12)
        nx, ny = (k_hi - k_lo).astype(int)
        return cls(float(x0), float(y0), float(cell), int(nx), int(ny))

    @property
    def area(self):
        """A cell's area [m2]."""
        return self.cell * self.cell

    def edges(self):
        """The cell edges along x and along y [m] (nx + 1 and ny + 1 values)."""
        return self.x0 + self.cell * np.arange(self.nx + 1), self.y0 + self.cell * np.arange(self.ny + 1)

    def centres(self):
        """The cells' centres: arrays X, Y [m] of shape (nx, ny) (to 1e-12 m: -0.1, not -0.09999999999999998)."""
        xs = np.round(self.x0 + self.cell * (np.arange(self.nx) + 0.5), 12)
        ys = np.round(self.y0 + self.cell * (np.arange(self.ny) + 0.5), 12)
        return np.meshgrid(xs, ys, indexing="ij")

    def extent(self):
        """(x_min, x_max, y_min, y_max) [m]."""
        return self.x0, self.x0 + self.nx * self.cell, self.y0, self.y0 + self.ny * self.cell

    def bin(self, x, y, f):
        """The forces f [N] at the points (x, y) [m] summed per cell: (forces [N] of shape (nx, ny),
        the force of the points outside the grid [N]). Non-finite input: ValueError."""
        x, y, f = (np.asarray(v, dtype=float).reshape(-1) for v in (x, y, f))
        if not (x.shape == y.shape == f.shape):
            raise ValueError(f"Grid.bin: x, y and f must have one length, got {len(x)}, {len(y)}, {len(f)}")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y)) and np.all(np.isfinite(f))):
            raise ValueError("Grid.bin: the positions and forces must be finite")
        i = np.floor((x - self.x0) / self.cell)
        j = np.floor((y - self.y0) / self.cell)
        inside = (i >= 0) & (i < self.nx) & (j >= 0) & (j < self.ny)
        flat = (i[inside] * self.ny + j[inside]).astype(np.int64)
        forces = np.bincount(flat, weights=f[inside], minlength=self.nx * self.ny).reshape(self.nx, self.ny)
        return forces, float(f[~inside].sum())

    def cell_of(self, x, y):
        """(i, j) of the cell holding the point (x, y) [m], None outside the grid."""
        i, j = math.floor((x - self.x0) / self.cell), math.floor((y - self.y0) / self.cell)
        return (i, j) if 0 <= i < self.nx and 0 <= j < self.ny else None


def load_centre(x, y, f):
    """The point of application of the resultant of the vertical forces f [N] at (x, y) [m]: the
    force-weighted mean position [m]; None if the forces sum to zero or less."""
    x, y, f = (np.asarray(v, dtype=float).reshape(-1) for v in (x, y, f))
    total = f.sum()
    if not total > 0:
        return None
    return float((f * x).sum() / total), float((f * y).sum() / total)


def cumulative_share(x, y, f, centre):
    """The points' distances from centre [m], increasing, and the share of the forces f [N] within
    each (its own included) [-]; None if the forces sum to zero or less."""
    x, y, f = (np.asarray(v, dtype=float).reshape(-1) for v in (x, y, f))
    total = f.sum()
    if not total > 0:
        return None
    d = np.hypot(x - centre[0], y - centre[1])
    order = np.argsort(d, kind="stable")
    return d[order], np.cumsum(f[order]) / total


def loaded_radius(x, y, f, fraction=FRACTION, centre=None):
    """The smallest distance r [m] from centre (default: load_centre) such that the forces f [N]
    of the points (x, y) [m] within r sum to at least `fraction` of all of them (the points
    themselves, no interpolation between them). None if the forces sum to zero or less."""
    if not 0 < fraction <= 1:
        raise ValueError(f"loaded_radius: the fraction must be in (0, 1], got {fraction!r}")
    centre = centre if centre is not None else load_centre(x, y, f)
    cum = cumulative_share(x, y, f, centre) if centre is not None else None
    if cum is None:
        return None
    d, share = cum
    # (a relative 1e-12: a share reached only after the round-off of the running sum)
    return float(d[int(np.argmax(share >= fraction * (1 - 1e-12)))])


def radial_profile(x, y, f, centre, width, r_max):
    """The point forces f [N] at (x, y) [m] in rings of width [m] about centre, out to r_max [m]:
    (the rings' inner radii [m], the mean pressure in each ring [Pa]: its force over its area,
    the share of the total force within each ring's outer radius [-])."""
    x, y, f = (np.asarray(v, dtype=float).reshape(-1) for v in (x, y, f))
    n = max(1, int(math.ceil(r_max / width - 1e-9)))
    r_in = width * np.arange(n)
    d = np.hypot(x - centre[0], y - centre[1])
    k = np.floor(d / width).astype(np.int64)
    ring = np.bincount(k[k < n], weights=f[k < n], minlength=n)[:n]
    area = math.pi * ((r_in + width) ** 2 - r_in ** 2)
    total = f.sum()
    share = np.cumsum(ring) / total if total != 0 else np.zeros(n)
    return r_in, ring / area, share


class PressureSeries:
    """The pressure maps of successive records on one grid. add(t, x, y, f) for each record (t
    increasing [s], the vertical point forces f [N] at (x, y) [m]); the point forces of the
    record with the largest total are kept (for the loaded radius and the radial profile)."""

    def __init__(self, grid):
        self.grid = grid
        self.t, self._forces, self.outside, self.total = [], [], [], []
        self.peak_points = None  # (x, y, f) of the record with the largest total
        self.peak_index = None

    def __len__(self):
        return len(self.t)

    def add(self, t, x, y, f):
        """One record's point forces; returns its total force [N] (in the grid and outside)."""
        forces, outside = self.grid.bin(x, y, f)
        total = float(forces.sum() + outside)
        self.t.append(float(t))
        self._forces.append(forces)
        self.outside.append(outside)
        self.total.append(total)
        if self.peak_index is None or total > self.total[self.peak_index]:
            self.peak_index = len(self.t) - 1
            self.peak_points = tuple(np.array(v, dtype=float).reshape(-1) for v in (x, y, f))
        return total

    def forces(self):
        """The cells' forces [N] of every record: shape (records, nx, ny)."""
        return np.array(self._forces).reshape(len(self._forces), self.grid.nx, self.grid.ny)

    def pressures(self):
        """The cells' pressures [Pa] of every record: shape (records, nx, ny)."""
        return self.forces() / self.grid.area

    def filtered_pressures(self, low_pass):
        """The pressures with each cell's history through low_pass(t, values) (a linear filter,
        yadeflex.force_filter.low_pass; cells that never carry a force stay 0); ValueError from
        low_pass (too few records) passes on."""
        p = self.pressures()
        out = np.zeros_like(p)
        flat, res = p.reshape(len(p), -1), out.reshape(len(p), -1)
        for c in np.flatnonzero(np.any(flat != 0, axis=0)):
            res[:, c] = low_pass(self.t, flat[:, c])
        return out

    def results(self, low_pass=None, fraction=FRACTION):
        """What the maps give (None where no record has a positive total):
        peak [Pa], peak_at (x, y) [m], peak_time [s] (DEFINITIONS); peak_map [Pa] (nx, ny): each
        cell's largest pressure over the records, peak_map_time [s]: when (NaN: a cell never
        loaded); at_peak [Pa] (nx, ny):
        the map of the record with the largest total force, at_peak_time [s], at_peak_force
        [N]; centre (x, y) [m] and loaded_radius [m] of that record; outside_max [N]; with
        low_pass: filtered_peak [Pa], filtered_peak_at, filtered_peak_time, filtered_peak_map [Pa],
        filtered [Pa] (records, nx, ny): every filtered map (or None and filter_error, the reason,
        if the records are too few)."""
        g = self.grid
        out = dict(cell=g.cell, fraction=fraction, records=len(self.t))
        if not self.t:
            return out
        p = self.pressures()
        X, Y = g.centres()
        k, i, j = np.unravel_index(int(np.argmax(p)), p.shape)
        peak_map = p.max(axis=0)
        out.update(peak=float(p[k, i, j]), peak_at=(float(X[i, j]), float(Y[i, j])), peak_time=self.t[k],
                   peak_map=peak_map, peak_map_time=np.where(np.any(p != 0, axis=0), np.asarray(self.t)[np.argmax(p, axis=0)], np.nan),
                   outside_max=float(max(abs(v) for v in self.outside)))
        kp = self.peak_index
        x, y, f = self.peak_points
        centre = load_centre(x, y, f)
        out.update(at_peak=p[kp], at_peak_time=self.t[kp], at_peak_force=self.total[kp], centre=centre,
                   loaded_radius=loaded_radius(x, y, f, fraction, centre) if centre is not None else None)
        if low_pass is not None:
            try:
                pf = self.filtered_pressures(low_pass)
                kf, i, j = np.unravel_index(int(np.argmax(pf)), pf.shape)
                out.update(filtered_peak=float(pf[kf, i, j]), filtered_peak_at=(float(X[i, j]), float(Y[i, j])),
                           filtered_peak_time=self.t[kf], filtered_peak_map=pf.max(axis=0), filtered=pf)
            except ValueError as e:
                out.update(filtered_peak=None, filtered_peak_at=None, filtered_peak_time=None, filtered_peak_map=None, filtered=None,
                           filter_error=str(e))
        return out
