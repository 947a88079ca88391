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
  done
} > RESULTS.md.partial
mv RESULTS.md.partial RESULTS.md
rm -rf "$out"
echo "wrote RESULTS.md"
