"""Golden optima of the human walking OCP (crates/corps-ocp/src/human_walk.rs; Maroger et al.,
seed 000 §3.17) solved by Crocoddyl's SolverDDP, for crates/corps-ocp/tests/human_walk_crocoddyl.rs.

The model is written here a second time, as Python action models for Crocoddyl (state
(x, y, θ, v_f, ω, v_o), controls the three accelerations, the running and terminal costs and
weights of the authors' estimation code); Crocoddyl's DDP solves each problem from zero
controls to its default tolerance (th_stop 1e-9), then further (1e-18, the near-flat orthogonal acceleration, weight 1e-6, needs it) so that the stored
optimum is converged beyond the test's tolerance.

Usage: pip install crocoddyl numpy; python3 tools/golden/human_walk_crocoddyl.py
Writes crates/corps-ocp/tests/data/human_walk_crocoddyl.json.
"""
import json
import math
from pathlib import Path

import crocoddyl
import numpy as np

RUNNING = [7.86951486, 4.00027971, 20.1459991, 1e-6, 9.99999967]
TERMINAL = [9.98999939, 9.98999934, 0.379999984, 3.35999389]
DT = 0.1


def wrap(a):
    while a > math.pi:
        a -= 2 * math.pi
    while a < -math.pi:
        a += 2 * math.pi
    return a


class Step(crocoddyl.ActionModelAbstract):
    def __init__(self, goal):
        crocoddyl.ActionModelAbstract.__init__(self, crocoddyl.StateVector(6), 3)
        self.goal = goal

    def heading(self, x):
        dx, dy = self.goal[0] - x[0], self.goal[1] - x[1]
        r2 = max(dx * dx + dy * dy, 1e-12)
        h = math.atan2(dy, dx) - x[2]
        g = np.array([dy / r2, -dx / r2, -1.0])
        hxx, hxy = 2 * dx * dy / r2**2, (dy * dy - dx * dx) / r2**2
        H = np.array([[hxx, hxy, 0.0], [hxy, -hxx, 0.0], [0.0, 0.0, 0.0]])
        return h, g, H

    def calc(self, data, x, u=None):
        if u is None:
            u = np.zeros(3)
        c, s = math.cos(x[2]), math.sin(x[2])
        data.xnext[:] = [
            x[0] + (c * x[3] - s * x[5]) * DT,
            x[1] + (s * x[3] + c * x[5]) * DT,
            x[2] + x[4] * DT,
            x[3] + u[0] * DT,
            x[4] + u[1] * DT,
            x[5] + u[2] * DT,
        ]
        h, _, _ = self.heading(x)
        w = RUNNING
        data.cost = w[0] + w[1] * u[0] ** 2 + w[2] * u[1] ** 2 + w[3] * u[2] ** 2 + w[4] * h * h

    def calcDiff(self, data, x, u=None):
        if u is None:
            u = np.zeros(3)
        c, s = math.cos(x[2]), math.sin(x[2])
        Fx = np.eye(6)
        Fx[0, 2], Fx[0, 3], Fx[0, 5] = (-s * x[3] - c * x[5]) * DT, c * DT, -s * DT
        Fx[1, 2], Fx[1, 3], Fx[1, 5] = (c * x[3] - s * x[5]) * DT, s * DT, c * DT
        Fx[2, 4] = DT
        Fu = np.zeros((6, 3))
        Fu[3:, :] = np.eye(3) * DT
        data.Fx[:, :] = Fx
        data.Fu[:, :] = Fu
        w = RUNNING
        h, g, H = self.heading(x)
        Lx = np.zeros(6)
        Lxx = np.zeros((6, 6))
        Lx[:3] = 2 * w[4] * h * g
        Lxx[:3, :3] = 2 * w[4] * (np.outer(g, g) + h * H)
        data.Lx[:] = Lx
        data.Lxx[:, :] = Lxx
        data.Lu[:] = [2 * w[1] * u[0], 2 * w[2] * u[1], 2 * w[3] * u[2]]
        data.Luu[:, :] = np.diag([2 * w[1], 2 * w[2], 2 * w[3]])


class End(crocoddyl.ActionModelAbstract):
    def __init__(self, goal):
        crocoddyl.ActionModelAbstract.__init__(self, crocoddyl.StateVector(6), 3)
        self.goal = goal

    def calc(self, data, x, u=None):
        g, t = self.goal, TERMINAL
        dth = wrap(g[2] - x[2])
        data.xnext[:] = x
        data.cost = (
            t[0] * ((g[0] - x[0]) ** 2 + (g[1] - x[1]) ** 2)
            + t[1] * dth * dth
            + t[2] * (x[3] ** 2 + x[4] ** 2)
            + t[3] * x[5] ** 2
        )

    def calcDiff(self, data, x, u=None):
        g, t = self.goal, TERMINAL
        dth = wrap(g[2] - x[2])
        data.Lx[:] = [
            -2 * t[0] * (g[0] - x[0]),
            -2 * t[0] * (g[1] - x[1]),
            -2 * t[1] * dth,
            2 * t[2] * x[3],
            2 * t[2] * x[4],
            2 * t[3] * x[5],
        ]
        data.Lxx[:, :] = np.diag([2 * t[0], 2 * t[0], 2 * t[1], 2 * t[2], 2 * t[2], 2 * t[3]])


# Start poses (x, y, θ) below the goal, which sits at the origin facing +y as the shared walks'
# goal does, over horizons of the length a person takes for such a distance. (From beside or
# above the goal the source's unwrapped heading term atan2(·) − θ meets atan2's branch cut and
# neither solver converges: those are left out.)
PROBLEMS = [
    {"start": [-1.0, -4.0, 1.2], "goal": [0.0, 0.0, math.pi / 2], "nodes": 50},
    {"start": [-2.0, -3.0, 1.0], "goal": [0.0, 0.0, math.pi / 2], "nodes": 40},
    {"start": [0.3, -2.5, 1.4], "goal": [0.0, 0.0, math.pi / 2], "nodes": 30},
    {"start": [2.5, -4.0, 2.2], "goal": [0.0, 0.0, math.pi / 2], "nodes": 60},
]


def solve(p):
    goal = p["goal"]
    step, end = Step(goal), End(goal)
    x0 = np.array(p["start"] + [0.0, 0.0, 0.0])
    problem = crocoddyl.ShootingProblem(x0, [step] * p["nodes"], end)
    ddp = crocoddyl.SolverDDP(problem)
    ddp.th_stop = 1e-18
    xs0 = [x0] * (p["nodes"] + 1)
    us0 = [np.zeros(3)] * p["nodes"]
    converged = ddp.solve(xs0, us0, 500)
    return {
        **p,
        "converged": bool(converged),
        "iterations": int(ddp.iter),
        "cost": float(ddp.cost),
        "xs": [[float(v) for v in x] for x in ddp.xs],
        "us": [[float(v) for v in u] for u in ddp.us],
    }


def main():
    out = {
        "source": "crocoddyl " + crocoddyl.__version__ + " SolverDDP, th_stop 1e-18",
        "dt": DT,
        "running_weights": RUNNING,
        "terminal_weights": TERMINAL,
        "problems": [solve(p) for p in PROBLEMS],
    }
    path = Path(__file__).resolve().parents[2] / "crates/corps-ocp/tests/data/human_walk_crocoddyl.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    for p in out["problems"]:
        print(p["start"], "converged", p["converged"], "iterations", p["iterations"], "cost", p["cost"])


if __name__ == "__main__":
    main()
