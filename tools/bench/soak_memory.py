#!/usr/bin/env python3
"""Memory of a long run: resident set size (RSS) over a `corps run`.

Runs the soak scenario (`scenarios/soak/stand_1h.toml`: TALOS standing one simulated hour
under TSID torque control, pushed every 30 s) for a short duration and for its whole
duration, samples each process's RSS from /proc every second, and prints the peak RSS of both
(the kernel's own figure for the whole process, plots included),
their ratio (the goal of the issue "corps under load": the long run within 1.3x the short
one) and the long run's RSS against the simulated time it had reached (from the log's rows).

Usage (from the repository root, after `cargo build --release`; Linux):
    python3 tools/bench/soak_memory.py [--short 10] [--long 3600] [scenario.toml]
"""
import argparse
import os
import pathlib
import subprocess
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = ROOT / "target" / "release" / "corps"
DEFAULT = "scenarios/soak/stand_1h.toml"


def rss_mb(pid: int) -> float | None:
    try:
        for line in pathlib.Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        return None
    return None


def last_time(log: pathlib.Path) -> float | None:
    """The time of the last whole row of a (partial) log."""
    try:
        with open(log, "rb") as f:
            f.seek(0, 2)
            f.seek(max(0, f.tell() - 4096))
            lines = f.read().split(b"\n")
        rows = [l for l in lines[:-1] if l and not l.startswith(b"t,")]
        return float(rows[-1].split(b",")[0]) if rows else None
    except (OSError, ValueError):
        return None


def run(scenario: str, duration: float, out: pathlib.Path) -> tuple[float, float, list]:
    """Runs the scenario; returns the wall time, the peak RSS (MB) and (wall s, simulated s,
    RSS MB) samples."""
    start = time.perf_counter()
    p = subprocess.Popen([str(BIN), "run", scenario, "-o", str(out), "--duration", str(duration)],
                         cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    samples, next_sample = [], start
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid == p.pid:
            break
        now = time.perf_counter()
        if now >= next_sample:
            r = rss_mb(p.pid)
            if r is not None:
                samples.append((now - start, last_time(out / "log.csv.partial"), r))
            next_sample = now + 1.0
        time.sleep(0.02)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"corps run exited {os.waitstatus_to_exitcode(status)}")
    # The kernel's peak resident set of the process (kB on Linux).
    return time.perf_counter() - start, usage.ru_maxrss / 1024, samples


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--short", type=float, default=10.0)
    ap.add_argument("--long", type=float, default=3600.0)
    ap.add_argument("scenario", nargs="?", default=DEFAULT)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        w_short, short, _ = run(args.scenario, args.short, tmp / "short")
        w_long, long, samples = run(args.scenario, args.long, tmp / "long")
    print(f"{args.scenario}")
    print(f"  {args.short:g} s simulated: peak RSS {short:.1f} MB ({w_short:.1f} s wall)")
    print(f"  {args.long:g} s simulated: peak RSS {long:.1f} MB ({w_long:.1f} s wall)")
    print(f"  ratio {long / short:.2f} (goal <= 1.3)")
    print("  RSS over the long run (simulated s: MB):")
    step = max(1, len(samples) // 12)
    for wall, sim, r in samples[::step]:
        print(f"    {'-' if sim is None else f'{sim:7.0f}'}: {r:6.1f}   (wall {wall:5.0f} s)")


if __name__ == "__main__":
    main()
