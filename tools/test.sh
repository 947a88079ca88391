#!/usr/bin/env bash
# Every test: the Rust workspace's (`cargo test --workspace`, built optimized), then the Python
# package's (pytest in a venv under target/, made and filled by python/setup_venv.sh; they
# compare corps with Pinocchio and `corps.run` with the `corps` command the Rust tests built),
# then the command's own at a terminal (pytest drives it in a pseudo-terminal).
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== cargo test --workspace"
cargo test --workspace
echo "== Python package (python/): pip install ./python, pytest"
bash python/setup_venv.sh target/py-venv
CORPS_BIN="$PWD/target/debug/corps" target/py-venv/bin/python -m pytest python/tests -q
echo "== the command at a terminal (tools/terminal_tests: corps teleop in a pseudo-terminal)"
CORPS_BIN="$PWD/target/debug/corps" target/py-venv/bin/python -m pytest tools/terminal_tests -q
