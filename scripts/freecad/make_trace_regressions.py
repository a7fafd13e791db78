#!/usr/bin/python3
"""Regression parts for the tracer (issue 19): small machined features that lie close
together, each provoking a seam event the tracer must locate and go on from: a fillet
meeting a hole, a thin rib on a plate, a boss near an edge, a slot ending in a round, a
chamfered pocket, a counterbore whose depth equals a channel's half-width, several small
features touching, a boss whose rounded corners end seams at a curved reflex edge, a
spherical shell whose faces reach their poles, a split blind hole whose seams run along the
line between its halves onto its floor's rim, a tapered pocket whose floor rim comes closer
than the junction with its wall, a plate written as NURBS whose hole's seam circles the
wall's parameter seam, a hole inscribed in a square pocket (seams that end at pinches), a
block with a shallow roof (seam points whose touch points the accuracy cannot separate), the
same block with one roof plane moved off its edges (an exporter's gap beyond the accuracy), a
box split into two blocks whose one top plane is moved off its edges (a ball that reaches into
the moved plane by the gap, with no junction there), the shallow roof written as two blocks with
half of one roof plane moved off its edges (a seam in the slight crease whose ball the gap moves
14 times as far where it crosses between the halves), an L-bracket whose reflex edge is a
B-spline bowed off one face (the faces' normals tilted off its normal plane), a
rib whose chamfered end meets its foot fillets tangentially at convex vertices, a blind hole
with a drill point (its apex written two ways), a cube whose corner dips 0.02 mm into a plate,
a thin tube grazing a cube's corner (analytic and as NURBS), a boss whose foot circle grazes the
line of an edge seam's touch points, a plate with two shallow pockets, a pin with a
hemispherical tip (a degenerate curve that ends where its ball is a face's sphere), a block
with a hip roof (seams touched by four faces), a plate with a pocket half as deep as the plate
is thick (a closed seam whose touch point runs along the pocket's foot edges), a pocket over a
thin floor (a face reached by sheet balls only, across its reflex edges), a frustum cut along
its axis (hyperbola edges), a hole whose wall passes 0.01 mm from a face (a seam whose r dips
towards 0 and rises again), a boss lower than it is wide (its foot circle's axis), the same boss near
the plate's side (a foot circle touched by a seam whose axis is still to be found), a thin tube closed
by a hemispherical end (a face too narrow for the seeds' first grid; faces touched only by a
sheet's balls), a flat ring with a bead round each rim whose fillet axis's balls reach the
bottom (a face touched at no listed touch point), a wall whose foot fillets end at its flat end
faces (seams that end at pinches under the cusp vertices there), a block's rounded edge cut
obliquely by a wall (a degenerate curve whose arc of contact shrinks to a vertex), by a
skew wall (the arc shrinks to a point inside the cut's edge), and a rib under a wide block
whose round end's foot arc a large ball's touch point runs round faster than its centre
turns (a step must not land on the arc's far side), and a round bar with a drilled end (the
drill point's apex, reached by the cone's seam edge, is the nearest boundary point of the
axis's balls), and a tapered pin with a drilled end (the pin's axis runs from its cylinder
onto its cone, a degenerate curve handed over at a convex circle), and a frustum (a cone's
axis, whose balls touch it all round along a circle off their centre's plane), and a box
with two edges rounded at one corner, meeting in a mitre (a rim whose faces come to one
tangent plane at its vertex: its sheet ends there along a free edge), and a bar whose rounded
edge ends against a block's wall, square and skew (the rim above the round ends at the vertex
where the round is tangent to the top: a free edge again), and a boss whose top rim ends against a
taller boss's wall (a rim between two reflex edges to one face: a free edge along that face's
normal), and a box with two cavities and a shelf twice as thick as its walls (junctions at the
shelf faces' corners), and the same shelf flush with the back wall (a seam that leaves those
junctions along the shelf faces' edges), and an '8' embossed 3 µm high (a seam round a stroke
whose long step jumps past a kinked join), and an 'O' embossed likewise (a junction at the
outline's kink just before a hand-over across the stroke), and a pin's chamfered seat beside two
shelves (a hyperbola edge's curvature limit just before a hand-over onto a shelf's edge), and
a fin whose tip is a plane and a cylinder folded onto each other (interior angle 0) and the
same sliver cut into a block as a crack (360), each turned so that rounding classified it the
other way, and an IC package body drafted in and out of its parting line with a lead out of its
front (a seam of four contacts, symmetric about the parting line, that splits where it meets the
lead's edge; and, the lead moved under its end, one whose symmetry a hand-over breaks a step
before its junction), and a plate whose side walls are tangent to a boss whose foot is rounded
(a wall and the round meet at a convex edge flattening to a vertex where they are tangent: a
pinch with a skeletal edge) and the same with that edge rounded (a blend tapering to a point
between two faces tangent there: a pinch with none), and a chip body between two caps whose
edges are rounded with the radius they stand out by (seams of four contacts whose touch points
on the body's two edges meet at the corner's vertex on the round's axis, whichever slots the
two edges have).

Run with Debian's python (not freecadcmd, not the pyenv python):

    /usr/bin/python3 scripts/freecad/make_trace_regressions.py [OUTDIR]   (default samples/trace)

Each part is built with FreeCAD's Part module, checked (valid, one closed solid, its exact
volume against OCCT's to 1e-9), written as AP214 STEP, and described in OUTDIR/manifest.json
with what is known about its medial axis: `open_ends` 0 (a seam may end only at a convex
vertex, a junction, a curvature limit, by closing, or at a degenerate piece) and the
volume. Deterministic up to the STEP header's timestamp.
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import samplelib as L  # noqa: E402  (sets up FreeCAD's sys.path)
from samplelib import Part, V  # noqa: E402

PI = math.pi
MADE_BY = "scripts/freecad/make_trace_regressions.py"
PARTS = []


def part(name, description, volume, mat_note, volume_rel=1e-9, edit=None):
    """`edit`: a function of the written STEP text returning the text to keep (a defect an
    exporter writes that FreeCAD would not)."""
    def deco(fn):
        PARTS.append(dict(name=name, description=description, volume=volume,
                          mat_note=mat_note, build=fn, volume_rel=volume_rel, edit=edit))
        return fn
    return deco


def cyl(r, h, x, y, z=0.0):
    return Part.makeCylinder(r, h, V(x, y, z))


def cut_split_hole(solid, r, h, x, y, z=0.0):
    """`solid` with a vertical hole r, h from (x, y, z) cut as two half cylinders meeting in
    the plane through its axis parallel to x, as exporters that split periodic faces write
    a hole's wall."""
    for a in (0, 180):
        half = Part.makeCylinder(r, h, V(x, y, z), V(0, 0, 1), 180)
        half.rotate(V(x, y, z), V(0, 0, 1), a)
        solid = solid.cut(half)
    return solid


@part("fillet_meets_hole",
      "Plate 40x30x8 with its four vertical edges filleted r=4 and a through hole r=3 "
      "whose rim passes 1 mm from one fillet.",
      40 * 30 * 8 - 4 * (16 - 4 * PI) * 8 - PI * 9 * 8,
      "The fillets' axes and the hole's are degenerate pieces; the seams from the "
      "plate's corners pass the fillets and meet the hole's sheet near the fillet.")
def fillet_meets_hole():
    b = Part.makeBox(40, 30, 8)
    b = b.makeFillet(4, [e for e in b.Edges if abs(e.tangentAt(0).z) > 0.99])
    return b.cut(cyl(3, 8, 8, 8))


@part("thin_rib_on_plate",
      "Plate 50x30x4 with a rib 1.5 mm thick and 10 mm high standing across its middle.",
      50 * 30 * 4 + 1.5 * 30 * 10,
      "The rib is thinner than the plate: its mid-plane sheet meets the plate's at "
      "junctions along the rib's foot, where the reflex edges' seams run.")
def thin_rib_on_plate():
    return Part.makeBox(50, 30, 4).fuse(Part.makeBox(1.5, 30, 10, V(24.25, 0, 4))).removeSplitter()


@part("boss_near_edge",
      "Plate 40x30x6 with a cylindrical boss r=5, 8 mm high, its side 1 mm from the "
      "plate's long edge.",
      40 * 30 * 6 + PI * 25 * 8,
      "The boss's reflex rim passes 1 mm from the plate's side: junctions of the rim's "
      "seams with the side face lie close together.")
def boss_near_edge():
    return Part.makeBox(40, 30, 6).fuse(cyl(5, 8, 20, 6, 6)).removeSplitter()


@part("slot_ends_in_round",
      "Block 50x30x10 with a slot 6 mm wide and 5 mm deep from one end, ending in a "
      "half-round r=3.",
      50 * 30 * 10 - (30 * 6 + PI * 9 / 2) * 5,
      "The slot's round end is a half cylinder: its axis is a degenerate piece; the "
      "seams of the slot's floor edges run into the round and meet it there.")
def slot_ends_in_round():
    b = Part.makeBox(50, 30, 10)
    slot = Part.makeBox(30, 6, 5, V(0, 12, 5)).fuse(cyl(3, 5, 30, 15, 5))
    return b.cut(slot).removeSplitter()


@part("chamfered_pocket",
      "Block 40x30x12 with a rectangular pocket 20x12x6 deep whose rim is chamfered "
      "1.5 mm.",
      None,
      "Chamfer faces meet the pocket walls and the top at shallow angles: seams leave "
      "the chamfer's corners between faces meeting at 135 degrees.")
def chamfered_pocket():
    b = Part.makeBox(40, 30, 12)
    b = b.cut(Part.makeBox(20, 12, 6, V(10, 9, 6)))
    rim = [e for e in b.Edges
           if abs(e.BoundBox.ZMin - 12) < 1e-9 and abs(e.BoundBox.ZMax - 12) < 1e-9
           and 10 - 1e-9 <= e.BoundBox.XMin and e.BoundBox.XMax <= 30 + 1e-9
           and 9 - 1e-9 <= e.BoundBox.YMin and e.BoundBox.YMax <= 21 + 1e-9]
    return b.makeChamfer(1.5, rim)


@part("counterbore_channel",
      "Block 40x30x16 with a channel 8 mm wide and 6 mm deep along x on its underside "
      "and a counterbore from the top (r=6, 4 deep, equal to the channel's half-width) "
      "over a hole r=3 through into the channel.",
      None,
      "The counterbore's floor lies as far from the top as the channel is half wide: "
      "balls of equal radius meet the floor, the channel walls and the hole together.")
def counterbore_channel():
    b = Part.makeBox(40, 30, 16)
    b = b.cut(Part.makeBox(40, 8, 6, V(0, 11, 0)))
    b = b.cut(cyl(6, 4, 20, 15, 12)).cut(cyl(3, 16, 20, 15, 0))
    return b.removeSplitter()


@part("touching_features",
      "Plate 40x24x6 with three holes r=2 in a row 5 mm apart (1 mm walls between them), "
      "a boss r=3 whose side touches a pocket's wall, and a pocket 8x8x3.",
      None,
      "Several small features close together: the junctions between neighbouring holes "
      "lie 1 mm apart and must stay distinct.")
def touching_features():
    b = Part.makeBox(40, 24, 6)
    for x in (8, 13, 18):
        b = b.cut(cyl(2, 6, x, 8))
    b = b.cut(Part.makeBox(8, 8, 3, V(26, 12, 3)))
    b = b.fuse(cyl(3, 4, 23, 16, 6))
    return b.removeSplitter()


@part("faceted_boss",
      "Plate 40x30x4 with a boss 4 mm high whose footprint is a 16x10 rectangle with its "
      "long sides each broken at their middle by 0.6 degrees, one outwards and one "
      "inwards (the walls meet there tangentially to 1 degree, a typical faceted profile).",
      None,
      "The reflex edges at the boss's foot meet at the break points at 0.6 degrees: the "
      "seams along them carry a touch point past each break, onto the next edge or, where "
      "the edges turn away from the ball, onto the vertex while the normal turns.")
def faceted_boss():
    bow = 8 * math.tan(math.radians(0.3))
    pts = [(12, 10, 4), (20, 10 - bow, 4), (28, 10, 4), (28, 20, 4), (20, 20 - bow, 4),
           (12, 20, 4)]
    foot = Part.Face(Part.makePolygon([V(*q) for q in pts] + [V(*pts[0])]))
    return Part.makeBox(40, 30, 4).fuse(foot.extrude(V(0, 0, 4))).removeSplitter()


KINK_B = 10.5 * math.tan(math.radians(0.5))
KINKED_PTS = [(0, 0), (1.5, 0), (12, -KINK_B), (12, 6), (1.5, 6 + KINK_B), (0, 6 + KINK_B)]


@part("kinked_walls",
      "Block 12x6x4 whose two long walls are each two planar faces meeting 1.5 mm from "
      "one end at 0.5 degrees (within the 1 degree tangent tolerance), one wall bent "
      "outwards (a convex kink) and one inwards (a reflex kink), as faceted exports write "
      "a wall.",
      4 * 0.5 * abs(sum(a[0] * b[1] - b[0] * a[1]
                        for a, b in zip(KINKED_PTS, KINKED_PTS[1:] + KINKED_PTS[:1]))),
      "The seams from the kinked end's corners carry their long-wall touch point across "
      "the kink at r of about 1.5. At the reflex kink the ball touches the edge itself "
      "while its normal turns by 0.5 degrees; at the convex kink it passes at the ball "
      "touching both faces (by the tolerance they are one tangent wall, so there is no "
      "kink sheet). The seams go on to the junctions at r = 2; Euler characteristic 1.")
def kinked_walls():
    foot = Part.Face(Part.makePolygon([V(x, y, 0) for x, y in KINKED_PTS]
                                      + [V(*KINKED_PTS[0], 0)]))
    return foot.extrude(V(0, 0, 4))


@part("split_hole",
      "Block 40x20x10 with a through hole r=4 at its middle whose wall is two half "
      "cylinders meeting along the block's plane of symmetry (as exporters that split "
      "periodic faces write it).",
      40 * 20 * 10 - PI * 16 * 10,
      "The seams of the hole with the block's ends and faces lie in the plane of symmetry, "
      "so their touch points on the hole run along the lines where its two halves meet. "
      "The medial axis has the solid's Euler characteristic, 0 (a block with a hole).")
def split_hole():
    return cut_split_hole(Part.makeBox(40, 20, 10), 4, 10, 20, 10)


@part("elliptic_bar",
      "Bar 16 mm high whose section is an ellipse with semi-axes 20 and 10: one lateral "
      "face, closed round.",
      PI * 20 * 10 * 16,
      "Balls inside the ellipse touch its one lateral face twice (radius 5 at the ends of "
      "the major axis to 10 at the centre). Where that radius is half the height, 8, the "
      "seams of the lateral face touched twice with the top and the bottom meet the seam "
      "of the lateral face with both, at junctions touching the lateral face twice: four "
      "seams each, two of them on the same elements.")
def elliptic_bar():
    e = Part.Ellipse(V(0, 0, 0), 20, 10)
    face = Part.Face(Part.Wire(e.toShape()))
    return face.extrude(V(0, 0, 16))


@part("rounded_boss_corners",
      "Plate 30x30x4 with a box boss 10x10x6 standing at its middle, the boss's vertical "
      "edges filleted r=0.6, so its foot is four straight reflex edges joined by quarter "
      "circles.",
      30 * 30 * 4 + (10 * 10 - (4 - PI) * 0.36) * 6,
      "Under each corner of the boss the seam of the plate's bottom with the two straight "
      "foot edges runs towards the corner. It ends where its centre is on the axis of the "
      "corner's quarter circle: there the ball touches that whole arc (r times the arc's "
      "curvature towards the centre is 1), a curvature limit on the curved reflex edge.")
def rounded_boss_corners():
    boss = Part.makeBox(10, 10, 6, V(10, 10, 4))
    boss = boss.makeFillet(0.6, [e for e in boss.Edges if abs(e.tangentAt(0).z) > 0.99])
    return Part.makeBox(30, 30, 4).fuse(boss).removeSplitter()


@part("half_spherical_shell",
      "Half of a spherical shell, outer radius 10 and inner 9, cut by a plane through the "
      "spheres' axis: each sphere face is a lune from pole to pole.",
      (2.0 / 3.0) * PI * (10 ** 3 - 9 ** 3),
      "The sheet halfway between the spheres (radius 9.5) meets the cut plane's sheets along "
      "one closed seam of r = 0.5 in the plane 0.5 from the cut, which passes next to both "
      "poles: its touch points on the lunes run into the corners where each lune reaches a "
      "pole.")
