#!/usr/bin/env bash
# Installs what the tests need beyond Rust, where it is missing:
#   - Debian's FreeCAD (Python modules) and OpenSCAD: apt-get, as root or through sudo;
#   - the venv .venv-ocp with OpenCASCADE's Python bindings (pip: cadquery-ocp-novtk).
# Does nothing for what is there already; exits non-zero naming what it could not install.
#
#   scripts/setup_tools.sh
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export DEBIAN_FRONTEND=noninteractive

if [ ! -e /usr/lib/freecad-python3/lib/FreeCAD.so ] || [ ! -x /usr/bin/openscad ]; then
    echo "== installing FreeCAD and OpenSCAD (Debian packages, about 75 s and 1.3 GB)" >&2
    if [ "$(id -u)" -eq 0 ]; then
        SUDO=()
    elif command -v sudo >/dev/null; then
        SUDO=(sudo)
    else
        echo "setup_tools.sh: FreeCAD/OpenSCAD missing and not root: run as root" \
            "apt-get install -y --no-install-recommends freecad-python3 openscad" >&2
        exit 1
    fi
    "${SUDO[@]}" apt-get update -qq
    "${SUDO[@]}" apt-get install -y -qq --no-install-recommends freecad-python3 openscad >/dev/null
fi

VENV="$ROOT/.venv-ocp"
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import OCP" 2>/dev/null; then
    echo "== creating $VENV (cadquery-ocp-novtk, about 400 MB)" >&2
    python3 -m venv "$VENV"
    # Pinned: the cross-check's expected failures count what this OCCT finds.
    "$VENV/bin/pip" install -q "cadquery-ocp-novtk==8.0.1.1.0"
    "$VENV/bin/python" -c "import OCP"
fi
