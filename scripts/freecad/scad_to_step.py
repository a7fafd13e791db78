#!/usr/bin/python3
"""OpenSCAD-made reference solids: scripts/openscad/<name>.scad -> <name>.step.

Run with Debian's python (NOT freecadcmd, NOT the pyenv python):

    /usr/bin/python3 scripts/freecad/scad_to_step.py [OUTDIR] [--meta METADIR] [--only a,b]

Route (OpenSCAD cannot write STEP): `openscad -o /abs/path/x.csg x.scad` (headless), then
FreeCAD's OpenSCAD importer importCSG.open(x.csg), keep only the solids of the root objects
(rotate_extrude leaves a stray 2D profile object), check them and export AP214 STEP, with the
same checks as make_samples.py (validity, exact volume and bbox, hand-written edge / vertex
kinds cross-checked from face normals).

Only cube / sphere / cylinder with the default $fn, booleans, multmatrix and rotate_extrude are
used: they come out as exact B-rep. hull() / minkowski() (triangle meshes) and $fn <= 16
(polygonal prisms) are avoided.
"""

import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import samplelib as L  # noqa: E402
from samplelib import FreeCAD, Part  # noqa: E402

MADE_BY = "scripts/freecad/scad_to_step.py"
SCAD_DIR = os.path.join(os.path.dirname(L.HERE), "openscad")
OPENSCAD = "/usr/bin/openscad"
PI = math.pi

SAMPLES = [
    dict(name="scad_difference",
         description="OpenSCAD difference(): cube [0,40]x[0,40]x[0,20] minus a cylinder r=10 "
                     "on the axis x=y=20 (a through hole); scripts/openscad/scad_difference.scad.",
         # block: 12 convex edges; the hole's top and bottom circles meet the planes at 90 deg
         # (material outside the hole) -> convex; the hole's seam line -> smooth.
         # 8 corners convex; the 2 seam vertices (closed circle, 2 convex ends + smooth seam)
         # -> crease.
         edge_kinds={"convex": 14, "reflex": 0, "smooth": 1},
         vertex_kinds={"convex": 8, "reflex": 0, "mixed": 0, "crease": 2, "smooth": 0},
         volume=40 * 40 * 20 - PI * 10 ** 2 * 20, bbox=[[0, 0, 0], [40, 40, 20]]),
    dict(name="scad_union",
         description="OpenSCAD union(): cube [0,40]x[0,40]x[0,20] and a sphere r=10 centred on "
                     "the top face at (20,20,20), i.e. a block with a hemispherical dome; "
                     "scripts/openscad/scad_union.scad.",
         # block: 12 convex edges; the dome's foot circle (z=20, r=10): the top plane meets the
         # vertical sphere tangent at 270 deg through the material -> reflex; the sphere's seam
         # (half meridian, foot circle to pole) -> smooth (OCCT's degenerate pole edge is not
         # an edge of the file). Vertices: 8 convex corners; the seam vertex on the foot circle
         # (2 reflex ends of the closed circle + smooth seam) -> crease; the pole (only the
         # seam) -> smooth.
         edge_kinds={"convex": 12, "reflex": 1, "smooth": 1},
         vertex_kinds={"convex": 8, "reflex": 0, "mixed": 0, "crease": 1, "smooth": 1},
         volume=40 * 40 * 20 + 2.0 / 3.0 * PI * 10 ** 3, bbox=[[0, 0, 0], [40, 40, 30]]),
    dict(name="scad_rotate_extrude",
         description="OpenSCAD rotate_extrude() of the rectangle x in [15,25], y in [0,8] about "
                     "z: a ring (washer) with inner radius 15, outer radius 25, z in [0,8]; "
                     "scripts/openscad/scad_rotate_extrude.scad.",
         # faces: outer and inner cylinders, two planar annuli. 4 circles where an annulus
         # meets a cylinder at 90 deg (material inside the ring) -> convex; each cylinder has
         # a seam line -> 2 smooth. 4 vertices (the rectangle's corners): each on one closed
         # circle (2 convex ends) and one seam -> crease.
         edge_kinds={"convex": 4, "reflex": 0, "smooth": 2},
         vertex_kinds={"convex": 0, "reflex": 0, "mixed": 0, "crease": 4, "smooth": 0},
         volume=PI * (25 ** 2 - 15 ** 2) * 8, bbox=[[-25, -25, 0], [25, 25, 8]],
         mat={"seams": 2, "junctions": [],
              "seam_circles": [{"centre": [0.0, 0.0, 4.0], "radius": 19.0, "ball_radius": 4.0},
                               {"centre": [0.0, 0.0, 4.0], "radius": 21.0, "ball_radius": 4.0}],
              "note": "A solid of revolution: the nearest point of any surface of revolution "
                      "lies in the point's meridian half-plane, so the medial surface is the "
                      "revolution of the 10x8 rectangle's 2D medial axis: its middle segment "
                      "r in [19,21], z=4 (radius 4) sweeps a flat annulus, its 4 corner "
                      "bisectors sweep cone sheets. Seams: the 2 circles r=19 and r=21 at z=4 "
                      "(nearest: top, bottom and the inner resp. outer cylinder), ball "
                      "radius 4. No junction points."}),
]


def scad_to_solids(name, workdir):
    import importCSG  # FreeCAD's OpenSCAD importer (needs add_openscad_paths())
    scad = os.path.join(SCAD_DIR, name + ".scad")
    # TRAP: OpenSCAD 2021.01 resolves a relative -o path against the .scad file's folder
    # and still exits 0; always pass an absolute output path and check that it exists.
    csg = os.path.abspath(os.path.join(workdir, name + ".csg"))
    r = subprocess.run([OPENSCAD, "-o", csg, scad], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0 or not os.path.exists(csg):
        raise L.SampleError(f"{name}: openscad failed:\n{r.stdout}")
    before = set(FreeCAD.listDocuments())
    importCSG.open(csg)
    new = [d for d in FreeCAD.listDocuments() if d not in before]
    doc = FreeCAD.getDocument(new[0]) if new else FreeCAD.ActiveDocument
    doc.recompute()
    roots = [o for o in doc.Objects if not o.InList and hasattr(o, "Shape")]
    solids = [s.copy() for o in roots for s in o.Shape.Solids]
    FreeCAD.closeDocument(doc.Name)
    if len(solids) == 1:
        return solids[0]
    return Part.makeCompound(solids)


def main():
    args = L.parse_args(sys.argv[1:], "samples")
    L.setup_step_writer()
    L.add_openscad_paths()
    os.makedirs(args.outdir, exist_ok=True)
    only = set(args.only.split(",")) if args.only else None
    with tempfile.TemporaryDirectory(prefix="matrace-scad-") as work:
        for s in SAMPLES:
            if only and s["name"] not in only:
                continue
            s = dict(s, solids=1, expect_text=[], mat=s.get("mat"))
            shape = scad_to_solids(s["name"], work)
            L.export_and_check(s, shape, args.outdir, args.meta, MADE_BY)


if __name__ == "__main__":
    L.run_main(main)
