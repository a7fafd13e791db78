"""Independent cross-check of a traced medial axis with OpenCASCADE (shares no code with matrace).

    .venv-ocp/bin/python scripts/ocp/crosscheck_mat.py PART.step PART.mat.json [--every N] [--tol T]

For every junction and every N-th seam point (plus each seam's ends) it checks, in OCCT:
  * the centre is inside the solid (BRepClass3d_SolidClassifier; a centre with r ~ 0 at a
    convex vertex may be ON);
  * its distance to the boundary (the shells, BRepExtrema_DistShapeShape) equals r;
  * each reported touch point lies on the boundary, at distance r from the centre, and the touch
    points are at least 3 (seam) / 4 (junction) distinct places (a ball may touch one face
    twice, or a reflex edge shared by two faces).
Degenerate balls (a cylinder's axis, a sphere's centre) are checked for the first two.
Lengths are in mm; the STEP reader converts units the same way matrace does. The tolerance
defaults to 1e-6 x the model's bounding-box diagonal plus 1e-7 mm (OCCT's own precision).
Prints one line per failure and a summary; exit status 1 when anything fails.
"""

import argparse
import json
import sys

from OCP.Bnd import Bnd_Box
from OCP.BRep import BRep_Builder
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
from OCP.BRepClass3d import BRepClass3d_SolidClassifier
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.gp import gp_Pnt
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_IN, TopAbs_ON, TopAbs_SHELL
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS_Compound


def read_step(path):
    r = STEPControl_Reader()
    if r.ReadFile(path) != IFSelect_RetDone:
        sys.exit(f"{path}: OCCT cannot read it")
    r.TransferRoots()
    return r.OneShape()


def collect(shape, kind):
    out = []
    ex = TopExp_Explorer(shape, kind)
    while ex.More():
        out.append(ex.Current())
        ex.Next()
    return out


def compound(shapes):
    c = TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(c)
    for s in shapes:
        b.Add(c, s)
    return c


def dist(a, b):
    d = BRepExtrema_DistShapeShape(a, b)
    d.Perform()
    return d.Value() if d.IsDone() else float("inf")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("step")
    ap.add_argument("report")
    ap.add_argument("--every", type=int, default=5)
    ap.add_argument("--tol", type=float, default=None)
    a = ap.parse_args()

    shape = read_step(a.step)
    shells = compound(collect(shape, TopAbs_SHELL))
    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    lo, hi = box.CornerMin(), box.CornerMax()
    diag = lo.Distance(hi)
    tol = a.tol if a.tol is not None else 1e-6 * diag + 1e-7
    report = json.load(open(a.report))
    mat = report["mat"]

    failures = []
    checked = 0

    def vertex(p):
        return BRepBuilderAPI_MakeVertex(gp_Pnt(*p)).Vertex()

    def check(what, centre, r, touch, need):
        nonlocal checked
        checked += 1
        v = vertex(centre)
        state = BRepClass3d_SolidClassifier(shape, gp_Pnt(*centre), 1e-7).State()
        if state != TopAbs_IN and not (state == TopAbs_ON and r <= tol):
            failures.append(f"{what}: centre {centre} not inside the solid")
        d = dist(v, shells)
        if abs(d - r) > tol:
            failures.append(f"{what}: distance to boundary {d:.9g}, r = {r:.9g}")
        places = []
        for t in touch:
            tv = vertex(t)
            if dist(tv, shells) > tol:
                failures.append(f"{what}: touch point {t} is not on the boundary")
            dc = sum((t[k] - centre[k]) ** 2 for k in range(3)) ** 0.5
            if abs(dc - r) > tol:
                failures.append(f"{what}: touch point {t} at {dc:.9g} from the centre, r = {r:.9g}")
            # Distinct places: a ball may touch one face twice, or a reflex edge between two.
            # (A tiny ball near a convex corner has its touch points within ~r of each other.)
            sep = min(max(10 * tol, 1e-4 * r), 0.05 * r)
            if all(sum((t[k] - q[k]) ** 2 for k in range(3)) ** 0.5 > sep for q in places):
                places.append(t)
        if r > tol and need and len(places) < need:
            failures.append(f"{what}: touches {len(places)} places, needs {need}")

    for j in mat["junctions"]:
        check(f"junction {j['id']}", j["point"], j["radius"], j["touch"], 4)
    for i, d in enumerate(mat.get("degenerate", [])):
        for k, b in enumerate(d["balls"]):
            check(f"degenerate {i} ball {k}", b[:3], b[3], [], 0)
    for s in mat["seams"]:
        pts = s["points"]
        picks = sorted(set(list(range(0, len(pts), max(1, a.every))) + [len(pts) - 1]))
        for k in picks:
            p = pts[k]
            # Where a seam ends by curvature the ball osculates a face: its two touch points
            # on that face have merged into one.
            end = s["ends"][0] if k == 0 else s["ends"][1] if k == len(pts) - 1 else None
            need = 2 if isinstance(end, dict) and "curvature_limit" in end else 3
            check(f"seam {s['id']} point {k}", p["point"][:3], p["point"][3], p["touch"], need)
    print(f"{a.step}: {checked} balls checked against OCCT, {len(failures)} failures (tol {tol:.3g} mm)")
    for f in failures[:50]:
        print("  " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
