#!/usr/bin/python3
"""Reference solids for matrace, built with FreeCAD's Part module and written as AP214 STEP.

Run with Debian's python (NOT freecadcmd, NOT the pyenv python first on PATH):

    /usr/bin/python3 scripts/freecad/make_samples.py [OUTDIR] [--meta METADIR] [--only a,b]

Each sample below is a builder function plus a literal, hand-written description of the
solid: edge kinds and vertex kinds (derived in a comment from the construction), exact
volume and bounding box, and what is known about its medial axis. For every sample the
script
  * checks shape.isValid(), that it is the expected number of closed solids,
  * checks the exact volume and bbox against OCCT,
  * exports STEP (AP214IS) and counts ADVANCED_FACE / EDGE_CURVE / VERTEX_POINT in the text,
  * recomputes edge / vertex kinds from face normals (samplelib.classify) and fails loudly
    if they disagree with the hand-written dicts,
  * writes METADIR/<name>.json for scripts/build_manifest.py.

Edge kinds: interior dihedral angle of the solid < 179 deg convex, > 181 deg reflex, else
smooth (a closed surface's seam is smooth). Vertex kinds: count the non-smooth incident edge
ends (a closed edge counts twice): 0 smooth, 1-2 crease, >=3 all convex -> convex, all
reflex -> reflex, both -> mixed. The kinds describe the topology written to the STEP file.
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import samplelib as L  # noqa: E402  (sets up FreeCAD's sys.path)
from samplelib import FreeCAD, Part, V  # noqa: E402

MADE_BY = "scripts/freecad/make_samples.py"
PI = math.pi

SAMPLES = []


def sample(name, description, edge_kinds, vertex_kinds, volume, bbox, mat=None,
           solids=1, expect_text=(), nurbs_of=None):
    def deco(fn):
        SAMPLES.append(dict(name=name, description=description, edge_kinds=edge_kinds,
                            vertex_kinds=vertex_kinds, volume=volume, bbox=bbox, mat=mat,
                            solids=solids, expect_text=list(expect_text), build=fn,
                            nurbs_of=nurbs_of))
        return fn
    return deco


def polygon_face(points):
    return Part.Face(Part.makePolygon([V(*p) for p in points] + [V(*points[0])]))


def profile_xz(points2d, depth):
    """Prism: polygon (x, z) in the plane y = 0 extruded by depth along +y."""
    face = polygon_face([(x, 0, z) for (x, z) in points2d])
    return face.extrude(V(0, depth, 0))


def solid_from_faces(faces):
    solid = Part.Solid(Part.Shell(faces))
    if solid.Volume < 0:
        solid.reverse()
    return solid


# ----------------------------------------------------------------------------------------
# box [0,a]x[0,b]x[0,c], c < b < a

BOX_A, BOX_B, BOX_C = 60.0, 40.0, 20.0


def box_mat(a, b, c, note_extra=""):
    h = c / 2
    return {
        "seams": 12,
        "junctions": [{"point": [x, y, h], "radius": h}
                      for y in (h, b - h) for x in (h, a - h)],
        "note": ("Box [0,a]x[0,b]x[0,c], c<b<a. Medial axis: the middle sheet z=c/2 over "
                 "[c/2,a-c/2]x[c/2,b-c/2] (nearest faces top and bottom) plus one bisector "
                 "sheet per edge. Seams (points with three nearest faces): the 4 sides of the "
                 "middle rectangle (top, bottom and one side face) and 8 corner trisectors "
                 "from each box corner to the nearest rectangle corner (three faces of the "
                 "corner) = 12. Junctions (four nearest faces: top, bottom and two adjacent "
                 "sides) are the rectangle corners (c/2 or a-c/2, c/2 or b-c/2, c/2), "
                 "radius c/2: there the distance to top, bottom and the two sides is c/2 and "
                 "to the far sides > c/2 since a,b > c. The sheet between opposite side "
                 "faces never exists because every point is within c/2 of top or bottom."
                 + note_extra),
    }


@sample("box", "Axis-aligned box [0,60]x[0,40]x[0,20] (three different sides).",
        # 12 edges, each between two perpendicular planes: interior angle 90 -> convex.
        # 8 corners, each with 3 convex edge ends -> convex.
        {"convex": 12, "reflex": 0, "smooth": 0},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=BOX_A * BOX_B * BOX_C, bbox=[[0, 0, 0], [BOX_A, BOX_B, BOX_C]],
        mat=box_mat(BOX_A, BOX_B, BOX_C))
def build_box():
    return Part.makeBox(BOX_A, BOX_B, BOX_C)


@sample("cube", "Cube [0,30]^3.",
        # as the box: 12 convex edges, 8 convex corners
        {"convex": 12, "reflex": 0, "smooth": 0},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=27000.0, bbox=[[0, 0, 0], [30, 30, 30]],
        mat={"seams": 8, "junctions": [{"point": [15.0, 15.0, 15.0], "radius": 15.0}],
             "note": "Medial axis = 12 triangles (edge bisector sheets) meeting at the centre. "
                     "Seams: the 8 corner trisectors (corner to centre); they all meet at the "
                     "centre, which is equidistant (s/2) from all 6 faces."})
def build_cube():
    return Part.makeBox(30, 30, 30)


# L-profile in the xz plane, extruded 30 along y:
#   (0,0) (60,0) (60,10) (10,10) (10,40) (0,40); the corner (10,10) is the reflex one.
L_PROFILE = [(0, 0), (60, 0), (60, 10), (10, 10), (10, 40), (0, 40)]
L_DEPTH = 30.0


@sample("l_bracket", "L-profile (60 wide, 40 high, 10 thick) extruded 30 along y; one reflex edge "
        "along y at x=10, z=10.",
        # 6 profile corners x 1 edge along y: 5 convex (90 deg), 1 reflex (270 deg);
        # 2 caps x 6 edges = 12 cap edges, all 90 deg -> convex.  17 convex, 1 reflex.
        # Vertices: the 2 ends of the reflex edge see 2 convex cap edges + 1 reflex -> mixed;
        # the other 10 see 3 convex -> convex.
        {"convex": 17, "reflex": 1, "smooth": 0},
        {"convex": 10, "reflex": 0, "mixed": 2, "crease": 0, "smooth": 0},
        volume=(60 * 10 + 10 * 30) * L_DEPTH, bbox=[[0, 0, 0], [60, L_DEPTH, 40]])
def build_l_bracket():
    return profile_xz(L_PROFILE, L_DEPTH)


U_PROFILE = [(0, 0), (60, 0), (60, 40), (50, 40), (50, 10), (10, 10), (10, 40), (0, 40)]


@sample("u_channel", "U-profile (60 wide, 40 high, walls and floor 10 thick) extruded 30 along y; "
        "two reflex edges at x=10 and x=50, z=10.",
        # 8 profile corners: 6 convex + 2 reflex edges along y; 16 cap edges convex.
        # Vertices: 4 ends of the reflex edges are mixed, the other 12 convex.
        {"convex": 22, "reflex": 2, "smooth": 0},
        {"convex": 12, "reflex": 0, "mixed": 4, "crease": 0, "smooth": 0},
        volume=(60 * 10 + 2 * 10 * 30) * 30.0, bbox=[[0, 0, 0], [60, 30, 40]])
def build_u_channel():
    return profile_xz(U_PROFILE, 30.0)


@sample("wedge", "Triangular prism: right triangle (0,0),(40,0),(0,30) in the xy plane "
        "(3-4-5, inradius 10, incentre (10,10)) extruded 60 along z.",
        # 3 lateral edges (90, ~36.9, ~53.1 deg) + 6 cap edges (90 deg): all convex.
        # 6 corners with 3 convex ends -> convex.
        {"convex": 9, "reflex": 0, "smooth": 0},
        {"convex": 6, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=600.0 * 60.0, bbox=[[0, 0, 0], [40, 30, 60]],
        mat={"seams": 7,
             "junctions": [{"point": [10.0, 10.0, 10.0], "radius": 10.0},
                           {"point": [10.0, 10.0, 50.0], "radius": 10.0}],
             "note": "Triangle incentre (10,10), inradius 10 = area/semiperimeter = 600/60. "
                     "Seams: the spine x=y=10, z in [10,50] (equidistant 10 from the three "
                     "side faces, farther from the caps) and 6 corner trisectors from each "
                     "prism corner to the junction of its cap; junctions where the spine meets "
                     "a cap's trisectors: four nearest faces (3 sides + cap), radius 10."})
def build_wedge():
    return polygon_face([(0, 0, 0), (40, 0, 0), (0, 30, 0)]).extrude(V(0, 0, 60))


# trirectangular tetrahedron O=(0,0,0), A=(36,0,0), B=(0,28,0), C=(0,0,24)
TA, TB, TC = 36.0, 28.0, 24.0


def tetra_mat():
    # exact incentre: sum(area of face opposite vertex i * vertex i) / sum(areas)
    area_opp_O = 0.5 * math.sqrt((TA * TB) ** 2 + (TB * TC) ** 2 + (TC * TA) ** 2)  # 744
    area_opp_A = 0.5 * TB * TC  # face x=0: 336
    area_opp_B = 0.5 * TA * TC  # face y=0: 432
    area_opp_C = 0.5 * TA * TB  # face z=0: 504
    total = area_opp_O + area_opp_A + area_opp_B + area_opp_C  # 2016
    inc = [area_opp_A * TA / total, area_opp_B * TB / total, area_opp_C * TC / total]
    vol = TA * TB * TC / 6.0  # 4032
    r = 3 * vol / total  # 6
    assert abs(area_opp_O - 744.0) < 1e-12 and abs(total - 2016.0) < 1e-12
    assert all(abs(x - 6.0) < 1e-12 for x in inc) and abs(r - 6.0) < 1e-12
    return {"seams": 4, "junctions": [{"point": [6.0, 6.0, 6.0], "radius": 6.0}],
            "note": "Vertices O(0,0,0) A(36,0,0) B(0,28,0) C(0,0,24). Face areas: opposite O "
                    "0.5*sqrt((ab)^2+(bc)^2+(ca)^2)=744, opposite A 336, B 432, C 504, sum "
                    "2016. Incentre = sum(A_i V_i)/sum(A_i) = (6,6,6); inradius = 3V/sum(A_i) "
                    "= 3*4032/2016 = 6. Medial axis = 6 edge bisector triangles; seams = the 4 "
                    "vertex trisectors, meeting at the incentre."}


@sample("tetrahedron", "Trirectangular (non-regular) tetrahedron (0,0,0),(36,0,0),(0,28,0),(0,0,24); "
        "incentre (6,6,6), inradius 6.",
        # 6 edges, all dihedral angles < 180 (convex polyhedron): convex; 4 convex corners.
        {"convex": 6, "reflex": 0, "smooth": 0},
        {"convex": 4, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=TA * TB * TC / 6.0, bbox=[[0, 0, 0], [TA, TB, TC]], mat=tetra_mat())
def build_tetrahedron():
    O, A, B, C = (0, 0, 0), (TA, 0, 0), (0, TB, 0), (0, 0, TC)
    return solid_from_faces([polygon_face(f) for f in ((O, B, A), (O, A, C), (O, C, B), (A, B, C))])


@sample("pyramid", "Right square pyramid: base [0,30]x[0,30] at z=0, apex (15,15,20) where 4 faces "
        "meet; slant height 25, inradius 7.5.",
        # 4 base edges + 4 lateral edges, convex polyhedron -> 8 convex.
        # 4 base corners (3 convex ends) + apex (4 convex ends) -> 5 convex.
        {"convex": 8, "reflex": 0, "smooth": 0},
        {"convex": 5, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=30 * 30 * 20 / 3.0, bbox=[[0, 0, 0], [30, 30, 20]],
        mat={"seams": 5, "junctions": [{"point": [15.0, 15.0, 7.5], "radius": 7.5}],
             "note": "Lateral face through y=0: 20y-15z=0 (|n|=25); distance of (15,15,z) is "
                     "(300-15z)/25 = 12-0.6z, equal to the base distance z at z=7.5: insphere "
                     "centre (15,15,7.5), radius 7.5 = (L/2)h/(L/2+slant) = 15*20/(15+25). "
                     "Seams: 4 base-corner trisectors to the insphere centre, plus the axis "
                     "segment from the centre up to the apex (equidistant from the 4 lateral "
                     "faces, a non-generic 4-fold seam). Junction: the insphere centre "
                     "(touches all 5 faces)."})
def build_pyramid():
    b = [(0, 0, 0), (30, 0, 0), (30, 30, 0), (0, 30, 0)]
    apex = (15, 15, 20)
    faces = [polygon_face(list(reversed(b)))]
    for i in range(4):
        faces.append(polygon_face([b[i], b[(i + 1) % 4], apex]))
    return solid_from_faces(faces)


HOLES = [(15.0, 25.0, 5.0), (40.0, 25.0, 8.0), (65.0, 25.0, 5.0)]  # (x, y, r)


@sample("plate_with_holes", "Plate [0,80]x[0,50]x[0,10] with three through holes along z: r=5 at "
        "(15,25), r=8 at (40,25), r=5 at (65,25).",
        # plate: 12 convex edges. Each hole: 2 circles (top/bottom plane meets the hole wall at
        # 90 deg, material outside the hole) convex + 1 seam line of the cylinder (smooth).
        # Vertices: 8 plate corners convex; each hole has 2 seam vertices where one closed
        # circle (2 convex ends) and the seam (smooth) meet -> 2 non-smooth ends -> crease.
        {"convex": 12 + 2 * 3, "reflex": 0, "smooth": 3},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 6, "smooth": 0},
        volume=80 * 50 * 10 - PI * sum(r * r for _, _, r in HOLES) * 10,
        bbox=[[0, 0, 0], [80, 50, 10]])
def build_plate_with_holes():
    s = Part.makeBox(80, 50, 10)
    for x, y, r in HOLES:
        s = s.cut(Part.makeCylinder(r, 20, V(x, y, -5)))
    return s


# bicubic B-spline top: 5x5 poles, knots (0, .5, 1) mults (4, 1, 4) in u and v.
BS_KNOTS = [0.0, 0.5, 1.0]
BS_MULTS = [4, 1, 4]
BS_GREVILLE = [0.0, 1 / 6, 0.5, 5 / 6, 1.0]      # averages of 3 consecutive knots
BS_BASIS_INTEGRALS = [0.125, 0.25, 0.25, 0.25, 0.125]  # (t_{i+4}-t_i)/4
BS_BUMP = [[0, 0, 0, 0, 0],
           [0, 2, 3, 2, 0],
           [0, 3, 6, 3, 0],
           [0, 2, 3, 2, 0],
           [0, 0, 0, 0, 0]]


def bspline_top_surface(a, b, c):
    poles = [[V(a * BS_GREVILLE[i], b * BS_GREVILLE[j], c + BS_BUMP[i][j]) for j in range(5)]
             for i in range(5)]
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots(poles, BS_MULTS, BS_MULTS, BS_KNOTS, BS_KNOTS, False, False, 3, 3)
    return s


def bspline_box_volume(a, b, c):
    # poles at Greville abscissae -> x = a u, y = b v exactly (linear precision), so the
    # volume is a*b*integral of z over the unit square = a*b*(c + sum w_i w_j h_ij)
    w = BS_BASIS_INTEGRALS
    return a * b * (c + sum(w[i] * w[j] * BS_BUMP[i][j] for i in range(5) for j in range(5)))


def bspline_box_zmax(a, b, c):
    # the bump is symmetric with a single peak at the centre pole: the maximum is z(0.5, 0.5)
    # (checked below by sampling)
    s = bspline_top_surface(a, b, c)
    z = s.value(0.5, 0.5).z
    samples = max(s.value(i / 100, j / 100).z for i in range(101) for j in range(101))
    assert samples <= z + 1e-12, (samples, z)
    return z


@sample("box_bspline_top", "Box [0,60]x[0,40] from z=0 whose top face is a non-rational bicubic "
        "B-spline surface (5x5 poles, knots 0,.5,1 with multiplicities 4,1,4 in u and v) at z=20 on "
        "its boundary with a gentle bump (max z=23.5 at the centre); 5 planar faces.",
        # the boundary rows of poles are at z=20 so the 4 top edges are straight and the sides
        # planar; the top leans at most ~20 deg, so all 12 edges are convex (top/side angle
        # 90 deg minus the slope, < 180); 8 corners with 3 convex ends -> convex.
        {"convex": 12, "reflex": 0, "smooth": 0},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=bspline_box_volume(60.0, 40.0, 20.0),
        bbox=[[0, 0, 0], [60, 40, None]])  # zmax filled in below
def build_box_bspline_top():
    a, b = 60.0, 40.0
    top = Part.Face(bspline_top_surface(a, b, 20.0))
    faces = [top]
    verticals = {}

    def vline(p):
        key = (round(p.x, 9), round(p.y, 9))
        if key not in verticals:
            verticals[key] = Part.LineSegment(V(p.x, p.y, 0), p).toShape()
        return verticals[key]

    bottom_edges = []
    for e in top.Edges:
        p0, p1 = e.firstVertex().Point, e.lastVertex().Point
        bl = Part.LineSegment(V(p0.x, p0.y, 0), V(p1.x, p1.y, 0)).toShape()
        bottom_edges.append(bl)
        faces.append(Part.Face(Part.Wire(Part.__sortEdges__([e, vline(p1), bl, vline(p0)]))))
    faces.append(Part.Face(Part.Wire(Part.__sortEdges__(bottom_edges))))
    solid = solid_from_faces(faces)
    for f in solid.Faces[1:]:
        if not isinstance(f.Surface, Part.Plane):
            raise L.SampleError("box_bspline_top: a side face is not planar")
    return solid


FIL_R = 4.0


def filleted_box_volume(a, b, c, r):
    # Minkowski sum of the inner box (a-2r)(b-2r)(c-2r) with a ball of radius r (Steiner)
    l1, l2, l3 = a - 2 * r, b - 2 * r, c - 2 * r
    return (l1 * l2 * l3 + 2 * (l1 * l2 + l2 * l3 + l1 * l3) * r + PI * (l1 + l2 + l3) * r * r
            + 4.0 / 3.0 * PI * r ** 3)


@sample("filleted_box", "Box [0,60]x[0,40]x[0,20] with all 12 edges filleted, radius 4: 6 planes, "
        "12 quarter-cylinders, 8 spherical corner patches.",
        # every edge of the result is a tangent junction (plane/cylinder, cylinder/sphere):
        # 12 fillets x 2 lines + 8 corners x 3 arcs = 48 smooth edges (OCCT also keeps one
        # degenerate pole edge per corner patch, not written to STEP). 24 vertices (8 corners
        # x 3), all incident ends smooth -> smooth.
        {"convex": 0, "reflex": 0, "smooth": 48},
        {"convex": 0, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 24},
        volume=filleted_box_volume(60, 40, 20, FIL_R), bbox=[[0, 0, 0], [60, 40, 20]],
        mat={"seams": 12,
             "junctions": [{"point": [x, y, 10.0], "radius": 10.0}
                           for y in (10.0, 30.0) for x in (10.0, 50.0)],
             "note": "The solid is the inner box [4,56]x[4,36]x[4,16] offset by r=4 (convex), so "
                     "its medial axis is the inner box's medial axis (closure included) with "
                     "radii +4: the same 12 seams as the box sample, the corner trisectors now "
                     "ending at the corner-sphere centres (4 or 56, 4 or 36, 4 or 16) with "
                     "radius 4; junctions identical to the unfilleted 60x40x20 box."})
def build_filleted_box():
    b = Part.makeBox(60, 40, 20)
    return b.makeFillet(FIL_R, b.Edges)


CF_R = 5.0


@sample("l_bracket_concave_fillet", "The l_bracket sample with its reflex edge (x=10, z=10) "
        "replaced by a concave fillet of radius 5 (quarter-cylinder, axis x=15, z=15).",
        # the reflex edge becomes a cylinder face: its 2 tangent lines are smooth, its 2 arcs
        # on the caps meet the caps at 90 deg -> convex. The other 17 edges stay convex.
        # Vertices: 10 old corners convex; the 4 fillet corners see cap line (convex),
        # arc (convex) and tangent line (smooth) -> 2 non-smooth ends -> crease.
        {"convex": 19, "reflex": 0, "smooth": 2},
        {"convex": 10, "reflex": 0, "mixed": 0, "crease": 4, "smooth": 0},
        volume=(60 * 10 + 10 * 30) * L_DEPTH + (CF_R ** 2 - PI * CF_R ** 2 / 4) * L_DEPTH,
        bbox=[[0, 0, 0], [60, L_DEPTH, 40]])
def build_l_bracket_concave_fillet():
    s = profile_xz(L_PROFILE, L_DEPTH)
    reflex = [e for e in s.Edges
              if abs(e.BoundBox.XMin - 10) < 1e-9 and abs(e.BoundBox.XMax - 10) < 1e-9
              and abs(e.BoundBox.ZMin - 10) < 1e-9 and abs(e.BoundBox.ZMax - 10) < 1e-9]
    if len(reflex) != 1:
        raise L.SampleError("l_bracket_concave_fillet: reflex edge not found")
    return s.makeFillet(CF_R, reflex)


@sample("cylinder", "Cylinder radius 10, height 30, axis z from the origin.",
        # 2 circles (disc meets the lateral face at 90 deg) convex, 1 seam line smooth.
        # 2 seam vertices: closed circle (2 convex ends) + seam -> crease.
        {"convex": 2, "reflex": 0, "smooth": 1},
        {"convex": 0, "reflex": 0, "mixed": 0, "crease": 2, "smooth": 0},
        volume=PI * 100 * 30, bbox=[[-10, -10, 0], [10, 10, 30]],
        mat={"seams": None,
             "junctions": [{"point": [0.0, 0.0, 10.0], "radius": 10.0},
                           {"point": [0.0, 0.0, 20.0], "radius": 10.0}],
             "axis_segment": {"from": [0.0, 0.0, 10.0], "to": [0.0, 0.0, 20.0], "radius": 10.0},
             "note": "Degenerate medial axis: the axis segment z in [10,20] (every point touches "
                     "a whole circle of the lateral face, radius 10) plus two conical sheets "
                     "(bisectors of each disc and the lateral face) from the rim circles to the "
                     "segment ends; the segment ends also touch the whole disc rim and the "
                     "disc centre. No generic seams."})
def build_cylinder():
    return Part.makeCylinder(10, 30)


@sample("sphere", "Sphere radius 15 centred at the origin.",
        # OCCT has 1 seam + 2 degenerate pole edges and 2 pole vertices; the STEP writer writes
        # one face bounded by a VERTEX_LOOP: 0 edges, 1 vertex (smooth).
        {"convex": 0, "reflex": 0, "smooth": 0},
        {"convex": 0, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 1},
        volume=4.0 / 3.0 * PI * 15 ** 3, bbox=[[-15, -15, -15], [15, 15, 15]],
        mat={"seams": 0, "junctions": [{"point": [0.0, 0.0, 0.0], "radius": 15.0}],
             "note": "Degenerate: the medial axis is the single centre point, radius 15, "
                     "touching the whole sphere."})
def build_sphere():
    return Part.makeSphere(15)


@sample("torus", "Torus, major radius 20, minor radius 5, axis z, centred at the origin.",
        # 2 seam edges (meridian and parallel circles), both with the same face on both sides
        # -> smooth; 1 vertex where they cross -> smooth.
        {"convex": 0, "reflex": 0, "smooth": 2},
        {"convex": 0, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 1},
        volume=2 * PI ** 2 * 20 * 5 ** 2, bbox=[[-25, -25, -5], [25, 25, 5]],
        mat={"seams": 0, "junctions": [],
             "core_circle": {"centre": [0.0, 0.0, 0.0], "axis": [0.0, 0.0, 1.0], "radius": 20.0,
                             "ball_radius": 5.0},
             "note": "Degenerate: the medial axis is the core circle x^2+y^2=400, z=0; every "
                     "point's maximal ball (radius 5) touches a whole meridian circle."})
def build_torus():
    return Part.makeTorus(20, 5)


@sample("boss_on_plate", "Plate [0,80]x[0,60]x[0,10] with a cylindrical boss radius 12 from z=10 to "
        "z=30 centred at (40,30), fused (removeSplitter).",
        # plate 12 convex edges; boss top circle convex (90 deg); boss foot circle where the
        # plate top meets the boss wall: interior angle 270 deg -> reflex; boss seam smooth.
        # Vertices: 8 plate corners convex; 2 seam vertices on the circles -> crease.
        {"convex": 13, "reflex": 1, "smooth": 1},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 2, "smooth": 0},
        volume=80 * 60 * 10 + PI * 144 * 20, bbox=[[0, 0, 0], [80, 60, 30]])
def build_boss_on_plate():
    plate = Part.makeBox(80, 60, 10)
    boss = Part.makeCylinder(12, 20, V(40, 30, 10))
    return plate.fuse(boss).removeSplitter()


@sample("box_with_void", "Box [0,60]x[0,40]x[0,30] with a spherical void radius 8 centred at "
        "(30,20,15): one solid with an outer and an inner shell (BREP_WITH_VOIDS).",
        # 12 convex box edges, 8 convex corners. The void sphere is written as a VERTEX_LOOP
        # face (no edge, 1 vertex, smooth).
        {"convex": 12, "reflex": 0, "smooth": 0},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 1},
        volume=60 * 40 * 30 - 4.0 / 3.0 * PI * 8 ** 3, bbox=[[0, 0, 0], [60, 40, 30]],
        expect_text=["BREP_WITH_VOIDS", "ORIENTED_CLOSED_SHELL"])
def build_box_with_void():
    s = Part.makeBox(60, 40, 30).cut(Part.makeSphere(8, V(30, 20, 15)))
    if len(s.Solids) != 1 or len(s.Solids[0].Shells) != 2:
        raise L.SampleError("box_with_void: expected one solid with two shells")
    return s


ELL_A, ELL_B, ELL_H = 30.0, 15.0, 40.0


def ellipse_lat_distance(x):
    """Distance from (x, 0) to the ellipse x^2/a^2 + y^2/b^2 = 1 (a > b), |x| < a - b^2/a:
    the two nearest points are at parameter t with cos t = a x / (a^2 - b^2)."""
    a, b = ELL_A, ELL_B
    c = a * x / (a * a - b * b)
    s2 = 1.0 - c * c
    return math.sqrt((a * c - x) ** 2 + b * b * s2)


@sample("elliptic_cylinder", "Elliptic cylinder: ellipse semi-axes 30 (x) and 15 (y) centred at "
        "the origin, extruded from z=0 to z=40.",
        # 2 rim ellipses between the caps and the lateral face: 90 deg -> convex; 1 seam line
        # of the closed lateral face -> smooth. 2 vertices where the seam meets the rims, each
        # with 2 convex edge ends -> crease.
        {"convex": 2, "reflex": 0, "smooth": 1},
        {"convex": 0, "reflex": 0, "mixed": 0, "crease": 2, "smooth": 0},
        volume=PI * ELL_A * ELL_B * ELL_H, bbox=[[-ELL_A, -ELL_B, 0], [ELL_A, ELL_B, ELL_H]],
        mat={"seams": 2, "junctions": [],
             "lateral_seams": {"x_range": [-(ELL_A - ELL_B ** 2 / ELL_A), ELL_A - ELL_B ** 2 / ELL_A],
                               "radius_at_x0": ELL_B, "radius_at_ends": ELL_B ** 2 / ELL_A},
             "note": "Two seams where the ball touches the lateral face twice (at (x_t, +-y_t)) "
                     "and one cap: centre (x, 0, r) and (x, 0, 40 - r) with r the distance from "
                     "(x, 0) to the ellipse, for |x| <= a - b^2/a = 22.5; r runs from 15 at x=0 "
                     "to b^2/a = 7.5 at the ends, the centres of curvature of the ellipse's "
                     "vertices, where the seams meet the skeletal edges x = +-22.5 of the "
                     "lateral-lateral sheet y = 0. No junction: r <= 15 < 20 = h/2, so no ball "
                     "touches both caps. No convex corner: seeds are needed."})
def build_elliptic_cylinder():
    e = Part.Ellipse(V(0, 0, 0), ELL_A, ELL_B)
    face = Part.Face(Part.Wire(e.toShape()))
    return face.extrude(V(0, 0, ELL_H))


@sample("two_solids", "Two disjoint solids in one file: box [0,30]x[0,20]x[0,10] and a cylinder "
        "radius 5, height 20 on axis x=60, y=10 from z=0.",
        # box: 12 convex edges, 8 convex corners; cylinder: 2 convex circles, 1 smooth seam,
        # 2 crease vertices.
        {"convex": 14, "reflex": 0, "smooth": 1},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 2, "smooth": 0},
        volume=30 * 20 * 10 + PI * 25 * 20, bbox=[[0, 0, 0], [65, 20, 20]], solids=2)
def build_two_solids():
    return Part.makeCompound([Part.makeBox(30, 20, 10), Part.makeCylinder(5, 20, V(60, 10, 0))])


# ---- NURBS variants: same geometry as rational / non-rational B-splines (shape.toNurbs())

def nurbs_variant(base):
    src = next(s for s in SAMPLES if s["name"] == base)

    def build():
        return src["build"]().toNurbs()

    SAMPLES.append(dict(
        name=base + "_nurbs",
        description="The " + base + " sample converted with shape.toNurbs(): same geometry and "
                    "topology, every surface and curve a (rational) B-spline.",
        edge_kinds=src["edge_kinds"], vertex_kinds=src["vertex_kinds"], volume=src["volume"],
        bbox=src["bbox"], mat=src["mat"], solids=src["solids"], expect_text=[], build=build,
        nurbs_of=base))


# ---- a part placed by an assembly transform

MOVED_BOX = (40.0, 30.0, 20.0)
MOVED_T = (100.0, 50.0, 10.0)  # rotation 90 deg about z, then this translation
# world bbox: (x,y,z) -> (-y, x, z) + T  =>  x in [100-30, 100], y in [50, 50+40], z in [10, 30]
MOVED_BBOX = [[70.0, 50.0, 10.0], [100.0, 90.0, 30.0]]


def moved_world(p):
    # rotation 90 deg about z: (x, y, z) -> (-y, x, z), then + MOVED_T
    return [MOVED_T[0] - p[1], MOVED_T[1] + p[0], MOVED_T[2] + p[2]]


def moved_mat():
    m = box_mat(*MOVED_BOX)
    for j in m["junctions"]:
        j["point"] = moved_world(j["point"])
    m["note"] = ("World coordinates (the local box [0,40]x[0,30]x[0,20] has junctions (10 or 30, "
                 "10 or 20, 10), mapped by (x,y,z) -> (100-y, 50+x, 10+z)). " + m["note"])
    return m


@sample("moved_part", "Box 40x30x20 (local [0,40]x[0,30]x[0,20]) placed in an App::Part "
        "assembly by a transform: rotation 90 deg about z then translation (100,50,10). The "
        "shape is stored in local coordinates; the placement is a STEP "
        "ITEM_DEFINED_TRANSFORMATION. World bbox [70,100]x[50,90]x[10,30].",
        # a box: 12 convex edges, 8 convex corners
        {"convex": 12, "reflex": 0, "smooth": 0},
        {"convex": 8, "reflex": 0, "mixed": 0, "crease": 0, "smooth": 0},
        volume=MOVED_BOX[0] * MOVED_BOX[1] * MOVED_BOX[2], bbox=MOVED_BBOX, mat=moved_mat(),
        expect_text=["REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION",
                     "ITEM_DEFINED_TRANSFORMATION", "NEXT_ASSEMBLY_USAGE_OCCURRENCE"])
def build_moved_part():
    return Part.makeBox(*MOVED_BOX)  # exported by export_moved_part()


def export_moved_part(local_shape, path):
    import Import
    doc = FreeCAD.newDocument("moved_part")
    part = doc.addObject("App::Part", "Assembly")
    box = doc.addObject("Part::Feature", "Box")
    box.Shape = local_shape
    # The App::Part's own Placement is the root of the exported tree and is NOT written
    # (FreeCAD 0.20): the transform must sit on the child inside the container.
    box.Placement = FreeCAD.Placement(V(*MOVED_T), FreeCAD.Rotation(V(0, 0, 1), 90))
    part.addObject(box)
    doc.recompute()
    world = box.Shape.copy()  # carries the placement
    Import.export([part], path)
    FreeCAD.closeDocument(doc.Name)
    return world


nurbs_variant("box")
nurbs_variant("l_bracket")
nurbs_variant("cylinder")
nurbs_variant("sphere")
nurbs_variant("elliptic_cylinder")

# fill in the computed top of the B-spline box
for _s in SAMPLES:
    if _s["name"] == "box_bspline_top":
        _s["bbox"][1][2] = bspline_box_zmax(60.0, 40.0, 20.0)


# ----------------------------------------------------------------------------------------

def make(s, outdir, meta_dir):
    shape = s["build"]()
    exporter = export_moved_part if s["name"] == "moved_part" else None
    # FreeCAD's .Volume is exact on analytic solids; on B-splines it is off by up to 1 %, so
    # it is only checked loosely there (scripts/build_manifest.py checks every file with
    # OCCT's BRepGProp and a tight tolerance).
    rel = 1e-9 if s["nurbs_of"] is None and s["name"] != "box_bspline_top" else None
    L.export_and_check(s, shape, outdir, meta_dir, MADE_BY, exporter=exporter, volume_rel=rel)


def main():
    args = L.parse_args(sys.argv[1:], "samples")
    L.setup_step_writer()
    os.makedirs(args.outdir, exist_ok=True)
    only = set(args.only.split(",")) if args.only else None
    for s in SAMPLES:
        if only and s["name"] not in only:
            continue
        make(s, args.outdir, args.meta)


if __name__ == "__main__":
    L.run_main(main)