def half_spherical_shell():
    outer = Part.makeSphere(10, V(0, 0, 0), V(0, 0, 1), -90, 90, 180)
    inner = Part.makeSphere(9, V(0, 0, 0), V(0, 0, 1), -90, 90, 180)
    return outer.cut(inner)


@part("split_blind_hole",
      "Block 40x20x20 with a blind hole r=4, 6 mm deep from the top, its axis 6 mm from the "
      "side y=20, whose wall is two half cylinders meeting in the plane y=14 (as exporters "
      "that split periodic faces write it).",
      40 * 20 * 20 - PI * 16 * 6,
      "A seam of the top, the side y=20 and the hole's wall passes r = 6 with its centre at "
      "(30, 14, 14), level with the hole's floor: its touch point on the wall comes to the "
      "vertex (24, 14, 14) where the wall's halves and the floor rim's two arcs meet, running "
      "along the line between the halves, and goes on along the rim.")
def split_blind_hole():
    return cut_split_hole(Part.makeBox(40, 20, 20), 4, 6, 20, 14, 14)


@part("tapered_pocket",
      "Block 24x24x16 with a tapered pocket in its top: 45 degree walls from radius 6 at "
      "the top to a flat floor of radius 2, 4 mm deep, centred at (15, 8).",
      24 * 24 * 16 - PI * 4 / 3 * (36 + 12 + 4),
      "The pocket's floor rim is a reflex edge (225 degrees). Seams of the block's faces "
      "growing towards the pocket come closer to that rim than r first, but the ball they "
      "meet touches the pocket's conical wall next to it (its normal is outside the rim's "
      "arc of normals): the junctions are with the cone.")
def tapered_pocket():
    b = Part.makeBox(24, 24, 16)
    return b.cut(Part.makeCone(2, 6, 4, V(15, 8, 12), V(0, 0, 1)))


@part("nurbs_hole_plate",
      "Plate 40x40x10 with a through hole r=5 at its centre, the whole solid converted to "
      "NURBS (as exporters that write every surface as a B-spline do): the hole's wall is a "
      "closed rational surface whose parameter range is one turn.",
      40 * 40 * 10 - PI * 25 * 10,
      "The seam of the hole's wall and the plate's top and bottom is the circle of radius 10 "
      "about the hole's axis in the plane z=5 (r = 5): a closed seam whose touch point on the "
      "wall crosses the wall's parameter seam.",
      # OCCT integrates a NURBS solid's volume to ~3e-4 only; the analytic plate is checked
      # to 1e-9 before it is converted.
      volume_rel=1e-3)
def nurbs_hole_plate():
    plate = Part.makeBox(40, 40, 10).cut(cyl(5, 10, 20, 20))
    L.check_volume("nurbs_hole_plate (analytic)", plate, 40 * 40 * 10 - PI * 25 * 10, rel=1e-9)
    return plate.toNurbs()


@part("hole_tangent_to_pocket",
      "Block 20x20x12 with a square pocket 6x6, 4 deep, in its bottom and a hole r=3 from the "
      "pocket's ceiling through the top, both centred at (10, 10): the hole's circle is "
      "inscribed in the pocket's square, so the ceiling is four corner pieces that meet the "
      "hole's wall and the pocket's walls at the four points where the circle touches the "
      "square.",
      20 * 20 * 12 - 6 * 6 * 4 - PI * 9 * 8,
      "At each tangent point the hole's wall and the pocket's reflex ceiling edges meet "
      "tangentially. The seam of an outer wall, the hole's wall and a ceiling edge comes down "
      "to the ceiling's plane there (r = 3.5 at (10, 16.5, 4) for the wall y=20), where the "
      "touch points on the hole's wall and on the edge meet at the tangent point: it ends at "
      "a pinch, and so does the seam of the same wall, the hole's wall and the ceiling edge "
      "on the other side, at the same ball.")
def hole_tangent_to_pocket():
    b = Part.makeBox(20, 20, 12).cut(Part.makeBox(6, 6, 4, V(7, 7, 0)))
    return b.cut(cyl(3, 8, 10, 10, 4)).removeSplitter()


@part("shallow_roof",
      "Block 40x30 whose top is a roof of two planes rising 2 degrees each from the long "
      "sides (height 10 there) to a ridge along y at x = 20: the ridge is a convex edge of "
      "176 degrees, shallower than a corner by far but beyond the 1 degree tangent tolerance.",
      40 * 30 * 10 + 0.5 * 40 * 20 * math.tan(math.radians(2)) * 30,
      "Seams leave the ridge's two end vertices between the two roof planes and an end wall. "
      "Near those vertices the ball's touch points on the two roof planes lie closer than "
      "sqrt(8 r a) (they separate as r times the 4 degree crease, the chord as the square "
      "root of r): the accuracy cannot tell them apart, so those seam points are listed as "
      "unresolved and held to two places, which the crease between the planes explains.")
def shallow_roof():
    h = 20 * math.tan(math.radians(2))
    pts = [V(0, 0, 0), V(40, 0, 0), V(40, 0, 10), V(20, 0, 10 + h), V(0, 0, 10), V(0, 0, 0)]
    return Part.Face(Part.makePolygon(pts)).extrude(V(0, 30, 0))


def shift_plane_points(text, offset):
    """Moves the placement point of every PLANE for which `offset(direction, point)` gives a
    displacement (not None) by it, its axes and the faces' edges left as they are; returns
    the text and how many planes moved."""
    import re
    ents = dict(re.findall(r"^(#\d+) = (.*);$", text, re.M))

    def coords(ref, kind):
        m = re.match(kind + r"\('',\(([^)]*)\)\)", ents[ref])
        return [float(x) for x in m.group(1).split(",")] if m else None

    moved = 0
    for pl in [ref for ref, e in ents.items() if e.startswith("PLANE(")]:
        ax = re.match(r"PLANE\('',(#\d+)\)", ents[pl]).group(1)
        loc, axis, _ = re.match(r"AXIS2_PLACEMENT_3D\('',(#\d+),(#\d+),(#\d+)\)",
                                ents[ax]).groups()
        d, p = coords(axis, "DIRECTION"), coords(loc, "CARTESIAN_POINT")
        shift = offset(d, p) if d is not None else None
        if shift is None:
            continue
        q = ",".join(f"{p[k] + shift[k]:.12f}" for k in range(3))
        text = re.sub(rf"^{loc} = CARTESIAN_POINT\('',\([^)]*\)\);$",
                      f"{loc} = CARTESIAN_POINT('',({q}));", text, count=1, flags=re.M)
        moved += 1
    return text, moved


def move_planes(text, name, offset, uncertainty):
    """Moves one PLANE off its face's edges by `offset` (see `shift_plane_points`) and
    declares the length uncertainty `uncertainty` (a STEP real), as exporters whose edges
    follow one face and not the other do. Exactly one plane must move."""
    import re
    text, moved = shift_plane_points(text, offset)
    if moved != 1:
        raise SystemExit(f"{name}: {moved} planes found to move, not 1")
    return re.sub(r"UNCERTAINTY_MEASURE_WITH_UNIT\(LENGTH_MEASURE\([^)]*\)",
                  f"UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({uncertainty})", text)


ROOF_GAP = 3e-4


def shift_roof_plane(text):
    """Moves the plane of the roof face that rises from x = 40 by ROOF_GAP along its normal,
    leaving its edges where they are (on the end wall and the other roof plane), and declares
    an uncertainty of 1e-3 mm."""
    n = (math.sin(math.radians(2)), 0.0, math.cos(math.radians(2)))

    def offset(d, p):
        if any(abs(a - b) > 1e-9 for a, b in zip(d, n)):
            return None
        return [ROOF_GAP * c for c in n]

    return move_planes(text, "roof_off_its_ridge", offset, "1.E-03")


@part("roof_off_its_ridge",
      "The shallow roof's block (40x30, roof planes rising 2 degrees to a ridge at x = 20) "
      "with the plane of the roof face rising from x = 40 moved 3e-4 mm up along its "
      "normal, its edges left where they were (on the end walls and the other roof plane): "
      "an exporter's gap between a face and its edges, six times the default accuracy "
      "(5.1e-5 mm), within the declared uncertainty (1e-3 mm). The volume is the unmoved "
      "solid's (the file's is 0.18 mm3 more).",
      40 * 30 * 10 + 0.5 * 40 * 20 * math.tan(math.radians(2)) * 30,
      "As the shallow roof's, to the gap: the moved plane's corner with the other roof plane "
      "and the end walls is 3e-4 / sin 4 degrees = 4.3e-3 mm past the ridge, so the seams "
      "from the ridge's ends start at the vertex and touch the other roof plane's surface "
      "past its trim until r is about 0.12. The report warns of the gap (kind `gap`, "
      "largest 3e-4 mm), and both checkers hold the balls near the moved face to the "
      "accuracy plus the gap, and no more.",
      volume_rel=1e-4,
      edit=shift_roof_plane)
def roof_off_its_ridge():
    return shallow_roof()


SPLIT_TOP_GAP = 3e-3


def raise_narrow_top_plane(text):
    """Moves the plane of the top face over y = 0..10.1 up by SPLIT_TOP_GAP (out of the
    material), leaving its edges where they are (on the other top face and the walls), and
    declares an uncertainty of 1e-2 mm."""
    def offset(d, p):
        top = abs(abs(d[2]) - 1) <= 1e-12 and abs(p[2] - 20) <= 1e-9
        return [0.0, 0.0, SPLIT_TOP_GAP] if top and p[1] < 10.1 - 1e-9 else None

    return move_planes(text, "split_top_off_its_edge", offset, "1.E-02")


@part("split_top_off_its_edge",
      "Box 60x40x20 written as two blocks 60x10.1x20 and 60x29.9x20 side by side (top, "
      "bottom and ends each split at y = 10.1 into two faces), with the plane of the narrow "
      "top face (y = 0..10.1) moved 3e-3 mm up, out of the material, its edges left where "
      "they were: an exporter's gap between a face and its edges (40 times the default "
      "accuracy), within the declared uncertainty (1e-2 mm). The volume is the unmoved box's.",
      60 * 40 * 20,
      "The box's medial axis, to the gap: 12 seams, 4 junctions. The balls touching the "
      "raised face, the front and the bottom (centred y = 10.0015, z = 10.0015, r = 10.0015) "
      "reach 3e-3 - 0.1^2/20 = 2.5e-3 mm into the face's own edge at the split (and its "
      "neighbour's), within the gap; so do the junctions at the ends of their seam (touching "
      "an end, the front, the bottom and the raised face), which are medial to the accuracy "
      "plus the gap, as both checkers hold them: refused as not empty, the six seams meeting "
      "them ended open (no junction).",
      volume_rel=1e-4,
      edit=raise_narrow_top_plane)
def split_top_off_its_edge():
    return Part.makeBox(60, 10.1, 20).fuse(Part.makeBox(60, 29.9, 20, V(0, 10.1, 0)))


CREASE_GAP = 3e-3


def raise_front_half_of_a_roof_plane(text):
    """Moves the plane of the roof face rising from x = 40 over y = 0..15 (the front half of
    that roof plane) by CREASE_GAP along its normal, out of the material, leaving its edges
    where they are, and declares an uncertainty of 1e-2 mm."""
    n = (math.sin(math.radians(2)), 0.0, math.cos(math.radians(2)))

    def offset(d, p):
        if any(abs(a - b) > 1e-9 for a, b in zip(d, n)) or p[1] > 15 - 1e-9:
            return None
        return [CREASE_GAP * c for c in n]

    return move_planes(text, "shallow_roof_with_its_front_half_off_its_edges", offset, "1.E-02")


@part("shallow_roof_with_its_front_half_off_its_edges",
      "The shallow roof's block (40x30x10, roof planes rising 2 degrees to a ridge at x = 20, "
      "a convex crease of 176 degrees) written as two blocks 15 deep side by side (every face "
      "split at y = 15, the halves of each meeting at a smooth edge), with the plane of the "
      "front half (y = 0..15) of the roof face rising from x = 40 moved 3e-3 mm up along its "
      "normal, its edges left where they were: an exporter's gap between a face and its edges "
      "(59 times the default accuracy), within the declared uncertainty (1e-2 mm). The volume "
      "is the unmoved solid's.",
      40 * 30 * 10 + 0.5 * 40 * 20 * math.tan(math.radians(2)) * 30,
      "As the shallow roof's, to the gap. The seam along the crease (its balls touching both "
      "roof planes, 2 r sin 2 degrees apart, and the bottom; r about 5.2) crosses y = 15, where "
      "one touch point passes from the moved half of its roof plane onto the other half across "
      "their smooth edge: the ball there moves by the gap over twice the sine of 2 degrees "
      "(4.3e-2 mm, 14 times the gap), the bisector of the two roof planes moving by that much. "
      "Before, the hand-over refused the ball it found (moved more than the gap) and the seam "
      "ended there from both sides (as the Prusa extruder motor plate's seams in a "
      "177.4-degree crease did at a B-spline blend off its edges by 3.9e-3 mm). Near the "
      "ridge's front end the ball is moved as far, and the unmoved plane's touch point lies "
      "past its trim (the ridge) by up to 0.043 mm, its surface there within the gap of the "
      "moved one: the seam from that vertex runs on to its junction (before, it ended at "
      "r 0.75, taken for a curvature limit of the moved plane).",
      volume_rel=1e-4,
      edit=raise_front_half_of_a_roof_plane)
def shallow_roof_with_its_front_half_off_its_edges():
    h = 20 * math.tan(math.radians(2))
    pts = [V(0, 0, 0), V(40, 0, 0), V(40, 0, 10), V(20, 0, 10 + h), V(0, 0, 10), V(0, 0, 0)]
    profile = Part.Face(Part.makePolygon(pts))
    front = profile.extrude(V(0, 15, 0))
    back = profile.extrude(V(0, 15, 0))
    back.translate(V(0, 15, 0))
    return front.fuse(back)


BOW = 3e-3


def bow_the_reflex_edge(text):
    """Writes the L-bracket's reflex edge (x = 10, z = 10, y = 0..30) as a quadratic B-spline
    whose middle control point is BOW off the line towards +x, in the plane z = 10: the curve
    lies on the flange's top face and up to BOW/2 off the leg's face x = 10, its tangent
    turned by up to 2*BOW/30 = 2e-4 rad from the faces' line, as an exporter's spline fit of an
    intersection curve is. Declares an uncertainty of 1e-2 mm."""
    import re
    ents = dict(re.findall(r"^(#\d+) = (.*?);$", text, re.M | re.S))

    def vertex(ref):
        p = re.match(r"VERTEX_POINT\('[^']*',(#\d+)\)", ents[ref]).group(1)
        m = re.match(r"CARTESIAN_POINT\('[^']*',\(([^)]*)\)\)", ents[p])
        return tuple(round(float(x), 9) for x in m.group(1).split(","))

    found = []
    for ref, e in ents.items():
        m = re.match(r"EDGE_CURVE\('[^']*',(#\d+),(#\d+),(#\d+),", e)
        if m and {vertex(m.group(1)), vertex(m.group(2))} == {(10, 0, 10), (10, 30, 10)}:
            found.append((ref, m.group(3)))
    if len(found) != 1:
        raise SystemExit(f"l_bracket_with_a_bowed_reflex_edge: {len(found)} reflex edges found")
    geometry = found[0][1]
    new = max(int(k[1:]) for k in ents) + 1
    points = [(10.0, 0.0, 10.0), (10.0 + BOW, 15.0, 10.0), (10.0, 30.0, 10.0)]
    lines = [f"#{new + k} = CARTESIAN_POINT('',({x!r},{y!r},{z!r}));"
             for k, (x, y, z) in enumerate(points)]
    lines.append(f"#{new + 3} = B_SPLINE_CURVE_WITH_KNOTS('',2,(#{new},#{new + 1},#{new + 2}),"
                 ".UNSPECIFIED.,.F.,.F.,(3,3),(0.,30.),.UNSPECIFIED.);")
    if ents[geometry].startswith("SURFACE_CURVE("):
        text, n = re.subn(rf"^({geometry} = SURFACE_CURVE\('[^']*',)#\d+,",
                          rf"\g<1>#{new + 3},", text, count=1, flags=re.M)
    else:
        text, n = re.subn(rf"^(#\d+ = EDGE_CURVE\('[^']*',#\d+,#\d+,){geometry},",
                          rf"\g<1>#{new + 3},", text, count=1, flags=re.M)
    if n != 1:
        raise SystemExit("l_bracket_with_a_bowed_reflex_edge: the edge's curve not replaced")
    i = text.rindex("ENDSEC;")
    text = text[:i] + "\n".join(lines) + "\n" + text[i:]
    return re.sub(r"UNCERTAINTY_MEASURE_WITH_UNIT\(LENGTH_MEASURE\([^)]*\)",
                  "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-02)", text)


