#!/usr/bin/env python3
"""Extract, from TSID's QP snapshots (../shared/data/qp/tsid-talos-double/qp_*.json), what a
re-implementation needs to rebuild each tick's whole-body QP: the state (q, v), every task's
gains, weights, masks and references, the contacts, the actuation bounds, TSID's per-task
computed values (for step-by-step checks) and eiquadprog's solution x. The QP matrices themselves
are already in crates/corps-qp/tests/data/tsid_talos_double.json.

Usage (from the repository root, with ../shared beside it):
    python3 crates/corps-control/tools/extract_tsid_ticks.py
Writes crates/corps-control/tests/data/tsid_ticks.json (numbers kept at full precision).

Single support: the shared snapshots hold double support only. The anchor harness of
../shared/tools/anchors (setup.sh builds it from TSID's PyPI wheels) dumps the QPs of its
`single` scenario (TALOS on the left sole, the right sole lifted 5 cm by a TaskSE3Equality at
priority 1):
    A=$(bash ../shared/tools/anchors/setup.sh)
    TSID_BENCH_QPDUMP=/tmp/tsid_single/qp TSID_BENCH_QPDUMP_TICKS=1500-1504,1800,2200,2600 \
      OMP_NUM_THREADS=1 $A/bin/tsid_bench robots/talos_data/robots/talos_reduced.urdf \
      robots/talos_data/srdf/talos.srdf fast single 1200
    python3 crates/corps-control/tools/extract_tsid_ticks.py --single /tmp/tsid_single
writes crates/corps-control/tests/data/tsid_ticks_single.json, each tick with its QP (H, g, A,
b, C, l, u) as eiquadprog received it, since no shared file holds those.
"""
import argparse
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


def se3_task(t):
    return {
        "frame": t["frame"],
        "priority": t["priority"],
        "weight": t["weight"],
        **keep(t, ["Kp", "Kd", "mask", "local_frame", "ref", "computed"]),
    }


def tick_of(d):
    t = d["tasks"]
    return {
        "tick": d["tick"],
        "t": d["t"],
        "q": d["q"],
        "v": d["v"],
        "x": d["x"],
        "com": keep(t["com"], ["Kp", "Kd", "mask", "weight", "ref", "computed"]),
        "posture": keep(t["posture"], ["Kp", "Kd", "mask", "weight", "ref", "computed"]),
        "am": keep(t["am"], ["Kp", "weight", "ref", "computed"]),
        "contacts": [contact(c) for c in t["contacts"]],
        "se3_tasks": [se3_task(s) for s in t.get("se3_tasks", [])],
        "actuation": keep(t["actuation"], ["lower", "upper"]),
    }


def snapshots(directory):
    paths = glob.glob(os.path.join(directory, "*_*.json"))
    return [json.load(open(p)) for p in sorted(paths, key=lambda p: int(p.split("_")[-1][:-5]))]


def single(directory):
    out_path = os.path.join(os.path.dirname(OUT), "tsid_ticks_single.json")
    ticks = []
    for d in snapshots(directory):
        tick = tick_of(d)
        tick["qp"] = {k: d[k] for k in ("H", "g", "A", "b", "C", "l", "u")}
        ticks.append(tick)
    out = {
        "source": "the anchor harness ../shared/tools/anchors/tsid_bench.cpp, scenario single (TSID 1.10.0, "
        "eiquadprog 1.3.2, TALOS talos_reduced): the left sole in contact, the right sole lifted by a "
        "TaskSE3Equality",
        "generator": "crates/corps-control/tools/extract_tsid_ticks.py --single DIR",
        "ticks": ticks,
    }
    with open(out_path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
    print(f"wrote {out_path}: {len(ticks)} ticks, {os.path.getsize(out_path)} bytes")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--single", metavar="DIR", help="the harness's single-support QP dumps")
    args = parser.parse_args()
    if args.single:
        single(args.single)
        return
    ticks = [tick_of(d) for d in snapshots(SRC)]
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
