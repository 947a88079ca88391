#!/usr/bin/env bash
# TSID 1.10 anchor timing on TALOS (talos_reduced.urdf, free-flyer, two 6D contacts, CoM
# sinusoid, posture, angular momentum, actuation bounds; 62 variables, 18 equalities, 66
# inequalities), one OpenMP thread, with the problem-data / eiquadprog split.
# Builds or reuses the anchor harness (../shared/tools/anchors/setup.sh beside this repository).
# Usage (from anywhere): bash tools/bench/run_tsid_bench.sh
set -euo pipefail
cd "$(dirname "$0")/../.."   # repository root
A=$(bash ../shared/tools/anchors/setup.sh | tail -n 1)
R=robots/talos_data
OMP_NUM_THREADS=1 TSID_BENCH_SPLIT=1 exec "$A/bin/tsid_bench" "$PWD/$R/robots/talos_reduced.urdf" "$PWD/$R/srdf/talos.srdf" fast double
