"""Golden optima of the current-limiting OCP (crates/corps-actuator/src/current_ocp.rs; seed 000
§3.13) solved by Crocoddyl's SolverDDP, for crates/corps-actuator/tests/ilqr.rs.

The model is written here a second time as a Python action model for Crocoddyl: state (q, q̇),
control the motor current, the elbow dynamics of Eq 3.13 with tanh(1000 q̇) friction, one RK4
step per node with its Jacobians by the chain rule, the tracking, current and exponential
barrier costs of Eq 3.14–3.15 with the thesis's Q, R, W, P and λ. The drive parameters come
from config/talos/actuators/elbow.toml. Crocoddyl's DDP solves each problem from the controls
that hold the start against gravity, to th_stop 1e-18, so that the stored optimum is converged
beyond the test's tolerance.

Usage: pip install crocoddyl numpy; python3 tools/golden/elbow_ilqr_crocoddyl.py
Writes crates/corps-actuator/tests/data/elbow_ilqr_crocoddyl.json.
"""
import json
import math
import tomllib
from pathlib import Path

import crocoddyl
import numpy as np

np.seterr(over="ignore", invalid="ignore")

ROOT = Path(__file__).resolve().parents[2]
DESC = tomllib.loads((ROOT / "config/talos/actuators/elbow.toml").read_text())
M = DESC["model"]
LIM = DESC["limits"]
G = 9.81
Q = [40.0, 0.01]
R = 1e-4
W = [1.0, 0.1]
P = 10.0
LAMBDA = [10.0, 1.0, 0.5]
MU = 1000.0
DT = 0.001


def barrier(lam, lo, hi, c):
    e_max = np.exp(lam * (1 - lam * (hi - c)))
    e_min = np.exp(lam * (1 - lam * (c - lo)))
    v = e_max + e_min
    return v, lam**2 * (e_max - e_min), lam**4 * v


def squared(w, b, c):
    v, d, dd = barrier(*b, c)
    return w * v * v, 2 * w * v * d, 2 * w * (d * d + v * dd)


class Joint:
    def __init__(self, payload_kg, distance_m):
        self.inertia = M["i_m"] + M["i_j"] + payload_kg * distance_m**2
        self.mx = M["m_x"]
        self.my = M["m_y"] + payload_kg * distance_m
        self.fv = M["f_vm"] + M["f_vj"]
        self.fs = M["f_sm"] + M["f_sj"]
        self.off = M["off_m"] + M["off_j"]
        self.k = M["drive_gain"]

    def f(self, x, u):
        q, v = x
        a = (self.k * u - self.fv * v - self.fs * math.tanh(MU * v) - self.off
             - G * (self.my * math.sin(q) + self.mx * math.cos(q))) / self.inertia
        return np.array([v, a])

    def fx(self, x):
        q, v = x
        dg = G * (self.my * math.cos(q) - self.mx * math.sin(q))
        sech2 = 1 - math.tanh(MU * v) ** 2
        return np.array([[0.0, 1.0], [-dg / self.inertia, -(self.fv + self.fs * MU * sech2) / self.inertia]])

    def rk4(self, x, u):
        h = DT
        b = np.array([0.0, self.k / self.inertia])
        k1 = self.f(x, u)
        x2 = x + 0.5 * h * k1
        k2 = self.f(x2, u)
        x3 = x + 0.5 * h * k2
        k3 = self.f(x3, u)
        x4 = x + h * k3
        k4 = self.f(x4, u)
        d1x = self.fx(x)
        d2x = self.fx(x2) @ (np.eye(2) + 0.5 * h * d1x)
        d3x = self.fx(x3) @ (np.eye(2) + 0.5 * h * d2x)
        d4x = self.fx(x4) @ (np.eye(2) + h * d3x)
        d1u = b
        d2u = self.fx(x2) @ (0.5 * h * d1u) + b
        d3u = self.fx(x3) @ (0.5 * h * d2u) + b
        d4u = self.fx(x4) @ (h * d3u) + b
        nxt = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        fx = np.eye(2) + h / 6 * (d1x + 2 * d2x + 2 * d3x + d4x)
        fu = h / 6 * (d1u + 2 * d2u + 2 * d3u + d4u)
        return nxt, fx, fu


