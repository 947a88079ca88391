#!/usr/bin/env bash
# Makes the venv the Python package's tests run in (default target/py-venv) and installs the
# package into it from this checkout: numpy, pytest, pandas and Pinocchio (`pin`, the reference
# the tests check against) from PyPI, then `pip install ./python` (maturin builds the extension
# with the workspace's `python` profile). Re-running it reinstalls the package only.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-target/py-venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
    "$venv/bin/pip" install -q --upgrade pip
    "$venv/bin/pip" install -q numpy pytest pandas "pin==4.1.0"
fi
"$venv/bin/pip" install -q --force-reinstall --no-deps ./python
