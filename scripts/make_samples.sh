#!/usr/bin/env bash
# Regenerate every reference solid and OUTDIR/manifest.json (default OUTDIR: samples/).
#
#   scripts/make_samples.sh [OUTDIR]
#
# Needs: Debian's FreeCAD and OpenSCAD and the OCP venv .venv-ocp, which
# scripts/setup_tools.sh installs (this script installs nothing: it runs inside the tests).
# FreeCAD scripts run with /usr/bin/python3 (not freecadcmd, not the pyenv python).
#
# Steps: FreeCAD Part solids -> OpenSCAD solids (via .csg and FreeCAD's importCSG) -> OCP
# unit variants (inch / metre) -> read everything back with FreeCAD and re-check ->
# manifest (STEP text counts + OCCT volume / bbox cross-check). Any failed check stops it
# with a non-zero status. Deterministic: a rerun gives the same files up to the
# timestamps in the STEP headers, and the same manifest.json.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/samples}"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
FCPY=/usr/bin/python3
VENV="$ROOT/.venv-ocp"

for tool in /usr/lib/freecad-python3/lib/FreeCAD.so /usr/bin/openscad; do
    if [ ! -e "$tool" ]; then
        echo "missing $tool: run scripts/setup_tools.sh" >&2
        exit 1
    fi
done
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import OCP" 2>/dev/null; then
    echo "missing $VENV with OCP: run scripts/setup_tools.sh" >&2
    exit 1
fi

META="$(mktemp -d /tmp/matrace-samples-meta.XXXXXX)"
trap 'rm -rf "$META"' EXIT

# FreeCAD's OpenSCAD importer (ply) prints harmless "WARNING: Token ... defined, but not used"
filter() { grep -v -e "^WARNING: Token '.*' defined, but not used" -e "^WARNING: There are [0-9]* unused tokens" || true; }

start=$(date +%s)
cd "$ROOT"
export PYTHONDONTWRITEBYTECODE=1
"$FCPY" scripts/freecad/make_samples.py "$OUT" --meta "$META"
"$FCPY" scripts/freecad/scad_to_step.py "$OUT" --meta "$META" 2>&1 | filter
"$VENV/bin/python" scripts/ocp/make_unit_variants.py "$OUT" --meta "$META"
"$FCPY" scripts/freecad/check_samples.py "$OUT" --meta "$META" | tail -1
"$VENV/bin/python" scripts/build_manifest.py "$OUT" --meta "$META" | tail -1
echo "done in $(( $(date +%s) - start )) s: $(ls "$OUT"/*.step | wc -l) STEP files in $OUT"