@part("l_bracket_with_a_bowed_reflex_edge",
      "The L-bracket (profile 60 wide, 40 high, 10 thick, extruded 30 along y) with its reflex "
      "edge (x = 10, z = 10) written as a quadratic B-spline bowed 1.5e-3 mm towards +x in the "
      "plane z = 10: on the flange's top face, up to 1.5e-3 mm off the leg's face (a gap, "
      "19 times the default accuracy), its tangent up to 2e-4 rad off the faces' line.",
      (60 * 10 + 10 * 30) * 30,
      "The L-bracket's medial axis, to the gap: 17 seams, 6 junctions. The faces' normals at "
      "the edge are perpendicular to its tangent only to 2e-4 rad; the arc of normals the "
      "edge owns is taken in its normal plane (`Tracer::edge_fan`). Between the unprojected "
      "normals, the test that a touch point's normal is inside the arc failed mid-arc by the "
      "square of that tilt, and six seams of the edge's balls ended open.",
      volume_rel=1e-4,
      edit=bow_the_reflex_edge)
def l_bracket_with_a_bowed_reflex_edge():
    profile = [(0, 0), (60, 0), (60, 10), (10, 10), (10, 40), (0, 40)]
    face = Part.Face(Part.makePolygon([V(x, 0, z) for (x, z) in profile + profile[:1]]))
    return face.extrude(V(0, 30, 0))


@part("chamfered_rib_end",
      "Plate 60x40x10 with a rib 16 mm wide and 6 mm high along y, its foot filleted r=2 "
      "(concave), its end at the plate's side y=40 chamfered by a plane rising 2 in 1 from "
      "the plate's top edge: the chamfer meets the side y=40 in the line of the plate's top "
      "face, so at the two ends of that edge the fillets' tangent lines meet it too, and "
      "the line is tangent to each fillet there.",
      None,
      "The seams of a fillet, the side y=40 and the chamfer come down to r = 0 at the "
      "convex vertices where the fillets' tangent lines meet the chamfer's edge. The three "
      "surfaces meet there tangentially (the chamfer's edge is tangent to the fillet), so r "
      "has a minimum of 0 at the vertex instead of crossing it: a step passes the vertex, "
      "the touch point on the fillet leaves it across its edge with the chamfer, and the "
      "seam must end at the vertex, not open at that edge.")
def chamfered_rib_end():
    b = Part.makeBox(60, 40, 10, V(-30, 0, -10)).fuse(Part.makeBox(16, 40, 6, V(-8, 0, 0)))
    b = b.removeSplitter()
    foot = [e for e in b.Edges
            if abs(e.tangentAt(0).y) > 0.99 and abs(e.BoundBox.ZMax) < 1e-9
            and abs(abs(e.BoundBox.XMin) - 8) < 1e-9]
    assert len(foot) == 2, foot
    b = b.makeFillet(2, foot)
    pts = [V(-20, 40, 0), V(-20, 36, 8), V(-20, 45, 8), V(-20, 45, 0), V(-20, 40, 0)]
    tool = Part.Face(Part.makePolygon(pts)).extrude(V(40, 0, 0))
    return b.cut(tool).removeSplitter()


@part("drilled_blind_hole",
      "Plate 40x30x10 with a blind hole r=2 drilled along y from the side y=0 at mid-height "
      "(axis at x=20, z=5), 14 mm deep to the shoulder, ending in a 118 degree drill point "
      "(a cone whose apex is a vertex of its face alone, 2/tan 59 deg = 1.20 mm further).",
      40 * 30 * 10 - PI * 4 * 14 - PI * 4 * (2 / math.tan(math.radians(59))) / 3,
      "The seams of the top, the bottom and the hole's wall run along the hole at mid-height, "
      "onto the drill point's cone and down it to the apex (r = 5). There the touch point "
      "passes onto the apex, a reflex point of the boundary: the ball touches it while its "
      "normal turns about the hole's axis (the centre on the circle of radius 5 about the "
      "apex in the mid-plane) and leaves onto the cone's other side: one seam around the "
      "hole's end.")
def drilled_blind_hole():
    tip = 2 / math.tan(math.radians(59))
    drill = Part.makeCylinder(2, 14, V(20, 0, 5), V(0, 1, 0)).fuse(
        Part.makeCone(2, 0, tip, V(20, 14, 5), V(0, 1, 0)))
    return Part.makeBox(40, 30, 10).cut(drill).removeSplitter()


def apex_as_vertex_loop(text):
    """Writes the drill point's cone as some exporters do: its seam edge, from the rim to the
    apex, left out, and the apex a `VERTEX_LOOP` of the face (the rim's loop alone bounds it
    otherwise)."""
    import re
    ents = dict(re.findall(r"^(#\d+) = (.*);$", text, re.M))
    seams = {ref for ref, e in ents.items() if e.startswith("SEAM_CURVE(")}
    edges = {ref: re.match(r"EDGE_CURVE\('',(#\d+),(#\d+),(#\d+),", e).groups()
             for ref, e in ents.items() if e.startswith("EDGE_CURVE(")}

    def alone(seam):
        """The seam edge's vertices no other edge has (the cone's apex)."""
        used = [v for ref, (a, b, _) in edges.items() if ref != seam for v in (a, b)]
        return [v for v in edges[seam][:2] if v not in used]

    tips = [(ref, alone(ref)) for ref, (_, _, c) in edges.items() if c in seams]
    tips = [(ref, a) for ref, a in tips if len(a) == 1]
    if len(tips) != 1:
        raise SystemExit(f"drilled_blind_hole_vertex_loop: {len(tips)} seam edges to an apex, "
                         "not 1")
    seam, apex = tips[0]
    oriented = {ref for ref, e in ents.items()
                if re.match(rf"ORIENTED_EDGE\('',\*,\*,{seam},", e)}
    loops = [ref for ref, e in ents.items()
             if e.startswith("EDGE_LOOP(") and oriented & set(re.findall(r"#\d+", e))]
    if len(loops) != 1:
        raise SystemExit(f"drilled_blind_hole_vertex_loop: {len(loops)} loops, not 1")
    loop = loops[0]
    kept = [r for r in re.findall(r"#\d+", ents[loop]) if r not in oriented]
    text = re.sub(rf"^{loop} = EDGE_LOOP\(.*\);$",
                  f"{loop} = EDGE_LOOP('',({','.join(kept)}));", text, count=1, flags=re.M)
    bound = [ref for ref, e in ents.items()
             if re.match(rf"FACE_(OUTER_)?BOUND\('',{loop},", e)][0]
    face = [ref for ref, e in ents.items()
            if e.startswith("ADVANCED_FACE(") and re.search(rf"[(,]{bound}[,)]", e)][0]
    # The seam edge and its uses go (a reader may warn of an edge no face uses).
    for ref in sorted(oriented) + [seam]:
        text = re.sub(rf"^{ref} = .*;\n", "", text, count=1, flags=re.M)
    top = max(int(r[1:]) for r in ents)
    vb, vl = f"#{top + 1}", f"#{top + 2}"
    text = re.sub(rf"^{face} = ADVANCED_FACE\('',\(([^)]*)\)",
                  lambda m: f"{face} = ADVANCED_FACE('',({m.group(1)},{vb})",
                  text, count=1, flags=re.M)
    extra = f"{vb} = FACE_BOUND('',{vl},.T.);\n{vl} = VERTEX_LOOP('',{apex[0]});\n"
    return text.replace("\nENDSEC;\nEND-ISO", f"\n{extra}ENDSEC;\nEND-ISO", 1)


@part("drilled_blind_hole_vertex_loop",
      "The drilled blind hole (plate 40x30x10, hole r=2 along y at mid-height, 14 mm deep "
      "with a 118 degree drill point) with the cone written as some exporters do: no seam "
      "edge, the apex a VERTEX_LOOP of the cone's face, the rim's loop the face's only edges.",
      40 * 30 * 10 - PI * 4 * 14 - PI * 4 * (2 / math.tan(math.radians(59))) / 3,
      "As the drilled blind hole's: the touch point passes from the cone onto the apex, a "
      "vertex with no edges, and back onto the cone's other side.",
      edit=apex_as_vertex_loop)
def drilled_blind_hole_vertex_loop():
    return drilled_blind_hole()


CORNER_DIP = 0.02


@part("cube_corner_in_plate",
      "Plate 30x30x5 with a 10 mm cube standing on one corner (its main diagonal vertical) "
      f"fused to it, the corner {CORNER_DIP} mm below the plate's top: the cube's three faces "
      "there meet the plate in a triangle of sides 0.049 mm.",
      None,
      "The seam of the cube's three bottom faces runs down from the cube's centre and meets "
      "the plate near the tiny triangle, at junctions. Its elements' surfaces meet at the "
      "buried corner, 0.02 mm inside the material and 0.0245 mm from the triangle's vertices "
      "(within 1000 times the accuracy): the seam must not end there, as if back at a convex "
      "vertex (r = 0 at a point of no face).")
def cube_corner_in_plate():
    c = Part.makeBox(10, 10, 10, V(-5, -5, -5))
    c.rotate(V(0, 0, 0), V(-1, -1, -1).cross(V(0, 0, -1)),
             math.degrees(math.acos(1 / math.sqrt(3))))
    c.translate(V(15, 15, 5 - CORNER_DIP + 5 * math.sqrt(3)))
    return Part.makeBox(30, 30, 5).fuse(c).removeSplitter()


def tube_grazing_cube_corner():
    """A 5 mm cube fused with a thin tube (r=2, bore 1.85) lying across its top corner: the
    tube's axis at the height of the cube's top, along (1, -1, 0), 0.017 mm nearer the corner
    (5, 5, 5) than the tube's radius, so the tube's outer wall takes that corner in."""
    R, bore, length, dip = 2.0, 1.85, 8.0, 0.017
    ax = V(1, -1, 0).normalize()
    start = V(5, 5, 5) + V(1, 1, 0).normalize() * (R - dip) - ax * (length / 2)
    tube = Part.makeCylinder(R, length, start, ax).cut(Part.makeCylinder(bore, length, start, ax))
    return Part.makeBox(5, 5, 5).fuse(tube).removeSplitter()


TUBE_NOTE = ("The seam of the cube's three faces at the corner runs from the cube's centre "
             "towards the corner; near it the touch points on the two side faces reach the "
             "tube together and pass onto the reflex edges where the cube meets the tube, then "
             "the top's onto its edge, and the seam ends at a junction with the tube's bore "
             "(r = 0.075, half the tube's wall).")


@part("tube_grazing_cube_corner",
      "A 5 mm cube with a thin tube (r=2, bore 1.85, 8 long) fused across its top corner, the "
      "tube's axis at the height of the cube's top and 0.017 mm nearer the corner than the "
      "tube's radius.",
      None, TUBE_NOTE)
def tube_grazing_cube_corner_analytic():
    return tube_grazing_cube_corner()


@part("tube_grazing_cube_corner_nurbs",
      "The tube grazing the cube's corner, written as NURBS (every face a B-spline patch: the "
      "tube's walls close on themselves at a seam along their top, where the cube's corner "
      "is), as the EGGTol cube_cylinder's exporter writes it. The volume is the analytic "
      "part's (OCCT integrates the NURBS solid to 1e-3 only: 139.6457).",
      tube_grazing_cube_corner().Volume, TUBE_NOTE + " As the analytic part's: the same seams "
      "and junctions.", volume_rel=2e-3)
def tube_grazing_cube_corner_nurbs():
    return tube_grazing_cube_corner().toNurbs()


@part("boss_tangent_to_edge_seam",
      "Sheet 100x20x0.4 with a cylindrical boss r=0.15, 0.3 mm high, at (50.7, 0.35): its "
      "foot circle is tangent, at (50.7, 0.2, 0.4), to the line y=0.2 on the top along which "
      "the balls of the sheet's edge y=0 (r = 0.2, half the thickness) touch it.",
      100 * 20 * 0.4 + PI * 0.15 ** 2 * 0.3,
      "The seam of the side y=0, the bottom and the top runs along the edge at y = z = 0.2; at "
      "x = 50.7 its touch point on the top grazes the boss's foot circle (a reflex edge) and "
      "goes on: the ball there touches the circle at its top touch point and the boss's wall "
      "comes no closer. It is one straight seam from end junction to end junction, as when "
      "the boss stands clear of that line.")
def boss_tangent_to_edge_seam():
    return Part.makeBox(100, 20, 0.4).fuse(cyl(0.15, 0.3, 50.7, 0.35, 0.4)).removeSplitter()


@part("shallow_pockets",
      "Plate 40x20x4 with two pockets in its top, 0.4 deep: a rectangle 12x10 (x 4..16, "
      "y 5..15) and a circle r=4 at (28, 10).",
      40 * 20 * 4 - 0.4 * (12 * 10 + PI * 16),
      "Round each pocket the plate's middle sheet (r = 2) ends in a closed loop of seams "
      "whose balls touch the top, the bottom and the pocket floor's rim, 1.2 from the rim "
      "(where sqrt(r^2 - 1.6^2) = 1.2): no convex vertex leads to them, and no ball sampled "
      "on the faces no seam touches (the pockets' walls and floors) touches both plate faces.")
def shallow_pockets():
    plate = Part.makeBox(40, 20, 4)
    plate = plate.cut(Part.makeBox(12, 10, 0.4, V(4, 5, 3.6)))
    return plate.cut(cyl(4, 0.4, 28, 10, 3.6))


@part("box_boss_on_plate",
      "Plate 40x30x6 with a box boss 10x8x5 standing on its top at (15..25, 11..19), away "
      "from its edges.",
      40 * 30 * 6 + 10 * 8 * 5,
      "Each vertical edge of the boss ends at the plate's top in a vertex with two reflex "
      "edges (the boss's foot). Below it the sheet of those two edges ends freely along a "
      "straight skeletal edge: the balls touching only the vertex, centres straight down "
      "from it, r from 0 to 3 (half the plate), where the seam of the two reflex edges and "
      "the plate's bottom ends with its two edge touch points at the vertex. The boss's "
      "edge's rim, that skeletal edge and the seam close the sheet; the medial axis has "
      "Euler characteristic 1, the solid's.")
def box_boss_on_plate():
    return Part.makeBox(40, 30, 6).fuse(Part.makeBox(10, 8, 5, V(15, 11, 6))).removeSplitter()


@part("rounded_pin",
      "Pin r=3 along z from z=0 to z=10 with a hemispherical tip r=3 (centre (0,0,10)) on a "
      "flat end at z=0.",
      PI * 9 * 10 + 2 * PI * 27 / 3,
      "The pin's axis is a degenerate curve (r = 3) from z = 3, where its ball touches the "
      "flat end at its centre, to z = 10, where the ball is the tip's sphere (it touches the "
      "sphere all over: the curve ends there, meeting it, and goes no further onto it).")
def rounded_pin():
    pin = Part.makeCylinder(3, 10, V(0, 0, 0), V(0, 0, 1))
    return pin.fuse(Part.makeSphere(3, V(0, 0, 10))).removeSplitter()


@part("hip_roof_block",
      "Block 30 x 30 x 10 (z from 0 to 10) under a square hip roof: four triangular faces "
      "rising from its top edges to an apex at (15, 15, 18).",
      30 * 30 * 10 + 30 * 30 * 8 / 3,
      "Five non-generic seams, each touched by four faces at every ball (its sheets are the "
      "four between neighbouring faces round it, not the two between opposite ones): from "
      "the apex straight down the block's axis between the four roof faces, r = "
      "(18 - z)·15/17, to the junction at z = 8.4375 (r = 8.4375) where the bottom touches "
      "the ball too; from each of the block's top corners, where two walls and two roof "
      "faces meet, down the corner's diagonal plane to the junction at (6.25, 6.25, 6.25) "
      "(and its mirror images), r = 6.25, with the bottom. Every sheet closes; the Euler "
      "characteristic is 1, the solid's.")
