#!/usr/bin/env python3
"""Throughput of `corps run` processes sharing the machine.

Starts N `corps run` processes of one scenario at the same moment (N = 1, 2, 4, 8 by default),
each into its own output directory, in the default mode (the adaptive overlap) and with
`--serial`, alternating the modes round by round so both see the same machine. For each N and
mode it prints the median over rounds of: the batch's wall time (all N done), runs per minute,
the median per-run wall time, and the per-run peak RSS. It also checks the goal of the issue
"corps under load": a batch of N default runs finishes within 1.25 x (a lone serial run's
wall time x N / cores).

Usage (from the repository root, after `cargo build --release`):
    python3 tools/bench/throughput.py [--rounds 5] [--counts 1 2 4 8] [scenario.toml]
"""
import argparse
import os
import pathlib
import statistics
import subprocess
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = ROOT / "target" / "release" / "corps"
DEFAULT = "scenarios/walk/tsid_torque_20cm.toml"
MODES = {"default": [], "serial": ["--serial"]}


def batch(scenario: str, n: int, flags: list[str], tmp: pathlib.Path) -> tuple[float, list[float], list[float]]:
    """Runs n processes at once; returns the batch wall time, each run's wall time and peak
    RSS (MB)."""
    start = time.perf_counter()
    procs = {}
    for k in range(n):
        p = subprocess.Popen([str(BIN), "run", scenario, "-o", str(tmp / f"run{k}"), *flags],
                             cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        procs[p.pid] = p
    walls, rss = [], []
    while procs:
        pid, status, usage = os.wait4(-1, 0)
        p = procs.pop(pid, None)
        if p is None:
            continue
        walls.append(time.perf_counter() - start)
        rss.append(usage.ru_maxrss / 1024)
        if os.waitstatus_to_exitcode(status) != 0:
            raise SystemExit(f"corps run failed: {p.stderr.read().decode()}")
        p.stderr.close()
    return time.perf_counter() - start, walls, rss


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--counts", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("scenario", nargs="?", default=DEFAULT)
    args = ap.parse_args()
    if not BIN.exists():
        raise SystemExit(f"{BIN} is missing: run `cargo build --release` first")
    cores = os.cpu_count() or 1
    results = {(n, m): [] for n in args.counts for m in MODES}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for r in range(args.rounds):
            for n in args.counts:
                order = list(MODES) if r % 2 == 0 else list(reversed(MODES))
                for mode in order:
                    results[(n, mode)].append(batch(args.scenario, n, MODES[mode], tmp))
            print(f"round {r + 1}/{args.rounds} done", flush=True)
    lone_serial = statistics.median(b for b, _, _ in results[(1, "serial")]) if 1 in args.counts else None
    print(f"\n{args.scenario}, {cores} cores, {args.rounds} rounds (medians; range of the batch wall time)")
    print(f"{'N':>3} {'mode':>8} {'batch wall s':>18} {'runs/min':>9} {'per-run wall s':>15} "
          f"{'peak RSS MB':>12} {'goal':>22}")
    for n in args.counts:
        for mode in MODES:
            rows = results[(n, mode)]
            b = [x for x, _, _ in rows]
            per_run = statistics.median(w for _, ws, _ in rows for w in ws)
            rss = max(x for _, _, rs in rows for x in rs)
            med = statistics.median(b)
            goal = ""
            if mode == "default" and lone_serial is not None and n >= cores:
                bound = 1.25 * lone_serial * n / cores
                ratio = med / (lone_serial * n / cores)
                goal = f"{ratio:.2f}x ideal ({'ok' if med <= bound else 'MISSED'})"
            print(f"{n:>3} {mode:>8} {med:>7.2f} ({min(b):.2f}-{max(b):.2f}) {60 * n / med:>9.1f} "
                  f"{per_run:>15.2f} {rss:>12.1f} {goal:>22}")
    if lone_serial is not None and (1, "default") in results:
        lone = statistics.median(b for b, _, _ in results[(1, "default")])
        print(f"\nlone run: default {lone:.3f} s, serial {lone_serial:.3f} s: "
              f"default {100 * (1 - lone / lone_serial):.1f}% faster (goal >= 15%)")


if __name__ == "__main__":
    main()
