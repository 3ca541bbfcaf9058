"""Error maps of the dynamic error compensation (HIMC manual 14.1): 1-D, 2-D, 3-D tables.

An error map gives the compensation [mm or deg] of one axis as a function of the
positions of one to three reference axes. Dimension i has `num_pt[i]` points, the first
at `base[i]`, spaced `interval[i]`; the values come from the User Table, dimension 0
varying fastest:

    value(i0, i1, i2) = table[start_idx + i0 + n0 * (i1 + n1 * i2)]

(the manual's 3-D example lists three 3x3 tables, one per point of its third reference
axis). Between points the map interpolates linearly (multilinear in 2-D and 3-D:
alg_type 0) or with natural cubic splines (alg_type 1, 1-D and 2-D only: a tensor
product, dimension 0 first). Beyond the table a reference position is clamped to the
first or last point, so the value of the nearest point applies (figure 14.1.1).

`ErrorMap` is pure and immutable: the axis side (motion/axis_filters.py) evaluates it
once per cycle with the reference axes' reference positions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

ALG_LINEAR = 0
ALG_SPLINE = 1
COMP_LIMIT = 1.0
"""[mm or deg] The controller's default maximum compensation (14.1, HCV_ID_max_comp_lim)."""


class MapError(ValueError):
    """A map that cannot be built: the message says which parameter and why."""


@dataclass(frozen=True, slots=True)
class ErrorMap:
    """An n-D error map (n = 1..3); see the module docstring."""

    base: tuple[float, ...]
    interval: tuple[float, ...]
    num_pt: tuple[int, ...]
    values: tuple[float, ...]
    alg_type: int = ALG_LINEAR
    _rows: tuple = field(init=False, repr=False, compare=False)
    """Spline maps: per row of dimension 0, its values and second derivatives."""

    def __post_init__(self) -> None:
        rows = ()
        if self.alg_type == ALG_SPLINE:
            n0 = self.num_pt[0]
            count = len(self.values) // n0
            rows = tuple(
                (r, _second_derivatives(r))
                for r in (self.values[j * n0 : (j + 1) * n0] for j in range(count))
            )
        object.__setattr__(self, "_rows", rows)

    @property
    def dims(self) -> int:
        return len(self.base)

    def value(self, pos: Sequence[float]) -> float:
        """The compensation at reference positions `pos` (one per dimension)."""
        if self.alg_type == ALG_SPLINE:
            return self._spline(pos)
        # multilinear: the cell's corner values weighted by the fractions
        cell, frac = [], []
        for x, b, h, n in zip(pos, self.base, self.interval, self.num_pt):
            u = (x - b) / h
            if u <= 0.0:
                cell.append(0)
                frac.append(0.0)
            elif u >= n - 1:
                cell.append(n - 2)
                frac.append(1.0)
            else:
                i = min(int(u), n - 2)
                cell.append(i)
                frac.append(u - i)
        vals = self.values
        strides = self._strides()
        total = 0.0
        for corner in range(1 << self.dims):
            w, index = 1.0, 0
            for d in range(self.dims):
                up = (corner >> d) & 1
                f = frac[d]
                w *= f if up else 1.0 - f
                index += (cell[d] + up) * strides[d]
            if w:
                total += w * vals[index]
        return total

    def _strides(self) -> tuple[int, ...]:
        out, s = [], 1
        for n in self.num_pt:
            out.append(s)
            s *= n
        return tuple(out)

    def _spline(self, pos: Sequence[float]) -> float:
        b, h = self.base, self.interval
        col = tuple(_spline_at(r, m, b[0], h[0], pos[0]) for r, m in self._rows)
        if self.dims == 1:
            return col[0]
        return _spline_at(col, _second_derivatives(col), b[1], h[1], pos[1])


def _spline_at(y: Sequence[float], m: Sequence[float], base: float, h: float, x: float) -> float:
    """The natural cubic spline through `y` at `base + i*h` (second derivatives times h^2
    `m`), at `x` clamped to the range."""
    n = len(y)
    u = (x - base) / h
    if u <= 0.0:
        return y[0]
    if u >= n - 1:
        return y[-1]
    i = min(int(u), n - 2)
    t = u - i
    s = 1.0 - t
    # in units of h: y'' scaled by h^2 / 6
    return s * y[i] + t * y[i + 1] + ((s**3 - s) * m[i] + (t**3 - t) * m[i + 1]) / 6.0


def _second_derivatives(y: Sequence[float]) -> tuple[float, ...]:
    """Second derivatives (times h^2) of the natural spline through `y` (Thomas algorithm)."""
    n = len(y)
    m = [0.0] * n
    if n < 3:
        return tuple(m)
    # m[i-1] + 4 m[i] + m[i+1] = 6 (y[i-1] - 2 y[i] + y[i+1]),  m[0] = m[n-1] = 0
    c = [0.0] * n
    d = [0.0] * n
    for i in range(1, n - 1):
        rhs = 6.0 * (y[i - 1] - 2.0 * y[i] + y[i + 1])
        denom = 4.0 - c[i - 1]
        c[i] = 1.0 / denom
        d[i] = (rhs - d[i - 1]) / denom
    for i in range(n - 2, 0, -1):
        m[i] = d[i] - c[i] * m[i + 1]
    return tuple(m)


def build(
    base: Sequence[float],
    interval: Sequence[float],
    num_pt: Sequence[int],
    start_idx: int,
    table: Sequence[float],
    alg_type: int,
) -> ErrorMap:
    """The map of `num_pt` points per dimension read from `table` at `start_idx`.

    MapError names the first bad parameter: a base or interval that is not a finite
    number, an interval <= 0, fewer than 2 points in a dimension, a range beyond the
    table, a table value that is not a finite number, spline interpolation of a 3-D map.
    """
    dims = len(base)
    for d in range(dims):
        if not math.isfinite(base[d]):
            raise MapError(f"base[{d}] {base[d]!r} is not a number")
        if not (math.isfinite(interval[d]) and interval[d] > 0.0):
            raise MapError(f"interval[{d}] {interval[d]!r} must be positive")
        if num_pt[d] < 2:
            raise MapError(f"num_pt[{d}] {num_pt[d]} must be at least 2")
    count = math.prod(num_pt)
    if start_idx < 0 or start_idx + count > len(table):
        raise MapError(
            f"{count} points from index {start_idx} do not fit the User Table (0..{len(table) - 1})"
        )
    if alg_type == ALG_SPLINE and dims == 3:
        raise MapError("3-D compensation does not support spline interpolation")
    values = tuple(float(table[start_idx + i]) for i in range(count))
    for i, v in enumerate(values):
        if not math.isfinite(v):  # it would drive the axis to its compensation limit
            raise MapError(f"User Table [{start_idx + i}] = {v!r} is not a number")
    return ErrorMap(
        tuple(float(b) for b in base),
        tuple(float(h) for h in interval),
        tuple(int(n) for n in num_pt),
        values,
        alg_type,
    )