def hip_roof_block():
    block = Part.makeBox(30, 30, 10)
    corners = [V(0, 0, 10), V(30, 0, 10), V(30, 30, 10), V(0, 30, 10)]
    apex = V(15, 15, 18)
    faces = [Part.Face(Part.makePolygon([corners[k], corners[(k + 1) % 4], apex, corners[k]]))
             for k in range(4)]
    faces.append(Part.Face(Part.makePolygon(corners + [corners[0]])))
    roof = Part.Solid(Part.Shell(faces))
    return block.fuse(roof).removeSplitter()


@part("pocket_half_plate_deep",
      "Plate 30x30x8 with a square pocket 10x10 at its middle, 4 mm deep: half the plate's "
      "thickness, so the pocket's floor lies in the plate's mid-plane.",
      30 * 30 * 8 - 10 * 10 * 4,
      "No seam from the plate's corners reaches the pocket (they run along the mid-plane "
      "4 mm in from the plate's sides), so its seams are found by sampling its faces. The "
      "ball between the plate's top and bottom (r = 4, in the mid-plane) touches a pocket "
      "wall at its foot edge, where the wall meets the floor: one closed seam runs round the "
      "pocket 4 mm from its walls, touching top, bottom and the walls, handed from a wall "
      "onto its foot edge, onto the floor's corner vertex and on to the next wall at each "
      "corner. Every sheet closes; the Euler characteristic is 1, the solid's.")
def pocket_half_plate_deep():
    return Part.makeBox(30, 30, 8).cut(Part.makeBox(10, 10, 4, V(10, 10, 4)))


@part("pocket_over_a_thin_floor",
      "Plate 60x40x10 with a rectangular pocket x 20..40, y 12..28, 7 mm deep: its floor 3 mm "
      "above the plate's bottom, the pocket's walls 16 and 20 mm apart.",
      60 * 40 * 10 - 20 * 16 * 7,
      "The balls under the floor (r = 1.5) touch the floor and the bottom; past the floor's "
      "edge they touch that edge, then the wall, growing, with the bottom all along, up to the "
      "closed seam round the pocket in the plate's mid-plane (r = 5, touching top, bottom and "
      "the walls). That one sheet runs across the floor's reflex edges, and no seam or junction "
      "touches the floor: it is reached by sheet balls only, through its reflex edges (as a "
      "plain milled pocket is in most parts). Every sheet closes; the Euler characteristic is "
      "1, the solid's.")
def pocket_over_a_thin_floor():
    return Part.makeBox(60, 40, 10).cut(Part.makeBox(20, 16, 7, V(20, 12, 3)))


@part("frustum_cut_along_its_axis",
      "Frustum (cone r = 2 at z = 0 to r = 8 at z = 10, axis z) with the part beyond the plane "
      "x = 1, parallel to its axis, cut away: the plane meets the cone in two hyperbola arcs, "
      "which FreeCAD writes as HYPERBOLA curves, their ends at parameters beyond -1..1.",
      None,
      "Read with its hyperbolas whole: truck trims a STEP hyperbola (and parabola) to the "
      "parameters -1..1 and its search for a vertex stays there, so the file was refused "
      "('the edge's vertices are not on its curve', 12.9 and 137.5 mm). The medial axis of "
      "the four faces: every ball passes both checkers.")
def frustum_cut_along_its_axis():
    return Part.makeCone(2, 8, 10).cut(Part.makeBox(20, 20, 20, V(1, -10, -5)))


NECK = 0.01


@part("hole_next_to_an_edge",
      f"Block 60x30x10 with a through hole r = 4 along z whose wall passes {NECK} mm from the "
      "front face y = 0, at x = 30: a neck 0.01 mm thick between them.",
      60 * 30 * 10 - PI * 16 * 10,
      "The seams of the balls touching the top, the front face and the hole run along the "
      "front edges, r falling towards the neck and rising past it: at x = 30 the ball is "
      "0.005 mm, touching the front face and the hole on either side of the neck. Steps grow "
      "along the straight seam while r falls linearly; one whose predictor heads below r = 0 "
      "landed on the far side of the dip, its touch point on the top past the front edge, and "
      "the seam ended open ('reached convex edge'). Such a step is refused and halved "
      "(`Tracer::step`): the seam runs through the dip, and every ball passes both checkers.")
def hole_next_to_an_edge():
    return Part.makeBox(60, 30, 10).cut(Part.makeCylinder(4, 12, V(30, 4 + NECK, -1)))


@part("short_boss_on_plate",
      "Plate 60x40x10 with a cylindrical boss r = 5, 3 mm high, at (30, 20) on its top: the boss "
      "lower than it is wide.",
      60 * 40 * 10 + PI * 25 * 3,
      "Under and in the boss the balls touch the boss's foot circle (a reflex circle, z = 10) "
      "all round on its axis, from the ball that touches the bottom too (centre z = 6.25, "
      "r = 6.25: 25 + (10 - z)^2 = z^2) to the one that touches the cap (z = 7.333, r = 5.667: "
      "13 - z = sqrt(25 + (10 - z)^2)): a degenerate curve of the circle. No seam touches the "
      "boss; its cap and wall are reached only through that curve, whose balls the sampled "
      "edge sheet passes between a ball touching the cap and one touching the bottom.")
def short_boss_on_plate():
    return Part.makeBox(60, 40, 10).fuse(Part.makeCylinder(5, 3, V(30, 20, 10))).removeSplitter()


@part("short_boss_near_a_side",
      "short_boss_on_plate with the boss moved towards the side y = 40: a plate 60x40x10 with "
      "a boss r=5, h=3 centred (30, 34), its foot circle 1 from that side.",
      60 * 40 * 10 + PI * 25 * 3,
      "The plate's edge seam along that side (balls r = 5 touching top, bottom and side, "
      "centres y = 35, z = 5) passes under the boss's foot circle, and there its balls touch "
      "the circle instead of the top: the foot circle is touched by a seam. Under the boss "
      "the balls touch the foot circle all round on its axis, from the ball that touches the "
      "side too (centre z = 6.683, r = 6: 25 + (10 - z)^2 = 36) to the one that touches the "
      "cap (z = 7.333, r = 5.667, as in short_boss_on_plate): a degenerate curve of the "
      "circle. Before, an edge touched by a seam was not sampled for its collapsed sheet: the "
      "curve was missed and the cap touched by no ball.")
def short_boss_near_a_side():
    return Part.makeBox(60, 40, 10).fuse(Part.makeCylinder(5, 3, V(30, 34, 10))).removeSplitter()


TUBE_R, TUBE_BORE, TUBE_LEN = 5.0, 4.8, 20.0


@part("test_tube",
      "A thin tube (r=5, bore 4.8, 20 long, along z from 0) closed at z=0 by a "
      "hemispherical shell of the same wall, open at z=20: the open end a 0.2 mm annulus.",
      PI * (TUBE_R ** 2 - TUBE_BORE ** 2) * TUBE_LEN
      + 2.0 / 3.0 * PI * (TUBE_R ** 3 - TUBE_BORE ** 3),
      "One closed seam, the circle r = 4.9 at z = 19.9 (balls r = 0.1 touching the annulus, "
      "the wall and the bore); no junction. The wall's sheet (the cylinder r = 4.9) runs on "
      "into the sphere r = 4.9 between the hemispheres, which no seam touches: the faces "
      "joined to the wall across smooth edges are touched by the sheet's balls only. The "
      "annulus covers 6 % of its face's domain: no centre of a 4 x 4 grid over it is on it.")
def test_tube():
    def body(r, extra):
        cylinder = Part.makeCylinder(r, TUBE_LEN + extra, V(0, 0, 0))
        cap = Part.makeSphere(r, V(0, 0, 0), V(0, 0, 1), -90, 0, 360)
        return cylinder.fuse(cap).removeSplitter()
    return body(TUBE_R, 0.0).cut(body(TUBE_BORE, 1.0)).removeSplitter()


def beaded_ring():
    """The (r, z) profile of a flat ring (r 10 to 20, 2 thick) with a bead of radius 1.5 round
    each rim, centred 1.5 above the bottom (tangent to the walls), revolved about z."""
    top = 2.0
    rise = math.sqrt(1.5 ** 2 - (top - 1.5) ** 2)

    def p(r, z):
        return V(r, 0, z)

    def arc(c, a0, a1):
        mid = 0.5 * (a0 + a1)
        return Part.Arc(*(p(c + 1.5 * math.cos(a), 1.5 + 1.5 * math.sin(a)) for a in (a0, mid, a1)))
    up = math.asin((top - 1.5) / 1.5)
    edges = [
        Part.LineSegment(p(10, 0), p(20, 0)).toShape(),
        Part.LineSegment(p(20, 0), p(20, 1.5)).toShape(),
        arc(18.5, 0.0, PI - up).toShape(),
        Part.LineSegment(p(18.5 - rise, top), p(11.5 + rise, top)).toShape(),
        arc(11.5, up, PI).toShape(),
        Part.LineSegment(p(10, 1.5), p(10, 0)).toShape(),
    ]
    face = Part.Face(Part.Wire(edges))
    return face.revolve(V(0, 0, 0), V(0, 0, 1), 360)


@part("beaded_ring",
      "A flat ring (r 10 to 20, 2 thick) with a bead of radius 1.5 round each rim, centred "
      "1.5 above the bottom and tangent to the wall, rising to z = 3 and meeting the top "
      "z = 2 at a reflex edge (the profile of NIST FTC 11, revolved).",
      None,
      "No vertex, no seam: the beads' axes (the tori's core circles, r = 1.5) are degenerate "
      "curves whose balls touch the bead along an arc, and the wall and the bottom at one "
      "point each (the bottom at the foot of the centre, at no listed touch point); the "
      "bottom is touched by no other ball the report lists.")
def beaded_ring_part():
    return beaded_ring()



@part("filleted_wall_end",
      "Plate 40x30x6 with a wall 20x4x8 standing on it (x 10 to 30, y 13 to 17), its two long "
      "foot edges filleted (r = 2); the fillets end flush with the wall's flat end faces.",
      40 * 30 * 6 + 20 * 4 * 8 + 2 * 20 * (4 - PI),
      "Where a fillet runs into the wall's end face, the end face's convex edge with the "
      "fillet comes down tangent to the floor and turns back along the end face's reflex "
      "foot edge: a cusp vertex. The rim sheet of that convex edge is closed there by a "
      "skeletal edge: the straight line of balls touching the vertex alone, from the vertex "
      "down to the ball where the seam of the fillet, the end face's foot edge and the "
      "plate's bottom ends (a pinch at the vertex, r = 3, centre 3 below it). Every sheet "
      "closes at those vertices.")
def filleted_wall_end():
    body = Part.makeBox(40, 30, 6).fuse(Part.makeBox(20, 4, 8, V(10, 13, 6))).removeSplitter()
    foot = [e for e in body.Edges
            if abs(e.BoundBox.ZMin - 6) < 1e-9 and abs(e.BoundBox.ZMax - 6) < 1e-9
            and abs(e.BoundBox.XLength - 20) < 1e-9
            and min(abs(e.BoundBox.YMin - 13), abs(e.BoundBox.YMin - 17)) < 1e-9]
    assert len(foot) == 2, foot
    return body.makeFillet(2, foot)

@part("round_cut_by_slanted_wall",
      "Block 30x20x10 whose front top edge (along x) is rounded (r = 3), with a slanted wall "
      "fused over it (x > z + 8, y from -5 to 20, up to z = 14): the wall's face crosses the "
      "round along an ellipse from (15, 0, 7) on the round's lower tangent line to "
      "(18, 3, 10) on its upper one.",
      None,
      "The round's axis (y = 3, z = 7) is a degenerate curve whose balls (r = 3) touch the "
      "round along an arc. It starts where its ball touches the end face x = 0 (centre "
      "x = 3); past x = 15 the wall cuts the arc down from below, and it shrinks to the "
      "vertex (18, 3, 10) where the ellipse meets the upper tangent line: the curve ends "
      "there freely, its last ball (centre (18, 3, 7), r = 3) osculating the round at that "
      "vertex and touching nothing else.")
def round_cut_by_slanted_wall():
    block = Part.makeBox(30, 20, 10)
    edge = [e for e in block.Edges
            if abs(e.BoundBox.YMax) < 1e-9 and abs(e.BoundBox.ZMin - 10) < 1e-9
            and abs(e.BoundBox.XLength - 30) < 1e-9]
    assert len(edge) == 1, edge
    block = block.makeFillet(3, edge)
    profile = Part.makePolygon([V(8, -5, 0), V(30, -5, 0), V(30, -5, 14), V(22, -5, 14),
                                V(8, -5, 0)])
    wall = Part.Face(profile).extrude(V(0, 25, 0))
    return block.fuse(wall).removeSplitter()


@part("round_cut_by_skew_wall",
      "Block 30x20x10 whose front top edge (along x) is rounded (r = 3), with a wall fused over "
      "it bounded by the plane x = 8 - y + z (the wall on its +x side, within x 0 to 30, y -5 "
      "to 20, z 0 to 14): the plane crosses the round along an ellipse from (15, 0, 7) to "
      "(15, 3, 10) that reaches x = 12 + 3 sqrt 2 = 16.2426 at the round's middle.",
      None,
      "The round's axis (y = 3, z = 7) is a degenerate curve of balls r = 3 touching the round "
      "along an arc. It starts where its ball touches the end face x = 0 (centre x = 3); past "
      "x = 15 the wall cuts the arc from both ends, and it shrinks to the point of the ellipse "
      "farthest along the axis, (16.2426, 0.8787, 9.1213), at 45 degrees round the round: the "
      "curve ends there freely, its last ball (centre (16.2426, 3, 7), r = 3) osculating the "
      "round at that point of the edge and touching nothing else.")
def round_cut_by_skew_wall():
    block = Part.makeBox(30, 20, 10)
    edge = [e for e in block.Edges
            if abs(e.BoundBox.YMax) < 1e-9 and abs(e.BoundBox.ZMin - 10) < 1e-9
            and abs(e.BoundBox.XLength - 30) < 1e-9]
    assert len(edge) == 1, edge
    block = block.makeFillet(3, edge)
    # The half-space x - 8 + y - z >= 0: a large box whose face x = 0 is turned onto the
    # plane's normal (1, 1, -1)/sqrt(3) and moved onto the point (8, 0, 0).
    half = Part.makeBox(400, 400, 400, V(0, -200, -200))
    half.rotate(V(0, 0, 0), V(0, 1, 1), math.degrees(math.acos(1 / math.sqrt(3))))
    half.translate(V(8, 0, 0))
    wall = Part.makeBox(30, 25, 14, V(0, -5, 0)).common(half)
    return block.fuse(wall).removeSplitter()


@part("rib_end_under_a_wide_ball",
      "Block 40x34x40 (x -20 to 20, y 0 to 34, z 0 to 40) with a rib under its bottom face: "
      "2.8 wide (y 15.8 to 18.6), 3 deep, from the end x = -20 to x = -3.6, where it ends in "
      "a half-round (radius 1.4 about the vertical line x = -3.6, y = 17.2).",
      40 * 34 * 40 + 2.8 * 3 * 16.4 + 3 * PI * 1.4 ** 2 / 2,
      "Balls of r = 17 fill the block between the walls y = 0 and y = 34 from x = -3 to 3 "
      "(17 from the end faces). A junction at x = -3: the ball centred (-3, 17, 16.9827) "
      "touches both walls, the end face x = -20 and the foot arc of the rib's round end "
      "(0.6325 from the arc's axis in plan, so 0.7675 from the arc). From it the seam of the "
      "two walls runs along x with its third touch point on the arc until, past "
      "x = -3.6 + sqrt(1.4^2 - 0.2^2) = -2.2143, the ball touches the bottom face directly "
      "below its centre; it ends at the junction x = 3. The seam of the wall y = 34, the "
      "bottom and the end face x = -20 (centres x + 20 = 34 - y = r) is handed from the "
      "bottom to the rib's foot edge y = 18.6 and round the arc to the junction, its touch "
      "point turning round the arc about 2.6 rad per mm of the centre's travel. A step whose "
      "linear predictor overshoots that turn lands the corrector on the arc's far side; it "
      "is refused (the tracer once ended that seam open, oscillating between the arc's two "
      "edges).")
def rib_end_under_a_wide_ball():
    block = Part.makeBox(40, 34, 40, V(-20, 0, 0))
    rib = Part.makeBox(16.4, 2.8, 3, V(-20, 15.8, -3))
    end = Part.makeCylinder(1.4, 3, V(-3.6, 17.2, -3), V(0, 0, 1))
    return block.fuse(rib.fuse(end)).removeSplitter()


