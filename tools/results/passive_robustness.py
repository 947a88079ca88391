#!/usr/bin/env python3
"""Plain TSID against the passive controller (seed 000 ch. 5) on the same TALOS scenarios:
gains x1, x2, x5, x10 over Table 5.2 (Kp and Kd of every task; the posture's Kd, always
2 sqrt(Kp) in corps, x sqrt(k)) under a 100 N push, a 10 cm
CoM reference step, the block under the pressing hand pulled away (the tool, block, force
schedule and emergency action of scenarios/passive/force_contact.toml, 40 s), pushes of 100,
200 and 300 N at the base. Both controllers read the same
gains file (config/talos/passive_torque.toml; plain TSID without its [tank]).

Per run: verdict, the peak energy the joints injected (max over t of the integral of
q_dot^T tau of the applied torques and the true velocity, column joint_power_W of the log),
and for the passive controller the tank at the start and its lowest energy, the ticks where
the power row was violated (h_dot_W above passivity_bound_W by more than 1e-6 W), the
fallbacks, the energy the robot received beyond the storage's loss that the empty tank could
not pay (sampled power, until the first fallback), and the largest energy given beyond both
(should be 0).

Usage: cargo build --release && python3 tools/results/passive_robustness.py [--corps PATH]
Prints a markdown table (RESULTS.md keeps it).
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
GAINS = ROOT / "config/talos/passive_torque.toml"
FORCE_SCENARIO = ROOT / "scenarios/passive/force_contact.toml"
DURATION = 6.0
PUSH_AT = 1.0


def scaled_gains(text, factor, tank):
    """The gains file with every Kp and Kd times `factor` (Kd written out where it was
    2 sqrt(Kp)), without [tank] when `tank` is False."""
    out, section = [], None
    body = text if tank else re.sub(r"\n\[tank\]\n.*?(?=\n\[|\n# |\Z)", "\n", text, flags=re.S)
    lines = body.splitlines()
    kp_seen = {}
    for line in lines:
        m = re.match(r"\[(\w+)\]", line)
        if m:
            section = m.group(1)
        km = re.match(r"(kp|kd)\s*=\s*([0-9.eE+-]+)", line)
        if km and section not in ("tank",):
            key, value = km.group(1), float(km.group(2)) * factor
            if key == "kp":
                kp_seen[section] = float(km.group(2))
            line = f"{key} = {value!r}"
        out.append(line)
    text = "\n".join(out) + "\n"
    # Sections whose Kd defaulted to 2 sqrt(Kp): write the scaled Kd explicitly.
    for section, kp in kp_seen.items():
        block = re.search(rf"\[{section}\]\n(.*?)(\n\[|\Z)", text, re.S)
        # The momentum task is P only (TSID's TaskAMEquality); the posture's Kd is always
        # 2 sqrt(Kp) (so x sqrt(k) there); the force task's absent Kd is 0 (Table 5.2).
        if block and "kd" not in block.group(1) and section not in ("angular_momentum", "posture", "force_contact"):
            kd = 2.0 * kp ** 0.5 * factor
            text = text.replace(f"[{section}]\n", f"[{section}]\nkd = {kd!r}\n", 1)
    return text


def scenario(kind, gains_path, motion, pushes, duration):
    s = f"""duration = {duration}

[controller]
kind = "{kind}"
gains = "{gains_path}"

{motion}

[sim]
integrator = "implicit_euler"
[sim.contact]
normal_stiffness = 4e8
tangential_stiffness = 4e8

[output]
log_every = 1
"""
    for force in pushes:
        s += f"""
