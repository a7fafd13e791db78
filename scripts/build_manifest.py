"""Write OUTDIR/manifest.json from the STEP files and the generators' metadata.

USES OCP (OpenCASCADE 8 Python bindings): run it with the project's OCP venv,

    .venv-ocp/bin/python scripts/build_manifest.py OUTDIR --meta METADIR

(scripts/make_samples.sh does this). Per sample:
  * faces / edges / vertices / solids / shells / surfaces / length_unit come from the STEP
    TEXT (scripts/steptext.py: distinct ADVANCED_FACE, EDGE_CURVE, VERTEX_POINT instances;
    MANIFOLD_SOLID_BREP + BREP_WITH_VOIDS; CLOSED_SHELL; the surface entity of each face);
  * edge_kinds / vertex_kinds / mat / description come from the generator (hand-written and
    already cross-checked there), occt = FreeCAD/OCCT's counts on the built shape;
  * volume and bbox are the exact values by construction (mm), cross-checked here against
    the file read back by OCCT 8 (converted to mm): BRepGProp volume with a tight tolerance
    (relative 1e-6) and the optimal bounding box (1e-4 mm). Any disagreement is an error.
"""

import argparse
import copy
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import steptext  # noqa: E402

from OCP.Bnd import Bnd_Box  # noqa: E402
from OCP.BRepBndLib import BRepBndLib  # noqa: E402
from OCP.BRepGProp import BRepGProp  # noqa: E402
from OCP.GProp import GProp_GProps  # noqa: E402
from OCP.IFSelect import IFSelect_RetDone  # noqa: E402
from OCP.STEPControl import STEPControl_Reader  # noqa: E402

SCHEMA = "matrace.samples/1"
NOTES = [
    "faces/edges/vertices: distinct ADVANCED_FACE / EDGE_CURVE / VERTEX_POINT instances in the "
    "STEP text; solids: MANIFOLD_SOLID_BREP + BREP_WITH_VOIDS; shells: CLOSED_SHELL (a void "
    "counts as a shell); totals for multi-solid files.",
    "occt: what FreeCAD/OCCT counts on the built shape (includes degenerate pole edges and the "
    "seams / poles that the STEP writer replaces by a VERTEX_LOOP).",
    "surfaces: the surface entity of each ADVANCED_FACE (bspline = non-rational "
    "B_SPLINE_SURFACE_WITH_KNOTS, nurbs = rational).",
    "edge_kinds: interior dihedral angle < 179 deg convex, > 181 deg reflex, else smooth (a "
    "closed surface's seam is smooth); written by hand, cross-checked from face normals at 9 "
    "points per edge. vertex_kinds: non-smooth incident edge ends (a closed edge counts twice): "
    "0 smooth, 1-2 crease, >=3 all convex -> convex, all reflex -> reflex, else mixed. Kinds "
    "describe the topology of the file, so they sum to edges / vertices.",
    "volume (mm^3) and bbox (mm) are exact by construction, in millimetres for every file "
    "whatever its length_unit; checked against OCCT (BRepGProp, optimal bbox) on the file.",
    "mat: what is known analytically about the medial axis (seams = curves with >= 3 nearest "
    "faces, junctions = points with >= 4 nearest faces, radius = distance to the boundary), "
    "null when nothing simple is known.",
]


def clean(x, nd):
    if isinstance(x, float):
        v = round(x, nd)
        return 0.0 if v == 0 else v
    if isinstance(x, list):
        return [clean(v, nd) for v in x]
    if isinstance(x, dict):
        return {k: clean(v, nd) for k, v in x.items()}
    return x


def order_mat(mat):
    """seams, junctions first, note last (stable, readable key order)."""
    if not isinstance(mat, dict):
        return mat
    keys = ["seams", "junctions"] + [k for k in mat if k not in ("seams", "junctions", "note")] + ["note"]
    return {k: mat[k] for k in keys if k in mat}


def quiet_occt():
    from OCP.Message import Message
    messenger = Message.DefaultMessenger_s()
    for p in list(messenger.Printers()):
        messenger.RemovePrinter(p)


def read_step(path):
    r = STEPControl_Reader()
    if r.ReadFile(path) != IFSelect_RetDone:
        raise SystemExit(f"cannot read {path}")
    r.TransferRoots()
    return r.OneShape()


def occt_volume(shape):
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-9)
    return props.Mass()


