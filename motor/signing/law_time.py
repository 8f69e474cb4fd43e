"""The law time of many dense wrist paths, in a few compiled passes over all their points.

:func:`motor.signing.lmp.law_fractions` of one path is a few dozen numpy calls on arrays of
tens of points — chords, turning angles, the soft clamp of the curvature, a grid of
``LAW_SMOOTHING / 4`` steps along the arc, ``np.interp`` onto it, scipy's
``gaussian_filter1d`` (mode ``"nearest"``), ``np.interp`` back and the trapezoid sum — and
a collection of signs has thousands of such paths. :class:`DensePaths` holds them all in
one array of points, and each of those steps runs once over all of them: the loops (sums,
interpolation, smoothing) compiled with the one-path function's operations in its order —
numpy's pairwise sum where numpy sums, ``einsum``'s order for a dot product, scipy's order
for the kernel's terms — and the transcendental functions (arccos, the clamp's powers, log,
exp) by numpy over the whole array, as numba's may differ from numpy's in the last bit.
The fractions are the one-path function's, bit for bit
(``tests/perf_equivalence/test_path_batch.py`` pins it).
"""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np

from motor.kernel_types import READ1, READ2, READ_INTS1, WRITE1, WRITE2, WRITE_INTS1
from motor.signing.lmp import LAW_SMOOTHING, NEGLIGIBLE
from motor.trajectory.power_law import EXPONENT, clamped_curvature
from motor.trajectory.spline import DEGENERATE_CHORD

#: Truncation of the Gaussian kernel in standard deviations (``gaussian_filter1d``'s default).
_TRUNCATE = 4.0
#: numpy's pairwise summation: blocks summed in eight lanes, and up to this many at once.
_PAIRWISE_BLOCK = 128

_jit = numba.njit(cache=True, error_model="numpy")


class DensePaths:
    """Paths ``(m, 3)`` (metres) laid end to end: ``points (n, 3)``, path ``i`` at rows
    ``starts[i]:starts[i + 1]``; their chords (the ``m − 1`` of each path from its first
    row on, 0 in its last row) and the arc length (m) at each point."""

    def __init__(self, points: np.ndarray, starts: np.ndarray) -> None:
        self.points = np.ascontiguousarray(points, dtype=float)
        self.starts = np.ascontiguousarray(starts, dtype=np.int64)
        self.chords = np.empty(self.points.shape[0])
        self.arc = np.empty(self.points.shape[0])
        _chords_and_arcs(self.points, self.starts, self.chords, self.arc)

    @classmethod
    def of(cls, paths: Sequence[np.ndarray]) -> DensePaths:
        """The paths ``(m, 3)`` laid end to end."""
        starts = np.zeros(len(paths) + 1, dtype=np.int64)
        np.cumsum([path.shape[0] for path in paths], out=starts[1:])
        return cls(np.concatenate(paths) if paths else np.empty((0, 3)), starts)

    def lengths(self) -> np.ndarray:
        """Each path's length (m): its chords summed as numpy sums them (pairwise)."""
        out = np.empty(self.starts.size - 1)
        _chord_sums(self.chords, self.starts, out)
        return out

    def law_fractions(self) -> np.ndarray:
        """:func:`motor.signing.lmp.law_fractions` of every path of three or more points,
        end to end ``(n,)`` as the points (what a shorter path's rows hold is undefined)."""
        curvature = np.empty(self.points.shape[0])
        grids = np.empty((self.starts.size - 1, 2))  # per path: grid spacing (m), kernel width (grid steps)
        counts = np.empty(self.starts.size - 1, dtype=np.int64)
        radii = np.empty(self.starts.size - 1, dtype=np.int64)
        _curvature_and_grids(np.arccos(self.turning_cosines()), self.chords, self.arc, self.starts, curvature, grids, counts, radii)
        log_curvature = np.log(clamped_curvature(curvature))
        kernels = np.zeros(radii.size + 1, dtype=np.int64)
        np.cumsum(2 * radii + 1, out=kernels[1:])
        exponents = np.empty(int(kernels[-1]))
        _kernel_exponents(grids, radii, kernels, exponents)
        smooth = np.zeros(self.points.shape[0])  # 0 where a path has no grid (its density unused)
        _smoothed(self.arc, log_curvature, self.starts, grids, counts, radii, kernels, np.exp(exponents), smooth)
        fractions = np.empty(self.points.shape[0])
        _law_time(np.exp(EXPONENT * smooth), self.chords, self.starts, counts, fractions)
        return fractions

    def turning_cosines(self) -> np.ndarray:
        """The cosine of the turn at each point (1 at a path's ends and next to a hold),
        as :func:`motor.trajectory.spline.turning_angles` takes it before its arccos."""
        cosines = np.empty(self.points.shape[0])
        _turning_cosines(self.points, self.starts, self.chords, cosines)
        return cosines

    def split(self, values: np.ndarray) -> list[np.ndarray]:
        """``values`` laid out as the points, one array (a view) per path."""
        return np.split(values, self.starts[1:-1])


