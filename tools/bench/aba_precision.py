#!/usr/bin/env python3
"""ABA precision of corps against Pinocchio on random states of a robot.

For each random state (q within the URDF limits, base anywhere in a 2 m cube, random v and tau)
it prints, for Pinocchio's ABA and corps' ABA (through `corps model eval`), the residual
||M (a - a*)|| against the exact answer a* (Newton-refined with a long-double RNEA,
tools/golden/rnea_extended.py), corps' relative error against Pinocchio and both forward errors.

    ~/.cache/corps-anchors/venv/bin/python tools/bench/aba_precision.py \
        --urdf robots/icub_description/robots/icub_reduced.urdf --states 50

The corps binary is target/release/corps (build it first with `cargo build --release`).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "golden"))
from rnea_extended import LD, rnea  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def random_q(model, rng):
    q = np.zeros(model.nq)
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    for j in model.joints[1:]:
        iq, nq, nv = j.idx_q, j.nq, j.nv
        if j.shortname() == "JointModelFreeFlyer":
            q[iq:iq + 3] = rng.uniform(-1.0, 1.0, 3)
            quat = rng.standard_normal(4)
            q[iq + 3:iq + 7] = quat / np.linalg.norm(quat)
        elif nq == 2 and nv == 1:
            t = rng.uniform(-math.pi, math.pi)
            q[iq:iq + 2] = (math.cos(t), math.sin(t))
        else:
            a, b = lo[iq], hi[iq]
            if not (abs(a) < 1e300 and abs(b) < 1e300):
                a, b = -math.pi, math.pi
            q[iq] = rng.uniform(a, b)
    return q


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--urdf", required=True)
    p.add_argument("--states", type=int, default=50)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--corps", default=os.path.join(REPO, "target", "release", "corps"))
    args = p.parse_args()
    urdf = os.path.join(REPO, args.urdf)
    model = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    data = model.createData()
    rng = np.random.default_rng(args.seed)
    states = []
    for _ in range(args.states):
        q = random_q(model, rng)
        v = rng.uniform(-1, 1, model.nv)
        tau = rng.uniform(-10, 10, model.nv)
        states.append((q, v, tau))
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump({"frames": [], "states": [{"q": q.tolist(), "v": v.tolist(), "tau": t.tolist()}
                                            for q, v, t in states]}, f)
        path = f.name
    out = subprocess.run([args.corps, "model", "eval", "--urdf", urdf, "--states", path],
                         check=True, capture_output=True, text=True).stdout
    os.unlink(path)
    ours = [np.array(r["aba"]) for r in json.loads(out)["results"]]
    rows = []
    for (q, v, tau), a_c in zip(states, ours):
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        h = pin.nonLinearEffects(model, data, q, v).copy()
        a_p = pin.aba(model, data, q, v, tau).copy()
        a_w = pin.aba(model, data, q, v, tau, pin.Convention.WORLD).copy()
        exact = a_p.astype(LD)
        for _ in range(4):
            exact = exact + np.linalg.solve(M, (tau.astype(LD) - rnea(model, q, v, exact)).astype(float)).astype(LD)

        def res(a):
            return float(np.linalg.norm(M.astype(LD) @ (a.astype(LD) - exact)))
        res_p, res_c, res_w = res(a_p), res(a_c), res(a_w)
        rel = np.linalg.norm(a_c - a_p) / np.linalg.norm(a_p)
        fwd_c = float(np.linalg.norm(a_c.astype(LD) - exact) / np.linalg.norm(exact))
        fwd_p = float(np.linalg.norm(a_p.astype(LD) - exact) / np.linalg.norm(exact))
        rows.append((np.linalg.cond(M), res_p, res_c, rel, res_w, fwd_c, fwd_p))
    rows = np.array(rows)
    print(f"{os.path.basename(urdf)}: {len(rows)} states (pin {pin.__version__})")
    print("Residuals ||M (a - a*)||; pin's ABA in its default LOCAL convention and in WORLD")
    print("            cond(M)   resid pin   resid corps   ratio   rel err vs pin   pin WORLD/LOCAL")
    for c, rp, rc, rel, rw, _, _ in rows:
        print(f"  {c:16.3e} {rp:11.3e} {rc:13.3e} {rc / rp:7.2f} {rel:16.3e} {rw / rp:17.2f}")
    ratio = rows[:, 2] / rows[:, 1]
    world = rows[:, 4] / rows[:, 1]
    good = rows[:, 1] <= 1e-12
    print(f"residual ratio corps/pin: median {np.median(ratio):.2f}, 90th percentile "
          f"{np.percentile(ratio, 90):.2f}, max {ratio.max():.2f}, over 3x in {(ratio > 3).sum()} "
          f"of {len(ratio)}")
    print(f"forward error ||a - a*|| / ||a*||: corps median {np.median(rows[:, 5]):.2e}, "
          f"Pinocchio {np.median(rows[:, 6]):.2e}")
    print(f"residual ratio pin WORLD/LOCAL: median {np.median(world):.2f}, max {world.max():.2f}")
    print(f"relative error: max {rows[:, 3].max():.3e}; where pin's residual <= 1e-12 "
          f"({good.sum()} states): max {rows[good, 3].max() if good.any() else float('nan'):.3e}")


if __name__ == "__main__":
    sys.exit(main())
