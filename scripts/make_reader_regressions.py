#!/usr/bin/env python3
"""Writes samples/reader/: one small file per way real exporters write STEP and IGES that the
reader must take in stride (with a warning) or refuse (with an error naming the entity).

Each is made from a reference sample by editing its text, so what the right answer is stays
obvious: the same solid as the sample (or, for the assemblies, the sample placed twice).
tests/it/reader.rs reads each and checks the warning or the error, and the answer.

    python3 scripts/make_reader_regressions.py      # rewrites samples/reader/
"""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
OUT = SAMPLES / "reader"


def text(name):
    return (SAMPLES / name).read_text()


def max_id(t):
    return max(int(m) for m in re.findall(r"^#(\d+)\s*=", t, re.M))


def add_before_endsec(t, lines):
    """Adds instances at the end of the DATA section."""
    i = t.rindex("ENDSEC;")
    return t[:i] + "".join(line + "\n" for line in lines) + t[i:]


def write(name, data):
    path = OUT / name
    if isinstance(data, str):
        data = data.encode("ascii")
    path.write_bytes(data)
    print(f"wrote {path.relative_to(ROOT)} ({len(data)} bytes)")


def unused_entities():
    """Cause 1: an exporter's stray EDGE_CURVE (with its vertices and line) that no face uses,
    and a loose face beside the solid: ignored with a warning, the box read as it is."""
    t = text("box.step")
    n = max_id(t)
    a = n + 1
    return add_before_endsec(t, [
        f"#{a} = CARTESIAN_POINT('',(100.,0.,0.));",
        f"#{a + 1} = CARTESIAN_POINT('',(100.,10.,0.));",
        f"#{a + 2} = VERTEX_POINT('',#{a});",
        f"#{a + 3} = VERTEX_POINT('',#{a + 1});",
        f"#{a + 4} = DIRECTION('',(0.,1.,0.));",
        f"#{a + 5} = VECTOR('',#{a + 4},1.);",
        f"#{a + 6} = LINE('',#{a},#{a + 5});",
        f"#{a + 7} = EDGE_CURVE('',#{a + 2},#{a + 3},#{a + 6},.T.);",
    ])


def scaled_directions():
    """Cause 2: CATIA V5 in inches writes every DIRECTION with length 1/25.4, and circle
    placements without a reference direction. Read right, it is the cylinder."""
    t = text("cylinder.step")

    def scale(m):
        ratios = [float(x) / 25.4 for x in m.group(2).split(",")]
        return f"DIRECTION({m.group(1)},({','.join(repr(r) for r in ratios)}))"

    t = re.sub(r"DIRECTION\(('[^']*'),\(([^)]*)\)\)", scale, t)
    # Every circle's placement loses its reference direction.
    circles = set(re.findall(r"CIRCLE\('[^']*',#(\d+),", t))
    for c in circles:
        t = re.sub(rf"^(#{c} = AXIS2_PLACEMENT_3D\('[^']*',#\d+,#\d+),#\d+\)",
                   r"\1,$)", t, flags=re.M)
    return t


def moved_vertex(uncertainty):
    """Cause 3: a vertex 5e-3 mm off its circle (moved radially), in a file declaring the
    given length uncertainty."""
    t = text("cylinder.step")
    t = t.replace("#23 = CARTESIAN_POINT('',(10.,-2.449293598295E-15,30.));",
                  "#23 = CARTESIAN_POINT('',(10.005,-2.449293598295E-15,30.));")
    assert "10.005" in t
    t = t.replace("UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07)",
                  f"UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({uncertainty})")
    return t


def edges_off_their_face():
    """Cause 3 (curve to surface): the box's top plane moved up by 0.015 mm, so its four edges
    lie 0.015 mm (up to 7e-4 of the coordinates' size) off the face's surface: within what
    the reader accepts (1e-3 of it), and reported with the largest gap."""
    t = text("box.step")
    old = "#128 = CARTESIAN_POINT('',(0.,0.,20.));"
    assert old in t
    return t.replace(old, "#128 = CARTESIAN_POINT('',(0.,0.,20.015));")


