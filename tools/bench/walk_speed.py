#!/usr/bin/env python3
"""Real-time factor of whole walks in the simulator, with control at 1 kHz.

Times `corps run` on a walk scenario (wall clock of the whole command: planning, simulation,
control, log, metrics and plots; by default the simulator prepares its next step on a second
thread while the controller computes) in alternating rounds with the same on one thread
(`--serial`) and with an anchor (serial): the same scenario on
the simulator setup the torque walks used before implicit Euler (4 RK4 substeps per tick on
the same stiff contact). The machine is shared and its speed drifts by up to 2x over
minutes, so both see the same load; the table gives medians over rounds, the range, and the
ratio. Real-time factor = simulated time (settle + controlled duration) / wall time.

Usage (from the repository root, after `cargo build --release`):
    python3 tools/bench/walk_speed.py [--rounds 7] [scenario.toml ...]
"""
import argparse
import pathlib
import re
import statistics
import subprocess
import tempfile
import time
import tomllib

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = ROOT / "target" / "release" / "corps"
DEFAULT = ["scenarios/walk/tsid_torque_20cm.toml"]


def rk4_variant(path: pathlib.Path) -> pathlib.Path:
    """The scenario with its implicit Euler replaced by 4 RK4 substeps, written beside it (its
    relative paths, gains files and CSVs, keep working); the caller deletes it."""
    text = path.read_text()
    if re.search(r"(?m)^substeps\s*=", text):
        raise SystemExit(f"{path}: already sets substeps; compare it by hand")
    text, n = re.subn(r'(?m)^integrator = "implicit_euler"$',
                      'integrator = "rk4"\nsubsteps = 4', text)
    if n != 1:
        raise SystemExit(f"{path}: no `integrator = \"implicit_euler\"` line to compare against")
    out = path.with_name(f".{path.stem}_rk4x4.toml")
    out.write_text(text)
    return out


def simulated_seconds(path: pathlib.Path) -> float:
    s = tomllib.loads(path.read_text())
    settle = s.get("controller", {}).get("settle", 0.5)
    return s["duration"] + settle


def wall(scenario: pathlib.Path, out: pathlib.Path, *flags: str) -> float:
    t = time.perf_counter()
    subprocess.run([str(BIN), "run", str(scenario), "-o", str(out), *flags], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("scenarios", nargs="*", default=DEFAULT)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        print("| walk | simulated | wall median (range) | real-time factor | "
              "`--serial`: wall median (range), real-time factor | "
              "anchor: 4 RK4 substeps, `--serial`, wall median | speed-up |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for name in args.scenarios:
            path = ROOT / name
            anchor = rk4_variant(path)
            sim_s = simulated_seconds(path)
            ours, serial, theirs = [], [], []
            try:
                for _ in range(args.rounds):
                    ours.append(wall(path, tmp / "ours"))
                    serial.append(wall(path, tmp / "serial", "--serial"))
                    theirs.append(wall(anchor, tmp / "anchor", "--serial"))
            finally:
                anchor.unlink()
            mo, ma = statistics.median(ours), statistics.median(theirs)
            ms = statistics.median(serial)
            print(f"| {path.stem} | {sim_s:.1f} s | {mo:.2f} s ({min(ours):.2f}–{max(ours):.2f}) "
                  f"| {sim_s / mo:.1f}× "
                  f"| {ms:.2f} s ({min(serial):.2f}–{max(serial):.2f}), {sim_s / ms:.1f}× "
                  f"| {ma:.2f} s | {ma / mo:.1f}× |", flush=True)


if __name__ == "__main__":
    main()
