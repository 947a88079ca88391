#!/usr/bin/env python3
"""Extract, from TSID's QP snapshots (../shared/data/qp/tsid-talos-double/qp_*.json), what a
re-implementation needs to rebuild each tick's whole-body QP: the state (q, v), every task's
gains, weights, masks and references, the contacts, the actuation bounds, TSID's per-task
computed values (for step-by-step checks) and eiquadprog's solution x. The QP matrices themselves
are already in crates/corps-qp/tests/data/tsid_talos_double.json.

Usage (from the repository root, with ../shared beside it):
    python3 crates/corps-control/tools/extract_tsid_ticks.py
Writes crates/corps-control/tests/data/tsid_ticks.json (numbers kept at full precision).
"""
import glob
import json
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
SRC = os.path.join(ROOT, "..", "shared", "data", "qp", "tsid-talos-double")
OUT = os.path.join(ROOT, "crates", "corps-control", "tests", "data", "tsid_ticks.json")


def keep(d, keys):
    return {k: d[k] for k in keys if k in d}


def contact(c):
    m = c["motion_task"]
    return {
        "frame": c["frame"],
        "contact_points": c["contact_points"],
        "normal": c["normal"],
        "mu": c["mu"],
        "fmin": c["fmin"],
        "fmax": c["fmax"],
        "motion": keep(m, ["Kp", "Kd", "mask", "ref", "computed"]),
        "force_reg": keep(c["force_reg"], ["weight", "component_weights", "f_ref"]),
    }


def main():
    ticks = []
    for path in sorted(glob.glob(os.path.join(SRC, "qp_*.json")), key=lambda p: int(p.split("_")[-1][:-5])):
        d = json.load(open(path))
        t = d["tasks"]
        ticks.append({
            "tick": d["tick"],
            "t": d["t"],
            "q": d["q"],
            "v": d["v"],
            "x": d["x"],
            "com": keep(t["com"], ["Kp", "Kd", "mask", "weight", "ref", "computed"]),
            "posture": keep(t["posture"], ["Kp", "Kd", "mask", "weight", "ref", "computed"]),
            "am": keep(t["am"], ["Kp", "weight", "ref", "computed"]),
            "contacts": [contact(c) for c in t["contacts"]],
            "actuation": keep(t["actuation"], ["lower", "upper"]),
        })
    out = {
        "source": "shared/data/qp/tsid-talos-double (TSID 1.10.0, eiquadprog 1.3.2, TALOS talos_reduced, scenario double)",
        "generator": "crates/corps-control/tools/extract_tsid_ticks.py",
        "ticks": ticks,
    }
    with open(OUT, "w") as f:
        json.dump(out, f, separators=(",", ":"))
    print(f"wrote {OUT}: {len(ticks)} ticks, {os.path.getsize(OUT)} bytes")


if __name__ == "__main__":
    main()
