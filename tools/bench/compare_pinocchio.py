#!/usr/bin/env python3
"""Times corps-model and Pinocchio 4.1 on TALOS in the same run and prints the ratio table.

Rounds alternate Pinocchio (tools/anchors/run_pin_bench.sh: best of 5 passes over 20,000
random states, µs per call) and corps (criterion, `cargo bench -p corps-model --bench
dynamics`: median over a pool of 1,000 random states) so that both see the same machine load.
The table gives the median over rounds of each side and corps/Pinocchio.

Usage (from the repository root, with ../shared beside it):
    python3 tools/bench/compare_pinocchio.py [--rounds 3] [--markdown]
"""
import argparse
import json
import pathlib
import statistics
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAIRS = [  # (label, pin_bench name, criterion name)
    ("RNEA", "rnea", "rnea"),
    ("NLE", "nle", "nle"),
    ("CRBA", "crba", "crba"),
    ("ABA", "aba", "aba"),
    ("joint Jacobians", "computeJointJacobians", "joint_jacobians"),
    ("CCRBA (A_G, h_G)", "ccrba", "ccrba"),
    ("all terms", "computeAllTerms", "all_terms"),
    ("FK (pos, vel, acc)", "fk_acc", "fk_acc"),
    ("M⁻¹", "minv", "minv"),
]


def pinocchio_round():
    out = subprocess.run(["bash", "tools/anchors/run_pin_bench.sh"], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    times = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[2] == "us":
            times[parts[0]] = float(parts[1])
    return times


def corps_round():
    subprocess.run(["cargo", "bench", "-q", "-p", "corps-model", "--bench", "dynamics"], cwd=ROOT,
                   check=True, capture_output=True, text=True)
    times = {}
    for _, _, name in PAIRS:
        est = ROOT / "target" / "criterion" / "talos" / name / "new" / "estimates.json"
        times[name] = json.loads(est.read_text())["median"]["point_estimate"] / 1000.0
    return times


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args()
    pin, ours = [], []
    for r in range(args.rounds):
        print(f"round {r + 1}/{args.rounds}: Pinocchio ...", flush=True)
        pin.append(pinocchio_round())
        print(f"round {r + 1}/{args.rounds}: corps ...", flush=True)
        ours.append(corps_round())
    rows = []
    for label, p, c in PAIRS:
        tp = statistics.median(x[p] for x in pin)
        tc = statistics.median(x[c] for x in ours)
        rows.append((label, tc, tp, tc / tp))
    if args.markdown:
        print("| algorithm (TALOS, nv = 38) | corps µs | Pinocchio 4.1 µs | ratio corps/Pinocchio |")
        print("|---|---:|---:|---:|")
        for label, tc, tp, ratio in rows:
            print(f"| {label} | {tc:.2f} | {tp:.2f} | {ratio:.2f} |")
    else:
        for label, tc, tp, ratio in rows:
            print(f"{label:22s} corps {tc:7.2f} µs   Pinocchio {tp:7.2f} µs   ratio {ratio:.2f}")


if __name__ == "__main__":
    main()
