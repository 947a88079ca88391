#!/usr/bin/env bash
# Pinocchio anchor timing on TALOS (talos_reduced.urdf, free-flyer root, nv = 38).
# Builds/reuses the anchor harnesses (../shared/tools/anchors/setup.sh, beside this repository),
# then times Pinocchio's algorithms with one thread. Extra arguments are ignored.
# Usage (from anywhere): bash tools/anchors/run_pin_bench.sh
set -euo pipefail
cd "$(dirname "$0")/../.."   # repository root
A=$(bash ../shared/tools/anchors/setup.sh | tail -n 1)
OMP_NUM_THREADS=1 exec "$A/bin/pin_bench" "$PWD/robots/talos_data/robots/talos_reduced.urdf"