[[push]]
frame = "base_link"
start = {PUSH_AT}
duration = 0.1
force = [{force}, 0.0, 0.0]
"""
    return s


def run(corps, tmp, name, kind, gains_text, motion, pushes, duration=DURATION):
    d = Path(tmp) / name
    d.mkdir()
    (d / "gains.toml").write_text(gains_text)
    (d / "scenario.toml").write_text(scenario(kind, d / "gains.toml", motion, pushes, duration))
    p = subprocess.run(
        [corps, "run", str(d / "scenario.toml"), "-o", str(d / "out"), "--serial"],
        capture_output=True,
        text=True,
    )
    if not (d / "out" / "log.csv").exists():
        sys.exit(f"{name}: corps run failed: {p.stderr.strip()}")
    verdict = next(
        (l.split("verdict:")[1].strip() for l in p.stdout.splitlines() if "verdict:" in l),
        p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "?",
    )
    rows = list(csv.DictReader(open(d / "out" / "log.csv")))
    dt = float(rows[1]["t"]) - float(rows[0]["t"])
    injected, peak = 0.0, 0.0
    for r in rows:
        injected += float(r["joint_power_W"]) * dt
        peak = max(peak, injected)
    res = {"verdict": verdict, "peak_injected_J": peak}
    if "tank_energy_J" in rows[0]:
        e = [float(r["tank_energy_J"]) for r in rows]
        viol = sum(
            1
            for r in rows
            if float(r["h_dot_W"]) > float(r["passivity_bound_W"]) + 1e-6
        )
        fallbacks = sum(1 for r in rows if r["h_dot_W"] == "NaN" or r["h_dot_W"] == "nan")
        s0 = float(rows[0]["task_energy_J"])

        def storage(r):
            # A tick that fell back (h_dot_W NaN) holds no task spring.
            if r["h_dot_W"].lower() == "nan":
                return float(r["tank_energy_J"])
            return (
                float(r["beta"]) * float(r["gamma"]) * float(r["task_energy_J"])
                + float(r["tank_energy_J"])
                - float(r["spring_payment_J"])
            )

        # The energy the robot received over each step (-tau^T dq, port_energy_J) beyond what
        # the storage H = beta gamma S + E_tank lost: all of it should be the bookings the
        # empty tank could not pay (unpaid_J); "beyond" is what is not.
        h0, given, unpaid, beyond, unpaid_first = storage(rows[0]), 0.0, 0.0, float("-inf"), None
        for r in rows:
            given -= float(r["port_energy_J"])
            unpaid += float(r["unpaid_J"])
            if r["h_dot_W"].lower() == "nan" and unpaid_first is None:
                unpaid_first = unpaid
            beyond = max(beyond, given - (h0 - storage(r)) - unpaid)
        res.update(
            tank0=e[0],
            tank_min=min(e),
            s0=s0,
            violations=viol,
            fallbacks=fallbacks,
            beyond=beyond,
            unpaid=unpaid if unpaid_first is None else unpaid_first,
        )
    return res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--corps", default=str(ROOT / "target/release/corps"))
    args = ap.parse_args()
    base = GAINS.read_text()
    cases = []
    push100 = ([100.0], "[motion]\nkind = \"stand\"")
    for k in [1, 2, 5, 10]:
        cases.append((f"(a) gains ×{k}, 100 N push", k, *push100))
    cases.append(
        (
            "(b) CoM reference step 10 cm (y) at 1 s",
            1,
            [],
            "[motion]\nkind = \"com_step\"\noffset = [0.0, 0.1, 0.0]\nat = 1.0",
        )
    )
    # (c): scenarios/passive/force_contact.toml's tool, block and schedule, 40 s.
    press = FORCE_SCENARIO.read_text().split("[motion]")[1].split("[sim]")[0]
    cases.append(("(c) contact lost: the block under the pressing hand removed at 32.3 s", 1, [], "[motion]" + press, 40.0))
    for f in [100, 200, 300]:
        cases.append((f"(d) push {f} N forward, 0.1 s", 1, [float(f)], "[motion]\nkind = \"stand\""))
    print("| case | plain TSID: verdict | plain: peak injected (J) | passive: verdict | passive: peak injected (J) | tank start / lowest (J) | S at start (J) | row violations | fallback ticks | unpaid before the first fallback (J) | unexplained (J) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for i, (label, k, pushes, motion, *duration) in enumerate(cases):
            d = duration[0] if duration else DURATION
            plain = run(args.corps, tmp, f"p{i}", "tsid_torque", scaled_gains(base, k, False), motion, pushes, d)
            passive = run(args.corps, tmp, f"t{i}", "passive_torque", scaled_gains(base, k, True), motion, pushes, d)
            print(
                f"| {label} | {plain['verdict']} | {plain['peak_injected_J']:.2f} | {passive['verdict']} | "
                f"{passive['peak_injected_J']:.2f} | {passive['tank0']:.2f} / {passive['tank_min']:.3f} | "
                f"{passive['s0']:.3f} | {passive['violations']} | {passive['fallbacks']} | "
                f"{passive['unpaid']:.3f} | {passive['beyond']:.1e} |",
                flush=True,
            )


if __name__ == "__main__":
    sys.exit(main())