class Node(crocoddyl.ActionModelAbstract):
    def __init__(self, joint, ref, barriers, terminal=False):
        crocoddyl.ActionModelAbstract.__init__(self, crocoddyl.StateVector(2), 1)
        self.joint, self.ref, self.barriers, self.terminal = joint, np.array(ref), barriers, terminal

    def state_cost(self, x):
        e = x - self.ref
        c = Q[0] * e[0] ** 2 + Q[1] * e[1] ** 2
        g = np.array([2 * Q[0] * e[0], 2 * Q[1] * e[1]])
        h = np.array([2 * Q[0], 2 * Q[1]])
        if self.barriers:
            for i in range(2):
                bc, bd, bdd = squared(W[i], self.barriers[i], x[i])
                c, g[i], h[i] = c + bc, g[i] + bd, h[i] + bdd
        return c, g, h

    def control_cost(self, u):
        c, d, dd = R * u * u, 2 * R * u, 2 * R
        if self.barriers:
            k = self.joint.k
            bc, bd, bdd = squared(P, self.barriers[2], k * u)
            c, d, dd = c + bc, d + bd * k, dd + bdd * k * k
        return c, d, dd

    def calc(self, data, x, u=None):
        if self.terminal or u is None:
            data.xnext[:] = x
            data.cost = self.state_cost(x)[0]
            return
        data.xnext[:] = self.joint.rk4(x, u[0])[0]
        data.cost = self.state_cost(x)[0] + self.control_cost(u[0])[0]

    def calcDiff(self, data, x, u=None):
        _, g, h = self.state_cost(x)
        data.Lx[:] = g
        data.Lxx[:, :] = np.diag(h)
        if self.terminal or u is None:
            return
        _, d, dd = self.control_cost(u[0])
        _, fx, fu = self.joint.rk4(x, u[0])
        data.Fx[:, :] = fx
        data.Fu[:] = fu.reshape(data.Fu.shape)
        data.Lu[:] = [d]
        data.Luu[:] = np.array([[dd]]).reshape(data.Luu.shape)


# Starts and references (q*, q̇*) over a 100-node, 1 ms horizon: tracking inside the limits,
# a reference beyond the position limit with a heavy payload (barriers active), a fast swing
# that needs more than the current limit, and the same without barriers. Near q̇ = 0 the
# tanh(1000 q̇) friction is nearly a step and DDP crawls there (from rest, neither solver
# reaches a tight tolerance in 500 iterations): the second problem stops there, and its
# stored "stop" (Σ‖Q_u‖²) says how far from stationary Crocoddyl's answer is.
PROBLEMS = [
    {"x0": [-0.5, -1.0], "payload_kg": 0.0, "distance_m": 0.05, "target": [-1.0, -1.5], "barrier": True},
    {"x0": [-2.2, -2.0], "payload_kg": 30.0, "distance_m": 0.05, "target": [-2.6, 0.0], "barrier": True},
    {"x0": [-1.0, -1.0], "payload_kg": 30.0, "distance_m": 0.05, "target": [-2.0, -4.0], "barrier": True},
    {"x0": [-1.0, -1.0], "payload_kg": 30.0, "distance_m": 0.05, "target": [-2.0, -4.0], "barrier": False},
]
NODES = 100


def solve(p):
    joint = Joint(p["payload_kg"], p["distance_m"])
    k = joint.k
    barriers = None
    if p["barrier"]:
        barriers = [
            (LAMBDA[0], *LIM["position"]),
            (LAMBDA[1], *LIM["velocity"]),
            (LAMBDA[2], LIM["current"][0] * k, LIM["current"][1] * k),
        ]
    running = [Node(joint, p["target"], barriers) for _ in range(NODES)]
    end = Node(joint, p["target"], barriers, terminal=True)
    x0 = np.array(p["x0"])
    problem = crocoddyl.ShootingProblem(x0, running, end)
    ddp = crocoddyl.SolverDDP(problem)
    ddp.th_stop = 1e-18
    q = p["x0"][0]
    hold = (G * (joint.my * math.sin(q) + joint.mx * math.cos(q)) + joint.off) / k
    us0 = [np.array([hold])] * NODES
    xs0 = problem.rollout(us0)
    converged = ddp.solve(xs0, us0, 500)
    return {
        **p,
        "nodes": NODES,
        "dt": DT,
        "initial_current": hold,
        "converged": bool(converged),
        "iterations": int(ddp.iter),
        "stop": float(ddp.stop),
        "cost": float(ddp.cost),
        "xs": [[float(v) for v in x] for x in ddp.xs],
        "us": [float(u[0]) for u in ddp.us],
    }


def main():
    out = {
        "source": f"crocoddyl {crocoddyl.__version__}, SolverDDP, th_stop 1e-18",
        "problems": [solve(p) for p in PROBLEMS],
    }
    for p in out["problems"]:
        print(p["x0"], p["target"], p["barrier"], "converged", p["converged"], "iterations",
              p["iterations"], "cost", p["cost"], "min current", min(p["us"]))
    path = ROOT / "crates/corps-actuator/tests/data/elbow_ilqr_crocoddyl.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1) + "\n")
    print("wrote", path)


if __name__ == "__main__":
    main()
