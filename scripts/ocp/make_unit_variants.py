"""box_inch.step and box_metre.step: the box sample written with another length unit.

USES OCP (OpenCASCADE 8 Python bindings), NOT FreeCAD. Run it with the project's OCP venv:

    python3 -m venv .venv-ocp && .venv-ocp/bin/pip install cadquery-ocp-novtk   # once
    .venv-ocp/bin/python scripts/ocp/make_unit_variants.py [OUTDIR] [--meta METADIR]

FreeCAD's exportStep always writes millimetres, so these two files are written with OCCT's
STEPControl_Writer and the static "write.step.unit": the shape is built in mm (OCCT's
session unit) and the writer scales every coordinate into the file's unit. The script then
checks the text: the length unit entity (CONVERSION_BASED_UNIT('INCH', ...) resp.
SI_UNIT($,.METRE.)) and that the box's far corner is written as (60,40,20)/25.4 resp.
(0.06,0.04,0.02); and reads the file back (OCCT converts to mm) to check the bbox.
Edge / vertex kinds are cross-checked from face normals by scripts/freecad/check_samples.py.
"""

import argparse
import json
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import steptext  # noqa: E402

from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox  # noqa: E402
from OCP.IFSelect import IFSelect_RetDone  # noqa: E402
from OCP.Interface import Interface_Static  # noqa: E402
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer  # noqa: E402
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_VERTEX  # noqa: E402
from OCP.TopExp import TopExp  # noqa: E402
from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap  # noqa: E402
from OCP.Bnd import Bnd_Box  # noqa: E402
from OCP.BRepBndLib import BRepBndLib  # noqa: E402

MADE_BY = "scripts/ocp/make_unit_variants.py"


def quiet_occt():
    """Silence OCCT's coloured transfer banners on stdout."""
    from OCP.Message import Message
    messenger = Message.DefaultMessenger_s()
    printers = messenger.Printers()
    for p in list(printers):
        messenger.RemovePrinter(p)

A, B, C = 60.0, 40.0, 20.0  # mm, the same box as samples/box.step

VARIANTS = [
    # (name, value of write.step.unit, manifest unit, size of the unit in mm, expected text)
    ("box_inch", "INCH", "inch", 25.4, r"CONVERSION_BASED_UNIT\s*\(\s*'INCH'"),
    ("box_metre", "M", "m", 1000.0, r"SI_UNIT\s*\(\s*\$\s*,\s*\.METRE\.\s*\)"),
]

# a box: 12 edges between perpendicular planes (90 deg) -> convex; 8 corners with 3 convex
# edge ends -> convex
EDGE_KINDS = {"convex": 12, "reflex": 0, "smooth": 0}
VERTEX_KINDS = {"convex": 8, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0}


def count(shape, kind):
    m = ShapeMap()
    TopExp.MapShapes_s(shape, kind, m)
    return m.Extent()


def cartesian_points_3d(path):
    pts = []
    with open(path, encoding="latin-1") as f:
        text = f.read()
    for _, body in steptext.split_instances(text):
        m = re.match(r"CARTESIAN_POINT\s*\(\s*'[^']*'\s*,\s*\(([^)]*)\)\s*\)", body)
        if m:
            xs = [float(v) for v in m.group(1).split(",")]
            if len(xs) == 3:
                pts.append(xs)
    return text, pts


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir", nargs="?", default="samples")
    ap.add_argument("--meta", default=None)
    ap.add_argument("--only", default=None)
    args = ap.parse_args()
    os.makedirs(args.outdir, exist_ok=True)
    quiet_occt()
    only = set(args.only.split(",")) if args.only else None
    box = BRepPrimAPI_MakeBox(A, B, C).Shape()
    for name, unit, unit_name, mm_per_unit, pattern in VARIANTS:
        if only and name not in only:
            continue
        path = os.path.join(args.outdir, name + ".step")
        # TRAP: the write.step.* statics exist only once the STEP controller is initialised;
        # before the first STEPControl_Writer is made SetCVal_s returns False and is ignored.
        writer = STEPControl_Writer()
        for key, val in (("write.step.schema", "AP214IS"), ("write.step.unit", unit)):
            if not Interface_Static.SetCVal_s(key, val):
                raise SystemExit(f"{name}: could not set {key}={val}")
        if writer.Transfer(box, STEPControl_AsIs) != IFSelect_RetDone or writer.Write(path) != IFSelect_RetDone:
            raise SystemExit(f"{name}: STEP write failed")

        # --- check the text
        text, pts = cartesian_points_3d(path)
        if not re.search(pattern, text):
            raise SystemExit(f"{name}: unit entity /{pattern}/ not found in {path}")
        info = steptext.analyse(path)
        if info["length_unit"] != unit_name:
            raise SystemExit(f"{name}: steptext reads unit {info['length_unit']}, expected {unit_name}")
        far = [max(p[i] for p in pts) for i in range(3)]
        want = [A / mm_per_unit, B / mm_per_unit, C / mm_per_unit]
        if any(abs(f - w) > 1e-9 * max(1.0, abs(w)) for f, w in zip(far, want)):
            raise SystemExit(f"{name}: far corner written as {far}, expected {want} ({unit_name})")

        # --- read back (OCCT converts to mm)
        r = STEPControl_Reader()
        if r.ReadFile(path) != IFSelect_RetDone:
            raise SystemExit(f"{name}: cannot read back")
        r.TransferRoots()
        back = r.OneShape()
        bb = Bnd_Box()
        BRepBndLib.AddOptimal_s(back, bb, False, False)
        lo, hi = bb.CornerMin(), bb.CornerMax()
        got = [[lo.X(), lo.Y(), lo.Z()], [hi.X(), hi.Y(), hi.Z()]]
        exp = [[0.0, 0.0, 0.0], [A, B, C]]
        if any(abs(got[i][j] - exp[i][j]) > 1e-6 for i in range(2) for j in range(3)):
            raise SystemExit(f"{name}: read back bbox {got} mm, expected {exp}")

        meta = {
            "file": name + ".step",
            "made_by": MADE_BY,
            "description": (f"The box sample [0,60]x[0,40]x[0,20] mm written with length unit "
                            f"{unit_name} (OCCT write.step.unit={unit}): coordinates in the file "
                            f"are in {unit_name}, e.g. the far corner is "
                            f"({want[0]:.12g},{want[1]:.12g},{want[2]:.12g})."),
            "length_unit": unit_name,
            "solids": 1,
            "edge_kinds": EDGE_KINDS,
            "vertex_kinds": VERTEX_KINDS,
            "volume": A * B * C,
            "bbox": exp,
            "occt": {"faces": count(box, TopAbs_FACE), "edges": count(box, TopAbs_EDGE),
                     "vertices": count(box, TopAbs_VERTEX)},
            "mat": {"same_as": "box.step",
                    "note": "Same solid as box.step (values in mm): see its medial axis."},
            "expect_text": [],
        }
        if args.meta:
            os.makedirs(args.meta, exist_ok=True)
            with open(os.path.join(args.meta, name + ".json"), "w") as f:
                json.dump(meta, f, indent=1)
        print(f"{name + '.step':32s} faces {info['faces']:3d} edges {info['edges']:3d} "
              f"vertices {info['vertices']:3d}  {info['surfaces']}  unit {unit_name}", flush=True)


if __name__ == "__main__":
    main()