def edge_on_part_of_a_curve():
    """Cause 3 (edge to curve): the box's edge from (0,0,0) to (0,0,20) written on the first of
    the two Bezier pieces of a cubic B-spline (0 <= t <= 2): the first straight along the edge,
    ending at its far vertex at t = 1, the second curling away from the box, as an exporter
    writes an edge on a stretch of a longer intersection curve. The far vertex is in the
    middle of the curve: a search for it from the curve's far end stops on the curl."""
    t = text("box.step")
    old = "#27 = LINE('',#28,#29);"
    assert old in t
    n = max_id(t)
    points = [(0, 0, 0), (0, 0, 20 / 3), (0, 0, 40 / 3), (0, 0, 20),
              (30, 5, 25), (40, 40, 30), (-10, 10, 60)]
    lines = [f"#{n + 1 + k} = CARTESIAN_POINT('',({x!r},{y!r},{z!r}));"
             for k, (x, y, z) in enumerate(points)]
    refs = ",".join(f"#{n + 1 + k}" for k in range(len(points)))
    curve = n + 1 + len(points)
    lines.append(f"#{curve} = B_SPLINE_CURVE_WITH_KNOTS('',3,({refs}),.UNSPECIFIED.,.F.,.F.,"
                 "(4,3,4),(0.,1.,2.),.UNSPECIFIED.);")
    t = t.replace("#26 = SURFACE_CURVE('',#27,", f"#26 = SURFACE_CURVE('',#{curve},")
    return add_before_endsec(t, lines)


def latin1_name():
    """Cause 4 (STEP): a product name in Windows-1252 / Latin-1 (not UTF-8)."""
    t = text("box.step")
    t = t.replace("#7 = PRODUCT('Open CASCADE STEP translator 7.6 1'",
                  "#7 = PRODUCT('Caf\xe9 Sch\xf6n'")
    assert "Caf" in t
    return t.encode("latin-1")


def utf8_iges_name():
    """Cause 4 (IGES): Inventor writes `8HSólido1`: UTF-8 bytes in a Hollerith string, counted
    in bytes. Two ASCII letters of the global section's file name become one 2-byte `ó`."""
    t = (SAMPLES / "iges" / "box.brep.igs").read_bytes()
    old = b"13HFilename.iges"
    assert old in t
    return t.replace(old, b"13HFile\xc3\xb3me.iges")


def empty_iges_range():
    """Cause 8: a 126 B-spline curve whose parameter range is written [0, 0]: the knots' own
    range is meant. The first edge curve of box_nurbs (OCCT's IGES) gets V1 = 0."""
    t = (SAMPLES / "iges" / "box_nurbs.brep.igs").read_bytes()
    old = b"126,1,1,1,0,1,0,0.,0.,20.,20.,1.,1.,0.,0.,0.,0.,0.,20.,0.,20.,   0000013P0000011"
    new = b"126,1,1,1,0,1,0,0.,0.,20.,20.,1.,1.,0.,0.,0.,0.,0.,20.,0.,0.,    0000013P0000011"
    assert old in t and len(old) == len(new)
    return t.replace(old, new)


