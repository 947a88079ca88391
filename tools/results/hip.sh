#!/usr/bin/env bash
# RESULTS.md's section on TALOS' flexible hip (issue 25, Deliver 3): the prose (hip.md) and
# tables of the scenarios of scenarios/hip/ and of `corps robot stiffness`, each run and read
# back here. Usage (from the repository root): bash tools/results/hip.sh [CORPS]
set -euo pipefail
cd "$(dirname "$0")/../.."
corps=${1:-./target/release/corps}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run() { "$corps" run "$1" -o "$out/$(basename "$1" .toml)" > /dev/null 2>&1 || true; }

cat tools/results/hip.md
echo
echo "### One-leg stance (scenarios/hip/one_foot_*.toml; means over the last 5 s)"
echo
echo "| stance | robot, controller | compensation | verdict | sole F/T moment about x (N·m) | CoP − controller's CoM, sideways (mm) | CoP − true CoM, sideways (mm) |"
echo "|---|---|---|---|---:|---:|---:|"
for side in left right; do
  for v in rigid "" fixed model; do
    f=scenarios/hip/one_foot_${side}${v:+_$v}.toml
    run "$f"
    python3 - "$out/$(basename "$f" .toml)" "$side" "${v:-none}" <<'PY'
import json, sys
d, side, v = sys.argv[1:]
m = json.load(open(f"{d}/metrics.json"))
h = m.get("hold") or {}
k = 0 if side == "left" else 1
robot = "rigid TALOS, IK position" if v == "rigid" else "flexible hip, IK position"
comp = "—" if v in ("rigid", "none") else v
cell = lambda x, s=1.0: f"{x * s:.2f}" if h else "—"
print(f"| {side} | {robot} | {comp} | {m['verdict']['verdict']} | {cell(h.get('ankle_torque_x_nm', [0, 0])[k])} "
      f"| {cell(h.get('zmp_minus_controller_com_m', [0, 0])[1], 1e3)} | {cell(h.get('zmp_minus_com_m', [0, 0])[1], 1e3)} |")
PY
  done
done
for v in _rigid ""; do
  f=scenarios/hip/tsid_torque_one_foot_left$v.toml
  run "$f"
  python3 - "$out/$(basename "$f" .toml)" "$v" <<'PY'
import json, sys
d, v = sys.argv[1:]
m = json.load(open(f"{d}/metrics.json"))
h = m.get("hold")
robot = "rigid TALOS, TSID torque" if v else "flexible hip, TSID torque"
if h is None:
    print(f"| left | {robot} | — | {m['verdict']['verdict']} | — | — | — |")
else:
    print(f"| left | {robot} | — | {m['verdict']['verdict']} | {h['ankle_torque_x_nm'][0]:.2f} "
          f"| {1e3 * h['zmp_minus_controller_com_m'][1]:.2f} | {1e3 * h['zmp_minus_com_m'][1]:.2f} |")
PY
done
echo
echo "### The 20 cm position walk (scenarios/hip/walk_20cm*.toml; landings until the run fails)"
echo
echo "| robot | compensation | verdict | landings L / R | landing error mean L / R (mm) | max L / R (mm) |"
echo "|---|---|---|---|---|---|"
for f in scenarios/walk/ik_position_20cm.toml scenarios/hip/walk_20cm.toml scenarios/hip/walk_20cm_fixed.toml scenarios/hip/walk_20cm_model.toml; do
  run "$f"
  python3 - "$out/$(basename "$f" .toml)" "$f" <<'PY'
import json, sys
d, f = sys.argv[1:]
m = json.load(open(f"{d}/metrics.json"))
v = m["verdict"]
ended = v["verdict"] if v.get("t") is None else f"{v['verdict']} at {v['t']:.2f} s"
robot = "rigid TALOS" if "walk/" in f else "flexible hip"
comp = "fixed" if "fixed" in f else "model" if "model" in f else "—"
L, R = m["feet"]
print(f"| {robot} | {comp} | {ended} | {L['landings']} / {R['landings']} "
      f"| {1e3 * L['landing_error_mean']:.1f} / {1e3 * R['landing_error_mean']:.1f} "
      f"| {1e3 * L['landing_error_max']:.1f} / {1e3 * R['landing_error_max']:.1f} |")
PY
done
echo
echo "### Identification (\`corps robot stiffness\`, the one-leg stance under the model compensation)"
for side in left right; do
  echo
  echo "    corps robot stiffness scenarios/hip/one_foot_${side}_model.toml --joints leg_${side}_hip_flex_roll,leg_${side}_hip_flex_pitch"
  echo
  echo '```text'
  "$corps" robot stiffness scenarios/hip/one_foot_${side}_model.toml \
    --joints "leg_${side}_hip_flex_roll,leg_${side}_hip_flex_pitch" 2>&1 || true
  echo '```'
done
