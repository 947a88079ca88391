#!/usr/bin/env bash
# RESULTS.md's section on corps-sim against MuJoCo: the prose (crossval.md, with the measured
# causes) and the table `python -m corps crossval` prints, run in the Python package's venv
# (made by python/setup_venv.sh). Usage (from the repository root): bash tools/results/crossval.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -x target/py-venv/bin/python ] || bash python/setup_venv.sh target/py-venv >&2
cat tools/results/crossval.md
echo
target/py-venv/bin/python -m corps crossval --markdown
