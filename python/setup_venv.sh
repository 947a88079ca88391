#!/usr/bin/env bash
# Makes the venv the Python package's tests run in (default target/py-venv) and installs the
# package into it from this checkout: numpy, pytest, pandas, Pinocchio (`pin`, the reference the
# tests check against), MuJoCo (the second plant) and Ray (learning campaigns on a cluster) from
# PyPI, then `pip install ./python` (maturin builds the extension with the `python` profile).
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-target/py-venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
    "$venv/bin/pip" install -q --upgrade pip
fi
"$venv/bin/pip" install -q --no-cache-dir numpy pytest pandas "pin==4.1.0" "mujoco==4.0.0" "ray==2.60.0"
"$venv/bin/pip" install -q --no-cache-dir --force-reinstall --no-deps ./python
