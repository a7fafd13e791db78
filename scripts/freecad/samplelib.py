"""Shared helpers for the FreeCAD sample scripts.

Run with Debian's python (/usr/bin/python3), not freecadcmd and not the pyenv python:
the FreeCAD 0.20 modules are found through /usr/lib/freecad-python3/lib.

What lives here:
  * setup()           - sys.path and the STEP writer preference (AP214IS)
  * classify()        - independent edge / vertex kind computation from face normals
  * check_kinds()     - compare a hand-written kind dict with classify(), fail loudly
  * check_solid()     - validity / closed-solid checks
  * write_meta()      - per-sample JSON consumed by scripts/build_manifest.py
"""

import json
import math
import os
import sys

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.dirname(HERE)

if FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)
if SCRIPTS not in sys.path:
    sys.path.insert(0, SCRIPTS)

import FreeCAD  # noqa: E402
import Part  # noqa: E402

import steptext  # noqa: E402  (scripts/steptext.py)

V = FreeCAD.Vector

EDGE_KEYS = ("convex", "reflex", "smooth")
VERTEX_KEYS = ("convex", "reflex", "mixed", "crease", "smooth")


class SampleError(RuntimeError):
    pass


def setup_step_writer():
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Part/STEP").SetString("Scheme", "AP214IS")


def add_openscad_paths():
    """sys.path for FreeCAD's OpenSCAD importer (importCSG) and the OpenSCAD binary."""
    for p in ["/usr/share/freecad/Mod", "/usr/share/freecad/Ext"]:
        if p not in sys.path:
            sys.path.append(p)
    mod = "/usr/share/freecad/Mod"
    for d in sorted(os.listdir(mod)):
        full = os.path.join(mod, d)
        if os.path.isdir(full) and full not in sys.path:
            sys.path.append(full)
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/OpenSCAD").SetString(
        "openscadexecutable", "/usr/bin/openscad")


# ----------------------------------------------------------------------------------------
# checks on the built shape

def check_solid(name, shape, n_solids=1):
    if shape.isNull():
        raise SampleError(f"{name}: null shape")
    if not shape.isValid():
        raise SampleError(f"{name}: shape.isValid() is False")
    solids = shape.Solids
    if len(solids) != n_solids:
        raise SampleError(f"{name}: expected {n_solids} solid(s), got {len(solids)}")
    for s in solids:
        if not s.isValid():
            raise SampleError(f"{name}: a solid is not valid")
        for sh in s.Shells:
            if not sh.isClosed():
                raise SampleError(f"{name}: a shell is not closed")
        if s.Volume <= 0:
            raise SampleError(f"{name}: non-positive volume {s.Volume}")
    # every face must belong to a solid (no loose faces in the compound)
    if len(shape.Faces) != sum(len(s.Faces) for s in solids):
        raise SampleError(f"{name}: faces outside the solids")


def occt_counts(shape):
    return {"faces": len(shape.Faces), "edges": len(shape.Edges), "vertices": len(shape.Vertexes)}


# ----------------------------------------------------------------------------------------
# independent kind computation

def _oriented_tangent(edge, t):
    d = edge.tangentAt(t)  # curve direction, orientation not applied
    if edge.Orientation == "Reversed":
        d = d * -1.0
    return d


def _face_normal(face, p):
    u, v = face.Surface.parameter(p)
    return face.normalAt(u, v)  # takes the face orientation into account (BRepGProp_Face)


def interior_angles(shape, n=9):
    """For every non-degenerate edge: list of solid interior angles (degrees) at n interior
    sample points, or the string 'seam' for a closed-surface seam (same face on both sides).

    Outward normals n1, n2 of the two faces; d_i = n_i x t_i points from the edge into face
    i, with t_i the edge tangent oriented as in face i's boundary (material on the left).
    The interior angle is the angle from d1 to d2 turning through the material (-n1 side).
    """
    faces = shape.Faces
    occ = {}  # edge hash -> list of (face, oriented edge)
    seams = set()
    for f in faces:
        for e in f.Edges:
            if e.Degenerated:
                continue
            h = e.hashCode()
            if e.isSeam(f):
                seams.add(h)
            occ.setdefault(h, []).append((f, e))
    result = []
    for e in shape.Edges:
        if e.Degenerated:
            continue
        h = e.hashCode()
        lst = [(f, oe) for (f, oe) in occ.get(h, []) if oe.isSame(e)]
        if h in seams:
            result.append((e, "seam"))
            continue
        if len(lst) != 2:
            raise SampleError(f"edge with {len(lst)} adjacent faces (not a closed 2-manifold)")
        (f1, e1), (f2, e2) = lst
        a, b = e.FirstParameter, e.LastParameter
        angles = []
        for k in range(n):
            t = a + (k + 0.5) / n * (b - a)
            p = e.valueAt(t)
            n1 = _face_normal(f1, p)
            n2 = _face_normal(f2, p)
            d1 = n1.cross(_oriented_tangent(e1, t))
            d2 = n2.cross(_oriented_tangent(e2, t))
            d1.normalize()
            d2.normalize()
            alpha = math.degrees(math.atan2(d2.dot(n1 * -1.0), d2.dot(d1)))
            if alpha < 0:
                alpha += 360.0
            angles.append(alpha)
        result.append((e, angles))
    return result