def soft_corner(start, t0, end, t1, a, b):
    """A cubic B-spline in the plane z = 0 from `start` (leaving along `t0`) to `end`
    (arriving along `t1`) whose curvature is 0 at both ends: its first three poles lie on the
    start tangent, its last three on the end tangent (the G2 blend some exporters write for
    a rounded corner)."""
    s, e = V(*start, 0), V(*end, 0)
    d0, d1 = V(*t0, 0), V(*t1, 0)
    poles = [s, s + d0 * a, s + d0 * (2 * a), e - d1 * (2 * b), e - d1 * b, e]
    c = Part.BSplineCurve()
    c.buildFromPoles(poles, False, 3)
    return c.toShape()


SOFT_KINK = 0.0038


@part("tab_with_soft_corners",
      "Plate 14x13.5x3.3 (x -6 to 8, y -6 to 7.5, z -3.3 to 0) with a tab 0.4 high on it: "
      "x 0 to 1.62, y 0 to 1.49, its end x = 0 a line from y = 0.49 to 1.04 joined to the "
      "sides y = 0 and y = 1.49 by soft corners (cubic B-splines with zero curvature at both "
      "ends, reaching 0.83 and 0.78 along x), each leaving the end line 0.0038 rad (0.22 "
      "deg) off its direction, bent outwards: the end wall and each corner's wall meet at a "
      "convex kink within the 1 degree tangent tolerance (a smooth edge), as a Voron part's "
      "tab is written.",
      None,
      "By the tolerance the end wall and the corners' walls are one tangent wall, so the "
      "kinks' sheets are not part of the medial axis: no seam runs down a kink from its top "
      "vertex (a ball there touches the two walls 0.0015 mm apart at r = 0.4, one place by "
      "the separation sqrt(8 r a)). Under the tab, balls touch the tab's reflex foot edges "
      "and its top (r up to 0.89) or the plate's bottom (r 1.65 to 1.73); on the seams of "
      "the end line's foot and an upper corner's foot, the touch point on the end line "
      "passes across the kink onto that corner's foot (the same ball touches it r sin 0.0038 "
      "further on), and the seam ends at the corner's curvature limit. (The tracer once seeded a seam of the "
      "kink's two walls and the tab's top, which met the foot edges at a junction with two "
      "touch points 0.0017 mm apart: a junction with 3 seam ends, sheets not closed.)")
def tab_with_soft_corners():
    plate = Part.makeBox(14, 13.5, 3.3, V(-6, -6, -3.3))
    return plate.fuse(soft_cornered_tab()).removeSplitter()


def soft_cornered_tab():
    """The tab of `tab_with_soft_corners`: 0.4 high on z = 0."""
    k = SOFT_KINK
    outline = [
        Part.makeLine(V(1.62, 0, 0), V(1.62, 1.49, 0)),
        Part.makeLine(V(1.62, 1.49, 0), V(0.78, 1.49, 0)),
        soft_corner((0.78, 1.49), (-1, 0), (0, 1.04), (-math.sin(k), -math.cos(k)),
                    0.25, 0.15),
        Part.makeLine(V(0, 1.04, 0), V(0, 0.49, 0)),
        soft_corner((0, 0.49), (-math.sin(k), -math.cos(k)), (0.83, 0), (1, 0), 0.15, 0.25),
        Part.makeLine(V(0.83, 0, 0), V(1.62, 0, 0)),
    ]
    return Part.Face(Part.Wire(Part.__sortEdges__(outline))).extrude(V(0, 0, 0.4))


@part("pocket_with_soft_corners",
      "Block 14x13.5x3.7 (x -6 to 8, y -6 to 7.5, z -3.3 to 0.4) with a pocket 0.4 deep "
      "cut from its top, shaped as the tab of tab_with_soft_corners: its end wall x = 0 meets "
      "its soft corners' walls at kinks of 0.0038 rad (0.22 deg), reflex seen from the "
      "material, within the 1 degree tangent tolerance (smooth edges).",
      None,
      "The block's mid-height sheet (z = -1.45; balls r = 1.85 touching its top and bottom) "
      "has the seams from its corners and a closed seam round the pocket, where those balls "
      "also touch the reflex edges at the foot of the pocket's walls (1.15 outside them in "
      "plan): its touch point passes each kink from edge to edge, or through the kink's "
      "vertex. No seam runs along a kink (by the tolerance the walls there are one tangent "
      "wall). Euler characteristic 1. (The tracer once seeded a seam on a kink here, ran it "
      "out of points and ended it open.)")
def pocket_with_soft_corners():
    block = Part.makeBox(14, 13.5, 3.7, V(-6, -6, -3.3))
    return block.cut(soft_cornered_tab()).removeSplitter()


def drill_along_z(radius, shoulder, length):
    """A drill's shape along +z: the hole r = `radius` from the shoulder z = `shoulder` up
    `length`, with a 118 degree drill point below the shoulder."""
    tip = radius / math.tan(math.radians(59))
    return Part.makeCylinder(radius, length, V(0, 0, shoulder), V(0, 0, 1)).fuse(
        Part.makeCone(0, radius, tip, V(0, 0, shoulder - tip), V(0, 0, 1)))


@part("bar_with_a_drilled_end",
      "Round bar r = 8, 40 long (axis x = y = 0, z 0 to 40), with a coaxial blind hole r = 3 "
      "drilled into its end z = 40, 12 mm deep to the shoulder (z = 28), ending in a 118 "
      "degree drill point whose apex is 3/tan 59 deg = 1.80 mm further (z = 26.197).",
      PI * 64 * 40 - PI * 9 * 12 - PI * 9 * (3 / math.tan(math.radians(59))) / 3,
      "Round the hole, the sheet between its wall and the bar's wall (r = 2.5 along the "
      "cylinders) is closed at the mouth by a circular seam (the end face, the hole's wall, "
      "the bar's wall) and runs on past the shoulder's rim, over the drill point's cone and "
      "its apex, to the bar's axis: the axis is a degenerate curve (r = 8) from the ball "
      "touching the bottom face (centre z = 8) to the one touching the apex (z = 18.197). "
      "No seam or junction ball touches the cone; the axis's last ball touches its apex.")
def bar_with_a_drilled_end():
    return Part.makeCylinder(8, 40).cut(drill_along_z(3, 28, 12)).removeSplitter()


@part("tapered_pin_with_a_drilled_end",
      "A pin: a cylinder r = 8 from z = 0 to 20, then a cone narrowing to r = 5 at z = 40 "
      "(half-angle atan(3/20) = 8.53 deg), with a blind hole r = 2 drilled into its top "
      "4.8 mm deep to the shoulder (z = 35.2), ending in a 118 degree drill point (apex at "
      "z = 35.2 - 2/tan 59 deg = 33.998).",
      PI * 64 * 20 + PI * 20 * (64 + 40 + 25) / 3 - PI * 4 * 4.8
      - PI * 4 * (2 / math.tan(math.radians(59))) / 3,
      "The pin's axis is one degenerate curve: from the ball touching the bottom face "
      "(centre z = 8, r = 8) up the cylinder's axis (r = 8), past the convex circle at z = 20 "
      "onto the cone's axis, whose balls touch the cone along a circle above their centre "
      "(r shrinking: the ball centred at z0 touches the cone where its normal, 8.53 deg off "
      "horizontal, meets the axis), to the ball that touches the drill point's apex (centre "
      "z = 27.1470, r = 6.8513). The hand-over is at the ball centred z = 19.4033 (r = 8), "
      "touching the cylinder along the circle z = 19.4033 and the cone along z = 20.5901; "
      "the rim sheet of the convex circle between them ends there, a disc joined to the axis "
      "at that one point. The medial axis's Euler characteristic is 1.")
def tapered_pin_with_a_drilled_end():
    pin = Part.makeCylinder(8, 20).fuse(Part.makeCone(8, 5, 20, V(0, 0, 20)))
    return pin.removeSplitter().cut(drill_along_z(2, 35.2, 4.8)).removeSplitter()


@part("frustum",
      "A truncated cone: r = 10 at z = 0 narrowing to r = 6 at z = 30 (half-angle "
      "atan(4/30) = 7.59 deg).",
      PI * 30 * (100 + 60 + 36) / 3,
      "Its axis is one degenerate curve whose balls touch the cone all round, along a circle "
      "above their centre (the cone's normal meets the axis below the point it leaves), from "
      "the ball touching the bottom face to the one touching the top face; two rims' sheets "
      "end at those balls. The medial axis's Euler characteristic is 1, counted.")
def frustum():
    return Part.makeCone(10, 6, 30)


@part("box_with_a_mitred_corner",
      "Box 40x30x10 (x 0 to 40, y 0 to 30, z 0 to 10) with two edges at its corner (40, 0, "
      "10) rounded r = 3: the vertical edge x = 40, y = 0 and the top edge x = 40, z = 10. "
      "The two rounds meet in a mitre: an ellipse between the two cylinders, convex, whose "
      "angle opens to 180 degrees at its lower end (40, 3, 7), where both rounds are tangent "
      "to the side face x = 40.",
      None,
      "The sheet of the mitre's rim ends at its lower vertex along a free edge: the balls "
      "tangent to both rounds there, centres (40 - s, 3, 7) and radius s for s from 0 to 3, "
      "up to the ball at (37, 3, 7) where the two rounds' axes end (each a degenerate curve "
      "touching its round along a quarter circle). Before, that rim's end was the only arc "
      "end at the vertex and the sheet did not close. The Euler characteristic is withheld "
      "(the rounds' axes bound sheets, not yet in the cell count).")
def box_with_a_mitred_corner():
    box = Part.makeBox(40, 30, 10)

    def corner_edge(e):
        p, q = e.Vertexes[0].Point, e.Vertexes[1].Point
        at_x = abs(p.x - 40) < 1e-9 and abs(q.x - 40) < 1e-9
        vertical = abs(p.y) < 1e-9 and abs(q.y) < 1e-9
        top = abs(p.z - 10) < 1e-9 and abs(q.z - 10) < 1e-9
        return at_x and (vertical or top)

    return box.makeFillet(3, [e for e in box.Edges if corner_edge(e)])


def bar_into_a_block(block):
    """A bar 20x12x8 (x 0 to 20, y 0 to 12, z 0 to 8) fused to `block` (as high) at its end
    x = 20, its edge between the top z = 8 and the side y = 0 rounded r = 3 up to the block."""
    s = Part.makeBox(20, 12, 8).fuse(block).removeSplitter()
    edge = [e for e in s.Edges
            if e.BoundBox.ZMin > 8 - 1e-9 and e.BoundBox.YMax < 1e-9 and e.BoundBox.XMin < 1e-9]
    return s.makeFillet(3, edge)


@part("round_ending_at_a_wall",
      "A bar 20x12x8 (x 0 to 20, y 0 to 12, z 0 to 8) running into a block 10x17x8 (x 20 to "
      "30, y -5 to 12), its edge between its top and its side y = 0 rounded r = 3 up to the "
      "block's wall x = 20. The round ends against the wall in a quarter circle (a reflex "
      "edge); above it the wall shows a sliver between the circle and the top, which narrows "
      "to nothing at the vertex (20, 3, 8) where the round is tangent to the top.",
      None,
      "The sheet of the top and the sliver (the rim of their convex edge) goes on past the "
      "sliver's foot as the sheet of the top and the quarter circle, whose two touch points "
      "meet at (20, 3, 8): it ends along a free edge, the balls tangent to the top there, "
      "centres (20, 3, 8 - s) and radius s, up to the ball at (20, 3, 5), r = 3, on the "
      "round's axis (a degenerate curve touching the round along a quarter circle). Before, "
      "the rim's end was the only arc end at that vertex and the sheet did not close.")
def round_ending_at_a_wall():
    return bar_into_a_block(Part.makeBox(10, 17, 8, V(20, -5, 0)))


@part("round_ending_at_a_skew_wall",
      "round_ending_at_a_wall with the block turned 30 degrees about the vertical line x = 20, "
      "y = 0 (a block 10x22x8 from (20, -8, 0), turned): the round ends against the skew wall "
      "in an ellipse, and the vertex where it is tangent to the top is (18.268, 3, 8).",
      None,
      "As in round_ending_at_a_wall, the sheet of the top and the wall's sliver ends along a "
      "free edge from (18.268, 3, 8) straight down to the round's axis, centres (18.268, 3, "
      "8 - s), radius s up to 3; the axis goes on past that ball (its arc of contact narrowing "
      "to the vertex (20, 0, 5) where the ellipse meets the bar's side), so the free edge meets "
      "it between two of its balls.")
def round_ending_at_a_skew_wall():
    block = Part.makeBox(10, 22, 8, V(20, -8, 0))
    block.rotate(V(20, 0, 0), V(0, 0, 1), 30)
    return bar_into_a_block(block)


@part("boss_against_a_taller_boss",
      "A plate 40x30x5 (x -15 to 25, y -15 to 15) with two bosses r=5 that overlap: one 4 "
      "high centred (0, 0), one 9 high centred (8, 0). The low boss's top rim ends against "
      "the tall boss's wall at (4, +-3, 9), each a vertex with the rim (convex) and two "
      "reflex edges to that wall.",
      40 * 30 * 5 + (4 + 9) * 25 * PI - 4 * (50 * math.acos(0.8) - 4 * 6),
      "The rim's sheet (balls touching the low boss's top and wall) ends at each of those "
      "vertices along a free edge: the balls tangent to the tall boss's wall there, centres "
      "(4, +-3, 9) + s(0.8, -+0.6, 0) and radius s, up to s = 5 on the tall boss's axis "
      "(8, 0, 9), the top end of its degenerate curve (balls r = 5 on the axis from z = 5 to "
      "9, touching its wall all round; the one at z = 9 touches its cap). Before, the rim "
      "ended there with nothing to pair it and the sheet did not close.")
def boss_against_a_taller_boss():
    plate = Part.makeBox(40, 30, 5, V(-15, -15, 0))
    low = Part.makeCylinder(5, 4, V(0, 0, 5))
    tall = Part.makeCylinder(5, 9, V(8, 0, 5))
    return plate.fuse(low).fuse(tall).removeSplitter()


@part("flange_on_a_shaft",
      "A disc r=4, 4 thick (z 0 to 4) with a shaft r=2, 6 long, standing on its top face. "
      "The disc's radius less its half-thickness is the shaft's radius.",
      PI * (16 * 4 + 4 * 6),
      "The disc's balls of radius 2 touching both its faces and its rim are centred on the "
      "circle of radius 2 at z = 2, and touch the top face exactly on the shaft's foot "
      "circle (a reflex edge): the seam seeded there on the top face hands its touch point "
      "onto that circle at once and goes round on it, so it closes where its ball comes "
      "back, not where its elements do (before, it went round to the point budget, 20,000 "
      "points each way: 40,072 points), and it is the circle's seam seeded on another "
      "sheet: one seam, traced once. The Euler characteristic is not yet the solid's "
      "(issue 20: the shaft's and the disc's degenerate curves are not joined to the "
      "sheets).")
def flange_on_a_shaft():
    return Part.makeCylinder(4, 4).fuse(Part.makeCylinder(2, 6, V(0, 0, 4))).removeSplitter()


PLANE_ORIGIN = (50.0, 68.0, 101.0)


def plane_origins_off_faces(text):
    """Writes every PLANE's placement point at the projection of PLANE_ORIGIN on it, its
    axes unchanged (the same planes; OCCT's sample refrigerator places its planes so): the
    faces' corners then fall on either side of their trim tests by rounding."""
    def offset(d, p):
        v = [PLANE_ORIGIN[k] - p[k] for k in range(3)]
        dn = sum(v[k] * d[k] for k in range(3))
        return [v[k] - dn * d[k] for k in range(3)]

    return shift_plane_points(text, offset)[0]


@part("shelf_twice_the_walls",
      "A box 46x70x148 with two cavities open at x = 46, one above the other (x 2 to 46, "
      "y 2 to 68; z 7 to 101 and 105 to 146): walls 2 thick at the back and the sides, and "
      "a shelf between the cavities 4 thick, twice the walls (as OCCT's sample "
      "refrigerator). Every plane is written with its placement point at the projection of "
      "(50, 68, 101) on it, as that sample's are.",
      46 * 70 * 148 - 44 * 66 * (94 + 41),
      "Where the shelf meets the back wall and a side wall, the balls of the seams between "
      "the back, the side and one face of the shelf grow to r = 2 at the shelf's mid-plane, "
      "where they touch the back and the side inside and both faces of the shelf exactly at "
      "their corners (the cavities' corner vertices): the junction is on those faces' "
      "borders, and the seams end there. Before, a corner computed 7e-15 mm outside its "
      "face's trim test was refused, and a seam ended open (a touch point oscillating "
      "between the shelf face and its corner vertex; on the sample refrigerator four ended "
      "open, no junction on the segments).",
      edit=plane_origins_off_faces)
