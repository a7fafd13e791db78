"""samples/iges/*.soup.igs: STEP samples written as IGES by FreeCAD's exportIges.

Run with Debian's python (see scripts/README.md):

    /usr/bin/python3 scripts/freecad/make_iges.py [OUTDIR] [--from STEPDIR] [--only a,b]

FreeCAD 0.20 writes a trimmed-surface "soup": one 144 trimmed surface per face, bounded by
142 curves on surface (3D curves, mostly 102 composites of 110 / 100 / 126), on 128 / 108 /
120 surfaces, with no topology: a reader has to sew the faces into a closed shell. The script
checks the shape is valid before writing and reads the file back with FreeCAD (Part.read)
to check the face count and the bounding box.
"""

import argparse
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402,F401
import Part  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

SAMPLES = ["box", "l_bracket", "cylinder", "plate_with_holes", "filleted_box", "box_nurbs",
           "tetrahedron", "sphere", "torus", "elliptic_cylinder", "box_with_void", "moved_part",
           "scad_difference", "scad_union", "l_bracket_concave_fillet"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir", nargs="?", default=os.path.join(ROOT, "samples", "iges"))
    ap.add_argument("--only", default="", help="comma-separated sample names")
    ap.add_argument("--from", dest="src", default=os.path.join(ROOT, "samples"),
                    help="folder of the STEP samples (default: samples/)")
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    names = a.only.split(",") if a.only else SAMPLES
    for name in names:
        shape = Part.read(os.path.join(a.src, name + ".step"))
        if not shape.isValid():
            sys.exit(f"{name}: STEP sample is not a valid shape")
        out = os.path.join(a.outdir, name + ".soup.igs")
        shape.exportIges(out)
        back = Part.read(out)
        if len(back.Faces) != len(shape.Faces):
            sys.exit(f"{name}: {len(back.Faces)} faces after IGES, {len(shape.Faces)} before")
        box = lambda s: s.optimalBoundingBox()  # noqa: E731 (exact, not FreeCAD's BoundBox)
        b0, b1 = box(shape), box(back)
        d = max(abs(getattr(b1, k) - getattr(b0, k))
                for k in ("XMin", "YMin", "ZMin", "XMax", "YMax", "ZMax"))
        if d > 1e-3 * b0.DiagonalLength:
            sys.exit(f"{name}: bbox moved by {d} mm")
        print(f"{out}: {len(shape.Faces)} faces")


if __name__ == "__main__":
    main()