def _edge_kind(angles, tol=1.0):
    if angles == "seam":
        return "smooth"
    kinds = set()
    for a in angles:
        if a < 180.0 - tol:
            kinds.add("convex")
        elif a > 180.0 + tol:
            kinds.add("reflex")
        else:
            kinds.add("smooth")
    return kinds.pop() if len(kinds) == 1 else "mixed"


def classify(shape):
    """Computed (edge_kinds, vertex_kinds, extra) of the non-degenerate topology of shape."""
    edges = interior_angles(shape)
    ek = {k: 0 for k in EDGE_KEYS}
    ek["mixed"] = 0
    ends = {}  # vertex hash -> list of kinds of incident edge ends
    for e, angles in edges:
        k = _edge_kind(angles)
        ek[k] += 1
        for v in (e.firstVertex(), e.lastVertex()):
            ends.setdefault(v.hashCode(), []).append(k)
    vk = {k: 0 for k in VERTEX_KEYS}
    for v in shape.Vertexes:
        kinds = [k for k in ends.get(v.hashCode(), []) if k != "smooth"]
        if "mixed" in kinds:
            raise SampleError("an edge changes kind along its length (mixed edge)")
        if len(kinds) == 0:
            vk["smooth"] += 1
        elif len(kinds) <= 2:
            vk["crease"] += 1
        elif all(k == "convex" for k in kinds):
            vk["convex"] += 1
        elif all(k == "reflex" for k in kinds):
            vk["reflex"] += 1
        else:
            vk["mixed"] += 1
    extra = {"nondegenerate_edges": len(edges), "vertices": len(shape.Vertexes)}
    return ek, vk, extra


def check_kinds(name, shape, hand_edges, hand_vertices, step_counts):
    """Fail loudly unless the hand-written kinds agree with classify(shape).

    The hand dicts describe the topology of the STEP FILE. The OCCT STEP writer drops a
    few smooth items of closed surfaces (a sphere's seam and one pole: it writes a
    VERTEX_LOOP instead), so the smooth counts are compared after removing the edges /
    vertices that are on the shape but not in the file; all other kinds must be equal.
    """
    ek, vk, extra = classify(shape)
    hand_edges = {k: hand_edges.get(k, 0) for k in EDGE_KEYS}
    hand_vertices = {k: hand_vertices.get(k, 0) for k in VERTEX_KEYS}
    dropped_e = extra["nondegenerate_edges"] - step_counts["edges"]
    dropped_v = extra["vertices"] - step_counts["vertices"]
    problems = []
    if ek["mixed"]:
        problems.append(f"{ek['mixed']} mixed edge(s)")
    if dropped_e < 0 or dropped_v < 0:
        problems.append(f"file has more edges/vertices than the shape ({dropped_e}, {dropped_v})")
    for k in ("convex", "reflex"):
        if hand_edges[k] != ek[k]:
            problems.append(f"edges {k}: hand {hand_edges[k]} != computed {ek[k]}")
    if hand_edges["smooth"] != ek["smooth"] - dropped_e:
        problems.append(f"edges smooth: hand {hand_edges['smooth']} != computed {ek['smooth']}"
                        f" - {dropped_e} not written to the file")
    for k in ("convex", "reflex", "mixed", "crease"):
        if hand_vertices[k] != vk[k]:
            problems.append(f"vertices {k}: hand {hand_vertices[k]} != computed {vk[k]}")
    if hand_vertices["smooth"] != vk["smooth"] - dropped_v:
        problems.append(f"vertices smooth: hand {hand_vertices['smooth']} != computed {vk['smooth']}"
                        f" - {dropped_v} not written to the file")
    if sum(hand_edges.values()) != step_counts["edges"]:
        problems.append(f"hand edge kinds sum to {sum(hand_edges.values())}, file has {step_counts['edges']} edges")
    if sum(hand_vertices.values()) != step_counts["vertices"]:
        problems.append(f"hand vertex kinds sum to {sum(hand_vertices.values())}, file has {step_counts['vertices']} vertices")
    if problems:
        raise SampleError(f"{name}: kind check failed: " + "; ".join(problems)
                          + f" (computed edges {ek}, vertices {vk})")
    return ek, vk


def check_bbox(name, shape, bbox, tol=1e-6):
    # TRAP (FreeCAD 0.20): optimalBoundingBox(False, False) kills the interpreter with
    # exit status 1 and no message, even inside try/except. One argument is fine
    # (useShapeTolerance defaults to False).
    bb = shape.optimalBoundingBox(False)
    got = [[bb.XMin, bb.YMin, bb.ZMin], [bb.XMax, bb.YMax, bb.ZMax]]
    for i in range(2):
        for j in range(3):
            if abs(got[i][j] - bbox[i][j]) > tol:
                raise SampleError(f"{name}: bbox {got} differs from the expected {bbox}")


