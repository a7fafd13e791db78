#!/usr/bin/python3
"""Regression parts for the distance queries: faces on which the nearest-point search used to
descend into the wrong basin of the distance. A point of such a face, inside its trim, must
be found at distance 0 from the boundary (the test in `src/geom/distance/query.rs` samples
every face of every part here).

Run with Debian's python (not freecadcmd, not the pyenv python):

    /usr/bin/python3 scripts/freecad/make_distance_regressions.py [OUTDIR]   (default samples/distance)

- `coil.step`: a square wire 0.4 mm wide wound 10 turns round a 3 mm radius at a 0.6 mm pitch
  (a rectangle swept along a helix). Its four B-spline faces wind round ten times, a turn
  0.2 mm from the next: the flat flanks' normals hardly turn, their parameter lines do. Cells
  as long as a turn seed the descent on the neighbouring turn (before the fix, half the points
  of the flanks were found 5e-3 to 0.2 mm away).
- `necked_vase.step`: a B-spline profile through (10, 0), (0.3, 2), (0.3, 4), (10, 6), (10, 40)
  (radius, height) revolved about z: a surface of revolution with a neck 0.3 mm from its
  axis. Seen from a point of its flare the nearest cell may lie across the axis, where the
  descent stops in another basin (before the fix, 74 of 576 points of the face were found up to
  26 mm away; OCCT's Bottom sample had such a face).

Each part is built with FreeCAD's Part module, checked (valid, one closed solid), written as
AP214 STEP, and listed in OUTDIR/manifest.json. Deterministic up to the STEP header's
timestamp.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import samplelib as L  # noqa: E402  (sets up FreeCAD's sys.path)
from samplelib import Part, V  # noqa: E402


MADE_BY = "scripts/freecad/make_distance_regressions.py"


def coil():
    helix = Part.makeHelix(0.6, 6.0, 3.0)
    square = Part.makePolygon([V(2.8, 0, -0.2), V(3.2, 0, -0.2), V(3.2, 0, 0.2),
                               V(2.8, 0, 0.2), V(2.8, 0, -0.2)])
    return Part.Wire(helix).makePipeShell([square], True, True)


def necked_vase():
    pts = [V(10, 0, 0), V(0.3, 0, 2), V(0.3, 0, 4), V(10, 0, 6), V(10, 0, 40)]
    profile = Part.BSplineCurve()
    profile.interpolate(pts)
    wire = Part.Wire([profile.toShape(), Part.LineSegment(pts[-1], V(0, 0, 40)).toShape(),
                      Part.LineSegment(V(0, 0, 40), V(0, 0, 0)).toShape(),
                      Part.LineSegment(V(0, 0, 0), pts[0]).toShape()])
    return Part.Face(wire).revolve(V(0, 0, 0), V(0, 0, 1), 360)


PARTS = [
    ("coil", coil, "A square wire 0.4 mm wide wound 10 turns round a 3 mm radius at a 0.6 mm "
     "pitch: four B-spline faces that wind round ten times, each turn 0.2 mm from the next."),
    ("necked_vase", necked_vase, "A B-spline profile through (r, z) = (10, 0), (0.3, 2), "
     "(0.3, 4), (10, 6), (10, 40) revolved about z: a surface of revolution with a neck "
     "0.3 mm from its axis, and its two end discs."),
]


def main():
    args = L.parse_args(sys.argv[1:], os.path.join(L.SCRIPTS, "..", "samples", "distance"))
    out = os.path.abspath(args.outdir)
    os.makedirs(out, exist_ok=True)
    L.setup_step_writer()
    manifest = []
    for name, build, description in PARTS:
        shape = build()
        L.check_solid(name, shape, 1)
        solid = shape.Solids[0]
        manifest.append(L.write_regression_part(out, name, solid, MADE_BY, description))
    L.write_manifest(out, MADE_BY, manifest)


if __name__ == "__main__":
    L.run_main(main)
