#!/usr/bin/env python3
"""OCCT's sample shapes (Debian's `occt-misc`: /usr/share/opencascade/data/occ/*.brep) written
as STEP by OpenCASCADE's own writer, for measuring the tracer on parts it was not written for
(`scripts/corpus_seams.py run BIN OUT 1 OUTDIR`). Only shapes with at least one solid and at
most 400 faces are written, as `occ_<name>.step`.

    .venv-ocp/bin/python scripts/ocp/occt_samples_to_step.py OUTDIR [SRCDIR]
"""
import glob
import os
import sys

from OCP.BRep import BRep_Builder
from OCP.BRepTools import BRepTools
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.TopAbs import TopAbs_FACE, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS_Shape

MAX_FACES = 400


def count(shape, kind):
    n, e = 0, TopExp_Explorer(shape, kind)
    while e.More():
        n += 1
        e.Next()
    return n


def main(argv):
    if not argv:
        sys.exit(__doc__)
    out = argv[0]
    src = argv[1] if len(argv) > 1 else "/usr/share/opencascade/data/occ"
    os.makedirs(out, exist_ok=True)
    for path in sorted(glob.glob(os.path.join(src, "*.brep"))):
        shape = TopoDS_Shape()
        if not BRepTools.Read_s(shape, path, BRep_Builder()):
            print(f"{path}: not read", file=sys.stderr)
            continue
        solids, faces = count(shape, TopAbs_SOLID), count(shape, TopAbs_FACE)
        name = os.path.basename(path)[:-len(".brep")]
        if solids == 0 or faces > MAX_FACES:
            print(f"{name}: {solids} solids, {faces} faces: skipped")
            continue
        writer = STEPControl_Writer()
        writer.Transfer(shape, STEPControl_AsIs)
        target = os.path.join(out, f"occ_{name}.step")
        if writer.Write(target) != IFSelect_RetDone:
            sys.exit(f"{target}: not written")
        print(f"{name}: {solids} solids, {faces} faces -> {target}")


if __name__ == "__main__":
    main(sys.argv[1:])
