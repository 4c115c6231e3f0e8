#!/usr/bin/python3
"""The paper's dynamic experiment (section 5.2) as an external master program.

Welds the two fillet seams of the box cell served by `vts serve`, guided by
the virtual sensor through the network protocol alone (docs/PROTOCOL.md,
python/vts_client.py): the master's plan, its parameters and the sensor come
from `sim.job`, the ground truth for the tracking error from `sim.truth`.

    build/bin/vts serve --seed 5 &
    examples/master.py --json            # the summary of `vts sim --json --seed 5`

Lockstep (default): a faithful port of tracker::Master::run (tracker/master.cpp)
and of the evaluation of `vts sim` (sensor/sim_cell.cpp evaluate,
pipeline/sim_run.cpp, apps/vts_sim.cpp). Each master cycle sends the tool pose
(`robot.servo`) and advances time by one cycle (`step`); the floating-point
arithmetic follows the C++ (and Eigen's) order of operations, so the summary
equals `vts sim --json` with the same seed.

--realtime, against `vts serve --realtime`: time runs on its own; the master
queues linear moves along the seam object (`robot.move`) and asks the sensor
for its joint data (`sensor.joints`) about every other second, as in the
paper. See run_realtime().

Standard library only; no numpy (the little linear algebra is below).
Units: mm, s, degrees.
"""

import argparse
import ctypes
import ctypes.util
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import vts_client  # noqa: E402

# ---------------------------------------------------------------------------
# Linear algebra on 3-vectors (lists of 3 floats) and 3x3 matrices (lists of
# rows), in the order of operations Eigen 3.4 uses on x86-64 (SSE2, no FMA):
# a dot product or squared norm sums ((0 + 1) + 2); a 3x3 matrix times a
# vector (or matrix) computes rows 0 and 1 that way and row 2 as
# (0 + (1 + 2)); an Isometry3d times a point adds the translation to
# ((0 + 1) + 2) for every row.
# ---------------------------------------------------------------------------

DBL_MIN = sys.float_info.min
DBL_EPS = sys.float_info.epsilon
INF = float("inf")

_libm = None


def c_hypot(x, y):
    """std::hypot as the C++ build calls it (the C library's), so that the
    result is the same bits; math.hypot if libm cannot be loaded."""
    global _libm
    if _libm is None:
        try:
            lib = ctypes.CDLL(ctypes.util.find_library("m") or "libm.so.6")
            lib.hypot.restype = ctypes.c_double
            lib.hypot.argtypes = [ctypes.c_double, ctypes.c_double]
            _libm = lib.hypot
        except OSError:
            _libm = math.hypot
    return _libm(x, y)


def v_add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def v_sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def v_scale(k, a):
    return [k * a[0], k * a[1], k * a[2]]


def v_neg(a):
    return [-a[0], -a[1], -a[2]]


def dot(a, b):
    return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]


def sq_norm(a):
    return (a[0] * a[0] + a[1] * a[1]) + a[2] * a[2]


def norm(a):
    return math.sqrt(sq_norm(a))


def normalized(a):
    z = sq_norm(a)
    if z > 0.0:
        s = math.sqrt(z)
        return [a[0] / s, a[1] / s, a[2] / s]
    return list(a)


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def mat_vec(m, v):
    """Eigen's Matrix3d * Vector3d."""
    return [(m[0][0] * v[0] + m[0][1] * v[1]) + m[0][2] * v[2],
            (m[1][0] * v[0] + m[1][1] * v[1]) + m[1][2] * v[2],
            m[2][0] * v[0] + (m[2][1] * v[1] + m[2][2] * v[2])]


def mat_mul(a, b):
    """Eigen's Matrix3d * Matrix3d."""
    out = [[0.0] * 3 for _ in range(3)]
    for c in range(3):
        col = mat_vec(a, [b[0][c], b[1][c], b[2][c]])
        for r in range(3):
            out[r][c] = col[r]
    return out


def transpose(m):
    return [[m[0][0], m[1][0], m[2][0]], [m[0][1], m[1][1], m[2][1]], [m[0][2], m[1][2], m[2][2]]]


