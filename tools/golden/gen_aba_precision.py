#!/usr/bin/env python3
"""Golden data for ABA's precision on ill-conditioned models, computed with Pinocchio.

    ~/.cache/corps-anchors/venv/bin/python tools/golden/gen_aba_precision.py

For each robot, N random states (joints uniform within their URDF limits, the base anywhere in
a 2 m cube, v uniform in [-1, 1], tau uniform in [-10, 10]) with Pinocchio's ABA in its default
LOCAL convention and the exact answer a* = M⁻¹(τ − h) to beyond double precision: Pinocchio's
answer refined by Newton steps a += M⁻¹ (τ − RNEA(q, v, a)), the residual in long double
(rnea_extended.py), stored as a pair of doubles (hi + lo). Written to
crates/corps-model/tests/golden/aba_precision.json; deterministic (fixed seed).
"""
import json
import os
import sys

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
from aba_precision import random_q  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rnea_extended import LD, rnea  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SEED = 20261127
STATES = 60
ROBOTS = [
    "robots/icub_description/robots/icub.urdf",          # with hands: cond(M) to 1e11
    "robots/icub_description/robots/icub_reduced.urdf",
    "robots/talos_data/robots/talos_reduced.urdf",
]


def main():
    out = {"pinocchio": pin.__version__, "convention": "LOCAL", "robots": []}
    for n, urdf in enumerate(ROBOTS):
        model = pin.buildModelFromUrdf(os.path.join(REPO, urdf), pin.JointModelFreeFlyer())
        data = model.createData()
        rng = np.random.default_rng(SEED + n)
        states = []
        for _ in range(STATES):
            q = random_q(model, rng)
            v = rng.uniform(-1, 1, model.nv)
            tau = rng.uniform(-10, 10, model.nv)
            a = pin.aba(model, data, q, v, tau).copy()
            M = pin.crba(model, data, q)
            M = np.triu(M) + np.triu(M, 1).T
            exact = a.astype(LD)
            for _ in range(4):
                r = tau.astype(LD) - rnea(model, q, v, exact)
                step = np.linalg.solve(M, r.astype(float))
                exact = exact + step.astype(LD)
            # Converged: the last Newton step is far below double's resolution of a*.
            assert np.linalg.norm(step) <= 1e-19 * np.linalg.norm(a) * np.linalg.cond(M), urdf
            hi = exact.astype(float)
            lo = (exact - hi.astype(LD)).astype(float)
            states.append({"q": q.tolist(), "v": v.tolist(), "tau": tau.tolist(), "aba": a.tolist(),
                           "exact_hi": hi.tolist(), "exact_lo": lo.tolist()})
        out["robots"].append({"urdf": urdf, "states": states})
    path = os.path.join(REPO, "crates", "corps-model", "tests", "golden", "aba_precision.json")
    with open(path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    print(path)


if __name__ == "__main__":
    main()
