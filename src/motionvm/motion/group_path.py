"""The geometry of an axis group's path segments (manual 8.2, 8.5): lines, arcs, helices, blends.

A pose is a tuple of n floats (n = the group's axis count, at most 6): X, Y, Z [mm] then
A, B, C [deg] (Cartesian kinematics, manual 8.1.3). The first min(n, 3) values are the
translation, the rest the rotation. Every segment runs from `start` to `end` as a
fraction f in [0, 1] grows; `point(f)` is the pose there and `point(1.0)` is `end`
itself, so a path ends exactly on its target. `lt` is the translation length [mm] and
`lr` the rotation length [deg] of the segment; the planner (motion/group_plan.py)
picks one of them as its path length and maps path position u to f = u / length.

- `Line`: every coordinate linear in f (translation and rotation together, 8.2.9).
- `Arc`: a circle about `center` in the plane normal to `normal` (right-hand rule),
  swept by a signed angle `phi` [rad], optionally rising along the normal (a helix,
  CircleAbs with an end off the plane); rotation coordinates linear in f.
- `Blend`: the transition curve of 8.1.5 between two segments: a cubic Bezier tangent
  to both at the trim points (for two lines it is the quadratic Bezier whose control
  point is the corner, the curve table 8.3.26.1 describes), held as a polyline of
  `BLEND_POINTS` chords parameterized exactly by chord length.

Decisions where the manual is silent: arc radii at start and end must agree within
`RADIUS_TOL` (relative) or the arc is refused; a full circle (start == end, CircleAbs,
Circle2D) sweeps 360 degrees per turn.
"""

from __future__ import annotations

import math

TWO_PI = 2.0 * math.pi
RADIUS_TOL = 1e-3
"""Relative difference [-] allowed between an arc's start and end radius."""
BLEND_POINTS = 33
"""Points of a blend curve's polyline (32 chords)."""


class PathError(ValueError):
    """A segment that cannot be built; `code` is the low half of the group error."""

    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code


def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _norm(v) -> float:
    return math.sqrt(sum(x * x for x in v))


def _unit(v):
    n = _norm(v)
    return [x / n for x in v] if n > 0.0 else [0.0] * len(v)


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _dot(a, b) -> float:
    return sum(x * y for x, y in zip(a, b))


def _pad3(v):
    v = list(v)[:3]
    return v + [0.0] * (3 - len(v))


class Segment:
    """Base of the segment kinds: start and end poses, translation and rotation lengths."""

    __slots__ = ("end", "lr", "lt", "n", "start")

    def __init__(self, start, end):
        self.start = tuple(float(x) for x in start)
        self.end = tuple(float(x) for x in end)
        self.n = len(self.start)

    def point(self, f: float) -> list[float]:  # pragma: no cover - abstract
        raise NotImplementedError

    def points(self, fs: list[float]) -> list[list[float]]:
        """The poses `point` gives at the fractions `fs`, one list per coordinate (the
        same values: the closed-form advance of a group computes many at once)."""
        if not fs:
            return [[] for _ in range(self.n)]
        return [list(c) for c in zip(*map(self.point, fs))]

    def tangent(self, f: float) -> list[float]:  # pragma: no cover - abstract
        """Unit direction of motion at f in the translation space (or the rotation
        space of a segment that only rotates)."""
        raise NotImplementedError

    @property
    def radius(self) -> float:
        """Smallest radius of curvature [mm] (inf for a line)."""
        return math.inf

    def bounds(self) -> tuple[list[float], list[float]]:  # pragma: no cover - abstract
        """(lowest, highest) value of each coordinate over the whole segment, or wider."""
        raise NotImplementedError

    def rates(self) -> list[float]:  # pragma: no cover - abstract
        """The largest |d x_i / d f| of each coordinate over the segment, or larger
        (inf where it cannot be bounded)."""
        raise NotImplementedError

    def sub(self, f_0: float, f_1: float) -> Segment:  # pragma: no cover - abstract
        """The part of the segment between fractions f_0 and f_1, as a segment."""
        raise NotImplementedError

    def _lengths(self, dt_vec) -> None:
        self.lt = _norm(dt_vec[:3])
        self.lr = _norm(dt_vec[3:])


