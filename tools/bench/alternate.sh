#!/usr/bin/env bash
# Times two commands run alternately (A, B, A, B, ...) N times each and prints the min,
# median and max wall time of each and the median of the paired ratios B/A: a speed figure
# against an anchor measured in the same session, as BENCHMARKS.md asks.
#   bash tools/bench/alternate.sh [-n N] "COMMAND A" "COMMAND B"
set -euo pipefail
n=9
if [ "${1:-}" = "-n" ]; then n=$2; shift 2; fi
if [ $# -ne 2 ]; then
  echo "usage: $0 [-n N] \"COMMAND A\" \"COMMAND B\"" >&2
  exit 2
fi
a=$1 b=$2
times_a=() times_b=()
now() { date +%s.%N; }
for _ in $(seq "$n"); do
  t0=$(now); bash -c "$a" >/dev/null 2>&1 || { echo "A failed: $a" >&2; exit 1; }; t1=$(now)
  bash -c "$b" >/dev/null 2>&1 || { echo "B failed: $b" >&2; exit 1; }; t2=$(now)
  times_a+=("$t0:$t1")
  times_b+=("$t1:$t2")
done
python3 - "${times_a[*]}" "${times_b[*]}" <<'PY'
import statistics, sys
def spans(text):
    return [float(e) - float(s) for s, e in (x.split(":") for x in text.split())]
a, b = spans(sys.argv[1]), spans(sys.argv[2])
for name, t in (("A", a), ("B", b)):
    print(f"{name}: min {min(t):.3f} s, median {statistics.median(t):.3f} s, max {max(t):.3f} s")
r = [y / x for x, y in zip(a, b)]
print(f"B/A: median {statistics.median(r):.3f} (min {min(r):.3f}, max {max(r):.3f}) over {len(r)} pairs")
PY
