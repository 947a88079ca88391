"""RESULTS.md's co-navigation table: every walk of shared/data/human-walking (every file, every
subject) in every mode (behind, beside, ahead), at a given rate of the person's recorded pace,
run with `corps run` from scenarios/conav/behind_E1540.toml with [human] replaced. Prints a
markdown summary and the failures; writes every run's figures to a CSV.

Usage (from the repository root):
    python3 tools/results/conav.py [--corps target/release/corps] [--rate 0.25] [--jobs 2]
        [--csv conav.csv] [--limit N] [--set KEY=VALUE ...] [--only NAMES_FILE]
"""

import argparse
import concurrent.futures as cf
import csv
import json
import math
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DATA = REPO.parent / "shared" / "data" / "human-walking"
TEMPLATE = REPO / "scenarios" / "conav" / "behind_E1540.toml"
MODES = ["behind", "beside", "ahead"]


def walk_time(rows, subject):
    """Recorded duration (s) of a subject's walk: path length over median speed
    (corps_ocp::recorded_walks' time base)."""
    x, y, vx, vy = rows[6 * subject], rows[6 * subject + 1], rows[6 * subject + 2], rows[6 * subject + 3]
    length = sum(math.hypot(x[k + 1] - x[k], y[k + 1] - y[k]) for k in range(len(x) - 1))
    speeds = sorted(math.hypot(a, b) for a, b in zip(vx, vy))
    return length / speeds[len(speeds) // 2], length


def initial_turn(rows, subject):
    """Angle (degrees) between the person's first direction (over the first 50 samples) and the
    straight line from their start to their goal: how much they turn early in the walk."""
    x, y = rows[6 * subject], rows[6 * subject + 1]
    first = math.atan2(y[50] - y[0], x[50] - x[0])
    whole = math.atan2(y[-1] - y[0], x[-1] - x[0])
    return math.degrees(abs((whole - first + math.pi) % (2 * math.pi) - math.pi))


def run(corps, scenario_text, name, duration, out):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{name}.toml"
        path.write_text(scenario_text)
        # The scenario sits in a temporary directory: its walk file is given absolute.
        proc = subprocess.run(
            [corps, "run", str(path), "--duration", f"{duration:.2f}", "-o", str(out / name)],
            capture_output=True, text=True, cwd=REPO)
        metrics = out / name / "metrics.json"
        if not metrics.exists():
            return {"name": name, "verdict": "error", "reason": proc.stderr.strip()[-300:]}
        m = json.loads(metrics.read_text())
        v = m["verdict"]
        return {
            "name": name, "verdict": v["verdict"], "t": v.get("t"), "reason": v.get("reason") or "",
            "mean_following_error_m": m.get("mean_following_error_m", float("nan")),
            "max_following_error_m": m.get("max_following_error_m", float("nan")),
            "steps": m.get("steps", 0), "max_lateral_step_m": m.get("max_lateral_step_m", float("nan")),
        }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--corps", default=str(REPO / "target" / "release" / "corps"))
    ap.add_argument("--rate", type=float, default=0.25)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--csv")
    ap.add_argument("--limit", type=int, default=0, help="at most N walks (a quick look)")
    ap.add_argument("--set", action="append", default=[],
                    help="KEY=VALUE added to [controller.set], e.g. angular_momentum.weight=0")
    ap.add_argument("--only", help="a file of run names (mode_walk_subject), one per line")
    ap.add_argument("--from-csv", help="print the tables of an earlier run's --csv, running nothing")
    args = ap.parse_args()
    template = TEMPLATE.read_text()
    jobs = []
    for f in sorted(DATA.glob("*.dat")):
        if f.name == "StartAndEnd.dat":
            continue
        rows = [[float(v) for v in line.split()] for line in f.read_text().splitlines() if line.strip()]
        for subject in range(len(rows) // 6):
            recorded, length = walk_time(rows, subject)
            turn = initial_turn(rows, subject)
            duration = 1.5 + recorded / args.rate + 4.0
            for mode in MODES:
                text = re.sub(r'(?m)^file = .*$', f'file = "{f}"', template)
                text = re.sub(r'(?m)^subject = .*$', f"subject = {subject}", text)
                text = re.sub(r'(?m)^mode = .*$', f'mode = "{mode}"', text)
                text = re.sub(r'(?m)^rate = .*$', f"rate = {args.rate}", text)
                # The campaign reads the metrics only: no figures.
                text = text.replace("[output]\n", "[output]\nplots = false\n", 1)
                for kv in args.set:
                    text = text.replace("[controller.set]\n", f"[controller.set]\n{kv}\n", 1)
                jobs.append((f"{mode}_{f.stem}_{subject}", text, duration, mode, f.stem, subject, length, turn))
    if args.from_csv:
        results = []
        with open(args.from_csv) as fh:
            for r in csv.DictReader(fh):
                for key in ("mean_following_error_m", "max_following_error_m", "max_lateral_step_m", "length_m"):
                    r[key] = float(r[key])
                r["steps"], r["subject"] = int(r["steps"]), int(r["subject"])
                if "initial_turn_deg" not in r:
                    rows = [[float(v) for v in line.split()]
                            for line in (DATA / f"{r['walk']}.dat").read_text().splitlines() if line.strip()]
                    r["initial_turn_deg"] = initial_turn(rows, r["subject"])
                r["initial_turn_deg"] = float(r["initial_turn_deg"])
                results.append(r)
        report(results)
        return
    if args.only:
        names = set(Path(args.only).read_text().split())
        jobs = [j for j in jobs if j[0] in names]
    if args.limit:
        jobs = jobs[: args.limit * len(MODES)]
    results = []
    with tempfile.TemporaryDirectory() as out, cf.ThreadPoolExecutor(args.jobs) as pool:
        futures = {pool.submit(run, args.corps, j[1], j[0], j[2], Path(out)): j for j in jobs}
        for k, fut in enumerate(cf.as_completed(futures), 1):
            j = futures[fut]
            r = fut.result()
            r.update({"mode": j[3], "walk": j[4], "subject": j[5], "length_m": j[6], "initial_turn_deg": j[7]})
            results.append(r)
            print(f"\r{k}/{len(jobs)}", end="", file=sys.stderr)
    print(file=sys.stderr)
    results.sort(key=lambda r: (r["mode"], r["walk"], r["subject"]))
    if args.csv:
        with open(args.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(results[0].keys()))
            w.writeheader()
            w.writerows(results)
    report(results)


def report(results):
    """The markdown tables of a campaign's results."""
    print(f"| mode | walks | completed | lost_human | fell | other | following error mean (mm), median of runs | max (mm), median of runs | worst max (mm) | widest sideways step (mm) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for mode in MODES:
        rs = [r for r in results if r["mode"] == mode]
        count = lambda v: sum(r["verdict"] == v for r in rs)
        ok = [r for r in rs if r["verdict"] == "completed"]
        med = lambda key, sel: statistics.median(r[key] for r in sel) * 1e3 if sel else float("nan")
        worst = max((r["max_following_error_m"] for r in ok), default=float("nan")) * 1e3
        side = max((r["max_lateral_step_m"] for r in ok), default=float("nan")) * 1e3
        other = len(rs) - count("completed") - count("lost_human") - count("fell")
        print(f"| {mode} | {len(rs)} | {count('completed')} | {count('lost_human')} | {count('fell')} | {other} "
              f"| {med('mean_following_error_m', ok):.0f} | {med('max_following_error_m', ok):.0f} | {worst:.0f} | {side:.0f} |")
    print()
    bins = [(0, 20, "< 20°"), (20, 45, "20–45°"), (45, 181, "> 45°")]
    print("Runs that did not complete, by how much the person turns early in the walk (the angle "
          "between their first direction and the line from their start to their goal):")
    print()
    print("| mode | " + " | ".join(label for _, _, label in bins) + " |")
    print("|---|" + "---|" * len(bins))
    for mode in MODES:
        cells = []
        for lo, hi, _ in bins:
            sel = [r for r in results if r["mode"] == mode and lo <= r["initial_turn_deg"] < hi]
            bad = sum(r["verdict"] != "completed" for r in sel)
            cells.append(f"{bad} of {len(sel)}")
        print(f"| {mode} | " + " | ".join(cells) + " |")
    print()
    failed = [r for r in results if r["verdict"] != "completed"]
    reasons = {}
    for r in failed:
        key = (r["verdict"], re.sub(r"[-0-9.]+", "#", r["reason"])[:90])
        reasons.setdefault(key, []).append(r["name"])
    for (verdict, reason), names in sorted(reasons.items(), key=lambda kv: -len(kv[1])):
        print(f"- {verdict} ({len(names)}): {reason} — e.g. {', '.join(names[:3])}")


if __name__ == "__main__":
    main()
