"""Count topology and geometry entities in a STEP (ISO 10303-21) file by reading its text.

Plain Python 3 (no FreeCAD, no OCP): imported by the FreeCAD scripts and by
scripts/build_manifest.py.  It is deliberately independent of OpenCASCADE, so the
counts in samples/manifest.json say what is *in the file*, not what a reader makes of it.

    python3 scripts/steptext.py FILE.step ...     # prints the counts as JSON
"""

import json
import re
import sys

# entity name -> manifest surface key
SURFACE_KINDS = {
    "PLANE": "plane",
    "CYLINDRICAL_SURFACE": "cylinder",
    "CONICAL_SURFACE": "cone",
    "SPHERICAL_SURFACE": "sphere",
    "TOROIDAL_SURFACE": "torus",
    "DEGENERATE_TOROIDAL_SURFACE": "torus",
    "B_SPLINE_SURFACE_WITH_KNOTS": "bspline",
    "BEZIER_SURFACE": "bspline",
    "SURFACE_OF_REVOLUTION": "revolution",
    "SURFACE_OF_LINEAR_EXTRUSION": "extrusion",
}

_INSTANCE = re.compile(r"#(\d+)\s*=\s*(.*)", re.S)
_NAME = re.compile(r"([A-Z_][A-Z0-9_]*)\s*\(")


def split_instances(text):
    """Yield (id, body) for every entity instance of the DATA section.

    Splits on ';' outside of quoted strings; a body is 'NAME(...)' (simple instance) or
    '( A(...) B(...) )' (complex instance)."""
    start = text.find("DATA;")
    if start < 0:
        raise ValueError("no DATA section")
    i = start + len("DATA;")
    n = len(text)
    buf = []
    in_str = False
    while i < n:
        ch = text[i]
        if in_str:
            buf.append(ch)
            if ch == "'":
                if i + 1 < n and text[i + 1] == "'":  # escaped quote
                    buf.append("'")
                    i += 1
                else:
                    in_str = False
        elif ch == "'":
            in_str = True
            buf.append(ch)
        elif ch == ";":
            stmt = "".join(buf).strip()
            buf = []
            if stmt.startswith("ENDSEC"):
                return
            m = _INSTANCE.match(stmt)
            if m:
                yield int(m.group(1)), " ".join(m.group(2).split())
        else:
            buf.append(ch)
        i += 1


def _strip_strings(body):
    return re.sub(r"'(?:[^']|'')*'", "''", body)


def entity_names(body):
    """Names of the entity types making up an instance (several for a complex instance)."""
    b = _strip_strings(body)
    if b.startswith("("):
        # complex instance: names at nesting depth 1
        names = []
        depth = 0
        j = 0
        while j < len(b):
            c = b[j]
            if c == "(":
                depth += 1
            elif c == ")":
                depth -= 1
            elif depth == 1:
                m = _NAME.match(b, j)
                if m:
                    names.append(m.group(1))
                    # skip to the matching parenthesis of this partial instance
                    j = m.end() - 1
                    continue
            j += 1
        return names
    m = _NAME.match(b)
    return [m.group(1)] if m else []


def _args(body):
    """Top-level arguments of a simple instance NAME(a, b, ...)."""
    b = _strip_strings(body)
    open_ = b.index("(")
    depth = 0
    args, cur = [], []
    for c in b[open_ + 1:]:
        if c == "(":
            depth += 1
        elif c == ")":
            if depth == 0:
                break
            depth -= 1
        if c == "," and depth == 0:
            args.append("".join(cur).strip())
            cur = []
        else:
            cur.append(c)
    args.append("".join(cur).strip())
    return args


def surface_kind(names):
    if "RATIONAL_B_SPLINE_SURFACE" in names:
        return "nurbs"
    for n in names:
        if n in SURFACE_KINDS:
            return SURFACE_KINDS[n]
    return names[0].lower() if names else "unknown"


def length_unit(ents):
    """'mm', 'm', 'inch', ... from the LENGTH_UNIT instances used by the contexts."""
    units = set()
    for _, (names, body) in ents.items():
        if "LENGTH_UNIT" not in names:
            continue
        if "CONVERSION_BASED_UNIT" in names:
            m = re.search(r"CONVERSION_BASED_UNIT\s*\(\s*'([^']*)'", body)
            units.add((m.group(1) if m else "?").lower())
        elif "SI_UNIT" in names:
            m = re.search(r"SI_UNIT\s*\(\s*([^,]*),\s*\.METRE\.", body)
            prefix = m.group(1).strip() if m else "?"
            units.add({"$": "m", ".MILLI.": "mm", ".CENTI.": "cm", ".MICRO.": "um"}.get(prefix, prefix + "m"))
    # a conversion-based unit references an SI unit (e.g. INCH -> 25.4 mm): report the named one
    named = sorted(u for u in units if u not in ("m", "mm", "cm", "um"))
    if named:
        return named[0] if len(named) == 1 else ",".join(named)
    return ",".join(sorted(units)) if units else None


def analyse(path):
    with open(path, "r", encoding="latin-1") as f:
        text = f.read()
    ents = {}
    for eid, body in split_instances(text):
        ents[eid] = (entity_names(body), body)
    count = {}
    for names, _ in ents.values():
        for n in names:
            count[n] = count.get(n, 0) + 1
    surfaces = {}
    for eid, (names, body) in ents.items():
        if names == ["ADVANCED_FACE"]:
            ref = _args(body)[2]
            sid = int(ref.lstrip("#"))
            k = surface_kind(ents[sid][0])
            surfaces[k] = surfaces.get(k, 0) + 1
    return {
        "faces": count.get("ADVANCED_FACE", 0),
        "edges": count.get("EDGE_CURVE", 0),
        "vertices": count.get("VERTEX_POINT", 0),
        "solids": count.get("MANIFOLD_SOLID_BREP", 0) + count.get("BREP_WITH_VOIDS", 0),
        "manifold_solid_breps": count.get("MANIFOLD_SOLID_BREP", 0),
        "breps_with_voids": count.get("BREP_WITH_VOIDS", 0),
        "shells": count.get("CLOSED_SHELL", 0) + count.get("OPEN_SHELL", 0),
        "surfaces": dict(sorted(surfaces.items())),
        "length_unit": length_unit(ents),
        "entity_counts": count,
    }


if __name__ == "__main__":
    out = {}
    for p in sys.argv[1:]:
        a = analyse(p)
        a.pop("entity_counts")
        out[p] = a
    print(json.dumps(out, indent=1))