class Line(Segment):
    """A straight line from `start` to `end` (all coordinates linear in f)."""

    __slots__ = ("_d", "_dir")

    def __init__(self, start, end):
        super().__init__(start, end)
        self._d = _sub(self.end, self.start)
        self._lengths(self._d)
        t = self._d[:3] if self.lt > 0.0 else self._d[3:]
        self._dir = _unit(t)

    def point(self, f: float) -> list[float]:
        if f >= 1.0:
            return list(self.end)
        return [s + d * f for s, d in zip(self.start, self._d)]

    def points(self, fs: list[float]) -> list[list[float]]:
        if not fs or max(fs) >= 1.0:
            return super().points(fs)
        return [[s + d * f for f in fs] for s, d in zip(self.start, self._d)]

    def tangent(self, f: float) -> list[float]:
        return self._dir

    def sub(self, f_0: float, f_1: float) -> Line:
        return Line(self.point(f_0), self.point(f_1))

    def bounds(self) -> tuple[list[float], list[float]]:
        return ([min(a, b) for a, b in zip(self.start, self.end)],
                [max(a, b) for a, b in zip(self.start, self.end)])  # fmt: skip

    def rates(self) -> list[float]:
        return [abs(d) for d in self._d]


class Arc(Segment):
    """A circular arc or helix about `center` [mm] with axis `normal` (unit, right hand).

    `r` is the radius at the start; the end's radius may differ by up to `RADIUS_TOL`
    (`_dr`): the radius then changes linearly with f, so the arc ends on its end point
    instead of jumping onto it in the last cycle."""

    __slots__ = ("_dr", "_e1", "_e2", "_h", "_rot0", "_rotd", "center", "normal", "phi", "r")

    def __init__(self, start, end, center, normal, phi: float, _trimmed=None):
        super().__init__(start, end)
        n = self.n
        if _trimmed is not None:
            (self.center, self.normal, self._e1, self._e2, self.r, self._h, self._dr) = _trimmed
        else:
            c = _pad3(center)
            nn = _unit(_pad3(normal))
            if _norm(nn) == 0.0:
                raise PathError(0x0262, "the normal vector of the circle is zero")
            s3, e3 = _pad3(self.start), _pad3(self.end)
            rs, re_ = _sub(s3, c), _sub(e3, c)
            hs, he = _dot(rs, nn), _dot(re_, nn)
            r0 = [x - hs * y for x, y in zip(rs, nn)]
            r1 = [x - he * y for x, y in zip(re_, nn)]
            rad0, rad1 = _norm(r0), _norm(r1)
            if rad0 <= 1e-9 or rad1 <= 1e-9:
                raise PathError(0x026C, "the centre of the circle is at its start or end point")
            if abs(rad0 - rad1) > RADIUS_TOL * max(rad0, rad1):
                raise PathError(
                    0x0280,
                    f"the circle's radius at the start ({rad0:g}) and at the end ({rad1:g}) differ",
                )
            # the circle's centre in the plane of the start point (the given centre may
            # lie anywhere on the axis)
            self.center = [x + hs * y for x, y in zip(c, nn)]
            self.normal, self.r, self._h, self._dr = nn, rad0, he - hs, rad1 - rad0
            self._e1 = [x / rad0 for x in r0]
            self._e2 = _cross(nn, self._e1)
        self.phi = phi
        self._rot0 = list(self.start[3:])
        self._rotd = _sub(self.end[3:], self.start[3:])
        # with a changing radius, the length at the larger one: the speed along the arc
        # never exceeds the planned path speed
        self.lt = math.hypot(max(self.r, self.r + self._dr) * phi, self._h, self._dr)
        self.lr = _norm(self._rotd)
        if n < 3 and abs(self._h) > 1e-9:
            raise PathError(0x028A, "a helix needs a Z axis in the group")

    def _xyz(self, f: float) -> list[float]:
        a = f * self.phi
        ca, sa = math.cos(a), math.sin(a)
        r, h = self.r + f * self._dr, f * self._h
        return [c + r * (ca * e1 + sa * e2) + h * nv
                for c, e1, e2, nv in zip(self.center, self._e1, self._e2, self.normal)]  # fmt: skip

    def point(self, f: float) -> list[float]:
        if f >= 1.0:
            return list(self.end)
        xyz = self._xyz(f)[: min(self.n, 3)]
        return xyz + [s + d * f for s, d in zip(self._rot0, self._rotd)]

    def points(self, fs: list[float]) -> list[list[float]]:
        if not fs or max(fs) >= 1.0:
            return super().points(fs)
        phi, r_0, dr, dh = self.phi, self.r, self._dr, self._h
        angles = [f * phi for f in fs]
        cas = list(map(math.cos, angles))
        sas = list(map(math.sin, angles))
        rs = [r_0 + f * dr for f in fs]
        hs = [f * dh for f in fs]
        k = min(self.n, 3)
        cols = [[c + r * (ca * e1 + sa * e2) + h * nv for r, ca, sa, h in zip(rs, cas, sas, hs)]
                for c, e1, e2, nv in zip(self.center[:k], self._e1[:k], self._e2[:k],
                                         self.normal[:k])]  # fmt: skip
        return cols + [[s + d * f for f in fs] for s, d in zip(self._rot0, self._rotd)]

    def tangent(self, f: float) -> list[float]:
        a = f * self.phi
        ca, sa = math.cos(a), math.sin(a)
        rp, dr = (self.r + f * self._dr) * self.phi, self._dr
        t = [rp * (-sa * e1 + ca * e2) + dr * (ca * e1 + sa * e2) + self._h * nv
             for e1, e2, nv in zip(self._e1, self._e2, self.normal)]  # fmt: skip
        return _unit(t[: min(self.n, 3)])

    @property
    def radius(self) -> float:
        return min(self.r, self.r + self._dr)

    def bounds(self) -> tuple[list[float], list[float]]:
        k = min(self.n, 3)
        reach = max(self.r, self.r + self._dr) + abs(self._h)
        lo = [c - reach for c in self.center[:k]]
        hi = [c + reach for c in self.center[:k]]
        lo += [min(a, b) for a, b in zip(self.start[3:], self.end[3:])]
        hi += [max(a, b) for a, b in zip(self.start[3:], self.end[3:])]
        return lo, hi

    def rates(self) -> list[float]:
        k = min(self.n, 3)
        rate = max(self.r, self.r + self._dr) * abs(self.phi) + abs(self._dr) + abs(self._h)
        return [rate] * k + [abs(d) for d in self._rotd]

    def sub(self, f_0: float, f_1: float) -> Arc:
        a0 = f_0 * self.phi
        ca, sa = math.cos(a0), math.sin(a0)
        e1 = [ca * x + sa * y for x, y in zip(self._e1, self._e2)]
        e2 = _cross(self.normal, e1)
        c = [cc + f_0 * self._h * nv for cc, nv in zip(self.center, self.normal)]
        return Arc(self.point(f_0), self.point(f_1), None, None, (f_1 - f_0) * self.phi,
                   _trimmed=(c, self.normal, e1, e2, self.r + f_0 * self._dr,
                             (f_1 - f_0) * self._h, (f_1 - f_0) * self._dr))  # fmt: skip