@numba.njit([numba.void(READ2, READ_INTS1, WRITE1, WRITE1)], cache=True, error_model="numpy")
def _chords_and_arcs(points, starts, chords, arc):  # noqa: ANN001, ANN202
    """Each path's chord norms (``np.linalg.norm``'s sum of squares) and their running sum."""
    for p in range(starts.size - 1):
        first, end = starts[p], starts[p + 1]
        if first == end:
            continue
        arc[first] = 0.0
        for i in range(first, end - 1):
            dx = points[i + 1, 0] - points[i, 0]
            dy = points[i + 1, 1] - points[i, 1]
            dz = points[i + 1, 2] - points[i, 2]
            chords[i] = np.sqrt((dx * dx + dy * dy) + dz * dz)
            arc[i + 1] = arc[i] + chords[i]
        chords[end - 1] = 0.0


@_jit
def pairwise_sum(values, first, n):  # noqa: ANN001, ANN202
    """``values[first:first + n].sum()`` in numpy's order: eight lanes per block of at most
    :data:`_PAIRWISE_BLOCK`, longer runs halved at a multiple of eight."""
    if n < 8:
        total = 0.0
        for i in range(first, first + n):
            total += values[i]
        return total
    if n <= _PAIRWISE_BLOCK:
        lanes = values[first : first + 8].copy()
        i = 8
        while i < n - n % 8:
            for lane in range(8):
                lanes[lane] += values[first + i + lane]
            i += 8
        total = ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]))
        for j in range(first + i, first + n):
            total += values[j]
        return total
    half = n // 2
    half -= half % 8
    return pairwise_sum(values, first, half) + pairwise_sum(values, first + half, n - half)


@numba.njit([numba.void(READ1, READ_INTS1, WRITE1)], cache=True, error_model="numpy")
def _chord_sums(chords, starts, out):  # noqa: ANN001, ANN202
    for p in range(starts.size - 1):
        out[p] = pairwise_sum(chords, starts[p], max(starts[p + 1] - starts[p] - 1, 0))


@numba.njit([numba.void(READ2, READ_INTS1, READ1, WRITE1)], cache=True, error_model="numpy")
def _turning_cosines(points, starts, chords, cosines):  # noqa: ANN001, ANN202
    """The cosine of the turn at each interior point (``einsum``'s dot product over the
    norms' product, 1 at a hold, clipped to [-1, 1]); 1 at each path's ends."""
    for p in range(starts.size - 1):
        first, end = starts[p], starts[p + 1]
        for i in range(first, end):
            cosines[i] = 1.0
        for i in range(first + 1, end - 1):
            ax, ay, az = points[i, 0] - points[i - 1, 0], points[i, 1] - points[i - 1, 1], points[i, 2] - points[i - 1, 2]
            bx, by, bz = points[i + 1, 0] - points[i, 0], points[i + 1, 1] - points[i, 1], points[i + 1, 2] - points[i, 2]
            denom = chords[i - 1] * chords[i]
            if denom > DEGENERATE_CHORD:
                cosine = (ax * bx + az * bz) + ay * by
                cosines[i] = min(max(cosine / denom, -1.0), 1.0)


@numba.njit(
    [numba.void(READ1, READ1, READ1, READ_INTS1, WRITE1, WRITE2, WRITE_INTS1, WRITE_INTS1)], cache=True, error_model="numpy"
)
def _curvature_and_grids(angles, chords, arc, starts, curvature, grids, counts, radii):  # noqa: ANN001, ANN202
    """Each path's curvature (turn over the mean of the adjacent chords, the ends as their
    neighbours), its law-time grid (size, spacing) and its smoothing kernel (width, radius);
    size 0 for a path of fewer than three points or no length."""
    for p in range(starts.size - 1):
        first, last = starts[p], starts[p + 1] - 1
        counts[p], radii[p] = 0, 0
        for i in range(first, last + 1):
            curvature[i] = 0.0
        if last - first < 2:
            continue
        for i in range(first + 1, last):
            span = 0.5 * (chords[i - 1] + chords[i])
            curvature[i] = angles[i] / (span if span >= NEGLIGIBLE else NEGLIGIBLE)
        curvature[first], curvature[last] = curvature[first + 1], curvature[last - 1]
        total = arc[last]
        if total < NEGLIGIBLE:
            continue
        step = min(LAW_SMOOTHING / 4.0, total / 8.0)
        count = int(np.ceil(total / step)) + 1
        spacing = total / (count - 1)
        sigma = min(LAW_SMOOTHING / spacing, 4.0 * count)
        counts[p], grids[p, 0], grids[p, 1] = count, spacing, sigma
        radii[p] = int(_TRUNCATE * sigma + 0.5)


