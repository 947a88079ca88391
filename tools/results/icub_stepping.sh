#!/usr/bin/env bash
# The RESULTS.md section of iCub stepping in place (seed 001 S2): the full 720 s run through
# the estimator, the same with the simulator's exact state, and the posture weight of Eq B.3
# at the QP's w_s for comparison. Usage: bash tools/results/icub_stepping.sh [CORPS]
set -euo pipefail
cd "$(dirname "$0")/../.."
corps=${1:-./target/release/corps}
out=$(mktemp -d)
scenario=scenarios/icub/fsm2_stepping.toml
cat tools/results/icub_stepping.md
echo '```text'
"$corps" run "$scenario" --duration 720 -o "$out/full" 2>&1 | grep -v -E "^  (wrote|  )|^corps: +[0-9]+% \(t = " || echo "(the run stopped with an error)"
echo '```'
echo
echo "The same 720 s with the simulator's exact state (\`--estimator ground-truth\`):"
echo
echo '```text'
"$corps" run "$scenario" --duration 720 -o "$out/truth" --estimator ground-truth 2>&1 \
  | grep -E "^  (error|CoM|left foot  |right foot  |strides|CoM error|feet error|contact-force|stride|state|verdict)" || echo "(the run stopped with an error)"
echo '```'
echo
echo "60 s with Eq B.3's posture weight at the QP's w_s = 1e-3 instead of 1e-6 (\`controller.set\`):"
echo
sed 's/^settle = 0.5/settle = 0.5\nset = { posture_consistency = { base_gain = 1.0, weight = 1e-3 } }/' "$scenario" > "$out/b3.toml"
echo '```text'
"$corps" run "$out/b3.toml" --duration 60 -o "$out/b3" 2>&1 \
  | grep -E "^  (error|CoM  |strides|CoM error . .*peak|feet error|stride|state|verdict)" || echo "(the run stopped with an error)"
echo '```'
echo
echo "The backpacked iCub (\`--robot icub_backpacked\`: \`robots/icub_description/icub_backpacked.toml\`,"
echo "a 1.8 kg pack on the chest, our assumption), same gains and state machine, 720 s:"
echo
echo '```text'
"$corps" run "$scenario" --duration 720 --robot icub_backpacked -o "$out/backpacked" 2>&1 \
  | grep -E "^  (error|CoM  |strides|CoM error . .*peak|feet error|contact-force error outside switching, peak|stride|state|verdict)" || echo "(the run stopped with an error)"
echo '```'
cat <<'TEXT'

With the pack the hand-tuned weights step 10 times and then fall (80.9 s): moving the CoM over
the right foot at 78 s it overshoots the reference by 8 mm, the stance sole rolls onto its
outer edge and the robot tips over it. The thesis's hand-tuned start point w0 also fails on its
backpacked model, there under randomized conditions (seed 001 L6703–L6741, S10); this run has
none.

### Shortfalls (S2)

- **CoM height**: the CoM's vertical error peaks at 12.5–13.3 mm (thesis: CoM error < 0.01 m).
  It dips as the CoM moves 10.5 cm over a foot: the legs tilt (at constant leg length the
  geometry alone lowers it by about 12 mm) and the QP's torque cost w_τ‖τ‖² (1e-4) against the
  CoM's soft PD (P = 5) leaves the dip. Stiffer CoM gains (P = 50) or a lighter torque cost
  (1e-6), tried, made the 60 s run fall.
- **CoM y through the estimator, 720 s**: peak 15.3 mm (4.9 mm on the exact state, 7.0 mm in
  the test's first 60 s). At t = 399 s the swing foot was still 0.5–0.8 mm above the ground
  when `two_feet_swap` sent the CoM back; the stance sole lifted 0.5 mm at its edge and the CoM
  ran up to 15 mm ahead of its reference until the touch-down 0.3 s later (a 519 N impact).
- **The true CoM drifts with the estimate**: the errors above compare the estimator's CoM with
  the references, as a robot's log does; against the simulator's CoM the x error grows with the
  leg odometry's drift (8.4 mm on average over 720 s, 16.7 mm peak).
- **Force error at switching**: up to 469 N in the tick a contact appears or goes (the thesis
  bounds it by half the robot's weight, 139 N, for controller #1): the contact is added or
  removed at once, as in the thesis, and the measured force jumps.
- **Speed** (Deliver 6): the tick takes 2.7× TALOS' TSID torque tick (goal ≤ 0.7×;
  BENCHMARKS.md).
- Not built: controllers (a) strict-tasks and (b) soft-tasks #1, FSM #1 and S1, S7.
TEXT
rm -rf "$out"
