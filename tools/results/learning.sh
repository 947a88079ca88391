#!/usr/bin/env bash
# RESULTS.md's section on learning task weights (issue 21, seed 001 ch. 5): the prose
# (learning.md) and the four campaigns of campaigns/icub/ (ϕp, ϕr, ϕpr with randomization, ϕpr
# without), each run in full with `corps learn` and read back here beside Table 5.2.
# Usage (from the repository root): bash tools/results/learning.sh [CORPS]   (about 10 minutes)
set -euo pipefail
cd "$(dirname "$0")/../.."
corps=${1:-./target/release/corps}
out=${LEARN_OUT:-$(mktemp -d)}
for c in phi_p phi_r phi_pr phi_pr_no_dr; do
  [ -f "$out/$c/tests.csv" ] || "$corps" learn "campaigns/icub/$c.toml" -o "$out/$c" > /dev/null
done
cat tools/results/learning.md
echo
python3 - "$out" <<'PY'
import csv, statistics, sys
out = sys.argv[1]
thesis = {
    "phi_p": ("ϕp", "Yes", ["1", "0.2±0.3", "1.1±1.2", "(1±3)e−3", "0.5±0.3", "(2±5)e−5"], "5/10", "0/10"),
    "phi_r": ("ϕr", "Yes", ["1", "1.6±1.2", "1.8±1.0", "0.1±0.1", "(4±7)e−3", "1e−10"], "7/10", "5/10"),
    "phi_pr": ("ϕpr", "Yes", ["1", "0.9±1.3", "2.4±1.1", "0.6±1.2", "1e−6", "1e−10"], "10/10", "10/10"),
    "phi_pr_no_dr": ("ϕpr", "No", ["1", "1.0±0.3", "0.1±0.3", "0.2±0.1", "1e−6", "(4±5)e−6"], "8/10", "2/10"),
}
print("| fitness | DR | | w_com | w_stance | w_swing | w_neck | w_s | w_τ | tethered | backpacked |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
start_row = None
for c, (fit, dr, tw, tt, tb) in thesis.items():
    rows = list(csv.DictReader(open(f"{out}/{c}/learned.csv")))
    names = [k for k in rows[0] if k not in ("repeat", "best_fitness")]
    cells = []
    for n in names:
        v = [float(r[n]) for r in rows]
        m, s = statistics.mean(v), statistics.pstdev(v)
        cells.append(f"{m:.2g}±{s:.1g}")
    tests = list(csv.DictReader(open(f"{out}/{c}/tests.csv")))
    def count(run, who):
        t = [r for r in tests if r["run"] == run and (r["weights"] == "start") == (who == "start")]
        return f"{sum(r['success'] == 'true' for r in t)}/{len(t)}"
    print(f"| {fit} | {dr} | corps | {' | '.join(cells)} | {count('tethered', 'learned')} | {count('backpacked', 'learned')} |")
    print(f"| | | thesis | {' | '.join(tw)} | {tt} | {tb} |")
    if start_row is None:
        start_row = (count("tethered", "start"), count("backpacked", "start"))
print(f"| start weights w0 (the text's, L6650) | — | corps | 1 | 1 | 1 | 0.1 | 1e−3 | 1e−4 | {start_row[0]} | {start_row[1]} |")
print("| hand tuning (Table 5.2) | — | thesis | 1 | 1 | 1 | 1 | 1e−3 | 1e−4 | 1/1 | 0/1 |")
print()
print("Best fitness at the end of the 200 iterations (mean over the 10 repeats, and its spread):")
print()
for c in thesis:
    rows = list(csv.DictReader(open(f"{out}/{c}/learned.csv")))
    f = [float(r["best_fitness"]) for r in rows]
    ev = list(csv.DictReader(open(f"{out}/{c}/evaluations.csv")))
    infeasible = sum(r["feasible"] == "false" for r in ev)
    print(f"- {c}: {statistics.mean(f):.4f} (from {min(f):.4f} to {max(f):.4f}); {len(ev)} evaluations, {infeasible} infeasible (rejected unevaluated)")
PY
