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
  echo "Every scenario of \`scenarios/control/\`, \`scenarios/walk/\` and \`scenarios/passive/\`, run by"
  echo "\`bash tools/results/run_all.sh\` ($(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD))."
  echo "Errors in mm (average / standard deviation / peak per axis); where a scenario carries the"
  echo "documents' figures they stand in the right-hand columns. Controller times are wall-clock"
  echo "on the shared 2-core VM, not benchmarks (see BENCHMARKS.md)."
  echo
  echo "Sensing: every run feeds its controller through the estimator (leg odometry + IMU + ankle"
  echo "F/T). The first table of each scenario runs without sensor noise, as the thesis's Gazebo"
  echo "model gave its sensors but for a gyro bias of 8e-7 rad/s (\`scenarios/sensors/talos_gazebo.toml\`,"
  echo "with its sources; that profile changes no printed figure of tsid_torque_20cm): like with"
  echo "like with the thesis's simulated tables. Where the scenario"
  echo "carries the thesis's figures, two more runs follow: on the simulator's exact state"
  echo "(\`--estimator ground-truth\`), and on the real TALOS' sensor noise"
  echo "(\`scenarios/sensors/talos_hardware.toml\`: encoder and joint-velocity levels from seed 000's"
  echo "19-bit encoders; IMU and F/T levels assumed, as that file says)."
  for f in scenarios/walk/*.toml scenarios/control/*.toml scenarios/passive/*.toml; do
    name=$(basename "$f" .toml)
    echo
    echo "## $name"
    echo
    echo '```text'
    if ! ./target/release/corps run "$f" -o "$out/$name" 2>&1 | grep -v -E "^  (wrote|  )|^corps: +[0-9]+% \(t = "; then
      echo "(the run stopped with an error)"
    fi
    echo '```'
    if grep -q '^\[thesis\]' "$f"; then
      echo
      echo "The same run with the simulator's exact state instead of the estimator (\`--estimator ground-truth\`):"
      echo
      echo '```text'
      ./target/release/corps run "$f" -o "$out/$name.truth" --estimator ground-truth 2>&1 \
        | grep -E "^  (error|CoM|ZMP|left foot  |right foot  |while|cost|short|state|verdict)" || echo "(the run stopped with an error)"
      echo '```'
      echo
      echo "With the estimator on TALOS' sensor noise (\`--noise scenarios/sensors/talos_hardware.toml\`):"
      echo
      echo '```text'
      ./target/release/corps run "$f" -o "$out/$name.noise" --noise scenarios/sensors/talos_hardware.toml 2>&1 \
        | grep -E "^  (error|CoM|ZMP|left foot  |right foot  |while|cost|short|state|verdict)" || echo "(the run stopped with an error)"
      echo '```'
    fi
  done
  echo
  echo "## Where corps falls short of the documents"
  echo
  echo 'Every figure above where corps, with its estimator, is worse than the document'"'"'s (the'
  echo '`short of the thesis` lines), then the measured causes (`tools/results/shortfall_causes.md`).'
  echo
  for f in scenarios/walk/*.toml scenarios/control/*.toml scenarios/passive/*.toml; do
    name=$(basename "$f" .toml)
    grep "short of the thesis" "$out/$name/metrics.txt" 2>/dev/null | sed "s/^  short of the thesis: /- $name: /" || true
    if ! grep -q '^expect = ' "$f"; then
      grep -E "^  verdict: (fell|diverged|controller_failed)" "$out/$name/metrics.txt" 2>/dev/null | sed "s/^  verdict: /- $name: /" || true
    fi
  done
  echo
  # The names of the figures short of the thesis in a metrics file (or `-`, stdin).
  figure() { sed -n "s/^  short of the thesis: \(.*\) [-0-9.]*\( mm\)\{0,1\} (thesis .*/\1/p" "$1" | sort; }
  echo "Further, on TALOS' sensor noise only (the \`talos_hardware.toml\` runs):"
  echo
  for f in scenarios/walk/*.toml scenarios/control/*.toml scenarios/passive/*.toml; do
    name=$(basename "$f" .toml)
    [ -f "$out/$name.noise/metrics.txt" ] || continue
    # The figures short with the noise and not without it (matched by name, not value).
    figure "$out/$name/metrics.txt" > "$out/known" || true
    grep "short of the thesis" "$out/$name.noise/metrics.txt" | while IFS= read -r line; do
      name_of=$(printf '%s\n' "$line" | figure -)
      grep -qxF "$name_of" "$out/known" || printf '%s\n' "$line" | sed "s/^  short of the thesis: /- $name: /"
    done || true
    if ! grep -qE "^  verdict: (fell|diverged|controller_failed)" "$out/$name/metrics.txt"; then
      grep -E "^  verdict: (fell|diverged|controller_failed)" "$out/$name.noise/metrics.txt" | sed "s/^  verdict: /- $name: /" || true
    fi
  done
  echo
  cat tools/results/shortfall_causes.md
  cat tools/results/passive.md
  python3 tools/results/passive_robustness.py --corps ./target/release/corps
  bash tools/results/drilling.sh ./target/release/corps
  cat tools/results/human_prediction.md
  bash tools/results/conav.sh ./target/release/corps
  bash tools/results/hip.sh ./target/release/corps
  cat tools/results/cmaes.md
  bash tools/results/learning.sh ./target/release/corps
  bash tools/results/mocap_teleop.sh ./target/release/corps
  bash tools/results/actuators.sh ./target/release/corps
  bash tools/results/icub_stepping.sh ./target/release/corps
  bash tools/results/crossval.sh
  bash tools/results/teleop.sh ./target/release/corps
  cat tools/results/joint_limits.md
  cat tools/results/bad_input.md
} > RESULTS.md.partial
mv RESULTS.md.partial RESULTS.md
rm -rf "$out"
echo "wrote RESULTS.md"
