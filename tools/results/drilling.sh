#!/usr/bin/env bash
# RESULTS.md's section on the fixed-base passive QP drilling a plate (issue 17, Deliver 6;
# seed 000 §3.19, S16): the prose (drilling.md), then `corps drill` on the shared scenario and
# on variants of its loops and thrust, read back from each run's metrics.json.
# Usage (from the repository root): bash tools/results/drilling.sh [CORPS]
set -euo pipefail
cd "$(dirname "$0")/../.."
corps=${1:-./target/release/corps}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

cat tools/results/drilling.md
echo
echo "### The cycle and its variants (\`corps drill scenarios/drilling/ur5_drilling.toml [flags]\`)"
echo
echo "| flags | verdict | stations | clamp while held (N) | touch → release: peak (N), slide (mm) | tangential / normal | hole position (mm) | QP interval (ms) | tank min (J) | QP's torques → arm (J), unpaid (J) | local loop → arm (J) |"
echo "|---|---|---:|---|---|---:|---:|---|---:|---|---:|"
k=0
while IFS= read -r flags; do
  k=$((k + 1))
  # shellcheck disable=SC2086
  "$corps" drill scenarios/drilling/ur5_drilling.toml --quiet -o "$out/$k" $flags > /dev/null 2>&1 || true
  python3 - "$out/$k/metrics.json" "${flags:-(none: 250 Hz ± 2 ms over 500 Hz)}" <<'PY'
import json, sys
try:
    m = json.load(open(sys.argv[1]))
except (OSError, ValueError) as e:
    print(f"| `{sys.argv[2]}` | no metrics ({e}) | | | | | | | | | |")
    sys.exit()
def f(key, digits):
    x = m.get(key)
    return "—" if x is None else f"{x:.{digits}f}"
print(f"| `{sys.argv[2]}` | {m['verdict']} | {m['stations_done']}/{m['stations']} | "
      f"{f('clamp_min_n', 1)}–{f('clamp_max_n', 1)} | {f('contact_peak_n', 1)}, {f('slide_max_mm', 3)} | "
      f"{f('slip_ratio_max', 3)} | {f('hole_position_error_max_mm', 2)} | "
      f"{f('qp_interval_mean_ms', 1)} ({f('qp_interval_min_ms', 0)}–{f('qp_interval_max_ms', 0)}) | "
      f"{f('tank_min_j', 2)} | {f('qp_energy_to_arm_j', 3)}, {m.get('tank_unpaid_j', 0):.1e} | {f('local_loop_energy_j', 3)} |")
PY
done <<'FLAGS'

--jitter 0
--jitter 0 --local-rate-hz 250
--qp-rate-hz 100 --jitter 0.004
--qp-rate-hz 100 --jitter 0.004 --local-rate-hz 100
--qp-rate-hz 50 --jitter 0.008
--qp-rate-hz 50 --jitter 0.008 --local-rate-hz 50
--thrust 40
--thrust 60
FLAGS
