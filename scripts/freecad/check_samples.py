#!/usr/bin/python3
"""Read every generated STEP file back with FreeCAD and check it against its metadata.

    /usr/bin/python3 scripts/freecad/check_samples.py OUTDIR --meta METADIR

For each METADIR/<name>.json: Part.read(OUTDIR/<name>.step) (OCCT converts inch / metre
files to mm and applies assembly transforms), then check validity, the number of solids,
the bbox (mm), the volume (loosely: FreeCAD's .Volume is imprecise on B-splines; the tight
check is BRepGProp in build_manifest.py) and the hand-written edge / vertex kinds against
the kinds computed from face normals on the shape read back, and the medial-axis junctions
given in "mat" (each point strictly inside, its distance to the boundary equal to the given
radius, and at least 4 faces at that distance when the sample has generic seams). This is
the kind cross-check
for the files not made by FreeCAD (scripts/ocp/make_unit_variants.py), and a round-trip
check for all others.
"""

import glob
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import samplelib as L  # noqa: E402
from samplelib import Part  # noqa: E402


def check_junctions(name, shape, mat, tol=1e-6):
    if not isinstance(mat, dict):
        return 0
    js = mat.get("junctions") or []
    generic = isinstance(mat.get("seams"), int) and mat["seams"] > 0
    for j in js:
        p = Part.Vertex(*j["point"])
        pt = p.Point
        if not shape.isInside(pt, 1e-9, False):
            raise L.SampleError(f"{name}: junction {j['point']} is not inside the solid")
        dists = [f.distToShape(p)[0] for f in shape.Faces]
        d = min(dists)
        if abs(d - j["radius"]) > tol:
            raise L.SampleError(f"{name}: junction {j['point']}: distance to the boundary {d}, "
                                f"manifest radius {j['radius']}")
        near = sum(1 for x in dists if x - d < tol)
        if generic and near < 4:
            raise L.SampleError(f"{name}: junction {j['point']} has only {near} nearest faces")
    return len(js)


def main():
    args = L.parse_args(sys.argv[1:], "samples")
    if not args.meta:
        raise SystemExit("--meta METADIR is required")
    metas = sorted(glob.glob(os.path.join(args.meta, "*.json")))
    if not metas:
        raise SystemExit(f"no metadata in {args.meta}")
    by_file = {}
    for mpath in metas:
        with open(mpath) as f:
            m = json.load(f)
        by_file[m["file"]] = m
    for meta in by_file.values():
        mat = meta["mat"]
        if isinstance(mat, dict) and "same_as" in mat:
            meta["mat"] = by_file[mat["same_as"]]["mat"]
        name = meta["file"][:-len(".step")]
        path = os.path.join(args.outdir, meta["file"])
        shape = Part.read(path)
        L.check_solid(name + " (read back)", shape, meta["solids"])
        L.check_bbox(name + " (read back)", shape, meta["bbox"], tol=1e-5)
        L.check_volume(name + " (read back)", shape, meta["volume"], rel=1e-2)
        step = L.steptext.analyse(path)
        L.check_kinds(name + " (read back)", shape, meta["edge_kinds"], meta["vertex_kinds"], step)
        nj = check_junctions(name + " (read back)", shape, meta["mat"])
        print(f"checked {meta['file']} ({nj} junctions)", flush=True)
    print(f"{len(metas)} files read back and checked")


if __name__ == "__main__":
    L.run_main(main)