def determinant(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def identity3():
    return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


class Pose:
    """world_from_frame: rotation R (3x3 rows) and translation t (mm)."""

    __slots__ = ("R", "t")

    def __init__(self, R=None, t=None):
        self.R = [list(r) for r in R] if R is not None else identity3()
        self.t = list(t) if t is not None else [0.0, 0.0, 0.0]

    @staticmethod
    def from_json(p):
        t, R = vts_client.pose_parts(p)
        return Pose(R, t)

    def to_json(self):
        return vts_client.pose(self.t, self.R)

    def apply(self, v):
        """Eigen's Isometry3d * Vector3d."""
        R, t = self.R, self.t
        return [t[0] + ((R[0][0] * v[0] + R[0][1] * v[1]) + R[0][2] * v[2]),
                t[1] + ((R[1][0] * v[0] + R[1][1] * v[1]) + R[1][2] * v[2]),
                t[2] + ((R[2][0] * v[0] + R[2][1] * v[1]) + R[2][2] * v[2])]

    def copy(self):
        return Pose(self.R, self.t)


# -- Eigen's SelfAdjointEigenSolver<Matrix3d> (tridiagonalization + implicit
#    symmetric QR steps), eigenvalues ascending --------------------------------

def _apply_rotation(x, y, c, s):
    """Eigen's apply_rotation_in_the_plane on two coordinate lists, in place:
    x = c x + s y, y = -s x + c y."""
    for i in range(len(x)):
        xi, yi = x[i], y[i]
        x[i] = c * xi + s * yi
        y[i] = -s * xi + c * yi


def _col(m, j):
    return [m[0][j], m[1][j], m[2][j]]


def _set_col(m, j, v):
    m[0][j], m[1][j], m[2][j] = v[0], v[1], v[2]


def _rotate_cols(m, p, q, c, s):
    """m.applyOnTheRight(p, q, J(c, s)): the columns with J's transpose."""
    x, y = _col(m, p), _col(m, q)
    _apply_rotation(x, y, c, -s)
    _set_col(m, p, x)
    _set_col(m, q, y)


def _rotate_rows(m, p, q, c, s):
    """m.applyOnTheLeft(p, q, J(c, s))."""
    x, y = list(m[p]), list(m[q])
    _apply_rotation(x, y, c, s)
    m[p], m[q] = x, y


def _make_givens(p, q):
    if q == 0.0:
        return (-1.0 if p < 0.0 else 1.0), 0.0
    if p == 0.0:
        return 0.0, (1.0 if q < 0.0 else -1.0)
    if abs(p) > abs(q):
        t = q / p
        u = math.sqrt(1.0 + t * t)
        if p < 0.0:
            u = -u
        c = 1.0 / u
        return c, -t * c
    t = p / q
    u = math.sqrt(1.0 + t * t)
    if q < 0.0:
        u = -u
    s = -1.0 / u
    return -t * s, s


def _eigen_hypot(x, y):
    x, y = abs(x), abs(y)
    if math.isinf(x) or math.isinf(y):
        return INF
    if math.isnan(x) or math.isnan(y):
        return float("nan")
    p = y if x < y else x  # numext::maxi(x, y)
    if p == 0.0:
        return 0.0
    qp = (x if x < y else y) / p  # numext::mini(y, x) / p
    return p * math.sqrt(1.0 + qp * qp)


def _qr_step(diag, sub, start, end, q):
    td = (diag[end - 1] - diag[end]) * 0.5
    e = sub[end - 1]
    mu = diag[end]
    if td == 0.0:
        mu -= abs(e)
    elif e != 0.0:
        e2 = e * e
        h = _eigen_hypot(td, e)
        if e2 == 0.0:
            mu -= e / ((td + (h if td > 0.0 else -h)) / e)
        else:
            mu -= e2 / (td + (h if td > 0.0 else -h))
    x = diag[start] - mu
    z = sub[start]
    k = start
    while k < end and z != 0.0:
        c, s = _make_givens(x, z)
        sdk = s * diag[k] + c * sub[k]
        dkp1 = s * sub[k] + c * diag[k + 1]
        diag[k] = c * (c * diag[k] - s * sub[k]) - s * (c * sub[k] - s * diag[k + 1])
        diag[k + 1] = s * sdk + c * dkp1
        sub[k] = c * sdk - s * dkp1
        if k > start:
            sub[k - 1] = c * sub[k - 1] - s * z
        x = sub[k]
        if k < end - 1:
            z = -s * sub[k + 1]
            sub[k + 1] = c * sub[k + 1]
        _rotate_cols(q, k, k + 1, c, s)
        k += 1


def sym_eigenvectors(a):
    """Eigenvalues (ascending) and eigenvectors (the columns of a 3x3 matrix)
    of the symmetric matrix a (its lower triangle is read), as
    Eigen::SelfAdjointEigenSolver<Matrix3d> computes them."""
    mat = [[a[0][0], 0.0, 0.0], [a[1][0], a[1][1], 0.0], [a[2][0], a[2][1], a[2][2]]]
    scale = 0.0
    for r in range(3):
        for c in range(3):
            scale = max(scale, abs(mat[r][c]))
    if scale == 0.0:
        scale = 1.0
    for r in range(3):
        for c in range(r + 1):
            mat[r][c] /= scale
    diag = [mat[0][0], 0.0, 0.0]
    sub = [0.0, 0.0]
    v1norm2 = mat[2][0] * mat[2][0]
    if v1norm2 <= DBL_MIN:
        diag[1], diag[2] = mat[1][1], mat[2][2]
        sub[0], sub[1] = mat[1][0], mat[2][1]
        q = identity3()
    else:
        beta = math.sqrt(mat[1][0] * mat[1][0] + v1norm2)
        inv_beta = 1.0 / beta
        m01 = mat[1][0] * inv_beta
        m02 = mat[2][0] * inv_beta
        qq = 2.0 * m01 * mat[2][1] + m02 * (mat[2][2] - mat[1][1])
        diag[1] = mat[1][1] + m02 * qq
        diag[2] = mat[2][2] - m02 * qq
        sub[0] = beta
        sub[1] = mat[2][1] - m01 * qq
        q = [[1.0, 0.0, 0.0], [0.0, m01, m02], [0.0, m02, -m01]]
    n = 3
    end, start, it = n - 1, 0, 0
    precision_inv = 1.0 / DBL_EPS
    max_iterations = 30
    while end > 0:
        for i in range(start, end):
            if abs(sub[i]) < DBL_MIN:
                sub[i] = 0.0
            else:
                scaled = precision_inv * sub[i]
                if scaled * scaled <= abs(diag[i]) + abs(diag[i + 1]):
                    sub[i] = 0.0
        while end > 0 and sub[end - 1] == 0.0:
            end -= 1
        if end <= 0:
            break
        it += 1
        if it > max_iterations * n:
            break
        start = end - 1
        while start > 0 and sub[start - 1] != 0.0:
            start -= 1
        _qr_step(diag, sub, start, end, q)
    if it <= max_iterations * n:
        for i in range(n - 1):
            k = i
            for j in range(i + 1, n):
                if diag[j] < diag[k]:
                    k = j
            if k != i:
                diag[i], diag[k] = diag[k], diag[i]
                ci, ck = _col(q, i), _col(q, k)
                _set_col(q, i, ck)
                _set_col(q, k, ci)
    return [d * scale for d in diag], q


# -- Eigen's JacobiSVD<Matrix3d> (two-sided Jacobi), full U and V ------------

def jacobi_svd(a):
    """(singular values descending, U, V) with a = U diag(sv) V^T, as
    Eigen::JacobiSVD<Matrix3d>(a, ComputeFullU | ComputeFullV) computes them."""
    scale = 0.0
    for r in range(3):
        for c in range(3):
            v = abs(a[r][c])
            if math.isnan(v):
                scale = v
                break
            scale = max(scale, v)
    if not math.isfinite(scale):
        raise ValueError("jacobi_svd: the matrix is not finite")
    if scale == 0.0:
        scale = 1.0
    w = [[a[r][c] / scale for c in range(3)] for r in range(3)]
    U, V = identity3(), identity3()
    precision = 2.0 * DBL_EPS
    max_diag = max(abs(w[0][0]), abs(w[1][1]), abs(w[2][2]))
    finished = False
    while not finished:
        finished = True
        for p in range(1, 3):
            for q in range(p):
                threshold = max(DBL_MIN, precision * max_diag)
                if abs(w[p][q]) > threshold or abs(w[q][p]) > threshold:
                    finished = False
                    # real_2x2_jacobi_svd
                    m = [[w[p][p], w[p][q]], [w[q][p], w[q][q]]]
                    t = m[0][0] + m[1][1]
                    d = m[1][0] - m[0][1]
                    if abs(d) < DBL_MIN:
                        s1, c1 = 0.0, 1.0
                    else:
                        u = t / d
                        tmp = math.sqrt(1.0 + u * u)
                        s1 = 1.0 / tmp
                        c1 = u / tmp
                    _rotate_rows(m, 0, 1, c1, s1)
                    # makeJacobi(m(0,0), m(0,1), m(1,1))
                    x, y, z = m[0][0], m[0][1], m[1][1]
                    deno = 2.0 * abs(y)
                    if deno < DBL_MIN:
                        cr, sr = 1.0, 0.0
                    else:
                        tau = (x - z) / deno
                        ww = math.sqrt(tau * tau + 1.0)
                        tt = 1.0 / (tau + ww) if tau > 0.0 else 1.0 / (tau - ww)
                        sign_t = 1.0 if tt > 0.0 else -1.0
                        nn = 1.0 / math.sqrt(tt * tt + 1.0)
                        sr = -sign_t * (y / abs(y)) * abs(tt) * nn
                        cr = nn
                    # j_left = rot1 * j_right.transpose()
                    crt, srt = cr, -sr
                    cl = c1 * crt - s1 * srt
                    sl = c1 * srt + s1 * crt
                    _rotate_rows(w, p, q, cl, sl)
                    _rotate_cols(U, p, q, cl, -sl)
                    _rotate_cols(w, p, q, cr, sr)
                    _rotate_cols(V, p, q, cr, sr)
                    max_diag = max(max_diag, max(abs(w[p][p]), abs(w[q][q])))
    sv = [0.0, 0.0, 0.0]
    for i in range(3):
        a_ii = w[i][i]
        sv[i] = abs(a_ii)
        if a_ii < 0.0:
            _set_col(U, i, v_neg(_col(U, i)))
    sv = [x * scale for x in sv]
    for i in range(3):
        pos = i
        for j in range(i + 1, 3):
            if sv[j] > sv[pos]:
                pos = j
        if sv[pos] == 0.0:
            break
        if pos != i:
            sv[i], sv[pos] = sv[pos], sv[i]
            for M in (U, V):
                ci, cp = _col(M, i), _col(M, pos)
                _set_col(M, i, cp)
                _set_col(M, pos, ci)
    return sv, U, V


# ---------------------------------------------------------------------------
# The master (tracker/master.cpp)
# ---------------------------------------------------------------------------

MASTER_DEFAULTS = {
    "speed_mm_s": 10.0, "control_rate_hz": 20.0, "lookahead_mm": 50.0, "search_margin_mm": 25.0,
    "search_margin_recalibrated_mm": 3.0, "search_extra_mm": 10.0, "max_search_retries": 2,
    "end_margin_mm": 20.0, "fit_window_mm": 10.0, "gate_mm": 1.0, "gate_after": 10,
    "direction_span_mm": 10.0, "refit_after_rejections": 6, "recalibrate": True,
}


class Params:
    """tracker::MasterParams, from sim.job's `master` (defaults as in C++)."""

    def __init__(self, d=None):
        d = d or {}
        for k, v in MASTER_DEFAULTS.items():
            val = d.get(k, v)
            if isinstance(v, bool):
                val = bool(val)
            elif isinstance(v, int):
                val = int(val)
            else:
                val = float(val)
            setattr(self, k, val)


class SeamObject:
    """The measured seam: joint points in world, arc length from the start
    point along the running line fit (tracker::SeamObject)."""

    SLACK_MM = 2.0

    def __init__(self):
        self.reset([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])

    def reset(self, origin, direction_guess):
        self.origin = list(origin)
        self.guess = normalized(direction_guess)
        self.points = []
        self.arcs = []
        self.sum = [0.0, 0.0, 0.0]
        self.sum_outer = [[0.0] * 3 for _ in range(3)]
        self.span = 0.0
        self._dir = None

    def size(self):
        return len(self.points)

    def direction(self):
        if self._dir is None:
            self._dir = self._direction()
        return self._dir

    def _direction(self):
        if len(self.points) < 2 or self.span < 2.0:
            return self.guess
        n = float(len(self.points))
        mean = [self.sum[0] / n, self.sum[1] / n, self.sum[2] / n]
        cov = [[self.sum_outer[r][c] / n - mean[r] * mean[c] for c in range(3)] for r in range(3)]
        _, vecs = sym_eigenvectors(cov)
        d = normalized(_col(vecs, 2))
        return v_neg(d) if dot(d, self.guess) < 0.0 else d

    def arc(self, p):
        return dot(v_sub(p, self.origin), self.direction())

    def centroid(self):
        if not self.points:
            return list(self.origin)
        n = float(len(self.points))
        return [self.origin[i] + self.sum[i] / n for i in range(3)]

    def max_arc(self):
        if not self.points:
            return 0.0
        d = self.direction()
        m = -INF
        for p in self.points[max(0, len(self.points) - 16):]:
            a = dot(v_sub(p, self.origin), d)
            m = a if m < a else m
        return m

    def at(self, s, window_mm):
        d = self.direction()
        lo_arc = s - window_mm - self.SLACK_MM
        hi_arc = s + window_mm + self.SLACK_MM
        arcs = self.arcs
        # partition_point(a < lo_arc) on the sorted arcs
        lo_i, hi_i = 0, len(arcs)
        while lo_i < hi_i:
            mid = (lo_i + hi_i) // 2
            if arcs[mid] < lo_arc:
                lo_i = mid + 1
            else:
                hi_i = mid
        sw = st = stt = 0.0
        sp = [0.0, 0.0, 0.0]
        stp = [0.0, 0.0, 0.0]
        lo, hi = INF, -INF
        o = self.origin
        i = lo_i
        while i < len(arcs) and arcs[i] <= hi_arc:
            p = self.points[i]
            i += 1
            t = dot(v_sub(p, o), d) - s
            if abs(t) > window_mm:
                continue
            sw += 1.0
            st += t
            stt += t * t
            sp = v_add(sp, p)
            stp = v_add(stp, v_scale(t, p))
            lo = t if t < lo else lo
            hi = t if hi < t else hi
        det = sw * stt - st * st
        if sw >= 3.0 and hi - lo >= 1.0 and det > 1e-9:
            return [(stt * sp[k] - st * stp[k]) / det for k in range(3)]
        if len(self.points) >= 2:
            c = self.centroid()
            return v_add(c, v_scale(s - dot(v_sub(c, o), d), d))
        return v_add(o, v_scale(s, d))

    def add(self, p, window_mm, gate_mm, gate_after):
        if self.size() >= gate_after:
            predicted = self.at(self.arc(p), window_mm)
            if norm(v_sub(p, predicted)) > gate_mm:
                return False
        else:
            d = self.direction()
            r = v_sub(p, self.origin)
            rd = dot(r, d)
            if norm(v_sub(r, v_scale(rd, d))) > gate_mm + 0.2 * abs(dot(r, d)):
                return False
        q = v_sub(p, self.origin)
        self.sum = v_add(self.sum, q)
        so = self.sum_outer
        for r in range(3):
            for c in range(3):
                so[r][c] = so[r][c] + q[r] * q[c]
        dist = norm(v_sub(p, self.origin))
        self.span = dist if self.span < dist else self.span
        self._dir = None
        self.points.append(list(p))
        self.arcs.append(self.arc(p))
        i = len(self.arcs) - 1
        while i > 0 and self.arcs[i] < self.arcs[i - 1]:
            self.arcs[i], self.arcs[i - 1] = self.arcs[i - 1], self.arcs[i]
            self.points[i], self.points[i - 1] = self.points[i - 1], self.points[i]
            i -= 1
        return True


def tool_rotation(direction, plate_normal, wall_normal):
    """The tool orientation for a seam: x along direction, z into the joint
    (against the bisector of the surface normals), y = z cross x."""
    x = normalized(direction)
    z = v_neg(normalized(v_add(plate_normal, wall_normal)))
    z = normalized(v_sub(z, v_scale(dot(z, x), x)))
    y = cross(z, x)
    return [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]


def recalibrate(believed, seam, start, end, measured_plate_normal, measured_wall_normal):
    """The workpiece pose mapping the plan's start and end onto the measured
    ones and its direction and face normals onto the measured ones (Kabsch)."""
    rb = [list(r) for r in believed.R]
    d_b = mat_vec(rb, normalized(v_sub(seam["end_mm"], seam["start_mm"])))
    d_m = normalized(v_sub(end, start))
    two_dm = v_scale(2.0, d_m)
    h = [[two_dm[r] * d_b[c] for c in range(3)] for r in range(3)]
    np_b, nw_b = mat_vec(rb, seam["plate_normal"]), mat_vec(rb, seam["wall_normal"])
    for measured, believed_n in ((measured_plate_normal, np_b), (measured_wall_normal, nw_b)):
        if norm(measured) > 0.5:
            mn = normalized(measured)
            for r in range(3):
                for c in range(3):
                    h[r][c] = h[r][c] + mn[r] * believed_n[c]
    _, U, V = jacobi_svd(h)
    Vt = transpose(V)
    fix = identity3()
    fix[2][2] = -1.0 if determinant(mat_mul(U, Vt)) < 0.0 else 1.0
    r = mat_mul(mat_mul(U, fix), Vt)
    out = Pose()
    out.R = mat_mul(r, rb)
    mid_plan = v_scale(0.5, v_add(seam["start_mm"], seam["end_mm"]))
    out.t = v_sub(v_scale(0.5, v_add(start, end)), mat_vec(out.R, mid_plan))
    return out


def surface_normal(d, u, like):
    if norm(u) < 1e-9:
        return [0.0, 0.0, 0.0]
    n = cross(d, normalized(u))
    if norm(n) < 1e-6:
        return [0.0, 0.0, 0.0]
    n = normalized(n)
    return v_neg(n) if dot(n, like) < 0.0 else n


def cpp_to_string(x):
    """std::to_string(double)."""
    return "%f" % x


class ProtocolSensor:
    """tracker::SensorInterface over the protocol, lockstep: advance() is
    robot.servo with the tool pose and a step to the cycle's time."""

    def __init__(self, client):
        self.c = client
        self._error = ""
        self.actual = [0.0, 0.0, 0.0]  # the TCP after the last step, as the simulator knows it
        self._start = None
        self._end = None

    def laser_on(self):
        try:
            a = self.c.laser_on()
        except vts_client.VtsError as e:
            if e.code != "failed":
                raise
            self._error = e.message
            return False
        if not a.get("confirmed", False):
            self._error = a.get("message", "")
            return False
        return True

    def laser_off(self):
        self.c.laser_off()

    def search_start(self):
        self.c.search_start()

    def start_tracking(self):
        self.c.start_tracking()

    def look_for_end(self):
        self.c.look_for_end()

    def error(self):
        return self._error

    def advance(self, now, tool):
        self.c.servo(tool.to_json())
        answer = self.c.step(to_s=now)
        # Where the TCP really is (the simulator's truth): the commanded pose
        # with a perfect robot, behind it and off it with an arm.
        self.actual = [float(x) for x in answer["world_from_tool_actual"]["t"]]
        self.c.events()  # pushed copies of the same alerts, if subscribed: the step's answer has them
        names = []
        for e in answer.get("events", []):
            name = e.get("event")
            names.append(name)
            if name == "start-found" and e.get("point") is not None:
                self._start = [float(x) for x in e["point"]]
            elif name == "end-found" and e.get("point") is not None:
                self._end = [float(x) for x in e["point"]]
            elif name == "stream-ended":
                self._error = e.get("message", "") or self._error
        return names

    def _state(self):
        return self.c.sensor_state()

    def state(self):
        return self._state()["state"]

    def start_point(self):
        if self._start is None:
            p = self._state().get("start_point")
            self._start = None if p is None else [float(x) for x in p]
        return self._start

    def end_point(self):
        if self._end is None:
            p = self._state().get("end_point")
            self._end = None if p is None else [float(x) for x in p]
        return self._end

    def latest_joint(self, now):
        return self.c.joint()


class SeamRun:
    def __init__(self):
        self.start_found = False
        self.end_found = False
        self.lost = False
        self.failure = ""
        self.search_mm = 0.0
        self.start_point = [0.0, 0.0, 0.0]
        self.end_point = [0.0, 0.0, 0.0]
        self.weld_start = [0.0, 0.0, 0.0]
        self.weld_end = [0.0, 0.0, 0.0]
        self.welded_mm = 0.0
        self.points = 0
        self.track_points = []
        self.max_gap_mm = 0.0  # the largest gap reported with the points accepted as they came
        self.rejected_points = 0
        self.refits = 0
        self.line_point = [0.0, 0.0, 0.0]
        self.line_direction = [1.0, 0.0, 0.0]


class Result:
    def __init__(self):
        self.samples = []  # (time_s, seam, phase, tcp)
        self.seams = []
        self.world_from_workpiece = []


class JointIntake:
    """The joint data into the seam object, as Master::run's poll does: the
    gate, the refit after refit_after_rejections consistent rejections, and
    the two surfaces' directions from break points 0 and 4 (for
    re-calibration)."""

    def __init__(self, P, obj, run, plate_normal, wall_normal):
        self.P, self.obj, self.run = P, obj, run
        self.np, self.nw = plate_normal, wall_normal
        self.rejected = []
        self.plate_dir = [0.0, 0.0, 0.0]
        self.wall_dir = [0.0, 0.0, 0.0]
        self.last_accepted = list(run.start_point)

    def take(self, j):
        """Adds joint data j (protocol dict); False if it was rejected."""
        P, obj, run, rejected = self.P, self.obj, self.run, self.rejected
        tp = [float(x) for x in j["track_point_world"]]
        if not obj.add(tp, P.fit_window_mm, P.gate_mm, P.gate_after):
            run.rejected_points += 1
            rejected.append(tp)
            if len(rejected) < P.refit_after_rejections:
                return False
            span = v_sub(rejected[-1], rejected[0])
            consistent = norm(span) > 1e-6
            for p in rejected:
                r = v_sub(p, rejected[0])
                sn = normalized(span)
                consistent = consistent and norm(v_sub(r, v_scale(dot(r, sn), sn))) <= P.gate_mm
            if not consistent:
                del rejected[0]
                return False
            sn = normalized(span)
            u = v_neg(sn) if dot(sn, obj.direction()) < 0.0 else sn
            c = rejected[0]
            obj.reset(v_add(c, v_scale(dot(v_sub(run.start_point, c), u), u)), u)
            for p in rejected:
                obj.add(p, P.fit_window_mm, INF, P.gate_after)
            run.track_points.extend(rejected[:-1])
            run.points += len(rejected) - 1
            run.rejected_points -= len(rejected)
            run.refits += 1
            rejected.clear()
        else:
            rejected.clear()
        run.points += 1
        run.track_points.append(tp)
        if j.get("gap_mm") is not None and j["gap_mm"] > run.max_gap_mm:
            run.max_gap_mm = j["gap_mm"]
        self.last_accepted = tp
        wfs = Pose.from_json(j["world_from_sensor"])
        bps = j.get("break_points_sensor") or []
        np_, nw = self.np, self.nw
        for b in (0, 4):
            if b >= len(bps) or bps[b] is None:
                continue
            yz = bps[b]
            u = v_sub(wfs.apply([0.0, float(yz[0]), float(yz[1])]), tp)
            if norm(u) < 3.0:
                continue
            un = normalized(u)
            if abs(dot(un, nw)) > abs(dot(un, np_)):
                self.plate_dir = v_add(self.plate_dir, v_neg(un) if dot(un, nw) < 0.0 else un)
            else:
                self.wall_dir = v_add(self.wall_dir, v_neg(un) if dot(un, np_) < 0.0 else un)
        return True


def seam_geometry(P, believed, plan, recalibrated):
    """A seam of the plan as the master sees it before welding it: planned
    start (world), unit direction, length, the two face normals (world), and
    the search margin (Master::run's start of a seam)."""
    step = P.speed_mm_s * (1.0 / P.control_rate_hz)
    s_plan, e_plan = believed.apply(plan["start_mm"]), believed.apply(plan["end_mm"])
    d_plan = normalized(v_sub(e_plan, s_plan))
    length = norm(v_sub(e_plan, s_plan))
    np_, nw = mat_vec(believed.R, plan["plate_normal"]), mat_vec(believed.R, plan["wall_normal"])
    # After re-calibration the start is known to well under a profile step:
    # put it halfway between two profiles' laser planes.
    margin = P.search_margin_recalibrated_mm + 0.5 * step if recalibrated else P.search_margin_mm
    return s_plan, d_plan, length, np_, nw, margin


def recalibrated_pose(believed, plan, run, obj, intake, np_, nw):
    """The workpiece pose re-estimated from a welded seam: its start and end
    moved onto the seam object's line, the faces' measured normals."""
    d = obj.direction()

    def on_line(p):
        return v_add(run.line_point, v_scale(dot(v_sub(p, run.line_point), d), d))

    return recalibrate(believed, plan, on_line(run.start_point), on_line(run.end_point),
                       surface_normal(d, intake.plate_dir, np_), surface_normal(d, intake.wall_dir, nw))


def run_master(sensor, P, world_from_workpiece, seams, log=None):
    """tracker::Master::run against a ProtocolSensor. seams: the plan
    (dicts with start_mm, end_mm, plate_normal, wall_normal; workpiece frame)."""
    res = Result()
    believed = world_from_workpiece.copy()
    recalibrated = False
    dt = 1.0 / P.control_rate_hz
    step = P.speed_mm_s * dt
    state = {"cycle": 0, "now": 0.0}
    tool = Pose()

    def tick(seam, phase, s):
        state["cycle"] += 1
        state["now"] = float(state["cycle"]) * dt
        events = sensor.advance(state["now"], tool)
        res.samples.append((state["now"], seam, phase, list(sensor.actual)))
        if log:
            log(state["now"], seam, phase, tool, events)
        return events

    for k, plan in enumerate(seams):
        res.world_from_workpiece.append(believed.copy())
        run = SeamRun()
        s_plan, d_plan, length, np_, nw, margin = seam_geometry(P, believed, plan, recalibrated)

        tool.R = tool_rotation(d_plan, np_, nw)
        begin = v_sub(s_plan, v_scale(margin + P.lookahead_mm, d_plan))
        tool.t = list(begin)
        tick(k, "move", 0.0)

        def finish():
            if sensor.state() != "idle":
                sensor.laser_off()
            res.seams.append(run)

        if not sensor.laser_on():
            run.failure = "the laser did not come on: " + sensor.error()
            finish()
            continue

        found = False
        attempt = 0
        while attempt <= P.max_search_retries and not found and not run.failure:
            sensor.search_start()
            travelled = 0.0
            limit = 2.0 * margin + P.search_extra_mm
            while True:
                tool.t = v_add(tool.t, v_scale(step, d_plan))
                travelled += step
                run.search_mm += step
                ev = tick(k, "search", 0.0)
                if "start-found" in ev:
                    found = True
                    break
                if "stream-ended" in ev:
                    run.failure = "the sensor stopped during the search: " + sensor.error()
                    break
                if "start-behind" in ev:
                    begin = v_sub(begin, v_scale(P.search_margin_mm, d_plan))
                    tool.t = list(begin)
                    tick(k, "move", 0.0)
                    if attempt == P.max_search_retries:
                        run.failure = "the start point lies behind every search"
                    break
                if travelled > limit:
                    run.failure = "no start point within " + cpp_to_string(limit) + " mm of search"
                    break
            attempt += 1
        if not found:
            finish()
            continue
        run.start_found = True
        run.start_point = list(sensor.start_point())
        sensor.start_tracking()

        obj = SeamObject()
        obj.reset(run.start_point, d_plan)
        st = {"last_index": -1, "stop_point": None, "last_accepted": list(run.start_point),
              "end_requested": False}
        intake = JointIntake(P, obj, run, np_, nw)

        def poll():
            j = sensor.latest_joint(state["now"])
            if j is None or j["profile_index"] == st["last_index"]:
                return
            st["last_index"] = j["profile_index"]
            if not intake.take(j):
                return
            tp = intake.last_accepted
            st["last_accepted"] = tp
            if (not st["end_requested"] and sensor.state() == "tracking"
                    and obj.arc(tp) >= length - P.end_margin_mm):
                sensor.look_for_end()
                st["end_requested"] = True

        def handle(ev):
            if st["stop_point"] is not None:
                return
            if "end-found" in ev:
                run.end_found = True
                run.end_point = list(sensor.end_point())
                st["stop_point"] = run.end_point
            elif "seam-lost" in ev:
                run.lost = True
                st["stop_point"] = st["last_accepted"]
            elif "stream-ended" in ev:
                run.failure = "the sensor stopped while tracking: " + sensor.error()
                st["stop_point"] = st["last_accepted"]
            else:
                return
            sensor.laser_off()

        poll()

        def travel_direction():
            return obj.direction() if obj.max_arc() >= P.direction_span_mm else d_plan

        approach_limit = int(4.0 * (P.lookahead_mm + 2.0 * margin + 50.0) / step) + 100
        c = 0
        while True:
            if c > approach_limit:
                run.failure = "the approach to the start point did not converge"
                break
            w0 = obj.at(0.0, P.fit_window_mm)
            to = v_sub(w0, tool.t)
            tool.R = tool_rotation(travel_direction(), np_, nw)
            if norm(to) <= step:
                tool.t = list(w0)
            else:
                tool.t = v_add(tool.t, v_scale(step, normalized(to)))
            ev = tick(k, "approach", 0.0)
            poll()
            handle(ev)
            if norm(to) <= step:
                break
            c += 1

        run.weld_start = list(sensor.actual)
        s = 0.0
        while not run.failure:
            stop = st["stop_point"]
            s_stop = obj.arc(stop) if stop is not None else INF
            if stop is not None and s >= s_stop - 1e-9:
                break
            s_next = min(s + step, s_stop)
            if stop is None and s_next > obj.max_arc():
                run.failure = "the torch caught up with the sensor data at s = " + cpp_to_string(s) + " mm"
                break
            if s > 2.0 * length + 50.0:
                run.failure = "no end of seam within twice the planned length"
                break
            s = s_next
            tool.t = obj.at(s, P.fit_window_mm)
            tool.R = tool_rotation(travel_direction(), np_, nw)
            ev = tick(k, "weld", s)
            poll()
            handle(ev)
        run.weld_end = list(sensor.actual)
        run.welded_mm = s
        run.line_direction = obj.direction()
        run.line_point = obj.centroid()
        finish()

        if P.recalibrate and run.start_found and run.end_found and not run.failure:
            believed = recalibrated_pose(believed, plan, run, obj, intake, np_, nw)
            recalibrated = True
    tick(-1, "done", 0.0)
    return res


# ---------------------------------------------------------------------------
# Evaluation (sensor/sim_cell.cpp evaluate, pipeline/sim_run.cpp)
# ---------------------------------------------------------------------------

class SeamTruth:
    def __init__(self, d):
        self.start = [float(x) for x in d["start"]]
        self.end = [float(x) for x in d["end"]]
        self.plate_normal = [float(x) for x in d["plate_normal"]]
        self.wall_normal = [float(x) for x in d["wall_normal"]]

    def direction(self):
        return normalized(v_sub(self.end, self.start))

    def length(self):
        return norm(v_sub(self.end, self.start))

    def lateral(self):
        l = normalized(cross(self.plate_normal, self.direction()))
        return v_neg(l) if dot(l, self.wall_normal) < 0.0 else l


def seam_error(seam, tcp):
    """(lateral, vertical) error of tcp from the true seam line, mm."""
    d = seam.direction()
    s = min(max(dot(v_sub(tcp, seam.start), d), 0.0), seam.length())
    true_point = v_add(seam.start, v_scale(s, d))
    r = v_sub(tcp, true_point)
    return dot(r, seam.lateral()), dot(r, seam.plate_normal)


def evaluate(truth, result):
    out = []
    for k in range(min(len(result.seams), len(truth))):
        run, t = result.seams[k], truth[k]
        m = {"samples": 0, "max_error_mm": 0.0, "rms_lateral_mm": 0.0, "rms_vertical_mm": 0.0,
             "sensor_rms_mm": 0.0}
        sl = sv = 0.0
        for (_, seam, phase, tcp) in result.samples:
            if seam != k or phase != "weld":
                continue
            lat, ver = seam_error(t, tcp)
            sl += lat * lat
            sv += ver * ver
            m["max_error_mm"] = max(m["max_error_mm"], c_hypot(lat, ver))
            m["samples"] += 1
        sp = 0.0
        for p in run.track_points:
            lat, ver = seam_error(t, p)
            sp += lat * lat + ver * ver
        if run.track_points:
            m["sensor_rms_mm"] = math.sqrt(sp / len(run.track_points))
        welded = run.start_found and m["samples"] > 0
        if m["samples"] > 0:
            m["rms_lateral_mm"] = math.sqrt(sl / m["samples"])
            m["rms_vertical_mm"] = math.sqrt(sv / m["samples"])
        d = t.direction()
        ds, de = v_sub(run.weld_start, t.start), v_sub(run.weld_end, t.end)
        m["start_error_mm"] = norm(ds) if welded else 0.0
        m["end_error_mm"] = norm(de) if welded else 0.0
        m["start_along_mm"] = dot(ds, d) if welded else 0.0
        m["end_along_mm"] = dot(de, d) if welded else 0.0
        m["welded"] = welded
        m["run"] = run
        out.append(m)
    return out


def seam_metrics_json(m, index):
    run = m["run"]
    return {
        "seam": index + 1,
        "rms_lateral_mm": m["rms_lateral_mm"],
        "rms_vertical_mm": m["rms_vertical_mm"],
        "max_error_mm": m["max_error_mm"],
        "start_error_mm": m["start_error_mm"],
        "end_error_mm": m["end_error_mm"],
        "start_along_mm": m["start_along_mm"],
        "end_along_mm": m["end_along_mm"],
        "search_mm": run.search_mm,
        "welded_mm": run.welded_mm,
        "start_found": run.start_found,
        "end_found": run.end_found,
        "lost": run.lost,
        "failure": run.failure,
        "sensor_rms_mm": m["sensor_rms_mm"],
        "sensor_max_gap_mm": run.max_gap_mm,
        "points": run.points,
        "rejected_points": run.rejected_points,
        "refits": run.refits,
    }


def completed(metrics):
    ok = True
    for m in metrics:
        ok = ok and m["welded"] and m["run"].end_found and not m["run"].failure
    return ok


def summary(job, truth, metrics, profiles, sim_time_s, wall_time_s):
    """The object `vts sim --json` prints, without out_dir."""
    sensor = job.get("sensor", {})
    return {
        "source": job.get("source"),
        "sensor": sensor.get("name"),
        "material": sensor.get("material"),
        "error_model": sensor.get("error_model"),
        "seed": job.get("seed"),
        "speed_mm_s": job.get("speed_mm_s"),
        "rate_hz": sensor.get("rate_hz"),
        "workpiece_offset_mm": truth.get("workpiece_offset_mm"),
        "workpiece_rotation_deg": truth.get("workpiece_rotation_deg"),
        "profiles": profiles,
        "sim_time_s": sim_time_s,
        "wall_time_s": wall_time_s,
        "completed": completed(metrics),
        "seams": [seam_metrics_json(m, k) for k, m in enumerate(metrics)],
    }


def print_text(summ, realtime_note=None):
    print("master.py: box cell, workpiece displaced %.2f mm and turned %.2f deg from nominal (seed %d)"
          % (summ["workpiece_offset_mm"], summ["workpiece_rotation_deg"], summ["seed"]))
    print("sensor %s, %s, error model %s, %s source, %.0f Hz, %.1f mm/s"
          % (summ["sensor"], summ["material"], "on" if summ["error_model"] else "off", summ["source"],
             summ["rate_hz"], summ["speed_mm_s"]))
    for k, m in enumerate(summ["seams"]):
        print("seam %d: search %.1f mm, start error %.3f mm, rms lateral %.3f mm, rms vertical %.3f mm, max %.3f mm, "
              "end error %.3f mm, welded %.1f mm; sensor track points rms %.4f mm%s%s%s%s"
              % (k + 1, m["search_mm"], m["start_error_mm"], m["rms_lateral_mm"], m["rms_vertical_mm"],
                 m["max_error_mm"], m["end_error_mm"], m["welded_mm"], m["sensor_rms_mm"],
                 ", largest gap %.2f mm" % m["sensor_max_gap_mm"] if m["sensor_max_gap_mm"] > 0 else "",
                 ", SEAM LOST" if m["lost"] else "", ", failed: " if m["failure"] else "", m["failure"]))
    print("%d profiles, %.1f s simulated in %.2f s" % (summ["profiles"], summ["sim_time_s"], summ["wall_time_s"]))
    if realtime_note:
        print(realtime_note)


def plan_from_job(job):
    seams = []
    for s in job["seams"]:
        if "path" in s:
            # A curved plan (the saddle scenarios): the C++ master's curved
            # program (tracker/master.cpp, docs/SIM.md "The pipe saddle") is
            # not ported here.
            sys.exit("master.py: seam %d is a curved seam (sim.job's 'path'): this port welds straight seams only; "
                     "run the scenario with `vts sim --scenario` instead" % (len(seams) + 1))
        seams.append({k: [float(x) for x in s[k]] for k in ("start_mm", "end_mm", "plate_normal", "wall_normal")})
    return seams


def run_lockstep(client):
    wall0 = time.monotonic()
    job = client.sim_job()
    truth = client.sim_truth()
    P = Params(job.get("master"))
    sensor = ProtocolSensor(client)
    res = run_master(sensor, P, Pose.from_json(job["world_from_workpiece"]), plan_from_job(job))
    metrics = evaluate([SeamTruth(s) for s in truth["seams"]], res)
    profiles = client.sensor_state()["counters"]["profiles"]
    sim_time = res.samples[-1][0] if res.samples else 0.0
    return summary(job, truth, metrics, profiles, sim_time, time.monotonic() - wall0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--host", default=vts_client.DEFAULT_HOST)
    ap.add_argument("--port", type=int, default=vts_client.DEFAULT_PORT)
    ap.add_argument("--json", action="store_true", help="print the summary as one JSON object (as vts sim --json)")
    ap.add_argument("--realtime", action="store_true",
                    help="against vts serve --realtime: queued robot moves, joint data polled every --poll-s")
    ap.add_argument("--poll-s", type=float, default=2.0, help="realtime: seconds between polls of the joint data")
    a = ap.parse_args(argv)
    with vts_client.Client(a.host, a.port, role="control", name="master.py") as client:
        if a.realtime:
            summ, note = run_realtime(client, a.poll_s)
        else:
            if client.server.get("mode") != "lockstep":
                print("master.py: the server runs in %s time; use --realtime" % client.server.get("mode"),
                      file=sys.stderr)
                return 2
            summ, note = run_lockstep(client), None
    if a.json:
        print(json.dumps(summ, separators=(",", ":")))
    else:
        print_text(summ, note)
    sys.stdout.flush()
    return 0 if summ["completed"] else 1


# ---------------------------------------------------------------------------
# Real time (vts serve --realtime)
# ---------------------------------------------------------------------------

class PoseSampler:
    """The evaluation's eye, not the master's: a second connection (an
    observer) that samples the TCP (robot.pose) every period_s, so that the
    tracking error can be measured along the weld as in lockstep."""

    def __init__(self, host, port, period_s=0.05):
        import threading
        self.samples = []  # (time_s, tcp)
        self._period = period_s
        self._stop = threading.Event()
        self._client = vts_client.Client(host, port, role="observe", name="master.py-sampler")
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        next_t = time.monotonic()
        while not self._stop.is_set():
            try:
                r = self._client.robot_pose()
            except (OSError, vts_client.VtsError):
                return
            self.samples.append((float(r["time_s"]), [float(x) for x in r["world_from_tool"]["t"]]))
            next_t += self._period
            self._stop.wait(max(0.0, next_t - time.monotonic()))

    def stop(self):
        self._stop.set()
        self._thread.join()
        self._client.close()


def servo_and_settle(client, pose, timeout_s=2.0):
    """robot.servo, then wait until the robot reports the TCP there: in real
    time the server applies a servo pose at its next tick, and a robot.move
    sent before that starts from the old TCP."""
    client.servo(pose.to_json())
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        r = client.robot_pose()
        if not r["moving"] and norm(v_sub([float(x) for x in r["world_from_tool"]["t"]], pose.t)) < 1e-6:
            return True
        time.sleep(0.01)
    return False


class RealtimeWait:
    """Events from the controlling connection, with a deadline."""

    def __init__(self, client):
        self.c = client

    def until(self, names, timeout_s):
        """The first event named in `names` within timeout_s (wall clock), or None."""
        deadline = time.monotonic() + timeout_s
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            ev = self.c.next_event(left)
            if ev is None:
                return None
            if ev.get("event") in names:
                return ev


def run_realtime(client, poll_s, seg_mm=5.0):
    """The experiment in real time: the robot moves on its own (queued linear
    moves at the weld speed, robot.move), the sensor takes profiles at its
    rate whatever the master does, and the master asks for the joint data
    (sensor.joints) every poll_s seconds, as the paper's master did about
    every other second; start, end and loss come as events. Per seam: jump
    to the search pose (robot.servo), laser on, one search move along the
    plan until start-found, a move to the start point, then moves of seg_mm
    along the seam object, queued as far as the joint data reach; after
    end-found the moves up to the end point, laser off. The workpiece pose is
    re-calibrated between seams as in lockstep. Returns (summary, note) with
    the profile rate the sensor held."""
    wall0 = time.monotonic()
    job = client.sim_job()
    truth = client.sim_truth()
    P = Params(job.get("master"))
    plan = plan_from_job(job)
    believed = Pose.from_json(job["world_from_workpiece"])
    client.subscribe(events=True)
    wait = RealtimeWait(client)
    sampler = PoseSampler(client.host, client.port)
    res = Result()
    recalibrated = False
    speed = P.speed_mm_s
    laser_s = 0.0
    laser_profiles = 0
    polls = 0
    last_index = -1  # of the joint data read so far (sensor.joints after_index)

    def now_and_profiles():
        t = client.time()["time_s"]
        return t, client.sensor_state()["counters"]["profiles"]

    try:
        for k, seam in enumerate(plan):
            res.world_from_workpiece.append(believed.copy())
            run = SeamRun()
            s_plan, d_plan, length, np_, nw, margin = seam_geometry(P, believed, seam, recalibrated)
            R0 = tool_rotation(d_plan, np_, nw)
            begin = v_sub(s_plan, v_scale(margin + P.lookahead_mm, d_plan))
            servo_and_settle(client, Pose(R0, begin))

            on = client.laser_on()
            if not on.get("confirmed", False):
                run.failure = "the laser did not come on: " + str(on.get("message", ""))
                res.seams.append(run)
                continue
            t_on, p_on = now_and_profiles()
            client.events()  # nothing from before the laser counts

            found = False
            for attempt in range(P.max_search_retries + 1):
                client.search_start()
                limit = 2.0 * margin + P.search_extra_mm
                client.move(Pose(R0, v_add(begin, v_scale(limit, d_plan))).to_json(), speed)
                ev = wait.until({"start-found", "start-behind", "stream-ended", "move-done"}, limit / speed + 10.0)
                tcp = client.robot_pose()["world_from_tool"]["t"]
                run.search_mm += max(0.0, dot(v_sub(tcp, begin), d_plan))
                name = ev.get("event") if ev else None
                if name == "start-found":
                    found = True
                    run.start_point = [float(x) for x in ev["point"]]
                    break
                if name == "stream-ended":
                    run.failure = "the sensor stopped during the search: " + str(ev.get("message", ""))
                    break
                if name == "start-behind":
                    client.stop()
                    begin = v_sub(begin, v_scale(P.search_margin_mm, d_plan))
                    servo_and_settle(client, Pose(R0, begin))
                    if attempt == P.max_search_retries:
                        run.failure = "the start point lies behind every search"
                        break
                    continue
                run.failure = "no start point within " + cpp_to_string(limit) + " mm of search"
                break
            t_start_found = client.time()["time_s"]
            if not found:
                client.stop()
                client.laser_off()
                t_off, p_off = now_and_profiles()
                laser_s += t_off - t_on
                laser_profiles += p_off - p_on
                res.seams.append(run)
                continue
            run.start_found = True
            client.start_tracking()
            # As the lockstep master's first poll: from the latest joint data
            # on (not the search's, nor the previous seam's).
            latest = client.joint()
            last_index = int(latest["profile_index"]) - 1 if latest else last_index

            obj = SeamObject()
            obj.reset(run.start_point, d_plan)
            intake = JointIntake(P, obj, run, np_, nw)

            def travel_direction():
                return obj.direction() if obj.max_arc() >= P.direction_span_mm else d_plan

            # The approach: on from where the search stopped to the start point.
            w0 = obj.at(0.0, P.fit_window_mm)
            client.move(Pose(tool_rotation(d_plan, np_, nw), w0).to_json(), speed)
            run.weld_start = w0
            last_target = w0
            queued_s = 0.0
            stop_point = None
            end_requested = False
            laser_on = True
            final_queued = False
            next_poll = time.monotonic() + poll_s
            give_up = time.monotonic() + (P.lookahead_mm + 2.0 * length + 50.0) / speed + 30.0
            while True:
                poll_now = False
                ev = client.next_event(max(0.0, next_poll - time.monotonic()))
                name = ev.get("event") if ev else None
                if stop_point is None and name in ("end-found", "seam-lost", "stream-ended"):
                    if name == "end-found":
                        run.end_found = True
                        run.end_point = [float(x) for x in ev["point"]]
                        stop_point = run.end_point
                    elif name == "seam-lost":
                        run.lost = True
                        stop_point = intake.last_accepted
                    else:
                        run.failure = "the sensor stopped while tracking: " + str(ev.get("message", ""))
                        stop_point = intake.last_accepted
                    poll_now = True
                elif name == "move-done":
                    if final_queued:
                        break
                    poll_now = True  # the torch caught up with the data it was given
                if not poll_now and time.monotonic() < next_poll:
                    continue
                polls += 1
                got = client.joints(after_index=last_index)
                for j in got.get("joints", []):
                    last_index = max(last_index, int(j["profile_index"]))
                    if not intake.take(j):
                        continue
                    if (not end_requested and stop_point is None
                            and obj.arc(intake.last_accepted) >= length - P.end_margin_mm
                            and client.sensor_state()["state"] == "tracking"):
                        client.look_for_end()
                        end_requested = True
                if stop_point is not None and laser_on:
                    client.laser_off()
                    laser_on = False
                    t_off, p_off = now_and_profiles()
                    laser_s += t_off - t_on
                    laser_profiles += p_off - p_on
                # Queue the torch along the seam object as far as the data reach.
                s_stop = obj.arc(stop_point) if stop_point is not None else INF
                target = s_stop if stop_point is not None else obj.max_arc() - 2.0
                queued = 0
                while queued_s < target - 1e-9 and queued < 32:
                    s = min(queued_s + seg_mm, target)
                    last_target = obj.at(s, P.fit_window_mm)
                    client.move(Pose(tool_rotation(travel_direction(), np_, nw), last_target).to_json(), speed,
                                queue=True)
                    queued_s = s
                    queued += 1
                if stop_point is not None and queued_s >= s_stop - 1e-9:
                    if not final_queued and queued == 0 and not client.robot_pose()["moving"]:
                        break
                    final_queued = True
                next_poll = time.monotonic() + poll_s
                if time.monotonic() > give_up:
                    run.failure = "no end of seam in time"
                    break
            if laser_on:
                client.laser_off()
                t_off, p_off = now_and_profiles()
                laser_s += t_off - t_on
                laser_profiles += p_off - p_on
            t_weld_end = client.time()["time_s"]
            run.weld_end = last_target
            run.welded_mm = queued_s
            run.line_direction = obj.direction()
            run.line_point = obj.centroid()
            res.seams.append(run)
            # The weld samples: the TCP on the seam object from its start on.
            for (t, tcp) in list(sampler.samples):
                if t_start_found <= t <= t_weld_end and 0.0 <= obj.arc(tcp) <= queued_s + 1e-6:
                    res.samples.append((t, k, "weld", tcp))

            if P.recalibrate and run.start_found and run.end_found and not run.failure:
                believed = recalibrated_pose(believed, seam, run, obj, intake, np_, nw)
                recalibrated = True
        sim_time, profiles = now_and_profiles()
    finally:
        sampler.stop()
    metrics = evaluate([SeamTruth(s) for s in truth["seams"]], res)
    summ = summary(job, truth, metrics, profiles, sim_time, time.monotonic() - wall0)
    summ["realtime"] = {"polls": polls, "poll_s": poll_s, "laser_on_s": laser_s, "laser_profiles": laser_profiles,
                        "laser_rate_hz": laser_profiles / laser_s if laser_s > 0 else 0.0,
                        "rate_hz_overall": profiles / sim_time if sim_time > 0 else 0.0,
                        "tcp_samples": len(sampler.samples)}
    note = ("real time: the sensor held %.2f Hz with the laser on (%d profiles in %.1f s; nominal %.0f Hz), "
            "%.2f Hz over the whole run; %d polls of the joint data, every %.1f s"
            % (summ["realtime"]["laser_rate_hz"], laser_profiles, laser_s, summ["rate_hz"],
               summ["realtime"]["rate_hz_overall"], polls, poll_s))
    return summ, note


if __name__ == "__main__":
    sys.exit(main())
