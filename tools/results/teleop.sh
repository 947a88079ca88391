#!/usr/bin/env bash
# RESULTS.md's section on keyboard teleoperation: the prose (teleop.md) and a table of key-script
# sessions of `corps teleop --keys` (headless, the same code as at the keyboard), each run and
# read back here. Usage (from the repository root): bash tools/results/teleop.sh [CORPS]
set -euo pipefail
cd "$(dirname "$0")/../.."
corps=${1:-./target/release/corps}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# A 300 N shove to the left for 0.2 s at 3 s on the walking robot.
{ cat scenarios/teleop/talos_keyboard.toml
  printf '\n[[push]]\nframe = "base_link"\nstart = 3.0\nduration = 0.2\nforce = [0.0, 300.0, 0.0]\n'
} > "$out/shoved.toml"
printf '0.5 i\n' > "$out/walk.keys"

cat tools/results/teleop.md
echo
echo "| session | keys | duration (s) | ended | travelled (m) | turned (°) | steps | plan CoM y at the end (mm) | base y at the end (mm) | median tick (µs) | wall time (s) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
session() { # name, scenario ('' = the default), keys, duration
  local name=$1 scenario=$2 keys=$3 duration=$4
  local start end
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  "$corps" teleop $scenario --keys "$keys" --duration "$duration" -o "$out/$name" > "$out/$name.txt" 2>/dev/null || true
  end=$(date +%s.%N)
  python3 - "$out/$name" "$out/$name.txt" "$name" "$keys" "$duration" "$start" "$end" <<'PY'
import csv, json, re, sys
d, report, name, keys, duration, start, end = sys.argv[1:]
text = open(report).read()
rows = list(csv.DictReader(open(f"{d}/log.csv")))
m = json.load(open(f"{d}/metrics.json"))
v = m["verdict"]
ended = v["verdict"] if v.get("t") is None else f"{v['verdict']} at {v['t']:.2f} s"
num = lambda pattern: float(re.search(pattern, text).group(1))
print(f"| {name} | `{keys.split('/')[-1] if keys.startswith('scenarios') else 'walk 0.1 m/s, shoved'}` | {m['duration']:.1f} | {ended} "
      f"| {num(r'travelled ([0-9.]+) m'):.3f} | {num(r'turned (-?[0-9.]+)°'):.1f} | {int(num(r'([0-9]+) steps'))} "
      f"| {1e3 * float(rows[-1]['com_ref_y']):.1f} | {1e3 * float(rows[-1]['base_y']):.1f} "
      f"| {m['tick_time']['median_us']:.1f} | {float(end) - float(start):.2f} |")
PY
}
session forward_turn "" scenarios/teleop/forward_turn.keys 13
session straight "" scenarios/teleop/straight.keys 14
session all_out "" scenarios/teleop/all_out.keys 14
session shoved "$out/shoved.toml" "$out/walk.keys" 60