def check_volume(name, shape, volume, rel=1e-9):
    got = shape.Volume
    if abs(got - volume) > rel * abs(volume):
        raise SampleError(f"{name}: volume {got} differs from the expected {volume}")


def export_and_check(s, shape, outdir, meta_dir, made_by, exporter=None, volume_rel=1e-9):
    """Check, export and describe one sample.

    s: dict with name, description, edge_kinds, vertex_kinds, volume, bbox, mat, solids,
    expect_text. exporter(shape, path) -> world-space shape, for special exports (default:
    shape.exportStep). The STEP file is written under a temporary name and renamed only
    when every check passed."""
    name = s["name"]
    path = os.path.join(outdir, name + ".step")
    tmp = os.path.join(outdir, "." + name + ".partial.step")
    try:
        check_solid(name, shape, s["solids"])
        if exporter is not None:
            world = exporter(shape, tmp)
        else:
            world = shape
            export = shape.Solids[0] if s["solids"] == 1 and shape.ShapeType != "Solid" else shape
            export.exportStep(tmp)
        check_bbox(name, world, s["bbox"], tol=1e-6)
        check_volume(name, world, s["volume"], rel=volume_rel if volume_rel else 1e-2)
        step = steptext.analyse(tmp)
        missing = [t for t in s.get("expect_text", []) if t not in step["entity_counts"]]
        if missing:
            raise SampleError(f"{name}: the STEP text lacks {missing}")
        if step["solids"] != s["solids"]:
            raise SampleError(f"{name}: {step['solids']} solids in the file, expected {s['solids']}")
        if step["length_unit"] != "mm":
            raise SampleError(f"{name}: length unit {step['length_unit']} in the file, expected mm")
        check_kinds(name, world, s["edge_kinds"], s["vertex_kinds"], step)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    meta = {
        "file": name + ".step",
        "made_by": made_by,
        "description": s["description"],
        "length_unit": "mm",
        "solids": s["solids"],
        "edge_kinds": s["edge_kinds"],
        "vertex_kinds": s["vertex_kinds"],
        "volume": s["volume"],
        "bbox": s["bbox"],
        "occt": occt_counts(world),
        "mat": s.get("mat"),
        "expect_text": s.get("expect_text", []),
    }
    write_meta(meta_dir, meta)
    print(f"{name + '.step':32s} faces {step['faces']:3d} edges {step['edges']:3d} "
          f"vertices {step['vertices']:3d}  {step['surfaces']}", flush=True)
    return meta


def write_regression_part(outdir, name, solid, made_by, description, extra=None):
    """Write one regression part's STEP file (under a temporary name, renamed when written)
    and return its manifest entry: file, made_by, description, the topology counts and the
    volume, then `extra`'s fields."""
    path = os.path.join(outdir, name + ".step")
    tmp = os.path.join(outdir, "." + name + ".partial.step")
    solid.exportStep(tmp)
    os.replace(tmp, path)
    entry = {
        "file": name + ".step",
        "made_by": made_by,
        "description": description,
        "faces": len(solid.Faces), "edges": len(solid.Edges),
        "vertices": len(solid.Vertexes),
        "volume": round(solid.Volume, 9),
    }
    entry.update(extra or {})
    print(f"{name + '.step':28s} faces {len(solid.Faces):3d} "
          f"edges {len(solid.Edges):3d} volume {solid.Volume:.6f}", flush=True)
    return entry


def write_manifest(outdir, made_by, parts):
    """OUTDIR/manifest.json: `{"made_by": ..., "parts": [...]}`."""
    with open(os.path.join(outdir, "manifest.json"), "w") as f:
        json.dump({"made_by": made_by, "parts": parts}, f, indent=1)
        f.write("\n")


def write_meta(meta_dir, meta):
    if not meta_dir:
        return
    os.makedirs(meta_dir, exist_ok=True)
    path = os.path.join(meta_dir, meta["file"][:-len(".step")] + ".json")
    with open(path, "w") as f:
        json.dump(meta, f, indent=1)


def run_main(main):
    """Run main() and make sure a failure is reported: some FreeCAD exceptions end the
    process with status 1 and no traceback, so print it ourselves."""
    import traceback
    try:
        main()
    except BaseException as e:  # noqa: BLE001
        if isinstance(e, SystemExit) and not e.code:
            raise
        sys.__stderr__.write(traceback.format_exc())
        sys.__stderr__.write(f"FAILED: {type(e).__name__}: {e!r}\n")
        sys.__stderr__.flush()
        sys.stdout.flush()
        os._exit(1)
    sys.stdout.flush()


def parse_args(argv, default_out):
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir", nargs="?", default=default_out)
    ap.add_argument("--meta", default=None,
                    help="directory for per-sample JSON metadata (read by scripts/build_manifest.py)")
    ap.add_argument("--only", default=None, help="comma-separated sample names")
    return ap.parse_args(argv)
