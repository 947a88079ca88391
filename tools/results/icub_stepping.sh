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
echo "The strict-tasks controller (Eq 2.40: \`strict = true\`, the CoM, neck and swing-foot tasks and the"
echo "feet in contact as equalities) on the same state machine, 60 s (seed 001 S3 gives no numbers:"
echo "\"too stiff, bad for stability\", L2245–L2257):"
echo
sed 's/^settle = 0.5/settle = 0.5\nset = { strict = true }/' "$scenario" > "$out/strict.toml"
echo '```text'
"$corps" run "$out/strict.toml" --duration 60 -o "$out/strict" 2>&1 \
  | grep -E "^  (CoM  |strides|safe|verdict)" || echo "(the run stopped with an error)"
echo '```'
echo
echo "Controller #2 with controller #1's torque bounds (Table A.3: \`torque_rate = 50\` N·m/s, so 0.5 N·m"
echo "per 10 ms tick, and \`torque_limit = 60\` N·m), 60 s:"
echo
sed 's/^settle = 0.5/settle = 0.5\nset = { torque_rate = 50.0, torque_limit = 60.0 }/' "$scenario" > "$out/rate.toml"
echo '```text'
"$corps" run "$out/rate.toml" --duration 60 -o "$out/rate" 2>&1 \
  | grep -E "^  (CoM  |strides|safe|verdict)" || echo "(the run stopped with an error)"
echo '```'
echo
echo "The backpacked iCub (\`--robot icub_backpacked\`: \`robots/icub_description/icub_backpacked.toml\`,"
echo "a 1.8 kg pack on the chest, our assumption), same gains and state machine, 720 s:"
echo
echo '```text'
"$corps" run "$scenario" --duration 720 --robot icub_backpacked -o "$out/backpacked" 2>&1 \
  | grep -E "^  (error|CoM  |strides|CoM error . .*peak|feet error|contact-force error outside switching, peak|stride|state|verdict)" || echo "(the run stopped with an error)"
echo '```'
echo
echo "S7 (seed 001 §3.3, L4305–L4488): the same stepping with the right elbow's posture reference at"
echo "22.5° (its limit 15°, Table 3.1) and the right hand pushed as Table 3.2 says"
echo "(\`scenarios/icub/s7_elbow_{classical,reparametrised}.toml\`; Eq 3.27 on the elbow, ξ clamped at"
echo "atanh(0.99)):"
echo
for law in classical reparametrised; do
  echo "$law:"
  echo
  echo '```text'
  "$corps" run "scenarios/icub/s7_elbow_$law.toml" -o "$out/s7_$law" 2>&1 \
    | grep -E "^  (smallest|safe|verdict)" || echo "(the run stopped with an error)"
  echo '```'
  echo
done
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
- **S7: the robot falls under the first push, under both laws** (thesis: recovers from each,
  5 s apart). The elbow claim holds: the classical PD takes the elbow 19.9° past its limit
  within 0.4 s of the 15 N forward push (the hand's force bends it), the re-parametrised law
  keeps it 0.39° inside. But the push comes while the robot stands on one foot, its CoM runs
  forward, the stance sole tips onto its toe at 5.3 s and the run diverges at 6.3 s. The same
  15 N in double support (a push at 1 s, tried) also topples it, 0.9 s into the push. The arm
  yields to the push (the classical elbow ends 85° past its limit): the posture's weight
  (w_s = 1e-3, its PD in the tasks' null space) counts for less than the torque that would hold
  the arm (w_τ = 1e-4; 15 N at the hand some 0.3 m from the shoulder is about 5 N·m, our
  estimate), so the QP lets the arm go, and the swinging arm adds to the push.
- **Joint limits in the simulator**: corps-sim does not enforce joint limits. During the
  stepping the right hip roll reaches 31°, 13.9° past the URDF's 17° (seed 001 Table 3.1 gives
  hip roll [−12°, 80°] in its own conventions).
- **Strict tasks** (S3): the QP turns infeasible at 14.7 s and the run diverges at 28.8 s (the
  thesis shows no results, "too stiff").
- **The torque-rate bound with held joints**: under 0.5 N·m per tick the QP is infeasible from
  the first contact release (4.47 s) and the robot falls: the held joints' acceleration
  equalities need torque jumps the bound forbids. Seed 001's controller #1 had no held joints
  (23 DOF); corps' iCub keeps 32.
- Not built: controller #1's configuration (Tables A.2–A.7) and FSM #1 (11 states), so S1 is not
  run; the rate bound and the strict formulation it needs are.
TEXT
rm -rf "$out"
