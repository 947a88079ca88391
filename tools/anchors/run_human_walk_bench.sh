#!/usr/bin/env bash
# Human path prediction (corps-ocp) against Crocoddyl's SolverDDP on the same OCP, in the same
# run (issue 25, Deliver 4): builds/reuses Crocoddyl 3.2.1 from its PyPI wheel in a venv under
# ${ANCHORS_DIR:-~/.cache/corps-anchors}/croc-venv, compiles tools/anchors/human_walk_croc_bench.cpp
# against it, then alternates rounds of corps' criterion bench (crates/corps-ocp/benches/
# human_walk.rs, which also writes the problems) and the C++ anchor, and prints the medians and
# the ratio corps/Crocoddyl per round and over rounds.
#   ROUNDS (default 3): corps, croc, corps, croc, ...
#   MEASUREMENT_TIME (default 5 s per criterion bench), REPS (default 300 C++ solves per problem)
# Usage (from anywhere): bash tools/anchors/run_human_walk_bench.sh
set -euo pipefail
cd "$(dirname "$0")/../.."   # repository root
root=$PWD
A=${ANCHORS_DIR:-$HOME/.cache/corps-anchors}
V="$A/croc-venv"
mkdir -p "$A/bin"
if [ ! -x "$V/bin/python" ] || ! "$V/bin/python" -c "import crocoddyl" 2>/dev/null; then
  python3 -m venv "$V"
  # cmeel-eigen: Eigen's headers (the crocoddyl wheel ships the library and its own headers).
  "$V/bin/pip" install -q "crocoddyl==3.2.1" "cmeel-eigen==3.4.1"
fi
P=$(ls -d "$V"/lib/python3*/site-packages/cmeel.prefix | head -1)
B="$A/bin/human_walk_croc_bench"
if [ ! -x "$B" ] || [ tools/anchors/human_walk_croc_bench.cpp -nt "$B" ]; then
  # No -march=native: the wheel is built for baseline x86-64 and Eigen's alignment must match
  # it (../shared/tools/anchors/setup.sh); no FMA contraction, as corps' Rust.
  # --disable-new-dtags: an RPATH, which libcrocoddyl's own dependencies (pinocchio) need.
  g++ -O3 -DNDEBUG -std=c++17 -fopenmp -ffp-contract=off \
    -I"$P/include" -I"$P/include/eigen3" tools/anchors/human_walk_croc_bench.cpp \
    -L"$P/lib" -Wl,--disable-new-dtags,-rpath,"$P/lib" -lcrocoddyl -o "$B"
fi
rounds=${ROUNDS:-3}
mtime=${MEASUREMENT_TIME:-5}
reps=${REPS:-300}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
target=${CARGO_TARGET_DIR:-$root/target}
cargo bench -q -p corps-ocp --bench human_walk --no-run
for r in $(seq 1 "$rounds"); do
  echo "== round $r: corps (cargo bench -p corps-ocp --bench human_walk)" >&2
  HUMAN_WALK_PROBLEMS="$out/problems.txt" cargo bench -q -p corps-ocp --bench human_walk -- \
    --warm-up-time 1 --measurement-time "$mtime" >"$out/corps_$r.log" 2>&1 || {
    cat "$out/corps_$r.log" >&2
    exit 1
  }
  grep -E '^(ddp|predict) ' "$out/corps_$r.log" >&2
  for d in "$target"/criterion/human_walk/*/; do
    name=$(basename "$d")
    [ -f "$d/new/estimates.json" ] || continue
    python3 -c 'import json,sys; e=json.load(open(sys.argv[1])); print(sys.argv[2], e["median"]["point_estimate"]/1e3)' \
      "$d/new/estimates.json" "$name"
  done >"$out/corps_$r.txt"
  echo "== round $r: crocoddyl ($B)" >&2
  OMP_NUM_THREADS=1 "$B" "$out/problems.txt" "$reps" | tee "$out/croc_$r.txt" >&2
done
python3 - "$out" "$rounds" <<'EOF'
import statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
rows = {}  # (kind, problem) -> per round: (corps, croc stock, croc corps' stop rule, solve() only)
info = {}
for r in range(1, rounds + 1):
    corps = dict(l.split() for l in open(f"{out}/corps_{r}.txt"))
    for line in open(f"{out}/croc_{r}.txt"):
        if line.startswith("#"):
            continue
        kind, name, *kv = line.split()
        f = dict(x.split("=", 1) for x in kv)
        rows.setdefault((kind, name), []).append((
            float(corps[f"{kind}_{name}"]), float(f["median_us"]),
            float(f["gradient_median_us"]), float(f.get("solve_median_us", "nan"))))
        info[(kind, name)] = f
def cells(c, k):
    return "– | –" if k != k else f"{k:.1f} | {c / k:.2f}"
print("Medians, µs per solve (ddp) or per prediction (predict); ratio = corps / Crocoddyl.")
print("| problem | corps | Crocoddyl | ratio | Crocoddyl, corps' stop rule | ratio "
      "| Crocoddyl solve() only | ratio |")
print("|---|---:|---:|---:|---:|---:|---:|---:|")
for (kind, name), v in rows.items():
    for r, (c, k, g, s) in enumerate(v, 1):
        print(f"| {kind} {name}, round {r} | {c:.1f} | {cells(c, k)} | {cells(c, g)} | {cells(c, s)} |")
for (kind, name), v in rows.items():
    c, k, g, s = (statistics.median(x[i] for x in v) for i in range(4))
    f = info[(kind, name)]
    if kind == "ddp":
        extra = (f"iterations corps {f['corps_iterations']}, Crocoddyl {f['iterations']} "
                 f"({f['gradient_iterations']} with corps' stop rule); cost rel. diff "
                 f"{f['rel_diff']} ({f['gradient_rel_diff']})")
    else:
        extra = (f"{f['horizons']} horizons, Crocoddyl {f['iterations']} iterations "
                 f"({f['gradient_iterations']} with corps' stop rule); cost at corps' horizon "
                 f"rel. diff {f['rel_diff']}; Crocoddyl's own search: {f['own_search_nodes']} "
                 f"nodes, {f['own_search_solves']} solves, {f['own_search_median_us']} µs "
                 f"(corps' stop rule: {f['gradient_own_search_nodes']} nodes, "
                 f"{f['gradient_own_search_solves']} solves)")
    only = "" if s != s else f", solve() only {s:.1f} µs ({c / s:.2f})"
    print(f"median over rounds: {kind} {name}: corps {c:.1f} µs, Crocoddyl {k:.1f} µs, "
          f"ratio {c / k:.2f} (goal ≤ 0.5); corps' stop rule {g:.1f} µs ({c / g:.2f}){only}; "
          f"{extra}")
EOF