def shelf_twice_the_walls():
    box = Part.makeBox(46, 70, 148)
    for z, h in ((7, 94), (105, 41)):
        box = box.cut(Part.makeBox(44, 66, h, V(2, 2, z)))
    return box.removeSplitter()


@part("shelf_flush_with_the_back_wall",
      "A box 30x40x50 with two cavities open at x = 0, one above the other (x 0 to 28, "
      "y 2 to 38; z 2 to 23 and 27 to 48): walls 2 thick at the back (x 28 to 30), the "
      "sides, the bottom and the top, and a shelf 4 thick between the cavities.",
      30 * 40 * 50 - 2 * 28 * 36 * 21,
      "The seam of the balls touching the back wall's outer face (x = 30) and both shelf "
      "faces is the line x = 28, z = 25, r = 2, from y = 2 to 38: its touch points on the "
      "shelf faces run exactly along those faces' edges with the cavities' back walls "
      "(x = 28). It leaves the junctions at the shelf's corners (touching a side, the back "
      "and both shelf faces at their corner vertices) along the faces' borders. Before, a "
      "touch point was handed between a shelf face, its edge and its corner vertex without "
      "the seam moving, and two seams ended open (oscillates).")
def shelf_flush_with_the_back_wall():
    box = Part.makeBox(30, 40, 50)
    for z in (2, 27):
        box = box.cut(Part.makeBox(28, 36, 21, V(0, 2, z)))
    return box.removeSplitter()


def plate_through_split_hub(length):
    """A hub r=36 along x from x=-length to 0, written as two half cylinders split at its top
    and bottom, fused with a plate 2 mm thick (x -40..40, y -50..50) through it."""
    s = Part.makeBox(80, 100, 2, V(-40, -50, -1))
    for a in (0, 180):
        half = Part.makeCylinder(36, length, V(-length, 0, 0), V(1, 0, 0), 180)
        half.rotate(V(0, 0, 0), V(1, 0, 0), a)
        s = s.fuse(half)
    # No removeSplitter: it would merge the halves into one cylinder.
    return s


@part("plate_through_a_split_hub",
      "A hub r=36 along x from x=-68 to 0, its wall written as two half cylinders split at "
      "its top and bottom (as CATIA writes the CAx-IF's tail turbine), through which a plate "
      "2 mm thick (x -40..40, y -50..50) passes.",
      None,
      "The plate cuts a notch 2 mm tall into each half cylinder. The seams of the hub's back, "
      "its wall and an edge where the plate meets the hub's front run with a touch point "
      "round a half cylinder in steps longer than the notch, its parameters a period past the "
      "face's (handed over between the halves at the bottom). The trim path test now shifts "
      "a step on a periodic face by whole periods onto the loops; it was not made at all, a "
      "step over the notch went unseen, and four seams ended open (no junction with the "
      "plate's other edge at the front). The geometric test is a unit test on this part "
      "(geom::trim::path).")
def plate_through_a_split_hub():
    return plate_through_split_hub(68)


PLATE_END_GAP = 2e-3


def plate_ends_off_their_edges(text):
    """Moves the two planes of the plate's ends at x = -40 by PLATE_END_GAP along x, their
    edges left on the hub's wall and the plate's faces, and declares an uncertainty of
    0.01 mm (the CAx-IF's tail turbine has its plate's end 2e-3 mm off its edges)."""
    import re

    def offset(d, p):
        if abs(abs(d[0]) - 1) < 1e-9 and abs(p[0] + 40) < 1e-6:
            return [PLATE_END_GAP, 0.0, 0.0]
        return None

    text, moved = shift_plane_points(text, offset)
    if moved != 2:
        raise SystemExit(f"plate_ends_off_their_edges: {moved} planes moved, not 2")
    return re.sub(r"UNCERTAINTY_MEASURE_WITH_UNIT\(LENGTH_MEASURE\([^)]*\)",
                  "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-02)", text)


@part("plate_end_off_its_edges_in_a_split_hub",
      "plate_through_a_split_hub with the planes of the plate's two ends (x = -40) written "
      "2e-3 mm off their edges, and an uncertainty of 0.01 mm declared.",
      None,
      "Where the plate's end meets the hub's wall, the seam of the end's arc edge, the "
      "plate's top edge along the wall and the hub's back runs until both touch points "
      "meet at their shared vertex: a pinch. With the end's arc 2e-3 mm off the vertex, the "
      "touch point on the arc was handed to the wall and back without the seam moving, and "
      "two seams ended open (oscillates); now the pinch at that vertex ends them.",
      edit=plate_ends_off_their_edges)
def plate_end_off_its_edges_in_a_split_hub():
    return plate_through_a_split_hub()


@part("slot_over_a_split_hub",
      "A hub r=36 along x from x=-80 to 0 written as two half cylinders split at its top and "
      "bottom, a plate 2 mm thick (x -40..40, y -50..50) through it, and a slot 3 mm wide, "
      "20 long and 6 deep (x -56.6..-36.6) cut in the hub's top.",
      None,
      "A closed seam (the ball touching the hub's back, its wall and an edge of the slot, "
      "round through ten hand-overs) is seeded and must close where it comes back to its "
      "seed. Its radius changes along it about 0.6 times as fast as the centre moves, and "
      "the seed lies anywhere on a step: the closing test compared the seed's radius with "
      "the step's end (0.9 mm off) instead of the chord's point beside the seed (1e-3 mm), "
      "and the seam went round 99 times to the point budget (40,368 points, both ends "
      "open); now 442 points in all, no end open.")
def slot_over_a_split_hub():
    return plate_through_split_hub(80).cut(Part.makeBox(20, 3, 10, V(-56.6, -1.5, 30)))


@part("pad_doubling_a_tube_wall",
      "A sector of a tube along x (r 72 to 73, x -20..20, z >= 60) with a flat pad 5 wide "
      "(x 5..20) on its top whose face is the plane z = 74, tangent to r = 74: the wall is "
      "2 thick under the pad's middle, 1 beside it, and the pad's end (x = 5) steps down by "
      "1 to the tube's outer face (as the CAx-IF's s1 main body front, from UG through "
      "Theorem's translator).",
      None,
      "Under the pad the wall's half thickness equals the step's height: the balls touching "
      "the pad's face, the tube's inner face and the pad's end touch the end at its foot, the "
      "arc r = 73, tangentially, once (under the pad's middle, where the wall is thinnest). "
      "A step's chord there dips across the arc by its sagitta: the touch point was handed "
      "onto the arc and back, and two seams ended open (oscillates). Now a touch point that "
      "runs along that arc shortens its step until the chord stays within the accuracy of it, "
      "and the seam runs on through the graze: no end open, both checkers pass.")
def pad_doubling_a_tube_wall():
    outer = Part.makeCylinder(73, 40, V(-20, 0, 0), V(1, 0, 0))
    inner = Part.makeCylinder(72, 40, V(-20, 0, 0), V(1, 0, 0))
    tube = outer.cut(inner).common(Part.makeBox(40, 60, 80, V(-20, -30, 60)))
    pad = Part.makeBox(15, 5, 3, V(5, -2.5, 71)).cut(inner)
    return tube.fuse(pad).removeSplitter()


def bottle_thread(radius, height):
    """The threading of OCCT's tutorial bottle on a neck of `radius` and `height` from z = 0:
    the loft between two wires on the cylinders 0.99 and 1.05 times the radius, each half an
    ellipse in the cylinder's (angle, z) parameters (major 2 pi along (2 pi, height / 4) from
    (2 pi, height / 2), minor height / 10 and a quarter of that) closed by its major axis."""
    V2 = L.FreeCAD.Base.Vector2d
    c1, c2 = Part.Cylinder(), Part.Cylinder()
    c1.Radius, c2.Radius = radius * 0.99, radius * 1.05
    centre = V2(2 * PI, height / 2)
    d = V2(2 * PI, height / 4)
    n = math.hypot(d.x, d.y)
    along, across = V2(d.x / n, d.y / n), V2(-d.y / n, d.x / n)
    major = 2 * PI

    def ellipse(minor):
        return Part.Geom2d.Ellipse2d(centre + V2(along.x * major, along.y * major),
                                     centre + V2(across.x * minor, across.y * minor), centre)
    e1, e2 = ellipse(height / 10), ellipse(height / 40)
    axis = Part.Geom2d.Line2dSegment(e1.value(0), e1.value(PI))
    wires = [Part.Wire([Part.Geom2d.ArcOfEllipse2d(e, 0, PI).toShape(c), axis.toShape(c)])
             for e, c in ((e1, c1), (e2, c2))]
    return Part.makeLoft(wires, True)


@part("threaded_bottle",
      "OCCT's tutorial bottle made in FreeCAD by the tutorial's steps (MakeBottle with width "
      "70, height 50, thickness 30): the profile's two arcs and segments extruded 50, every "
      "edge filleted 2.5, a neck r 7.5 and 5 high fused on top, hollowed to a wall 0.6 thick "
      "through the neck's top, and the threading fused on the neck.",
      None,
      "Along the thread the balls touch the neck's inner wall and the thread's two feet on "
      "the neck's outer wall, the wall being 0.6 thick: r = 0.3 + (half the thread's width at "
      "its foot)^2 / 1.2, down to 0.3 at the thread's ends, where the feet meet at a vertex. "
      "There the outer wall beyond the end comes in (closer than r by a hair, within the "
      "polygon's stray of the feet's loop: a coarse_trim warning) just as the touch points on "
      "the feet meet: the seam ended open (no junction with the outer wall; on OCCT's own "
      "sample bottle the steps shrank to nothing before the end instead). Now both ends are "
      "pinches at the thread's ends.")
def threaded_bottle():
    w, h, t = 70.0, 50.0, 30.0
    p1, p2, p3 = V(-w / 2, 0, 0), V(-w / 2, -t / 4, 0), V(0, -t / 2, 0)
    p4, p5 = V(w / 2, -t / 4, 0), V(w / 2, 0, 0)
    half = Part.Wire([Part.LineSegment(p1, p2).toShape(), Part.Arc(p2, p3, p4).toShape(),
                      Part.LineSegment(p4, p5).toShape()])
    turn = L.FreeCAD.Matrix()
    turn.rotateZ(PI)
    other = half.copy()
    other.transformShape(turn)
    body = Part.Face(Part.Wire([half, other])).extrude(V(0, 0, h))
    body = body.makeFillet(t / 12, body.Edges)
    radius, height = t / 4, h / 10
    body = body.fuse(Part.makeCylinder(radius, height, V(0, 0, h)))
    top = max((f for f in body.Faces if isinstance(f.Surface, Part.Plane)),
              key=lambda f: f.Surface.Position.z)
    body = body.makeThickness([top], -t / 50, 1e-3)
    thread = bottle_thread(radius, height)
    thread.translate(V(0, 0, h))
    return body.fuse(thread).removeSplitter()


def elliptic_boss_in_halves():
    """Plate 40x30x4 with an elliptic boss (semi-axes 10 and 5, 3 high) on its top, the
    ellipse written as two half arcs meeting at the ends of its major axis."""
    ellipse = Part.Ellipse(V(20, 15, 4), 10, 5)
    halves = [Part.ArcOfEllipse(ellipse, a, a + PI).toShape() for a in (0, PI)]
    boss = Part.Face(Part.Wire(halves)).extrude(V(0, 0, 3))
    return Part.makeBox(40, 30, 4).fuse(boss)


ELLIPTIC_BOSS_NOTE = (
    "Where the boss's wall and its foot end at the ellipse's major vertices, the seams "
    "between the two halves run out to the vertices' centre of curvature (r·κ = 1 on the "
    "half walls, or the feet's two touch points meeting at the vertex): the touch points on "
    "the two halves, one tangent surface or curve, meet there, and the seams ended open "
    "(two touch points coincide); now they end at that curvature limit (or at a pinch at "
    "the vertex, where both touch points are there)."
)


@part("elliptic_boss_in_halves",
      "Plate 40x30x4 with an elliptic boss (semi-axes 10 and 5, 3 high) on its top, centred "
      "at (20, 15), its wall and foot written as two halves meeting at the ends of the major "
      "axis (as exporters split closed curves).",
      40 * 30 * 4 + PI * 50 * 3, ELLIPTIC_BOSS_NOTE)
def elliptic_boss_in_halves_analytic():
    return elliptic_boss_in_halves()


@part("elliptic_boss_in_halves_nurbs",
      "elliptic_boss_in_halves with every face and edge as NURBS (OCCT's volume of it is "
      "1.8e-4 above the exact one, matrace's 1.5e-7 below: checked loosely here).",
      40 * 30 * 4 + PI * 50 * 3, ELLIPTIC_BOSS_NOTE, volume_rel=1e-3)
def elliptic_boss_in_halves_nurbs():
    return elliptic_boss_in_halves().toNurbs()


def kinked_ellipse(cx, cy, a, b, z, kink, start=-PI / 2):
    """A closed ellipse (semi-axes a along x, b along y) written as two B-spline halves
    through nine of its points each, joined at the ends of its y axis (or at the angles
    `start` and `start` + π) with their end tangents turned by `kink` radians towards the
    outside: two corners of 2·kink, as a font's outline joins its curves."""
    def half(t0, t1):
        pts = [V(cx + a * math.cos(t), cy + b * math.sin(t), z)
               for t in (t0 + (t1 - t0) * k / 8 for k in range(9))]

        def tangent(t, turn):
            d = V(-a * math.sin(t), b * math.cos(t), 0)
            d.normalize()
            c, s = math.cos(turn), math.sin(turn)
            return V(c * d.x - s * d.y, s * d.x + c * d.y, 0)
        curve = Part.BSplineCurve()
        curve.interpolate(pts, InitialTangent=tangent(t0, kink),
                          FinalTangent=tangent(t1, -kink))
        return curve.toShape()
    return Part.Wire([half(start, start + PI), half(start + PI, start + 2 * PI)])


# The embossed glyphs' block (2x1.25, its top at EMBOSSED_TOP), the lettering's height and the
# half-angle of its outlines' kinked joins.
EMBOSSED_TOP, EMBOSSED_HEIGHT, EMBOSSED_KINK = 0.78, 0.003, math.radians(1.35)


def embossed(outline):
    """The block with the glyph `outline` (a face in the top's plane) embossed on its top."""
    body = Part.makeBox(2, 1.25, EMBOSSED_TOP, V(-1, -0.625, 0))
    return body.fuse(outline.extrude(V(0, 0, EMBOSSED_HEIGHT))).removeSplitter()


EMBOSSED_EIGHT_NOTE = (
    "The seam under the lower bowl's stroke (balls touching the glyph's top and the foot "
    "edges on either side of the stroke) curves round the bowl; where its touch points reach "
    "the outline's kinked joins at the bottom, a long step landed past the foot edge's end "
    "on another stretch of the seam, and every shorter probe of the hand-over's bisection "
    "failed on the turn of its tangent: the 'crossing' found was where the probes began to "
    "fail, and the seam ended open (no seam point after handing the foot edge to the top "
    "face, the system singular). The step is now shortened instead, and the seam goes on. "
    "Below the waist, balls touch the outline's foot corners 2 µm apart, closer than the "
    "checkers separate places on elements that do not meet (`separated`, both checkers)."
)


@part("embossed_eight",
      "A block 2x1.25x0.78 with an '8' embossed 0.003 high on its top, as a KiCad resistor's "
      "value is lettered: the outline is two ellipses fused (0.082x0.078 about (0.1, 0.2) "
      "and 0.07x0.066 about (0.1, 0.33)) less two elliptic counters (0.05x0.048 and "
      "0.04x0.035), each ellipse two B-spline halves meeting at 2.7-degree corners.",
      None, EMBOSSED_EIGHT_NOTE)
def embossed_eight():
    z, kink = EMBOSSED_TOP, EMBOSSED_KINK
    outline = Part.Face(kinked_ellipse(0.1, 0.2, 0.082, 0.078, z, kink)).fuse(
        Part.Face(kinked_ellipse(0.1, 0.33, 0.07, 0.066, z, kink)))
    for cx, cy, a, b in ((0.1, 0.2, 0.05, 0.048), (0.1, 0.335, 0.04, 0.035)):
        outline = outline.cut(Part.Face(kinked_ellipse(cx, cy, a, b, z, kink)))
    return embossed(outline)


