"""Random mechanical parts written by FreeCAD as STEP: a stress corpus for the tracer and its
checks, the kind of part a FreeCAD user makes. Each is a plate (30..80 x 20..60 x 4..15 mm)
with one to five features (pockets, cylindrical bosses, through holes, slots, ribs,
counterbores; with --kinds also tilted cuts, spherical dimples, countersinks) and fillets or
chamfers on some straight edges. The same seed gives the same parts.

Run with Debian's python (/usr/bin/python3; see samplelib.py), then trace them all:

    /usr/bin/python3 scripts/freecad/make_random_parts.py OUTDIR COUNT SEED [--kinds K,K,...]
    matrace batch OUTDIR -o OUTDIR/mat --verify --no-svg --no-mesh

Every part that fails (`summary.csv`) is a medial axis the tracer got incomplete, or a check
that is wrong: look at the failure, find the general cause, and make a small regression part of
it in make_trace_regressions.py. What two batches of 40 found is in docs/testing.md.
"""

import argparse
import os
import random

import samplelib  # noqa: F401  (sys.path for FreeCAD)
import FreeCAD
import Part

V = FreeCAD.Vector

KINDS = ["pocket", "boss", "hole", "slot", "rib", "cbore"]
MORE_KINDS = ["tilt", "dimple", "csink"]


def feature(rng, shape, kind, size):
    """`shape` with one feature of `kind` at a random place on its top."""
    length, width, height = size
    x, y = rng.uniform(0.15, 0.85) * length, rng.uniform(0.15, 0.85) * width
    if kind == "pocket":
        a, b = rng.uniform(4, length / 3), rng.uniform(4, width / 3)
        depth = rng.uniform(1, height * 0.7)
        return shape.cut(Part.makeBox(a, b, depth + 1, V(x - a / 2, y - b / 2, height - depth)))
    if kind == "boss":
        r, h = rng.uniform(2, min(length, width) / 5), rng.uniform(2, 12)
        return shape.fuse(Part.makeCylinder(r, h, V(x, y, height)))
    if kind == "hole":
        r = rng.uniform(1, min(length, width) / 6)
        return shape.cut(Part.makeCylinder(r, height + 2, V(x, y, -1)))
    if kind == "slot":
        r, span = rng.uniform(1.5, 5), rng.uniform(5, length / 2)
        depth = rng.uniform(1, height * 0.6)
        slot = Part.makeBox(span, 2 * r, depth + 1, V(0, -r, 0))
        slot = slot.fuse(Part.makeCylinder(r, depth + 1))
        slot = slot.fuse(Part.makeCylinder(r, depth + 1, V(span, 0, 0)))
        slot.rotate(V(0, 0, 0), V(0, 0, 1), rng.uniform(0, 180))
        slot.translate(V(x, y, height - depth))
        return shape.cut(slot)
    if kind == "rib":
        t, h = rng.uniform(1.5, 5), rng.uniform(3, 12)
        return shape.fuse(Part.makeBox(t, width * rng.uniform(0.3, 0.9), h, V(x, width * 0.05, height)))
    if kind == "cbore":
        r1 = rng.uniform(1, 3)
        r2, depth = r1 + rng.uniform(1, 3), rng.uniform(1, height / 2)
        shape = shape.cut(Part.makeCylinder(r1, height + 2, V(x, y, -1)))
        return shape.cut(Part.makeCylinder(r2, depth + 1, V(x, y, height - depth)))
    if kind == "tilt":
        cut = Part.makeBox(length, width, height)
        cut.rotate(V(0, 0, 0), V(rng.uniform(-1, 1), rng.uniform(-1, 1), 0), rng.uniform(5, 40))
        cut.translate(V(x - length / 2, y - width / 2, height * rng.uniform(0.4, 0.9)))
        return shape.cut(cut)
    if kind == "dimple":
        r = rng.uniform(1.5, min(length, width) / 6)
        return shape.cut(Part.makeSphere(r, V(x, y, height + rng.uniform(-1, 1))))
    if kind == "csink":
        r1 = rng.uniform(1, 3)
        shape = shape.cut(Part.makeCylinder(r1, height + 2, V(x, y, -1)))
        cone = Part.makeCone(r1, r1 + rng.uniform(1, 3), rng.uniform(1, 3) + 0.01,
                             V(x, y, height - 1.5), V(0, 0, 1))
        return shape.cut(cone)
    raise ValueError(kind)


def straight_edges(shape):
    """The shape's straight edges (an edge whose curve FreeCAD cannot type is skipped)."""
    out = []
    for e in shape.Edges:
        try:
            if isinstance(e.Curve, Part.Line):
                out.append(e)
        except Exception:  # FreeCAD: "undefined curve type"
            pass
    return out


def part(rng, kinds):
    """A random part and the names of what was done to it."""
    size = (rng.uniform(30, 80), rng.uniform(20, 60), rng.uniform(4, 15))
    shape = Part.makeBox(*size)
    done = []
    for _ in range(rng.randint(1, 5)):
        kind = rng.choice(kinds)
        try:
            shape = feature(rng, shape, kind, size)
            done.append(kind)
        except Exception:  # an OCC boolean that fails: the part without this feature
            pass
    shape = shape.removeSplitter()
    mode = rng.choice(["none", "fillet", "chamfer", "fillet_vertical"])
    if mode != "none":
        edges = straight_edges(shape)
        if mode == "fillet_vertical":
            edges = [e for e in edges if abs(e.Curve.Direction.z) > 0.99]
        rng.shuffle(edges)
        pick = edges[: rng.randint(1, max(1, min(8, len(edges))))]
        radius = rng.uniform(0.3, 2.0)
        for _ in range(3):
            try:
                made = shape.makeChamfer(radius, pick) if mode == "chamfer" else shape.makeFillet(radius, pick)
                if made.isValid() and len(made.Solids) == 1:
                    shape = made
                    done.append(mode)
                    break
            except Exception:  # OCC cannot round these edges at this radius: try smaller
                pass
            radius *= 0.5
    return shape, done


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("count", type=int)
    ap.add_argument("seed", type=int)
    ap.add_argument("--kinds", default=",".join(KINDS),
                    help=f"features to choose from (also: {', '.join(MORE_KINDS)})")
    args = ap.parse_args()
    kinds = args.kinds.split(",")
    unknown = [k for k in kinds if k not in KINDS + MORE_KINDS]
    if unknown:
        ap.error(f"unknown kinds: {unknown}")
    samplelib.setup_step_writer()
    os.makedirs(args.outdir, exist_ok=True)
    for i in range(args.count):
        rng = random.Random(args.seed * 1000 + i)
        shape, done = part(rng, kinds)
        if not shape.isValid() or len(shape.Solids) != 1:
            print(f"part {i}: not one valid solid, skipped")
            continue
        path = os.path.join(args.outdir, f"random_{args.seed}_{i:03d}.step")
        shape.exportStep(path)
        print(path, " ".join(done))


if __name__ == "__main__":
    main()