def occt_bbox(shape):
    bb = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, bb, False, False)
    lo, hi = bb.CornerMin(), bb.CornerMax()
    return [[lo.X(), lo.Y(), lo.Z()], [hi.X(), hi.Y(), hi.Z()]]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir", nargs="?", default="samples")
    ap.add_argument("--meta", required=True)
    args = ap.parse_args()
    quiet_occt()
    metas = {}
    for mpath in sorted(glob.glob(os.path.join(args.meta, "*.json"))):
        with open(mpath) as f:
            m = json.load(f)
        metas[m["file"]] = m
    on_disk = sorted(os.path.basename(p) for p in glob.glob(os.path.join(args.outdir, "*.step")))
    stray = [f for f in on_disk if f not in metas]
    if stray:
        raise SystemExit(f"STEP files in {args.outdir} that no generator made (delete them): {stray}")
    missing = [f for f in metas if f not in on_disk]
    if missing:
        raise SystemExit(f"generated files missing from {args.outdir}: {missing}")

    errors = []
    samples = []
    for fname in sorted(metas):
        m = metas[fname]
        path = os.path.join(args.outdir, fname)
        t = steptext.analyse(path)
        if t["length_unit"] != m["length_unit"]:
            errors.append(f"{fname}: unit {t['length_unit']} in the file, generator says {m['length_unit']}")
        if t["solids"] != m["solids"]:
            errors.append(f"{fname}: {t['solids']} solids in the file, generator says {m['solids']}")
        if sum(m["edge_kinds"].values()) != t["edges"] or sum(m["vertex_kinds"].values()) != t["vertices"]:
            errors.append(f"{fname}: kinds do not sum to the file's edges / vertices")
        if fname != "box_with_void.step" and t["solids"] == 1 and t["manifold_solid_breps"] != 1:
            errors.append(f"{fname}: expected one MANIFOLD_SOLID_BREP")
        if t["faces"] == 0:
            errors.append(f"{fname}: no ADVANCED_FACE")
        for ent in m.get("expect_text", []):
            if ent not in t["entity_counts"]:
                errors.append(f"{fname}: no {ent} in the text")
        shape = read_step(path)
        vol = occt_volume(shape)
        if abs(vol - m["volume"]) > 1e-6 * abs(m["volume"]):
            errors.append(f"{fname}: BRepGProp volume {vol!r} != exact {m['volume']!r}")
        bb = occt_bbox(shape)
        if any(abs(bb[i][j] - m["bbox"][i][j]) > 1e-4 for i in range(2) for j in range(3)):
            errors.append(f"{fname}: OCCT optimal bbox {bb} != exact {m['bbox']}")
        mat = m["mat"]
        if isinstance(mat, dict) and "same_as" in mat:
            base = copy.deepcopy(metas[mat["same_as"]]["mat"])
            base["note"] = (base.get("note", "") + " " + mat["note"]).strip()
            mat = base
        samples.append({
            "file": fname,
            "made_by": m["made_by"],
            "description": m["description"],
            "length_unit": t["length_unit"],
            "solids": t["solids"],
            "shells": t["shells"],
            "faces": t["faces"],
            "edges": t["edges"],
            "vertices": t["vertices"],
            "surfaces": t["surfaces"],
            "edge_kinds": {k: m["edge_kinds"].get(k, 0) for k in ("convex", "reflex", "smooth")},
            "vertex_kinds": {k: m["vertex_kinds"].get(k, 0)
                             for k in ("convex", "reflex", "mixed", "crease", "smooth")},
            "volume": clean(float(m["volume"]), 6),
            "bbox": clean([[float(v) for v in c] for c in m["bbox"]], 9),
            "occt": {k: m["occt"][k] for k in ("faces", "edges", "vertices")},
            "mat": clean(order_mat(mat), 12),
        })
        print(f"{fname:32s} faces {t['faces']:3d} edges {t['edges']:3d} vertices {t['vertices']:3d}"
              f"  volume {vol:.6f} (exact {m['volume']:.6f})", flush=True)
    if errors:
        for e in errors:
            print("ERROR:", e, file=sys.stderr)
        raise SystemExit(1)
    out = os.path.join(args.outdir, "manifest.json")
    with open(out, "w") as f:
        json.dump({"schema": SCHEMA, "notes": NOTES, "samples": samples}, f, indent=1)
        f.write("\n")
    print(f"wrote {out} ({len(samples)} samples)")


if __name__ == "__main__":
    main()
