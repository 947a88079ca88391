#!/usr/bin/env python3
"""Golden data for ABA's precision on ill-conditioned models, computed with Pinocchio.

    ~/.cache/corps-anchors/venv/bin/python tools/golden/gen_aba_precision.py

For each robot, N random states (joints uniform within their URDF limits, the base anywhere in
a 2 m cube, v uniform in [-1, 1], tau uniform in [-10, 10]) with Pinocchio's ABA in its default
LOCAL convention and the exact answer a* = M⁻¹(τ − h) to beyond double precision: Pinocchio's
answer refined by Newton steps a += M⁻¹ (τ − RNEA(q, v, a)), the residual in long double
(rnea_extended.py), stored as a pair of doubles (hi + lo). The same refinement on corps' own
model of the URDF (its joint placements and merged inertias as corps rounded them, printed by
`cargo run --release -p corps-model --example dump_model`) gives a second exact answer, for
corps' model (`exact_corps_hi`, `exact_corps_lo`): each implementation is judged against the
exact answer of the model it was given, so that the two parsers' rounding of the URDF does not
count as the algorithm's error. Written to crates/corps-model/tests/golden/aba_precision.json;
deterministic (fixed seed).
"""
import json
import os
import subprocess
import sys
from types import SimpleNamespace

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


SHORTNAMES = {
    "free_flyer": "JointModelFreeFlyer",
    "revolute": "JointModelRevoluteUnaligned",
    "revolute_unbounded": "JointModelRevoluteUnboundedUnaligned",
    "prismatic": "JointModelPrismaticUnaligned",
}


def corps_model(urdf):
    """corps' model of `urdf` (free-flyer root) with the attributes rnea_extended reads of a
    Pinocchio model (joint 0 the universe, as Pinocchio numbers them)."""
    dump = subprocess.run(
        ["cargo", "run", "-q", "--release", "-p", "corps-model", "--example", "dump_model", "--",
         os.path.join(REPO, urdf)], cwd=REPO, check=True, capture_output=True, text=True).stdout
    d = json.loads(dump)
    universe = SimpleNamespace(shortname=lambda: "universe", idx_q=0, idx_v=0, nv=0)
    joints, placements, parents, inertias = [universe], [None], [0], [None]
    for j in d["joints"]:
        axis = np.array(j["axis"]) if j["axis"] is not None else None
        joints.append(SimpleNamespace(
            name=j["name"], shortname=lambda kind=j["kind"]: SHORTNAMES[kind], idx_q=j["idx_q"],
            idx_v=j["idx_v"], nv=j["nv"], extract=lambda axis=axis: SimpleNamespace(axis=axis)))
        placements.append(SimpleNamespace(rotation=np.array(j["rotation"]),
                                          translation=np.array(j["translation"])))
        parents.append(0 if j["parent"] is None else j["parent"] + 1)
        inertias.append(SimpleNamespace(mass=j["mass"], lever=np.array(j["lever"]),
                                        inertia=np.array(j["inertia"])))
    return SimpleNamespace(njoints=len(joints), nv=d["nv"], joints=joints,
                           jointPlacements=placements, parents=parents, inertias=inertias,
                           gravity=SimpleNamespace(linear=np.array(d["gravity"])))


def refine(model, q, v, tau, start, M, reference):
    """Newton steps a += M⁻¹ (τ − RNEA(q, v, a)) in long double from `start`, to convergence."""
    exact = start.astype(LD)
    for _ in range(4):
        r = tau.astype(LD) - rnea(model, q, v, exact)
        step = np.linalg.solve(M, r.astype(float))
        exact = exact + step.astype(LD)
    # Converged: the last Newton step is far below double's resolution of a*.
    assert np.linalg.norm(step) <= 1e-19 * np.linalg.norm(reference) * np.linalg.cond(M)
    hi = exact.astype(float)
    lo = (exact - hi.astype(LD)).astype(float)
    return hi, lo


def main():
    out = {"pinocchio": pin.__version__, "convention": "LOCAL", "robots": []}
    for n, urdf in enumerate(ROBOTS):
        model = pin.buildModelFromUrdf(os.path.join(REPO, urdf), pin.JointModelFreeFlyer())
        ours = corps_model(urdf)
        assert ours.nv == model.nv and ours.njoints == model.njoints, urdf
        # The same joints in the same order (the states' q and v index both models alike); the
        # root is Pinocchio's "root_joint" and corps' own name for it.
        for i in range(2, model.njoints):
            j, pj = ours.joints[i], model.joints[i]
            assert (j.name, j.idx_q, j.idx_v) == (model.names[i], pj.idx_q, pj.idx_v), (urdf, i)
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
            hi, lo = refine(model, q, v, tau, a, M, a)
            corps_hi, corps_lo = refine(ours, q, v, tau, hi, M, a)
            states.append({"q": q.tolist(), "v": v.tolist(), "tau": tau.tolist(), "aba": a.tolist(),
                           "exact_hi": hi.tolist(), "exact_lo": lo.tolist(),
                           "exact_corps_hi": corps_hi.tolist(), "exact_corps_lo": corps_lo.tolist()})
        out["robots"].append({"urdf": urdf, "states": states})
    path = os.path.join(REPO, "crates", "corps-model", "tests", "golden", "aba_precision.json")
    with open(path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    print(path)


if __name__ == "__main__":
    main()