EMBOSSED_ZERO_NOTE = (
    "Along the side strokes, the seam under the stroke (balls touching the glyph's top, the "
    "outline's foot edge and, across the stroke, the counter's foot) reaches the outline's "
    "kinked join, a corner pointing out of the stroke whose two foot edges both come closer "
    "than r beside it, within one step of where its touch point across the stroke leaves the "
    "counter's kinked foot vertex for the next foot edge (the counter 0.0003 higher than the "
    "outline). The two events were located in the wrong order: the junction with the "
    "outline's next foot edge touches the counter's vertex, not the edge the touch point had "
    "been handed to, and the seam ended open (no seam point after handing the outline's "
    "vertex to its next edge, or that edge closer than r with no junction). The junction is "
    "now solved with that hand-over undone, before it. The wall halves meeting at each of "
    "the outline's two kinks bound two small sheets, one at each kink, which the sheets "
    "count as one sheet with two loops (Euler characteristic -1 for the solid's 1: issue "
    "20)."
)


@part("embossed_zero",
      "A block 2x1.25x0.78 with an 'O' embossed 0.003 high on its top: the outline an "
      "ellipse 0.08x0.12 about (0.1, 0.3) less an elliptic counter 0.05x0.09 about "
      "(0.1, 0.3003), each two B-spline halves meeting at the ends of its x axis at "
      "2.7-degree corners, the counter's corners 0.0003 above the outline's.",
      None, EMBOSSED_ZERO_NOTE)
def embossed_zero():
    z, kink = EMBOSSED_TOP, EMBOSSED_KINK
    outline = Part.Face(kinked_ellipse(0.1, 0.3, 0.08, 0.12, z, kink, start=0.0)).cut(
        Part.Face(kinked_ellipse(0.1, 0.3003, 0.05, 0.09, z, kink, start=0.0)))
    return embossed(outline)



SOCKET_BETWEEN_SHELVES_NOTE = (
    "On each side of the socket a seam's balls touch the block's side face and, twice, the "
    "hyperbola where the socket's chamfer cone meets its flat on that side (a reflex edge of "
    "the solid); the two touch points close in on the hyperbola's top and meet there, at the "
    "edge's curvature limit (r about 0.3146, the side face touched about 0.420 high). The "
    "shelf's reflex edge is 1 and 2 µm above that: the step that passed the limit also "
    "passed the edge, and the hand-over onto it found the two touch points coinciding (or, "
    "on the other side, no ball), so both seams ended open. The limit is now located first, "
    "as after an ordinary step, and ends both seams."
)


@part("socket_between_shelves",
      "A block 1.6x2x2 about the origin with a socket inside (a ring-shaped void as a pin's "
      "chamfered seat leaves: a cylinder R 0.2286 cut by flats at x = ±0.1905, less a cone "
      "narrowing upwards at 29.899 degrees from R 0.2286 at z = 0.46327, up to z = 0.5715) "
      "and a shelf 0.2 wide along each side face, its underside 0.421 (+x) and 0.422 (-x) "
      "above the socket's axis point z = 0, as FreeCAD's IDF library's TSM headers have "
      "their pin seats over a pocket's end.",
      None, SOCKET_BETWEEN_SHELVES_NOTE)
def socket_between_shelves():
    block = Part.makeBox(1.6, 2.0, 2.0, V(-0.8, -1.0, -1.0))
    z0, z1, apex, semi = 0.46327, 0.5715, 0.8608, math.radians(29.899)

    def radius(z):
        return (apex - z) * math.tan(semi)
    seat = Part.makeCylinder(0.2286, z1 - z0, V(0, 0, z0)).common(
        Part.makeBox(0.381, 1.0, z1 - z0, V(-0.1905, -0.5, z0)))
    cone = Part.makeCone(radius(z0), radius(z1), z1 - z0, V(0, 0, z0))
    # The cone's seam line on the cylinder's side, not across a flat.
    cone.rotate(V(0, 0, 0), V(0, 0, 1), 90)
    shelves = Part.makeBox(0.2, 2.0, 1.0 - 0.421, V(0.8, -1.0, 0.421)).fuse(
        Part.makeBox(0.2, 2.0, 1.0 - 0.422, V(-1.0, -1.0, 0.422)))
    return block.fuse(shelves).removeSplitter().cut(seat.cut(cone))

def fold_profile(crack):
    """The profile (z = 0) of a fold: the sliver between the line y = 0 and an arc R 20 tangent
    to it at the origin, out to x = 10 (0.28 high there); with `crack`, a square 20x20 about
    the origin with that sliver cut in from its right side."""
    r, a = 20.0, 10.0

    def arc_y(x):
        return r - math.sqrt(r * r - x * x)
    tip, foot, top = V(0, 0, 0), V(a, 0, 0), V(a, arc_y(a), 0)
    arc = Part.Arc(top, V(a / 2, arc_y(a / 2), 0), tip).toShape()
    if not crack:
        return Part.Wire([Part.LineSegment(tip, foot).toShape(),
                          Part.LineSegment(foot, top).toShape(), arc])
    corners = [V(a, a, 0), V(-a, a, 0), V(-a, -a, 0), V(a, -a, 0)]
    path = [top] + corners + [foot, tip]
    return Part.Wire([Part.LineSegment(path[i], path[i + 1]).toShape()
                      for i in range(len(path) - 1)] + [arc.reversed()])


# The sliver's area: the rectangle 10 x 20 less the circle's area between x = 0 and 10
# under its arc's far side.
FOLD_SLIVER_AREA = 20.0 * 10.0 - (5.0 * math.sqrt(300.0) + 200.0 * math.asin(0.5))


def folded(crack, axis, degrees):
    """The fold's profile extruded 5 along z, turned about `axis`: axis-aligned, the faces'
    normals at the fold are exactly opposite and the classifier's first-order test happened
    to fall the right way; turned so, it fell the wrong way."""
    solid = Part.Face(fold_profile(crack)).extrude(V(0, 0, 5))
    solid.rotate(V(0, 0, 0), axis, degrees)
    return solid


@part("fin_folded_to_its_tip",
      "A fin 5 deep whose profile is the sliver between the line y = 0 and an arc R 20 "
      "tangent to it at the origin, out to x = 10, turned 37 degrees about z: its tip is an "
      "edge where a plane and a cylinder fold back onto each other (interior angle 0), as "
      "each lead of FreeCAD's IDF library's MSOP-10 has one.",
      5 * FOLD_SLIVER_AREA,
      "The tip edge is convex with an interior angle of 0 degrees (a fin of no thickness), "
      "not 360: the classifier decides by the faces' second-order separation. The medial "
      "axis is the fin's mid-surface sheet, bounded by the seams of the corner triplets at "
      "the ends, which run to the tip's vertices with r falling as the square of the "
      "distance: within a few accuracies of nothing every touch point is within r of an "
      "edge of its face, and the seam ends at the vertex ahead.")
def fin_folded_to_its_tip():
    return folded(False, V(0, 0, 1), 37)


@part("crack_folded_to_its_bottom",
      "A square block 20x20x5 about the origin with the sliver of fin_folded_to_its_tip "
      "cut in from its right side, turned 37 degrees about z: the crack's bottom is an edge "
      "where a plane and a cylinder fold back onto each other (interior angle 360).",
      20 * 20 * 5 - 5 * FOLD_SLIVER_AREA,
      "The crack's bottom edge is reflex with an interior angle of 360 degrees (a cusp "
      "of no width), not 0; points past it are inside the solid.")
def crack_folded_to_its_bottom():
    return folded(True, V(0, 0, 1), 37)



# An IC package's body (a DPAK's, an SOT's): 6 x 5, its sides drafted in and out of a parting
# line 1 above the floor (the creases there 165.19 degrees), with one lead 0.6 wide and 0.3
# thick out of its front, flush with the parting line, and reaching 0.1 into the body.
PACKAGE_DRAFT = 0.13


def package_with_a_lead(x):
    """The package body with its lead at x .. x + 0.6."""
    def rect(inset, z):
        return Part.makePolygon([V(inset, inset, z), V(6 - inset, inset, z),
                                 V(6 - inset, 5 - inset, z), V(inset, 5 - inset, z),
                                 V(inset, inset, z)])
    lower = Part.makeLoft([rect(PACKAGE_DRAFT, 0), rect(0, 1)], True, True)
    upper = Part.makeLoft([rect(0, 1), rect(PACKAGE_DRAFT, 2)], True, True)
    lead = Part.makeBox(0.6, 1.5, 0.3, V(x, -1.4, 0.7))
    return lower.fuse(upper).fuse(lead).removeSplitter()


def package_volume():
    """Two prismatoids (h/6 (A1 + 4 Am + A2)) and the lead's part outside the lower front
    face (y = d (1 - z)): 0.6 x the integral of 1.4 + d (1 - z) over z 0.7 .. 1."""
    d = PACKAGE_DRAFT
    half = (5.74 * 4.74 + 4 * (6 - d) * (5 - d) + 30) / 6
    return 2 * half + 0.6 * (1.4 * 0.3 + d * 0.3 ** 2 / 2)


@part("package_corner_split_at_a_lead",
      "An IC package body 6x5x2 whose sides are drafted in and out of a parting line at half "
      "its height (creases of 165.19 degrees; its drafted faces B-spline lofts), with one lead "
      "0.6x0.3 out of its front at x = 0.5 to 1.1, flush with the parting line.",
      package_volume(),
      "The seams from the corners in the parting line are touched by four faces, the two "
      "drafted faces on each side (the body is symmetric about the parting line): their "
      "touch points lie round a circle, and the sheets are between neighbours round it. The "
      "one from the corner at the lead meets the lead's edge with the lower front face and "
      "splits there into two seams of three: that junction has three seam ends, and the "
      "sheets round it close.")
def package_corner_split_at_a_lead():
    return package_with_a_lead(0.5)


@part("package_lead_under_the_corner_seam",
      "The package of package_corner_split_at_a_lead with its lead at x = 1 to 1.6: the "
      "lead's edge with the lower front face runs up to (1, 0, 1), under the end of the seam "
      "from the front left corner.",
      package_volume(),
      "The seam from the front left corner, touched by four faces by symmetry, hands its "
      "touch point on the lower front face to the lead's edge 0.012 before the junction "
      "where the ball reaches the floor; past that hand-over the upper left face no longer "
      "touches the ball (it is 3.4e-5 farther than r at that junction): the seam ends at the "
      "hand-over, at a junction at (1, 1, 1) with r = 0.99166, whose two other seams (the "
      "lead's edge, the lower left and upper front faces; the three faces without the "
      "lead's edge) leave it.")
def package_lead_under_the_corner_seam():
    return package_with_a_lead(1.0)

# A boss on a plate whose side walls are tangent to it, its foot rounded into the plate's top
# (after the Voron Manta DIN mount's F146/F147/F173 at V275): boss r TB_R about the z axis up
# to TB_H, plate x 0..TB_L, y -TB_R..TB_R, z 0..TB_TOP, the foot round r TB_FOOT a torus
# (major TB_R + TB_FOOT, centre z = TB_TOP + TB_FOOT) tangent to the boss at that height.
TB_R, TB_TOP, TB_FOOT, TB_H, TB_L, TB_ROUND = 3.0, 4.0, 2.0, 6.8, 10.0, 0.5
# The wider rounds of blend_wider_than_the_ball_tapering_to_a_tip.
TB_WIDE = 0.9


def tangent_walls_and_foot_round():
    plate = Part.makeBox(TB_L, 2 * TB_R, TB_TOP, V(0, -TB_R, 0))
    boss = Part.makeCylinder(TB_R, TB_H, V(0, 0, 0))
    # The foot round as a solid ring (the annulus outside the torus) cut to the plate's
    # outline; the torus turned half a turn so that its parameter seam lies off the plate.
    torus = Part.makeTorus(TB_R + TB_FOOT, TB_FOOT, V(0, 0, TB_TOP + TB_FOOT))
    torus.rotate(V(0, 0, 0), V(0, 0, 1), 180)
    ring = (Part.makeCylinder(TB_R + TB_FOOT, TB_FOOT, V(0, 0, TB_TOP))
            .cut(Part.makeCylinder(TB_R, TB_FOOT, V(0, 0, TB_TOP)))
            .cut(torus))
    ring = ring.common(Part.makeBox(TB_L, 2 * TB_R, TB_FOOT, V(0, -TB_R, TB_TOP)))
    solid = plate.fuse(boss).fuse(ring).removeSplitter()
    tips = [V(0, s * TB_R, TB_TOP + TB_FOOT) for s in (1, -1)]
    if not all(any(v.Point.distanceToPoint(t) < 1e-7 for v in solid.Vertexes) for t in tips):
        raise RuntimeError("no vertex where a wall and the foot round are tangent")
    return solid


@part("wall_tangent_to_a_foot_round",
      "A boss r=3 about the z axis, 6.8 high, on a plate x 0..10, y -3..3, 4 thick whose side "
      "walls y = +-3 are tangent to the boss; the boss's foot rounded r=2 into the plate's "
      "top (a torus, major radius 5, tangent to the boss at z = 6). Each wall meets the round "
      "along a convex edge from (4, +-3, 4) whose angle opens to 180 degrees at (0, +-3, 6), "
      "where the wall, the round and the boss are tangent.",
      None,
      "The seam of balls touching a wall, the foot round and the boss's top runs to the ball "
      "at (0, +-2.2, 6), r 0.8, where its touch points on the wall and the round meet at the "
      "tangent vertex: a pinch. The wall and the round share the convex edge that flattens "
      "out there: their sheet ends on the line of balls tangent at that vertex, a skeletal "
      "edge from the pinch down to it.")
def wall_tangent_to_a_foot_round():
    return tangent_walls_and_foot_round()


@part("blend_tapering_between_tangent_faces",
      "wall_tangent_to_a_foot_round with the walls' convex edges above the plate's top (their "
      "top edges, and the edges with the foot round) rounded r=0.5: a cylinder along each top "
      "edge and a B-spline blend up each wall/round edge that tapers to a point at "
      "(0, +-3, 6), where the wall and the round, which share no edge, are tangent.",
      None,
      "The seam of balls touching a wall, the foot round and the boss's top runs to the ball "
      "at (0, +-2.2, 6), r 0.8, where its touch points on the wall and the round meet at the "
      "tangent vertex: a pinch, not the blend's curvature limit (its radius there is 0.49, "
      "the ball's 0.8). No reflex edge ends at that vertex and the wall and the round share "
      "no edge there: a ball touching the vertex alone has one contact, so no skeletal edge "
      "starts; the sheets close at the pinch's ball, as at a curvature limit.")
def blend_tapering_between_tangent_faces():
    return tapering_blends(TB_ROUND)


def tapering_blends(radius):
    """tangent_walls_and_foot_round with the walls' convex edges above the plate's top
    rounded `radius` (a rolling-ball blend up each wall/round edge, which tapers to a point
    where the wall and the round are tangent)."""
    solid = tangent_walls_and_foot_round()
    edges = []
    for e in solid.Edges:
        pts = e.discretize(9)
        in_wall = any(all(abs(p.y - s * TB_R) < 1e-6 for p in pts) for s in (1, -1))
        if (in_wall and all(p.z > TB_TOP - 1e-6 for p in pts)
                and not all(p.x > TB_L - 1e-6 for p in pts)):
            edges.append(e)
    if len(edges) != 4:
        raise RuntimeError(f"expected 4 edges to round, found {len(edges)}")
    return solid.makeFillet(radius, edges)


# A step whose upper block's corner is a quadratic Bezier from (-PK_L, 0) to (0, -PK_L) with
# its control point at the corner (0, 0): a parabola, radius of curvature 2*PK_L at its ends
# and PK_L/sqrt(2) at its apex, the peak. Base z 0..PK_BASE, the upper block PK_STEP higher
# (after the Voron Dragon mount's F54/F70/F95 at E156).
PK_L, PK_BASE, PK_STEP, PK_SIDE = 0.54 * math.sqrt(2.0), 6.0, 0.5, 10.0