class Polyline(Segment):
    """Points joined by chords, parameterized by chord length (a blend curve)."""

    __slots__ = ("_cum", "_pts")

    def __init__(self, points):
        pts = [tuple(float(x) for x in p) for p in points]
        super().__init__(pts[0], pts[-1])
        self._pts = pts
        cum = [0.0]
        k = min(self.n, 3)
        for a, b in zip(pts, pts[1:]):
            cum.append(cum[-1] + _norm(_sub(b[:k], a[:k])))
        self._cum = cum
        self.lt = cum[-1]
        self.lr = sum(_norm(_sub(b[3:], a[3:])) for a, b in zip(pts, pts[1:]))

    def _locate(self, f: float) -> tuple[int, float]:
        u = f * self.lt
        cum = self._cum
        lo, hi = 0, len(cum) - 2
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if cum[mid] <= u:
                lo = mid
            else:
                hi = mid - 1
        span = cum[lo + 1] - cum[lo]
        return lo, (u - cum[lo]) / span if span > 0.0 else 0.0

    def point(self, f: float) -> list[float]:
        if f >= 1.0:
            return list(self.end)
        i, g = self._locate(f)
        a, b = self._pts[i], self._pts[i + 1]
        return [x + (y - x) * g for x, y in zip(a, b)]

    def tangent(self, f: float) -> list[float]:
        i, _ = self._locate(min(f, 1.0 - 1e-12))
        a, b = self._pts[i], self._pts[i + 1]
        return _unit(_sub(b, a)[: min(self.n, 3)])

    @property
    def max_turn(self) -> float:
        """The largest |t_1 - t_0| of the unit directions at the polyline's corners."""
        k = min(self.n, 3)
        pts = self._pts
        out = 0.0
        for a, b, c in zip(pts, pts[1:], pts[2:]):
            t0, t1 = _unit(_sub(b[:k], a[:k])), _unit(_sub(c[:k], b[:k]))
            out = max(out, _norm(_sub(t1, t0)))
        return out

    @property
    def radius(self) -> float:
        """The smallest discrete radius chord / turn angle at the polyline's corners."""
        k = min(self.n, 3)
        r = math.inf
        pts = self._pts
        for a, b, c in zip(pts, pts[1:], pts[2:]):
            t0, t1 = _unit(_sub(b[:k], a[:k])), _unit(_sub(c[:k], b[:k]))
            turn = _norm(_sub(t1, t0))
            if turn > 1e-12:
                r = min(r, min(_norm(_sub(b[:k], a[:k])), _norm(_sub(c[:k], b[:k]))) / turn)
        return r

    def bounds(self) -> tuple[list[float], list[float]]:
        cols = list(zip(*self._pts))
        return [min(c) for c in cols], [max(c) for c in cols]

    def rates(self) -> list[float]:
        lt = self.lt
        if lt == 0.0:  # (the pose jumps to the end at f = 1)
            return [0.0 if a == b else math.inf for a, b in zip(self.start, self.end)]
        out = [0.0] * self.n
        for a, b, c_0, c_1 in zip(self._pts, self._pts[1:], self._cum, self._cum[1:]):
            span = c_1 - c_0
            for i, (x, y) in enumerate(zip(a, b)):
                if x != y:
                    r = abs(y - x) / span * lt if span > 0.0 else math.inf
                    if r > out[i]:
                        out[i] = r
        return out

    def sub(self, f_0: float, f_1: float) -> Polyline:
        return Polyline([self.point(f_0), self.point(f_1)])