@numba.njit([numba.void(READ2, READ_INTS1, READ_INTS1, WRITE1)], cache=True, error_model="numpy")
def _kernel_exponents(grids, radii, kernels, out):  # noqa: ANN001, ANN202
    """The Gaussian kernel's exponents ``−½ / σ² · k²`` for ``k = −r … r`` of each path."""
    for p in range(radii.size):
        scale = -0.5 / (grids[p, 1] * grids[p, 1])
        for k in range(-radii[p], radii[p] + 1):
            out[kernels[p] + radii[p] + k] = scale * float(k * k)


@_jit
def _interp(x, count, xp, fp, first, end, out, at):  # noqa: ANN001, ANN202
    """``np.interp(x[:count], xp[first:end], fp[first:end])`` into ``out[at:]``, for ``x``
    ascending: numpy's cases and arithmetic, the interval found by walking along."""
    j = first
    for i in range(count):
        value = x[i]
        if np.isnan(value):
            out[at + i] = value
        elif value > xp[end - 1]:
            out[at + i] = fp[end - 1]
        elif value < xp[first]:
            out[at + i] = fp[first]
        else:
            while j + 1 < end and xp[j + 1] <= value:
                j += 1
            if j == end - 1 or xp[j] == value:
                out[at + i] = fp[j]
            else:
                slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
                result = slope * (value - xp[j]) + fp[j]
                if np.isnan(result):
                    result = slope * (value - xp[j + 1]) + fp[j + 1]
                    if np.isnan(result) and fp[j] == fp[j + 1]:
                        result = fp[j]
                out[at + i] = result


@numba.njit(
    [numba.void(READ1, READ1, READ_INTS1, READ2, READ_INTS1, READ_INTS1, READ_INTS1, READ1, WRITE1)], cache=True, error_model="numpy"
)
def _smoothed(arc, log_curvature, starts, grids, counts, radii, kernels, phi, out):  # noqa: ANN001, ANN202
    """Each path's log curvature interpolated onto its grid, smoothed there (scipy's
    symmetric correlation: the centre's term, then the pairs from the outermost in, the
    edge values repeated past the ends) and interpolated back at its points."""
    width = max(counts.max(), 1) if counts.size else 1
    grid, values, smooth = np.empty(width), np.empty(width), np.empty(width)
    weights = np.empty(2 * (radii.max() if radii.size else 0) + 1)
    for p in range(starts.size - 1):
        count, radius, first, end = counts[p], radii[p], starts[p], starts[p + 1]
        if count == 0:
            continue
        for j in range(count - 1):
            grid[j] = j * grids[p, 0]
        grid[count - 1] = arc[end - 1]
        _interp(grid, count, arc, log_curvature, first, end, values, 0)
        total = pairwise_sum(phi, kernels[p], 2 * radius + 1)
        for k in range(2 * radius + 1):
            weights[k] = phi[kernels[p] + k] / total
        for j in range(count):
            acc = values[j] * weights[radius]
            for k in range(radius, 0, -1):
                acc = acc + (values[max(j - k, 0)] + values[min(j + k, count - 1)]) * weights[radius - k]
            smooth[j] = acc
        _interp(arc[first:end], end - first, grid, smooth, 0, count, out, first)


@numba.njit([numba.void(READ1, READ1, READ_INTS1, READ_INTS1, WRITE1)], cache=True, error_model="numpy")
def _law_time(density, chords, starts, counts, out):  # noqa: ANN001, ANN202
    """Each path's law time (the trapezoid sum of the density over its chords) as a share
    of its total; evenly spaced (``np.linspace``'s) on a path of no length."""
    for p in range(starts.size - 1):
        first, last = starts[p], starts[p + 1] - 1
        if last - first < 2:
            continue
        if counts[p] == 0:
            step = 1.0 / (last - first)
            for i in range(first, last):
                out[i] = (i - first) * step
            out[last] = 1.0
            continue
        out[first] = 0.0
        for i in range(first, last):
            out[i + 1] = out[i] + 0.5 * (density[i + 1] + density[i]) * chords[i]
        total = out[last]
        for i in range(first, last + 1):
            out[i] = out[i] / total


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when the module is imported):
    :func:`motor.compiled.warm_up`."""
    paths = DensePaths.of([np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.01, 0.01, 0.0]])])
    paths.lengths()
    paths.law_fractions()