@part("step_round_corner_curvature_peak",
      "A base x, y -10..10, z 0..6; on it, a block 0.5 high over x, y -10..0 whose corner at "
      "(0, 0) is a parabola (a quadratic Bezier from (-0.764, 0) to (0, -0.764), control point "
      "(0, 0)): the block's foot is a reflex B-spline edge whose radius of curvature is 1.53 "
      "at its ends and 0.54 at its apex (-0.191, -0.191, 6).",
      2 * PK_SIDE * 2 * PK_SIDE * PK_BASE + PK_STEP * (PK_SIDE * PK_SIDE - PK_L * PK_L / 6),
      "Under the block, balls touch its top and its foot twice, their centres below the "
      "base's top: where they touch the parabola twice, its two touch points meet at the "
      "apex at the ball of r 0.5416 (centre 0.0416 below z = 6, 0.54 from the apex in plan), "
      "its curvature limit, a step before the touch points reach the end of the edge's arc "
      "of normals (r 0.5, the centre in the base's top plane).")
def step_round_corner_curvature_peak():
    base = Part.makeBox(2 * PK_SIDE, 2 * PK_SIDE, PK_BASE, V(-PK_SIDE, -PK_SIDE, 0))
    z = PK_BASE
    corner = Part.BSplineCurve()
    corner.buildFromPolesMultsKnots([V(-PK_L, 0, z), V(0, 0, z), V(0, -PK_L, z)],
                                    [3, 3], [0.0, 1.0], False, 2)
    outline = Part.Wire([
        Part.LineSegment(V(-PK_SIDE, 0, z), V(-PK_L, 0, z)).toShape(),
        corner.toShape(),
        Part.LineSegment(V(0, -PK_L, z), V(0, -PK_SIDE, z)).toShape(),
        Part.LineSegment(V(0, -PK_SIDE, z), V(-PK_SIDE, -PK_SIDE, z)).toShape(),
        Part.LineSegment(V(-PK_SIDE, -PK_SIDE, z), V(-PK_SIDE, 0, z)).toShape(),
    ])
    block = Part.Face(outline).extrude(V(0, 0, PK_STEP))
    return base.fuse(block).removeSplitter()


@part("blend_wider_than_the_ball_tapering_to_a_tip",
      "blend_tapering_between_tangent_faces with the rounds r=0.9 instead of 0.5: a cylinder "
      "along each wall's top edge and a B-spline blend up each wall/round edge, tapering to a "
      "point at (0, +-3, 6); where it tapers, the blend's radius of curvature falls below "
      "its nominal 0.9.",
      None,
      "The seams of balls touching the foot round, a wall and the boss's top run towards the "
      "tip until the touch point on the round reaches the blend at the ball "
      "(0.0625, +-2.1274, 5.9274), r 0.8726, whose radius there is the blend's radius of "
      "curvature to 1.3 accuracies: the seam ends at that curvature limit. (The hand-over "
      "onto the blend solved for a foot 2.4e-3 mm off it, the foot indeterminate where the "
      "ball nearly osculates, and the seams ended open.)")
def blend_wider_than_the_ball_tapering_to_a_tip():
    return tapering_blends(TB_WIDE)


# The foot outline of a 0.5 mm boss under the Prusa extruder motor plate (its faces F17-F24,
# edges E102-E123): eight quadratic B-splines of two spans each, joined tangent at their
# ends, whose curvature jumps there; poles in the plate's x, y less (-47, -20.4).
MOTOR_BOSS_POLES = [
    [(-0.80913, 0.001323), (-0.80913, 0.29792), (-0.660832, 0.683495), (-0.527364, 0.79719)],
    [(-0.527364, 0.79719), (-0.388952, 0.915829), (-0.047866, 1.0), (0.144922, 1.0)],
    [(0.144922, 1.0), (0.30805, 1.0), (0.644192, 0.915829), (0.792491, 0.85651)],
    [(0.792491, 0.85651), (0.792491, 0.816963), (0.802377, 0.629119), (0.802377, 0.485764)],
    [(0.802377, 0.485764), (0.802377, -0.043166), (0.619476, -0.680849), (0.476121, -0.843977)],
    [(0.476121, -0.843977), (0.372312, -0.977445), (0.095489, -1.09114), (-0.052809, -1.09114)],
    [(-0.052809, -1.09114), (-0.176391, -1.09114), (-0.463101, -0.967559), (-0.561966, -0.843977)],
    [(-0.561966, -0.843977), (-0.680605, -0.695679), (-0.80913, -0.349649), (-0.80913, 0.001323)],
]
MB_H, MB_PLATE, MB_SIDE = 0.5, 2.0, 3.0


@part("boss_whose_foot_tightens_at_a_tangent_joint",
      "A plate x, y -3..3, z 0.5..2.5 with a boss 0.5 high under it (z 0..0.5), about "
      "1.6 x 2.1, whose outline is the Prusa extruder motor plate's: eight quadratic "
      "B-splines joined tangent, their radius of curvature jumping at the joints; at "
      "(-0.0528, -1.0911) from 0.774 to 0.494.",
      None,
      "Inside the boss, balls touch its bottom and its foot edge (the reflex edge where it "
      "meets the plate) twice, on the two B-splines either side of the joint at "
      "(-0.0528, -1.0911), their centres above the foot's plane (r > 0.5). As the seam comes "
      "down towards that plane (r 0.5, where both touch points reach the end of their "
      "edges' arcs of normals at the joint), the touch point past the joint runs to where "
      "that edge bends tighter than the ball (its radius of curvature 0.503 at 0.009 from "
      "the joint, 0.494 at it): the ball osculates the edge there (r·κ = 1) at r 0.5001, "
      "centre (-0.0528, -0.5910, 0.5001), and the seam ends at that edge's curvature limit, "
      "within the step that crosses the arcs' end. (It ended 0.05 short, at the last point "
      "before that step, r 0.5496; on the motor plate itself, at the crossing, r 0.5, whose "
      "ball pokes through that edge.) The seam from the plate's top ends alike at r 1.0618.")
def boss_whose_foot_tightens_at_a_tangent_joint():
    edges = []
    for poles in MOTOR_BOSS_POLES:
        c = Part.BSplineCurve()
        c.buildFromPolesMultsKnots([V(x, y, 0) for x, y in poles], [3, 1, 3],
                                   [0.0, 1.0, 2.0], False, 2)
        edges.append(c.toShape())
    boss = Part.Face(Part.Wire(edges)).extrude(V(0, 0, MB_H))
    plate = Part.makeBox(2 * MB_SIDE, 2 * MB_SIDE, MB_PLATE, V(-MB_SIDE, -MB_SIDE, MB_H))
    return plate.fuse(boss).removeSplitter()


@part("blend_of_radius_one_tapering_to_a_tip",
      "blend_tapering_between_tangent_faces with the rounds r=1.0: a cylinder along each "
      "wall's top edge and a B-spline blend up each wall/round edge, tapering to a point at "
      "(0, +-3, 6).",
      None,
      "The seams of balls touching a wall, the boss's top and the blend up that wall end where "
      "their touch points on the wall and on the blend meet at the blend's edge with the "
      "wall: the ball osculates the blend there, r 0.962905 (the blend's radius of curvature "
      "at that point), centre (0.1352, +-2.0371, 5.8371). (The march's point was within a "
      "step of that meeting, no shorter step had the two apart, and the seam ended at the "
      "step's ball, r 0.962774, 8.2 accuracies short of osculating; `verify` rejected it.)")
def blend_of_radius_one_tapering_to_a_tip():
    return tapering_blends(1.0)


@part("blend_of_radius_one_and_a_half_tapering_to_a_tip",
      "blend_tapering_between_tangent_faces with the rounds r=1.5: a cylinder along each "
      "wall's top edge and a B-spline blend up each wall/round edge, tapering to a point at "
      "(0, +-3, 6).",
      None,
      "The seams of balls touching the foot round, a wall and the boss's top hand their touch "
      "point on the round onto the blend where the ball is within 0.4 % of osculating it "
      "(r·κ 0.9964): the same ball's foot on the blend lies 280 times as far along it as the "
      "kink between the faces moves it on a flat face. They go on, and end where two touch "
      "points on the blend meet, at its curvature limit, r 1.3846, centre "
      "(0.4084, +-1.6154, 5.4154). (With that factor capped at 10 the hand-overs were "
      "refused, though the ball was the same to 1e-6 mm, and both seams ended open.) The "
      "degenerate curve along the axis of one top edge's cylinder (r 1.5) ends open where "
      "the blend comes in (issue 20).")
def blend_of_radius_one_and_a_half_tapering_to_a_tip():
    return tapering_blends(1.5)


# A chip resistor's body between two terminal caps (after FreeCAD's IDF library 2225_SMD):
# the body x -5..5, y -4..4, z 1..5; each cap 3 long, larger than the body by its edges'
# round radius CAP_ROUND on every side, its four long edges rounded CAP_ROUND, so that each
# round's axis runs into the body's corner, the vertex where the cap's inner face meets two
# of the body's edges.
CAP_ROUND = 1.0


def capped_body():
    body = Part.makeBox(10, 8, 4, V(-5, -4, 1))
    solid = body
    for x in (5, -8):
        cap = Part.makeBox(3, 10, 6, V(x, -5, 0))
        cap = cap.makeFillet(CAP_ROUND, [e for e in cap.Edges if abs(e.tangentAt(0).x) > 0.99])
        solid = solid.fuse(cap)
    return solid.removeSplitter()


@part("body_between_rounded_caps",
      "A box 10x8x4 (x -5..5, y -4..4, z 1..5) between two caps 3x10x6 (x 5..8 and -8..-5, "
      "y -5..5, z 0..6) whose four edges along x are rounded r=1: each round's axis runs "
      "into a corner of the body, where the cap's inner face meets two of the body's edges.",
      10 * 8 * 4 + 2 * 3 * (10 * 6 - (4 - PI) * CAP_ROUND ** 2),
      "The seam of balls touching a cap's two faces beside a round and the body's two edges "
      "at a corner (four contacts) runs along x to the ball of r 1 on the round's axis at "
      "x = +-6, touching the corner's vertex: its touch points on the two edges meet there, "
      "and it ends at that vertex's curvature limit, with a skeletal edge down to the vertex "
      "(it was named for the cap's inner face, a plane, when the two edges were its first "
      "and last touch points). The round's axis, a degenerate curve, meets the same ball.")
def body_between_rounded_caps():
    return capped_body()


# The profile of a convex round on the Voron Revo hotend mount (its face F87): a cubic
# B-spline of 19 poles from the wall x = 0 (leaving along +z) to the top z = 0 (arriving along
# +x), the poles less the corner (5.093756, -19.711577), knots as written. Its radius of
# curvature wanders from 0.26 to 0.62 and back along it: several peaks of curvature.
WAVY_ROUND_POLES = [
    (0.0, -0.444643), (0.000345, -0.426735), (0.001024, -0.391523), (0.01131, -0.340858),
    (0.026774, -0.293612), (0.046979, -0.249122), (0.075026, -0.209161), (0.108919, -0.172461),
    (0.149137, -0.139821), (0.195391, -0.1102), (0.246891, -0.08339), (0.305042, -0.060934),
    (0.369199, -0.042953), (0.439012, -0.026179), (0.515294, -0.01546), (0.597431, -0.006225),
    (0.685647, -0.000985), (0.746422, -0.000334), (0.777678, 0.0),
]
WAVY_ROUND_KNOTS = [
    0.0, 0.053310374, 0.104825319, 0.153373354, 0.201407724, 0.249898953, 0.298251949,
    0.349950005, 0.403855305, 0.461801763, 0.522774444, 0.58932927, 0.660365441, 0.736671322,
    0.818792774, 0.906806342, 1.0,
]
WAVY_SIDE, WAVY_LENGTH, WAVY_LONG = 30.0, 0.8, 20.0


@part("block_with_a_wavy_round",
      "A block x 0..30, y 0..0.8, z -30..0 whose edge along y at x = 0, z = 0 is rounded by "
      "a cubic B-spline profile (the Voron Revo hotend mount's round F87, 0.78 along x by "
      "0.44 down z, 19 poles), whose curvature wanders: its radius of curvature has minima "
      "at two knots, 0.29035 at t = 0.05331 and 0.26083 at t = 0.20141, and at t = 0.30 "
      "(0.3506), 0.46 and beyond, whose osculating circles cross the profile elsewhere.",
      None,
      "Near each end cap, balls touch the cap and the round twice: where the two touch points "
      "close in on the knot at t = 0.20141 the seam ends at its centre of curvature, r "
      "0.26083, centre (0.27473, r, -0.37931) (and its mirror at y = 0.8 - r). (The steps "
      "there once overshot onto balls tangent at one point twice over, and the seam ended "
      "at r 0.3345, short of it.) The knot at t = 0.05331 is a curvature limit too (its "
      "osculating circle lies inside), but no seam reaches it on this block (one does on the "
      "same round 6 wide and 1 long): a junction of three touches on the round is missed "
      "(issue 19).")
def block_with_a_wavy_round():
    return wavy_round_block(WAVY_LENGTH)


@part("long_block_with_a_wavy_round",
      "block_with_a_wavy_round 20 long (y 0..20).",
      None,
      "Near each cap, the seam of balls touching the cap and the round twice (from a junction "
      "where they touch the wall x = 0 too) meets a junction where the round bulges into the "
      "ball between its two touch points (r 0.3604, a third touch at t 0.105): one seam on "
      "from there ends at the knot t = 0.20141's centre of curvature, r 0.26083, the other "
      "at the knot t = 0.05331's, r 0.29035, where its two touch points meet on the knot line "
      "(the curvature peaks there with a kink; the steps fail from r 0.2935 on, and the seam "
      "ended there). (The nearest-point search settled in a "
      "touched basin, and the seams ran on past the junctions through 26 balls the round pokes "
      "into by up to 5e-4 mm, which OCCT rejected and verify did not, and ended at r 0.354, "
      "no curvature limit.)")
def long_block_with_a_wavy_round():
    return wavy_round_block(WAVY_LONG)


def wavy_round_block(length):
    """The block of block_with_a_wavy_round, `length` long along y."""
    c = Part.BSplineCurve()
    mults = [4] + [1] * (len(WAVY_ROUND_KNOTS) - 2) + [4]
    c.buildFromPolesMultsKnots([V(x, 0, z) for x, z in WAVY_ROUND_POLES], mults,
                               WAVY_ROUND_KNOTS, False, 3)
    end = WAVY_ROUND_POLES[0][1]
    outline = Part.Wire([
        c.toShape(),
        Part.LineSegment(V(WAVY_ROUND_POLES[-1][0], 0, 0), V(WAVY_SIDE, 0, 0)).toShape(),
        Part.LineSegment(V(WAVY_SIDE, 0, 0), V(WAVY_SIDE, 0, -WAVY_SIDE)).toShape(),
        Part.LineSegment(V(WAVY_SIDE, 0, -WAVY_SIDE), V(0, 0, -WAVY_SIDE)).toShape(),
        Part.LineSegment(V(0, 0, -WAVY_SIDE), V(0, 0, end)).toShape(),
    ])
    return Part.Face(outline).extrude(V(0, length, 0))


def main():
    args = L.parse_args(sys.argv[1:], os.path.join(L.SCRIPTS, "..", "samples", "trace"))
    out = os.path.abspath(args.outdir)
    os.makedirs(out, exist_ok=True)
    L.setup_step_writer()
    only = set(args.only.split(",")) if getattr(args, "only", None) else None
    manifest = []
    for p in PARTS:
        if only and p["name"] not in only:
            continue
        shape = p["build"]()
        L.check_solid(p["name"], shape, 1)
        solid = shape.Solids[0]
        if p["volume"] is not None:
            L.check_volume(p["name"], solid, p["volume"], rel=p["volume_rel"])
        entry = L.write_regression_part(
            out, p["name"], solid, MADE_BY, p["description"],
            {"volume_exact": p["volume"] is not None,
             "mat": {"open_ends": 0, "note": p["mat_note"]}})
        if p["edit"] is not None:
            path = os.path.join(out, p["name"] + ".step")
            with open(path) as f:
                text = p["edit"](f.read())
            with open(path, "w") as f:
                f.write(text)
            # The counts are the edited file's, as OCCT reads it.
            edited = Part.read(path)
            entry.update(faces=len(edited.Faces), edges=len(edited.Edges),
                         vertices=len(edited.Vertexes))
        # Where OCCT's volume is only checked loosely (a NURBS solid), the manifest gives the
        # exact one.
        if p["volume"] is not None and p["volume_rel"] > 1e-9:
            entry["volume"] = round(p["volume"], 9)
        manifest.append(entry)
    L.write_manifest(out, MADE_BY, manifest)


if __name__ == "__main__":
    L.run_main(main)