def blend(p0, t0, p3, t1, d0: float, d1: float, n_points: int = BLEND_POINTS) -> Polyline:
    """The transition curve from p0 (leaving along unit tangent t0) to p3 (arriving along
    t1), the trim lengths d0 and d1 being the arc lengths cut from either segment."""
    k = len(t0)
    p1 = list(p0)
    p2 = list(p3)
    for i in range(k):
        p1[i] += t0[i] * d0 * (2.0 / 3.0)
        p2[i] -= t1[i] * d1 * (2.0 / 3.0)
    for i in range(k, len(p0)):  # rotation: linear between the trim points
        p1[i] = p0[i] + (p3[i] - p0[i]) / 3.0
        p2[i] = p0[i] + (p3[i] - p0[i]) * 2.0 / 3.0
    pts = []
    for j in range(n_points):
        s = j / (n_points - 1)
        m = 1.0 - s
        w0, w1, w2, w3 = m * m * m, 3.0 * m * m * s, 3.0 * m * s * s, s * s * s
        pts.append([w0 * a + w1 * b + w2 * c + w3 * e for a, b, c, e in zip(p0, p1, p2, p3)])
    pts[0], pts[-1] = list(p0), list(p3)
    return Polyline(pts)


# ---- building arcs from the manual's arguments ------------------------------------------


def _ccw_angle(r0, r1, normal) -> float:
    """Angle [rad] in (0, 2 pi] from r0 to r1 turning about `normal` (right hand);
    2 pi when they point the same way (a full circle)."""
    a = math.atan2(_dot(_cross(r0, r1), normal), _dot(r0, r1))
    if a <= 1e-12:
        a += TWO_PI
    return a


def sweep(start, end, center, normal, turns: int) -> float:
    """The signed angle [rad] of CircleAbs / Circle2D (8.2.17): turns >= 0 counter-
    clockwise, < 0 clockwise; |turns| <= 1 less than (or, start == end, exactly) one
    turn, each further turn 360 degrees more; turns 0 and 1 are the same."""
    c = _pad3(center)
    nn = _unit(_pad3(normal))
    r0, r1 = _sub(_pad3(start), c), _sub(_pad3(end), c)
    r0 = [x - _dot(r0, nn) * y for x, y in zip(r0, nn)]
    r1 = [x - _dot(r1, nn) * y for x, y in zip(r1, nn)]
    ccw = _ccw_angle(r0, r1, nn)
    if turns >= 0:
        return ccw + (max(turns, 1) - 1) * TWO_PI
    cw = TWO_PI - ccw
    if cw <= 1e-12:
        cw = TWO_PI
    return -(cw + (-turns - 1) * TWO_PI)


def arc_center_3pt(p0, p1, p2) -> list[float] | None:
    """Centre of the circle through three points of the XY plane, None if collinear."""
    ax, ay = p0[0], p0[1]
    bx, by = p1[0], p1[1]
    cx, cy = p2[0], p2[1]
    dd = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    scale = max(abs(ax - bx), abs(ay - by), abs(cx - bx), abs(cy - by), 1e-300)
    if abs(dd) <= 1e-12 * scale * scale:
        return None
    a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    ux = (a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / dd
    uy = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / dd
    return [ux, uy]


def turn_angle(t0, t1) -> float:
    """Angle [rad] between two unit directions (0: straight on, pi: reversal)."""
    c = max(-1.0, min(1.0, _dot(t0, t1)))
    return math.acos(c)
