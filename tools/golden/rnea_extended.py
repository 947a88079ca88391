"""RNEA in extended precision (numpy longdouble: 64-bit mantissa on x86-64), for golden data
whose accuracy must exceed double's. Local-frame recursion (Featherstone, RBDA Table 5.1) on a
Pinocchio model's joint placements, inertias and joint types; q, v, a are taken as exact."""
import numpy as np

LD = np.longdouble


def _skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]], dtype=LD)


def _rot(axis, c, s):
    axis = np.asarray(axis, dtype=LD)
    axis = axis / np.sqrt(axis @ axis)
    k = _skew(axis)
    return np.eye(3, dtype=LD) + s * k + (1 - c) * (k @ k)


def _quat(x, y, z, w):
    x, y, z, w = (LD(t) for t in (x, y, z, w))
    n = np.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]], dtype=LD)


_AXES = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}


def _joint(jm, q):
    """(R, p, S (6 x nv), linear-first) of the joint's motion at q."""
    name = jm.shortname()
    iq, nv = jm.idx_q, jm.nv
    zero = np.zeros(3, dtype=LD)
    if name == "JointModelFreeFlyer":
        return _quat(*q[iq + 3:iq + 7]), np.array(q[iq:iq + 3], dtype=LD), np.eye(6, dtype=LD)
    if name.startswith("JointModelRUB") or name == "JointModelRevoluteUnboundedUnaligned":
        axis = _AXES[name[-1]] if name.startswith("JointModelRUB") else jm.extract().axis
        c, s = LD(q[iq]), LD(q[iq + 1])
        n = np.sqrt(c * c + s * s)
        c, s = c / n, s / n
    elif name.startswith("JointModelR"):
        axis = _AXES[name[-1]] if name in ("JointModelRX", "JointModelRY", "JointModelRZ") else jm.extract().axis
        t = LD(q[iq])
        c, s = np.cos(t), np.sin(t)
    elif name.startswith("JointModelP"):
        axis = _AXES[name[-1]] if name in ("JointModelPX", "JointModelPY", "JointModelPZ") else jm.extract().axis
        a = np.array(axis, dtype=LD)
        S = np.zeros((6, 1), dtype=LD)
        S[:3, 0] = a
        return np.eye(3, dtype=LD), a * LD(q[iq]), S
    else:
        raise RuntimeError(f"unhandled joint {name}")
    a = np.array(axis, dtype=LD)
    S = np.zeros((6, nv), dtype=LD)
    S[3:, 0] = a / np.sqrt(a @ a)
    return _rot(a, c, s), zero, S


def rnea(model, q, v, a):
    """tau = M(q) a + h(q, v), every operation in long double."""
    n = model.njoints
    g = np.array(model.gravity.linear, dtype=LD)
    vel = [np.zeros(6, dtype=LD) for _ in range(n)]
    acc = [np.zeros(6, dtype=LD) for _ in range(n)]
    acc[0][:3] = -g
    frc = [np.zeros(6, dtype=LD) for _ in range(n)]
    place = [None] * n
    subspace = [None] * n
    for i in range(1, n):
        jm = model.joints[i]
        jp = model.jointPlacements[i]
        Rj, pj, S = _joint(jm, q)
        R0, p0 = np.array(jp.rotation, dtype=LD), np.array(jp.translation, dtype=LD)
        R, p = R0 @ Rj, R0 @ pj + p0     # child in parent
        place[i], subspace[i] = (R, p), S
        lam = model.parents[i]
        iv, nv = jm.idx_v, jm.nv
        qd = np.array(v[iv:iv + nv], dtype=LD)
        qdd = np.array(a[iv:iv + nv], dtype=LD)

        def act_inv(m):
            lin, ang = m[:3], m[3:]
            return np.concatenate([R.T @ (lin - np.cross(p, ang)), R.T @ ang])

        vj = S @ qd
        vel[i] = act_inv(vel[lam]) + vj
        vi = vel[i]
        cross = np.concatenate([np.cross(vi[3:], vj[:3]) + np.cross(vi[:3], vj[3:]), np.cross(vi[3:], vj[3:])])
        acc[i] = act_inv(acc[lam]) + S @ qdd + cross
        Y = model.inertias[i]
        m, c, Ic = LD(Y.mass), np.array(Y.lever, dtype=LD), np.array(Y.inertia, dtype=LD)

        def inertia_times(x):
            lin, ang = x[:3], x[3:]
            f = m * (lin - np.cross(c, ang))
            return np.concatenate([f, Ic @ ang + np.cross(c, f)])

        h = inertia_times(vi)
        ai = acc[i]
        f = inertia_times(ai)
        f += np.concatenate([np.cross(vi[3:], h[:3]), np.cross(vi[3:], h[3:]) + np.cross(vi[:3], h[:3])])
        frc[i] = f
    tau = np.zeros(model.nv, dtype=LD)
    for i in range(n - 1, 0, -1):
        jm = model.joints[i]
        tau[jm.idx_v:jm.idx_v + jm.nv] = subspace[i].T @ frc[i]
        lam = model.parents[i]
        if lam > 0:
            R, p = place[i]
            f = frc[i]
            lin = R @ f[:3]
            frc[lam] += np.concatenate([lin, R @ f[3:] + np.cross(p, lin)])
    return tau