class Iges:
    """A fixed-format IGES file as its sections, with each entity's Directory Entry fields and
    parameter text, so that entities can be retyped and their parameters rewritten; `bytes()`
    lays the Parameter Data out again and updates every entry's pointer and line count."""

    def __init__(self, data):
        lines = data.decode("ascii").splitlines()
        self.start = [l for l in lines if l[72:73] == "S"]
        self.glob = [l for l in lines if l[72:73] == "G"]
        d = [l for l in lines if l[72:73] == "D"]
        p = [l for l in lines if l[72:73] == "P"]
        self.entries = []  # [fields of line 1 (9), fields of line 2 (9)]
        for k in range(0, len(d), 2):
            f1 = [d[k][8 * i:8 * i + 8] for i in range(9)]
            f2 = [d[k + 1][8 * i:8 * i + 8] for i in range(9)]
            self.entries.append([f1, f2])
        self.params = {}
        for l in p:
            de = int(l[64:72])
            self.params[de] = self.params.get(de, "") + l[:64].rstrip()

    def entity_type(self, de):
        return int(self.entries[(de - 1) // 2][0][0])

    def retype(self, de, entity_type, form, params):
        f1, f2 = self.entries[(de - 1) // 2]
        f1[0] = f2[0] = "%8d" % entity_type
        f2[4] = "%8d" % form
        self.params[de] = params

    def bytes(self):
        out, plines = [], []
        for k, (f1, f2) in enumerate(self.entries):
            de = 2 * k + 1
            text = self.params[de]
            first = len(plines) + 1
            while text:
                cut = len(text) if len(text) <= 64 else text.rfind(",", 0, 64) + 1
                plines.append("%-64s %7d" % (text[:cut], de))
                text = text[cut:]
            f1[1] = "%8d" % first
            f2[3] = "%8d" % (len(plines) + 1 - first)
        for name, sec in (("S", self.start), ("G", self.glob)):
            out += [l[:72] + name + "%7d" % (i + 1) for i, l in enumerate(sec)]
        d = []
        for f1, f2 in self.entries:
            d += ["".join(f1), "".join(f2)]
        out += ["%-72sD%7d" % (l, i + 1) for i, l in enumerate(d)]
        out += ["%sP%7d" % (l, i + 1) for i, l in enumerate(plines)]
        out.append("S%7dG%7dD%7dP%7d%40sT%7d" % (len(self.start), len(self.glob), len(d),
                                                len(plines), "", 1))
        return ("\n".join(out) + "\n").encode("ascii")


def loose_faces_iges():
    """Cause 8 (IGES): B-rep faces (510) that no shell (514) or solid (186) lists: OCCT's box
    with its 186 and 514 made null entities (type 0). The faces are sewn into a closed shell by
    their edges' geometry, as a soup is."""
    g = Iges((SAMPLES / "iges" / "box.brep.igs").read_bytes())
    n = 0
    for k in range(len(g.entries)):
        de = 2 * k + 1
        if g.entity_type(de) in (186, 514):
            g.retype(de, 0, 0, "0;")
            n += 1
    assert n == 2
    return g.bytes()


def shells_without_solid_iges():
    """Cause 8 (IGES): a surface model: OCCT's box with a void, its 186 made a null entity, so
    that two closed shells (514) remain and nothing says the inner one is a void."""
    g = Iges((SAMPLES / "iges" / "box_with_void.brep.igs").read_bytes())
    n = 0
    for k in range(len(g.entries)):
        de = 2 * k + 1
        if g.entity_type(de) == 186:
            g.retype(de, 0, 0, "0;")
            n += 1
    assert n == 1
    return g.bytes()


def bounded_surfaces_iges():
    """Cause 8 (IGES): bounded surfaces (143) with boundaries (141) and no shell: FreeCAD's
    soup of the plate with holes, each trimmed surface (144) rewritten as a 143 and each curve
    on a surface (142) as a 141 listing its model-space curve."""
    g = Iges((SAMPLES / "iges" / "plate_with_holes.soup.igs").read_bytes())
    n = 0
    for k in range(len(g.entries)):
        de = 2 * k + 1
        t = g.entity_type(de)
        p = g.params[de].rstrip(";").split(",")
        if t == 144:
            # 144: PTS, N1, N2, PTO, PTI… → 143: TYPE 0, SPTR, N, BDPT…
            pts, n2, pto, pti = p[1], int(p[3]), p[4], p[5:5 + int(p[3])]
            g.retype(de, 143, 0, ",".join(["143", "0", pts, str(1 + n2), pto] + pti) + ";")
            n += 1
        elif t == 142:
            # 142: CRTN, SPTR, BPTR, CPTR, PREF → 141: TYPE 0, PREF, SPTR, N 1, CRVPT, SENS 1, K 0
            sptr, cptr = p[2], p[4]
            g.retype(de, 141, 0, ",".join(["141", "0", "0", sptr, "1", cptr, "1", "0"]) + ";")
    assert n > 0
    return g.bytes()


def assembly(reversed_order):
    """Cause 5: the box as a part placed twice in an assembly by NAUO / CDSR / RRWT /
    ITEM_DEFINED_TRANSFORMATION: once moved by (100, 0, 0), once turned 90° about z and moved
    by (0, 200, 0). ISO's order puts the component's representation first; SolidWorks writes
    the assembly's first (`reversed_order`). The right answer is two boxes, where placed."""
    t = text("box.step")
    n = max_id(t)
    a = n + 1
    # The assembly's product, its shape representation with three placements (origin and
    # the two targets), and two NAUOs of the box's product definition #5.
    lines = [
        f"#{a} = PRODUCT('assembly','assembly','',(#8));",
        f"#{a + 1} = PRODUCT_DEFINITION_FORMATION('','',#{a});",
        f"#{a + 2} = PRODUCT_DEFINITION('design','',#{a + 1},#9);",
        f"#{a + 3} = PRODUCT_DEFINITION_SHAPE('','',#{a + 2});",
        f"#{a + 4} = CARTESIAN_POINT('',(0.,0.,0.));",
        f"#{a + 5} = DIRECTION('',(0.,0.,1.));",
        f"#{a + 6} = DIRECTION('',(1.,0.,0.));",
        f"#{a + 7} = AXIS2_PLACEMENT_3D('',#{a + 4},#{a + 5},#{a + 6});",
        f"#{a + 8} = CARTESIAN_POINT('',(100.,0.,0.));",
        f"#{a + 9} = AXIS2_PLACEMENT_3D('',#{a + 8},#{a + 5},#{a + 6});",
        f"#{a + 10} = CARTESIAN_POINT('',(0.,200.,0.));",
        f"#{a + 11} = DIRECTION('',(0.,1.,0.));",
        f"#{a + 12} = AXIS2_PLACEMENT_3D('',#{a + 10},#{a + 5},#{a + 11});",
        f"#{a + 13} = SHAPE_REPRESENTATION('assembly',(#{a + 7},#{a + 9},#{a + 12}),#345);",
        f"#{a + 14} = SHAPE_DEFINITION_REPRESENTATION(#{a + 3},#{a + 13});",
    ]
    k = a + 15
    for target in (a + 9, a + 12):
        nauo, pds, idt, rr, cdsr = k, k + 1, k + 2, k + 3, k + 4
        k += 5
        if reversed_order:
            rep1, rep2, item1, item2 = a + 13, 10, target, 11
        else:
            rep1, rep2, item1, item2 = 10, a + 13, 11, target
        lines += [
            f"#{nauo} = NEXT_ASSEMBLY_USAGE_OCCURRENCE('{nauo}','box','',#{a + 2},#5,$);",
            f"#{pds} = PRODUCT_DEFINITION_SHAPE('','',#{nauo});",
            f"#{idt} = ITEM_DEFINED_TRANSFORMATION('','',#{item1},#{item2});",
            f"#{rr} = ( REPRESENTATION_RELATIONSHIP('','',#{rep1},#{rep2}) "
            f"REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{idt}) "
            f"SHAPE_REPRESENTATION_RELATIONSHIP() );",
            f"#{cdsr} = CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{rr},#{pds});",
        ]
    return add_before_endsec(t, lines)


def assembly_unplaced_component():
    """Cause 5: the ISO-order assembly with the second use's CONTEXT_DEPENDENT_SHAPE_
    REPRESENTATION left out: nothing places that component, so it is taken in the assembly's
    coordinates (as OCCT takes it), with a warning naming its NAUO."""
    t = assembly(False)
    lines = t.split("\n")
    cdsr = [k for k, l in enumerate(lines) if "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION" in l]
    assert len(cdsr) == 2
    del lines[cdsr[1]]
    return "\n".join(lines)


def mapped_item():
    """Cause 5: the part's shape given as a MAPPED_ITEM of the brep's representation (a
    REPRESENTATION_MAP with the representation's own placement as origin) with a target moved
    by (50, 0, 0) and turned 90° about z: the box must come out there, not where its
    representation has it."""
    t = text("box.step")
    old = "#3 = SHAPE_DEFINITION_REPRESENTATION(#4,#10);"
    assert old in t
    a = max_id(t) + 1
    t = t.replace(old, f"#3 = SHAPE_DEFINITION_REPRESENTATION(#4,#{a + 6});")
    return add_before_endsec(t, [
        f"#{a} = CARTESIAN_POINT('',(50.,0.,0.));",
        f"#{a + 1} = DIRECTION('',(0.,0.,1.));",
        f"#{a + 2} = DIRECTION('',(0.,1.,0.));",
        f"#{a + 3} = AXIS2_PLACEMENT_3D('',#{a},#{a + 1},#{a + 2});",
        f"#{a + 4} = REPRESENTATION_MAP(#11,#10);",
        f"#{a + 5} = MAPPED_ITEM('',#{a + 4},#{a + 3});",
        f"#{a + 6} = SHAPE_REPRESENTATION('',(#{a + 5}),#345);",
    ])


def void_faces_into_the_void():
    """Cause 6: Inventor writes a void as ORIENTED_CLOSED_SHELL(.F.) over a CLOSED_SHELL whose
    faces already point into the void, so the .F. turns them into the material. Here the
    spherical void of box_with_void (FreeCAD writes its face pointing out of the void) has its
    face's sense turned. Read right, it is box_with_void: the void's centre is outside."""
    t = text("box_with_void.step")
    t2 = t.replace("#347 = ADVANCED_FACE('',(#348),#352,.T.);",
                   "#347 = ADVANCED_FACE('',(#348),#352,.F.);")
    assert t2 != t
    return t2


def flipped_face():
    """Cause 7: one ADVANCED_FACE of the box with its sense flag turned (its loops, and every
    other face, as before). Read as written, the box gets four "reflex" edges; the loops say
    which way the face points, so it is turned back."""
    t = text("box.step")
    t2 = t.replace("#17 = ADVANCED_FACE('',(#18),#32,.F.);", "#17 = ADVANCED_FACE('',(#18),#32,.T.);")
    assert t2 != t
    return t2


def surface_model(closed):
    """Cause 8 (STEP): no solid, the box's shell stored in a SHELL_BASED_SURFACE_MODEL (as
    some exporters write a closed body). Closed, it is read as the box, with a warning; made
    open (one face left out), it is refused."""
    t = text("box.step")
    t = t.replace("#15 = MANIFOLD_SOLID_BREP('',#16);", "#15 = SHELL_BASED_SURFACE_MODEL('',(#16));")
    t = t.replace("ADVANCED_BREP_SHAPE_REPRESENTATION", "MANIFOLD_SURFACE_SHAPE_REPRESENTATION")
    if not closed:
        t = t.replace("#16 = CLOSED_SHELL('',(#17,#137,#237,#284,#331,#338));",
                      "#16 = OPEN_SHELL('',(#17,#137,#237,#284,#331));")
    assert "SHELL_BASED_SURFACE_MODEL" in t and (closed or "OPEN_SHELL" in t)
    return t


def repeated_id():
    """Cause 7: the length unit #346 defined a second time, in metres: which one a reference
    means is unknown, so the file is refused."""
    t = text("box.step")
    return add_before_endsec(t, ["#346 = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.METRE.) );"])


def zero_direction():
    """A DIRECTION of length zero gives no direction: refused, naming it."""
    t = text("box.step")
    t2 = t.replace("#13 = DIRECTION('',(0.,0.,1.));", "#13 = DIRECTION('',(0.,0.,0.));")
    assert t2 != t
    return t2


def main():
    OUT.mkdir(exist_ok=True)
    write("unused_entities.step", unused_entities())
    write("scaled_directions.step", scaled_directions())
    write("gap_within_uncertainty.step", moved_vertex("0.01"))
    write("gap_beyond_uncertainty.step", moved_vertex("1.E-07"))
    write("edges_off_their_face.step", edges_off_their_face())
    write("edge_on_part_of_a_curve.step", edge_on_part_of_a_curve())
    write("latin1_name.step", latin1_name())
    write("utf8_name.igs", utf8_iges_name())
    write("empty_range.igs", empty_iges_range())
    write("loose_faces.igs", loose_faces_iges())
    write("bounded_surfaces.igs", bounded_surfaces_iges())
    write("shells_without_solid.igs", shells_without_solid_iges())
    write("assembly_iso_order.step", assembly(False))
    write("assembly_reversed_order.step", assembly(True))
    write("mapped_item.step", mapped_item())
    write("assembly_unplaced_component.step", assembly_unplaced_component())
    write("void_faces_into_the_void.step", void_faces_into_the_void())
    write("flipped_face.step", flipped_face())
    write("surface_model_closed.step", surface_model(True))
    write("surface_model_open.step", surface_model(False))
    write("repeated_id.step", repeated_id())
    write("zero_direction.step", zero_direction())


if __name__ == "__main__":
    main()
