#!/usr/bin/env python3
"""Times corps' Python package against Pinocchio's (`pin`) from Python, in the same process:
the cost a notebook user pays per call, binding overhead included.

Both sides get the same random states (TALOS and iCub from the repository's URDFs, free-flyer),
as contiguous float64 arrays. Rounds alternate the two libraries; each round times `CALLS`
calls over a pool of states with time.perf_counter_ns and keeps µs per call. The table gives
the median over rounds of each side and the ratio corps/pin.

Usage (a venv with corps installed, `pip install ./python`, and pin):
    python tools/bench/python_vs_pin.py [--rounds 15] [--markdown]
"""
import argparse
import pathlib
import statistics
import sys
import time

import numpy as np
import pinocchio as pin

import corps

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python" / "tests"))
from conftest import ROBOTS, random_state  # noqa: E402

CALLS = 2000
POOL = 100


def cases(model, data, pmodel, pdata, frame):
    pid = pmodel.getFrameId(frame)
    fid = model.get_frame_id(frame)
    return [  # (label, corps call, pin call), each on a state (q, v, a, tau)
        ("rnea", lambda s: corps.rnea(model, data, s[0], s[1], s[2]),
         lambda s: pin.rnea(pmodel, pdata, s[0], s[1], s[2])),
        ("aba", lambda s: corps.aba(model, data, s[0], s[1], s[3]),
         lambda s: pin.aba(pmodel, pdata, s[0], s[1], s[3])),
        ("crba", lambda s: corps.crba(model, data, s[0]),
         lambda s: pin.crba(pmodel, pdata, s[0])),
        ("frame Jacobian (LWA)",
         lambda s: corps.compute_frame_jacobian(model, data, s[0], fid, corps.LOCAL_WORLD_ALIGNED),
         lambda s: pin.computeFrameJacobian(pmodel, pdata, s[0], pid, pin.LOCAL_WORLD_ALIGNED)),
        ("center of mass", lambda s: corps.center_of_mass(model, data, s[0]),
         lambda s: pin.centerOfMass(pmodel, pdata, s[0])),
    ]


def per_call_us(fn, states):
    start = time.perf_counter_ns()
    for k in range(CALLS):
        fn(states[k % len(states)])
    return (time.perf_counter_ns() - start) / CALLS / 1e3


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args()
    frames = {"talos": "left_sole_link", "icub": "l_sole"}
    rows = []
    for name, (urdf, _) in ROBOTS.items():
        model = corps.Model.from_urdf(str(ROOT / urdf))
        pmodel = pin.buildModelFromUrdf(str(ROOT / urdf), pin.JointModelFreeFlyer())
        data, pdata = model.create_data(), pmodel.createData()
        rng = np.random.default_rng(7)
        states = [random_state(model, rng) for _ in range(POOL)]
        for label, ours, theirs in cases(model, data, pmodel, pdata, frames[name]):
            a, b = [], []
            for _ in range(args.rounds):
                a.append(per_call_us(ours, states))
                b.append(per_call_us(theirs, states))
            ca, cb = statistics.median(a), statistics.median(b)
            rows.append((f"{name} (nv = {model.nv})", label, ca, cb, ca / cb))
    if args.markdown:
        print("| robot | call | corps µs | pin µs | ratio corps/pin |")
        print("|---|---|---:|---:|---:|")
        for r in rows:
            print(f"| {r[0]} | {r[1]} | {r[2]:.2f} | {r[3]:.2f} | {r[4]:.2f} |")
    else:
        for r in rows:
            print(f"{r[0]:<16} {r[1]:<22} corps {r[2]:7.2f} µs  pin {r[3]:7.2f} µs  ratio {r[4]:.2f}")


if __name__ == "__main__":
    main()
