"""Coordinate systems of an axis group (manual 8.1.2): MCS, PCS, WCS1-15, OFFSET.

A transform is six values {X, Y, Z [mm], A, B, C [deg]}: a translation and a fixed-axis
Roll-Pitch-Yaw rotation (A about X, B about Y, C about Z; R = Rz(C) Ry(B) Rx(A), the
ZYX Tait-Bryan angles of 8.1.2). A coordinate system word is a combination of

    CS_MCS 0 (the machine coordinates), CS_ACS 0x1 (the axes), CS_PCS 0x2,
    CS_OFFSET 0x4, CS_GLOBAL 0x8 (not supported, as on the controller),
    CS_WCS1 .. CS_WCS15 = n << 4 (a 4-bit field: one workpiece system at a time),

and a pose given in `CS_OFFSET | CS_WCSn | CS_PCS` is in machine coordinates

    p_MCS = T_OFFSET * T_WCSn * T_PCS * p

(the chain MCS -> OFFSET -> WCSn -> PCS of example 5-3); a system left out of the word
is the identity. These values are motionvm's: the manual names the constants without
numbers.
"""

from __future__ import annotations

import math

CS_MCS, CS_ACS, CS_PCS, CS_OFFSET, CS_GLOBAL = 0x0, 0x1, 0x2, 0x4, 0x8
WCS_SHIFT, WCS_MASK = 4, 0xF0
VALID_BITS = CS_ACS | CS_PCS | CS_OFFSET | WCS_MASK


def rpy_matrix(a_deg: float, b_deg: float, c_deg: float) -> list[list[float]]:
    """R = Rz(c) Ry(b) Rx(a) (fixed-axis roll, pitch, yaw in degrees)."""
    a, b, c = math.radians(a_deg), math.radians(b_deg), math.radians(c_deg)
    ca, sa, cb, sb, cc, sc = (
        math.cos(a),
        math.sin(a),
        math.cos(b),
        math.sin(b),
        math.cos(c),
        math.sin(c),
    )
    return [
        [cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa],
        [sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa],
        [-sb, cb * sa, cb * ca],
    ]


def matrix_rpy(r: list[list[float]]) -> tuple[float, float, float]:
    """The (A, B, C) [deg] of a rotation matrix (inverse of `rpy_matrix`)."""
    sb = -r[2][0]
    sb = max(-1.0, min(1.0, sb))
    b = math.asin(sb)
    if abs(sb) < 1.0 - 1e-12:
        a = math.atan2(r[2][1], r[2][2])
        c = math.atan2(r[1][0], r[0][0])
    else:  # gimbal lock: put everything into C
        a = 0.0
        c = math.atan2(-r[0][1], r[1][1])
    return math.degrees(a), math.degrees(b), math.degrees(c)


def _mul(p: list[list[float]], q: list[list[float]]) -> list[list[float]]:
    return [[sum(p[i][k] * q[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def _t(r: list[list[float]]) -> list[list[float]]:
    return [[r[j][i] for j in range(3)] for i in range(3)]


class Frame:
    """A rigid transform: rotation `r` (3x3) and translation `t` [mm]."""

    __slots__ = ("r", "t")

    def __init__(self, r=None, t=None):
        self.r = r if r is not None else [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        self.t = list(t) if t is not None else [0.0, 0.0, 0.0]

    @classmethod
    def of(cls, params) -> Frame:
        x, y, z, a, b, c = (float(v) for v in params)
        return cls(rpy_matrix(a, b, c), [x, y, z])

    def compose(self, other: Frame) -> Frame:
        """self * other: first `other`, then `self`."""
        return Frame(_mul(self.r, other.r), self.apply_point(other.t))

    def inverse(self) -> Frame:
        rt = _t(self.r)
        return Frame(rt, [-sum(rt[i][k] * self.t[k] for k in range(3)) for i in range(3)])

    def apply_point(self, p) -> list[float]:
        r, t = self.r, self.t
        return [r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + t[i] for i in range(3)]

    def apply_vector(self, v) -> list[float]:
        r = self.r
        return [r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2] for i in range(3)]

    def apply_pose(self, pose) -> list[float]:
        """A pose (1 to 6 values, missing ones 0) in this frame's parent coordinates."""
        n = len(pose)
        p6 = list(pose) + [0.0] * (6 - n)
        xyz = self.apply_point(p6[:3])
        if n > 3:
            abc = matrix_rpy(_mul(self.r, rpy_matrix(*p6[3:6])))
            return (xyz + list(abc))[:n]
        return xyz[:n]

    @property
    def is_identity(self) -> bool:
        return self.t == [0.0, 0.0, 0.0] and self.r == Frame().r


class CoordSystems:
    """The transforms of one group: PCS, WCS1-15 and OFFSET (all identity at first)."""

    def __init__(self) -> None:
        self.params: dict[int, list[float]] = {}
        """System word (CS_PCS, CS_OFFSET, n << 4) -> its six transform values."""

    @staticmethod
    def valid(cs: int) -> bool:
        """A word SetGrpCoordSys accepts (CS_ACS alone or a chain of PCS, WCSn, OFFSET)."""
        if cs == CS_ACS:
            return True
        return cs >= 0 and not cs & ~(CS_PCS | CS_OFFSET | WCS_MASK)

    @staticmethod
    def single(cs: int) -> bool:
        """One system whose transform can be set: CS_PCS, CS_OFFSET or one CS_WCSn."""
        return cs in (CS_PCS, CS_OFFSET) or (cs & ~WCS_MASK == 0 and cs & WCS_MASK != 0)

    def set(self, cs: int, params) -> None:
        self.params[cs] = [float(v) for v in params]

    def get(self, cs: int) -> list[float]:
        return list(self.params.get(cs, [0.0] * 6))

    def _frame(self, cs: int) -> Frame:
        p = self.params.get(cs)
        return Frame.of(p) if p is not None else Frame()

    def to_mcs(self, cs: int) -> Frame:
        """The frame taking a pose in system word `cs` to machine coordinates."""
        f = Frame()
        if cs & CS_OFFSET:
            f = f.compose(self._frame(CS_OFFSET))
        if cs & WCS_MASK:
            f = f.compose(self._frame(cs & WCS_MASK))
        if cs & CS_PCS:
            f = f.compose(self._frame(CS_PCS))
        return f
