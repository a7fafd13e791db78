#!/usr/bin/env bash
# The whole test suite on a fresh machine: installs what the tests need
# (scripts/setup_tools.sh: FreeCAD, OpenSCAD, the OpenCASCADE venv), then runs `cargo test`
# with the arguments given (e.g. `scripts/test.sh --test it crosscheck`).
#
#   scripts/test.sh [CARGO TEST ARGS...]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
scripts/setup_tools.sh
exec cargo test "$@"
