#!/usr/bin/env bash
# RESULTS.md's section on walking with a person: the prose (conav.md), every shared walk in
# every mode at a quarter of the person's pace and at their own pace (conav.py), the findings
# (conav_findings.md). Usage (from the repository root): bash tools/results/conav.sh [CORPS]
set -euo pipefail
cd "$(dirname "$0")/../.."
corps=${1:-./target/release/corps}
cat tools/results/conav.md
echo
python3 tools/results/conav.py --corps "$corps" --rate 0.25
cat tools/results/conav_findings.md
echo
echo "At the person's own pace (\`rate = 1\`), the first ten walks in file order (30 runs):"
echo
python3 tools/results/conav.py --corps "$corps" --rate 1.0 --limit 10
