"""samples/iges/*.brep.igs: STEP samples written as IGES B-rep (entity 186) by OpenCASCADE.

USES OCP (OpenCASCADE 8 Python bindings), NOT FreeCAD. Run it with the project's OCP venv:

    .venv-ocp/bin/python scripts/ocp/make_iges.py [OUTDIR] [--from STEPDIR] [--only a,b]

Each sample's STEP file is read with STEPControl_Reader (OCCT converts to mm) and written with
IGESControl_Writer("MM", 1): B-rep mode, so the file holds 186 manifold solid B-rep objects
with 514 shells, 510 faces, 508 loops, 504 edge lists and 502 vertex lists. The script then
reads the IGES back with IGESControl_Reader and checks that the face / edge / vertex counts
and the bounding box agree with the STEP original.
"""

import argparse
import os
import sys

from OCP.BRepBndLib import BRepBndLib
from OCP.Bnd import Bnd_Box
from OCP.IFSelect import IFSelect_RetDone
from OCP.IGESControl import IGESControl_Reader, IGESControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_VERTEX
from OCP.TopExp import TopExp
from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# The samples converted (a representative set: planar, analytic curved, NURBS, holes, fillets).
SAMPLES = ["box", "l_bracket", "cylinder", "plate_with_holes", "filleted_box", "box_nurbs",
           "tetrahedron", "sphere", "torus", "elliptic_cylinder", "box_with_void", "moved_part",
           "scad_difference", "scad_union", "l_bracket_concave_fillet"]


def quiet_occt():
    from OCP.Message import Message
    messenger = Message.DefaultMessenger_s()
    for p in list(messenger.Printers()):
        messenger.RemovePrinter(p)


def counts(shape):
    out = []
    for kind in (TopAbs_FACE, TopAbs_EDGE, TopAbs_VERTEX):
        m = ShapeMap()
        TopExp.MapShapes_s(shape, kind, m)
        out.append(m.Size())
    return out


def bbox(shape):
    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False, False)
    return (b.CornerMin().X(), b.CornerMin().Y(), b.CornerMin().Z(),
            b.CornerMax().X(), b.CornerMax().Y(), b.CornerMax().Z())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir", nargs="?", default=os.path.join(ROOT, "samples", "iges"))
    ap.add_argument("--only", default="", help="comma-separated sample names")
    ap.add_argument("--from", dest="src", default=os.path.join(ROOT, "samples"),
                    help="folder of the STEP samples (default: samples/)")
    a = ap.parse_args()
    quiet_occt()
    os.makedirs(a.outdir, exist_ok=True)
    names = a.only.split(",") if a.only else SAMPLES
    for name in names:
        r = STEPControl_Reader()
        if r.ReadFile(os.path.join(a.src, name + ".step")) != IFSelect_RetDone:
            sys.exit(f"{name}: cannot read the STEP sample")
        r.TransferRoots()
        shape = r.OneShape()
        Interface_Static.SetIVal_s("write.iges.brep.mode", 1)
        w = IGESControl_Writer("MM", 1)
        w.AddShape(shape)
        w.ComputeModel()
        out = os.path.join(a.outdir, name + ".brep.igs")
        if not w.Write(out):
            sys.exit(f"{name}: IGES writer failed")
        back = IGESControl_Reader()
        if back.ReadFile(out) != IFSelect_RetDone:
            sys.exit(f"{name}: cannot read the IGES back")
        back.TransferRoots()
        again = back.OneShape()
        if counts(again) != counts(shape):
            sys.exit(f"{name}: counts {counts(again)} after IGES, {counts(shape)} before")
        b0 = bbox(shape)
        diag = sum((b0[k + 3] - b0[k]) ** 2 for k in range(3)) ** 0.5
        d = max(abs(x - y) for x, y in zip(bbox(again), b0))
        # OCCT's optimal box of a B-spline face is itself only close (about 1e-3 of the size).
        if d > 1e-3 * diag:
            sys.exit(f"{name}: bbox moved by {d} mm")
        print(f"{out}: faces/edges/vertices {counts(shape)}")


if __name__ == "__main__":
    main()
