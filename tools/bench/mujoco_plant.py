#!/usr/bin/env python3
"""The per-tick cost of MuJoCo as a plant of corps' runs against corps' own simulator, on
TALOS's 20 cm walk under the TSID torque controller (1 kHz control, 1 ms physics steps).

For each plant: the wall time of the whole run per control tick, the controller's own time per
tick (from the run's metrics), and the rest (plant, sensors, estimator, recording). For the
MuJoCo plant the rest is split further by timing its methods: `mj_step` itself, and the
Python glue (state conversion, contact forces, torques). Medians over rounds.

Usage (in the Python package's venv, from the repository root):
    target/py-venv/bin/python tools/bench/mujoco_plant.py [--rounds 5]
"""
import argparse
import statistics
import time

import mujoco

import corps
from corps.mujoco_plant import MujocoPlant

WALK = "scenarios/walk/tsid_torque_20cm.toml"


class Timed(MujocoPlant):
    """MujocoPlant with its methods' time (s) and mj_step's time accumulated."""

    def __init__(self, robot):
        super().__init__(robot)
        self.t_methods, self.t_mj = 0.0, 0.0

    def step(self, command):
        start = time.perf_counter()
        real = mujoco.mj_step

        def timed(m, d):
            t0 = time.perf_counter()
            real(m, d)
            self.t_mj += time.perf_counter() - t0

        mujoco.mj_step = timed
        try:
            super().step(command)
        finally:
            mujoco.mj_step = real
        self.t_methods += time.perf_counter() - start

    def state(self):
        start = time.perf_counter()
        out = super().state()
        self.t_methods += time.perf_counter() - start
        return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    rows = {"corps-sim": [], "MuJoCo": []}
    for _ in range(args.rounds):
        for name in rows:
            plant = Timed("talos") if name == "MuJoCo" else None
            start = time.perf_counter()
            r = corps.run(WALK, plant=plant)
            wall = time.perf_counter() - start
            ticks = len(r)
            controller = r.metrics["tick_time"]["avg_us"]
            entry = {"wall": 1e6 * wall / ticks, "controller": controller}
            if plant is not None:
                entry["mj_step"] = 1e6 * plant.t_mj / ticks
                entry["glue"] = 1e6 * (plant.t_methods - plant.t_mj) / ticks
            rows[name].append(entry)
    print(f"µs per control tick, medians over {args.rounds} rounds (TALOS 20 cm walk, {ticks} ticks)")
    for name, entries in rows.items():
        med = {k: statistics.median(e[k] for e in entries) for k in entries[0]}
        rest = med["wall"] - med["controller"]
        line = f"{name:<10} whole run {med['wall']:7.1f}   controller {med['controller']:6.1f}   rest {rest:7.1f}"
        if "mj_step" in med:
            line += f"   (mj_step {med['mj_step']:6.1f}, Python glue {med['glue']:6.1f})"
        print(line)


if __name__ == "__main__":
    main()
