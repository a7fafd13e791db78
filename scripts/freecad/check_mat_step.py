#!/usr/bin/python3
"""Open a `<stem>.mat.step` written by `matrace trace` with FreeCAD and check it against the
JSON report written next to it.

    /usr/bin/python3 scripts/freecad/check_mat_step.py PART.mat.step PART.mat.json \\
        [--every K] [--with-solid PART.step]

Checks (every failure is listed, then the exit status is 1):
* `Part.read` gives exactly one free edge (an edge not inside a solid) per seam of the report,
  in the report's order, each starting and ending at its seam's first and last traced point,
  then one per skeletal edge (`mat.skeletal_edges`, reports made before them have none), each
  a straight line from its first ball's centre to its last (the vertex), every ball on it;
  then one per degenerate curve with two balls or more (`mat.degenerate` of kind `curve`: a
  cylinder's axis, a torus's core), every ball's centre within the fit tolerance of it;
* every K-th traced point of each seam (and its last) is within the report's fit tolerance
  (`mat.fit.tol`) of that seam's edge (`distToShape`);
* exactly one free vertex per junction, each at its junction's point;
* with `--with-solid PART.step`: the file also holds the input part as FreeCAD reads
  `PART.step` on its own (same number of solids and faces, same volume, and its own free
  edges and vertices after ours), and every junction lies strictly inside it (so units and
  placements agree with the seams).

Run with Debian's python (FreeCAD 0.20 modules), never freecadcmd (it exits 0 on errors).
Prints one summary line on success.
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import samplelib as L  # noqa: E402
from samplelib import FreeCAD, Part  # noqa: E402

# OCCT's point-to-curve extrema stop at ~1e-9 relative; allow that much beyond the
# tolerance the fit reports it honours (measured by its own Newton projection).
SLACK_REL = 1e-6
SLACK_ABS = 1e-9


def walk(shape, out):
    """Free edges, free vertices and solids of a compound tree, in order."""
    if shape.isNull():  # what OCCT makes of a wireframe with no curves and no points
        return
    t = shape.ShapeType
    if t == "Compound":
        for c in shape.SubShapes:
            walk(c, out)
    elif t == "Edge":
        out["edges"].append(shape)
    elif t == "Vertex":
        out["vertices"].append(shape)
    elif t in ("Solid", "CompSolid"):
        out["solids"].append(shape)
    elif t == "Wire":
        out["edges"].extend(shape.Edges)
    else:
        out["other"].append(shape)


def dist(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5


def balls_on_edge(edge, balls, what, within, problems, worst, checked):
    """Every ball's centre within `within` of `edge` (the first that is not is a problem):
    the worst distance and the count of balls checked, carried on."""
    for i, b in enumerate(balls):
        d = edge.distToShape(Part.Vertex(FreeCAD.Vector(*b[:3])))[0]
        worst = max(worst, d)
        checked += 1
        if d > within:
            problems.append(f"{what} ball {i}: {d:.3e} mm from its edge")
            break
    return worst, checked


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("step")
    ap.add_argument("report")
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--with-solid", dest="solid", default=None)
    args = ap.parse_args()

    report = json.load(open(args.report))
    seams = report["mat"]["seams"]
    skeletal = report["mat"].get("skeletal_edges", [])
    # (index in the report, piece) of each degenerate curve written as an edge.
    degenerate = [(i, d) for i, d in enumerate(report["mat"].get("degenerate", []))
                  if d.get("kind") == "curve" and len(d.get("balls", [])) >= 2]
    junctions = report["mat"]["junctions"]
    tol = report["mat"]["fit"]["tol"]
    diag = report["model"]["diagonal"]
    slack = tol * SLACK_REL + SLACK_ABS

    shape = Part.read(args.step)
    parts = {"edges": [], "vertices": [], "solids": [], "other": []}
    walk(shape, parts)
    problems = []
    ref = None
    if args.solid:
        # The part as FreeCAD reads it on its own; its free edges and vertices (wireframe
        # annotations of some files) come after ours (ours are the first product in the file).
        ref = Part.read(args.solid)
        own = {"edges": [], "vertices": [], "solids": [], "other": []}
        walk(ref, own)
        for key in ("edges", "vertices"):
            extra = len(own[key])
            if extra and len(parts[key]) >= extra:
                parts[key] = parts[key][:-extra]
    if parts["other"]:
        problems.append(f"unexpected shapes: {[s.ShapeType for s in parts['other']]}")

    edges = parts["edges"]
    if len(edges) != len(seams) + len(skeletal) + len(degenerate):
        problems.append(f"{len(edges)} free edges for {len(seams)} seams"
                        + (f", {len(skeletal)} skeletal edges" if skeletal else "")
                        + (f", {len(degenerate)} degenerate curves" if degenerate else ""))
    worst = 0.0
    checked = 0
    for seam, edge in zip(seams, edges):
        pts = [p["point"] for p in seam["points"]]
        ends = [edge.Vertexes[0].Point, edge.Vertexes[-1].Point]
        for want, got in ((pts[0], ends[0]), (pts[-1], ends[-1])):
            if dist(want[:3], got) > slack + 1e-9 * diag:
                problems.append(f"seam {seam['id']}: edge ends at {tuple(got)}, seam at {want[:3]}")
        sample = list(range(0, len(pts), args.every))
        if sample[-1] != len(pts) - 1:
            sample.append(len(pts) - 1)
        for i in sample:
            d = edge.distToShape(Part.Vertex(FreeCAD.Vector(*pts[i][:3])))[0]
            worst = max(worst, d)
            checked += 1
            if d > tol + slack:
                problems.append(f"seam {seam['id']} point {i}: {d:.3e} mm from its edge "
                                f"(fit tolerance {tol:.3e})")
                break

    for k, edge in zip(skeletal, edges[len(seams):]):
        balls = k["balls"]
        ends = [edge.Vertexes[0].Point, edge.Vertexes[-1].Point]
        for want, got in ((balls[0], ends[0]), (balls[-1], ends[-1])):
            if dist(want[:3], got) > 1e-9 * diag:
                problems.append(f"skeletal edge {k['id']}: edge ends at {tuple(got)}, "
                                f"its balls at {want[:3]}")
        worst, checked = balls_on_edge(edge, balls, f"skeletal edge {k['id']}", tol + slack,
                                       problems, worst, checked)

    for (i, d), edge in zip(degenerate, edges[len(seams) + len(skeletal):]):
        worst, checked = balls_on_edge(edge, d["balls"], f"degenerate curve {i}", tol + slack,
                                       problems, worst, checked)

    vertices = parts["vertices"]
    if len(vertices) != len(junctions):
        problems.append(f"{len(vertices)} free vertices for {len(junctions)} junctions")
    for j, v in zip(junctions, vertices):
        if dist(j["point"], v.Point) > 1e-9 * diag:
            problems.append(f"junction {j['id']} at {j['point']}, vertex at {tuple(v.Point)}")

    solids = parts["solids"]
    if ref is not None:
        if len(solids) != len(ref.Solids):
            problems.append(f"{len(solids)} solids, the part has {len(ref.Solids)}")
        faces = sum(len(s.Faces) for s in solids)
        if faces != len(ref.Faces):
            problems.append(f"{faces} faces, the part has {len(ref.Faces)}")
        volume = sum(s.Volume for s in solids)
        if abs(volume - ref.Volume) > 1e-9 * abs(ref.Volume):
            problems.append(f"volume {volume}, the part's {ref.Volume}")
        for j in junctions:
            p = FreeCAD.Vector(*j["point"])
            if not any(s.isInside(p, 1e-9 * diag, False) for s in solids):
                problems.append(f"junction {j['id']} at {j['point']} is not inside the solid")
    elif solids:
        problems.append(f"{len(solids)} solids in a file written without --with-solid")

    if problems:
        print(f"{args.step}: {len(problems)} problems", file=sys.stderr)
        for p in problems:
            print(f"  {p}", file=sys.stderr)
        sys.stderr.flush()
        os._exit(1)
    print(json.dumps({"file": args.step, "edges": len(edges), "vertices": len(vertices),
                      "solids": len(solids), "points_checked": checked,
                      "worst_distance": worst, "tol": tol}))


if __name__ == "__main__":
    L.run_main(main)
