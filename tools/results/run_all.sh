#!/usr/bin/env bash
# Runs every controller and walking scenario with `corps run` and writes RESULTS.md: each run's
# metrics table (with the documents' figures beside ours where the scenario gives them).
# Usage (from anywhere): bash tools/results/run_all.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q -p corps
out=$(mktemp -d)
{
  echo "# Results: corps runs beside the documents"
  echo
  echo "Every scenario of \`scenarios/control/\` and \`scenarios/walk/\`, run by"
  echo "\`bash tools/results/run_all.sh\` ($(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD))."
  echo "Errors in mm (average / standard deviation / peak per axis); where a scenario carries the"
  echo "documents' figures they stand in the right-hand columns. Controller times are wall-clock"
  echo "on the shared 2-core VM, not benchmarks (see BENCHMARKS.md)."
  for f in scenarios/walk/*.toml scenarios/control/*.toml; do
    name=$(basename "$f" .toml)
    echo
    echo "## $name"
    echo
    echo '```text'
    if ! ./target/release/corps run "$f" -o "$out/$name" 2>&1 | grep -v -E "^  (wrote|  )"; then
      echo "(the run stopped with an error)"
    fi
    echo '```'
    if grep -q '^\[thesis\]' "$f"; then
      echo
      echo "The same run with the simulator's exact state instead of the estimator (\`--estimator ground-truth\`):"
      echo
      echo '```text'
      ./target/release/corps run "$f" -o "$out/$name.truth" --estimator ground-truth 2>&1 \
        | grep -E "^  (error|CoM|ZMP|left foot  |right foot  |cost|short|state)" || echo "(the run stopped with an error)"
      echo '```'
    fi
  done
  echo
  echo "## Where corps falls short of the documents"
  echo
  echo 'Every figure above where corps, with its estimator, is worse than the document'"'"'s (the'
  echo '`short of the thesis` lines), then the measured causes (`tools/results/shortfall_causes.md`).'
  echo
  for f in scenarios/walk/*.toml scenarios/control/*.toml; do
    name=$(basename "$f" .toml)
    grep "short of the thesis" "$out/$name/metrics.txt" 2>/dev/null | sed "s/^  short of the thesis: /- $name: /" || true
  done
  echo
  cat tools/results/shortfall_causes.md
  cat tools/results/bad_input.md
} > RESULTS.md.partial
mv RESULTS.md.partial RESULTS.md
rm -rf "$out"
echo "wrote RESULTS.md"
