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
echo "| flags | verdict | stations | clamp while held (N) | touch → hold: peak (N), slide (mm) | slide held (mm) | tangential / normal | hole position (mm) | QP interval (ms) | tank min (J) | local PD+ energy (J) |"
echo "|---|---|---:|---|---|---:|---:|---:|---|---:|---:|"
k=0
while IFS= read -r flags; do
  k=$((k + 1))
  # shellcheck disable=SC2086
  "$corps" drill scenarios/drilling/ur5_drilling.toml --quiet -o "$out/$k" $flags > /dev/null 2>&1 || true
  python3 - "$out/$k/metrics.json" "${flags:-(none: 250 Hz ± 2 ms over 500 Hz)}" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
print(f"| `{sys.argv[2]}` | {m['verdict']} | {m['stations_done']}/{m['stations']} | "
      f"{m['clamp_min_n']:.1f}–{m['clamp_max_n']:.1f} | {m['touch_peak_n']:.1f}, {m['touch_slide_max_mm']:.2f} | "
      f"{m['slip_max_mm']:.3f} | {m['slip_ratio_max']:.3f} | {m['hole_position_error_max_mm']:.2f} | "
      f"{m['qp_interval_mean_ms']:.1f} ({m['qp_interval_min_ms']:.0f}–{m['qp_interval_max_ms']:.0f}) | "
      f"{m['tank_min_j']:.2f} | {m['local_loop_energy_j']:.3f} |")
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
