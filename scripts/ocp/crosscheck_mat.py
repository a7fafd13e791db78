"""Independent cross-check of a traced medial axis with OpenCASCADE (shares no code with matrace).

    .venv-ocp/bin/python scripts/ocp/crosscheck_mat.py PART.step PART.mat.json
        [--every N] [--tol T] [--mesh PART.sheets.obj] [--mesh-samples K] [--json]

A point B with radius r is on the medial axis of a solid when B is inside it, its nearest
boundary points are at distance r, and there are at least two of them in separate places
(three along a seam, four at a junction). Checked in OCCT, for every junction, every seam point
(every N-th with --every N; default: all), every degenerate ball and every ball of a skeletal
edge at a vertex (the straight line of balls touching that vertex alone where a sheet ends
freely; `skeletal_edges`: its last ball is a vertex of the part, r = 0):

  finite             every number of the ball is a number;
  inside             the centre is inside the solid (BRepClass3d_SolidClassifier, retried at
                     six nearby points where its ray grazes an edge; ON within the file's
                     gap, below; a ball with r <= tol, a seam's end at a convex vertex, is
                     exempt);
  distance           its distance to the boundary shells (BRepExtrema_DistShapeShape) is r;
  touch_on_boundary  each reported touch point is on the boundary,
  touch_at_radius    and at distance r from the centre;
  separated          the touch points make enough separate places (the most of them pairwise
                     separate): two count as separate when farther apart than sqrt(8 r e),
                     the chord over which a sphere of radius r and a surface tangent to it stay
                     within e of each other, so that one smooth contact cannot pass for two
                     (e: the ball's own error -- its distance's, its touch points' off the ball
                     and off the boundary -- where finer than tol, and at least 1e-7 mm and
                     1e-9 of the diagonal: a touch point that close to another on one contact
                     would be off the ball by more than e), or when they lie on one edge that
                     curls round the ball between them (the second derivative of the squared
                     distance along it at most tol |C''|: the distance has a maximum between
                     them). Seam points need 3 (2 at a seam end at
                     a curvature limit, where the ball osculates a face, or at a pinch, where
                     two touch points meet at a vertex), junctions 4, degenerate balls 2
                     (1 at an end where the arc of contact shrinks to a point), a skeletal
                     edge's balls 1 (the vertex).
                     A seam point the report lists in its seam's `unresolved`, or a junction
                     marked `unresolved`, needs one place fewer, where every two touch points
                     closer than that lie on different faces that share a vertex (a shallow
                     crease, a sliver face) and not on the same faces, or on one face of a seam
                     that ends at a curvature limit or a pinch; one place, where the seam ends
                     at a convex vertex and each touch point lies on a face of that vertex, no
                     two on the same (the touch points converge on it faster than the
                     separation where its faces meet at shallow angles). Exempt: r <= tol.

With --mesh, K distinct vertices of the sheet mesh (default 200, spread over the file) are checked too:
`inside`, and `mesh_contacts` -- the ball of radius r = distance to the boundary has a second
contact, separated from the first (among every face's nearest point and the extrema of the
distance on each face's surface inside the face, within r + tol; for a centre on the axis of a
face of revolution, its contacts on that face turned round the axis by eighths of a turn, and
on a torus's core circle, round the core's tangent), or else the growth test steps the centre away from the first contact
(by r/2, r/8, r/32); the nearest boundary point from there, projected back from the centre onto
the face, edge or vertex it lies on, must be at distance r (+ tol) and separated. A ball that
could grow away from its only contact is not on the medial axis.

The report must describe a medial axis, not merely hold no wrong point:
  nonempty           the report has balls;
  faces_touched      every face of the part is touched by some ball (a touch point on it, or
                     within r + tol of its centre, in the solid holding it), or
                     a face joined to it across smooth edges is (the medial axis does not see
                     an edge where the faces' normals agree, within 1 degree at 9 points
                     along it: a hemisphere closing a tube is touched only by the wall's
                     sheet, which no seam need reach);
  seam_ends          no seam end is open, and at a seam end at a pinch two of the touch points
                     are at a vertex of the part;
  junction_seams     every junction with 4 segments has 4 seam ends (unless a seam of more than
                     3 contacts ends there: it splits there into two seams of 3), and every
                     junction a seam ends at exists.
  curvature_limits   every seam end at a curvature limit is where its ball osculates the
                     boundary: at a face's or an edge's limit, over the places near one of its
                     touch points (or of the boundary points nearest its centre) where the
                     boundary stays within 2 tol (plus the file's gap there) of the ball's
                     sphere and is tangent to it -- rays in eight directions across each face
                     there and both ways along each edge, a 1024th of a place apart over the
                     first 64th (touch points met at a B-spline's knot, its curvature peaking
                     between them), a 64th of a place apart over the
                     first place (two touch points about to meet may lie closer than a quarter
                     place, a B-spline's curvature peaking between them) and a quarter place
                     apart beyond, out to 17 places -- the faces' radius of curvature towards
                     the centre (1/k, k the larger principal curvature, OCCT's, signed by the
                     face's orientation) or the edges' (1/(k N.u), u the unit vector to the
                     centre) come within 8 tol (plus the gap) of r or lie on both sides of it
                     (a B-spline whose curvature jumps at a knot, or two edges or faces joined
                     there whose curvatures differ); at a vertex's limit, the ball touches a
                     vertex of the part (within tol plus the gap of a touch point, and OCCT's
                     tolerance of the vertex, at r);
  degenerate_ends    every degenerate curve is traced to two located ends (its ball touching
                     another element on the boundary at distance r, r = 0 at a vertex of the
                     part, or, where its arc of contact shrinks to a point, the ball osculating
                     a face at that point: centre t - r n, 1/r its larger principal
                     curvature) or closes on itself; an open end fails.
  accuracy           the accuracy the report claims is positive and at most 1e-3 x the
                     bounding-box diagonal (without --tol).

The file's own gaps: where an exporter wrote a face's edges off its surface (they follow the
neighbouring face), the boundary there is defined only to that gap. An error of `distance`,
`touch_on_boundary` or `touch_at_radius` beyond the tolerance passes when it is within the
tolerance plus the largest gap of the faces near the point (within the error, and r for the
centre); a centre that OCCT's classifier puts ON the boundary (its tolerance there widened to
the gap by the reader) passes `inside` when it is no farther than that gap plus the
tolerance from the boundary. A face's gap is measured here, as the largest distance from its surface
(GeomAPI_ProjectPointOnSurf) of 17 points along each of its edges' 3D curves. Such passes are
counted (`held_to_gap`). For `separated`, a touch point on no face within the tolerance but
within such a gap is on the faces next to the one nearest it on whose surfaces it lies.

Lengths are in mm (OCCT's STEP reader converts units as matrace does). The tolerance is the
accuracy the report claims (`options.accuracy`; 1e-6 x OCCT's bounding-box diagonal when the
report has none) plus 1e-7 mm, OCCT's own precision; --tol T sets it. Prints one line
per failure (the first 50) and a summary, or with --json one object {"checked": {check: n},
"failed": {check: n}, "failures": [...]}; exit status 1 when anything fails, 2 when the input
cannot be read.
"""

import argparse
import json
import math
import sys

from OCP.Bnd import Bnd_Box
from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
from OCP.BRepClass import BRepClass_FaceClassifier
from OCP.BRepTools import BRepTools
from OCP.BRepClass3d import BRepClass3d_SolidClassifier
from OCP.BRepExtrema import BRepExtrema_DistShapeShape, BRepExtrema_SupportType
from OCP.GeomAPI import GeomAPI_ProjectPointOnCurve, GeomAPI_ProjectPointOnSurf
from OCP.GeomLProp import GeomLProp_CLProps, GeomLProp_SLProps
from OCP.GeomAbs import (GeomAbs_Cone, GeomAbs_Cylinder, GeomAbs_Sphere, GeomAbs_SurfaceOfRevolution,
                         GeomAbs_Torus)
from OCP.gp import gp_Ax1, gp_Dir, gp_Lin, gp_Pnt, gp_Pnt2d, gp_Vec
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import (TopAbs_EDGE, TopAbs_FACE, TopAbs_IN, TopAbs_ON, TopAbs_OUT, TopAbs_REVERSED,
                        TopAbs_SHELL, TopAbs_SOLID, TopAbs_VERTEX)
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Compound
from OCP.collections import (
    IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeListMap,
    IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap,
)

SEAM_PLACES = 3
# Faces whose normals agree within this angle along an edge, at as many points, are one
# smooth surface (faces_touched).
SMOOTH_DEG = 1.0
SMOOTH_SAMPLES = 9
# An edge is reflex when the points this far (relative to the diagonal) off its middle, along
# the difference of its faces' normals, are inside (faces_touched).
REFLEX_STEP_REL = 1e-5
# Cells a side of the grid over an untouched face at which its sheet balls are grown, and the
# bisection's resolution on their radius, relative to the diagonal (faces_touched).
SHEET_SAMPLE_GRID = 8
SHEET_BALL_REL = 1e-9
CURVATURE_END_PLACES = 2
# curvature_limits: how far from r (in tol, plus the gap) a radius of curvature near the end
# ball's touch points may be; how close to the ball's sphere (in tol, plus the gap) the boundary
# must stay for its radius to count; the step (in places) and the reach (in steps) of the rays.
CURVATURE_LIMIT_TOLS = 8.0
OSCULATION_NEAR_TOLS = 2.0
OSCULATION_FINEST_STEP_PLACES = 1.0 / 1024.0
OSCULATION_FINEST_STEPS = 16
OSCULATION_FINE_STEP_PLACES = 1.0 / 64.0
OSCULATION_COARSE_STEP_PLACES = 0.25
OSCULATION_STEPS = 64
# The distances from a touch point (in places) at which the curvature is taken: finest steps
# over the first 64th of a place (two touch points that have met at a B-spline's knot lie a few
# accuracies apart, with the curvature's peak between them), fine steps over the first place (two
# touch points about to meet may lie closer than a quarter place, and a B-spline's curvature peak
# between them), coarse ones beyond.
OSCULATION_OFFSETS = ([m * OSCULATION_FINEST_STEP_PLACES for m in range(OSCULATION_FINEST_STEPS + 1)]
                      + [m * OSCULATION_FINE_STEP_PLACES for m in range(2, OSCULATION_STEPS + 1)]
                      + [OSCULATION_STEPS * OSCULATION_FINE_STEP_PLACES + m * OSCULATION_COARSE_STEP_PLACES
                         for m in range(1, OSCULATION_STEPS + 1)])
PINCH_END_PLACES = 2
# The mesh that gives OCCT's distance its faces' boxes (see `Part`): its linear deflection
# relative to the part's diagonal, and its angular deflection (radians).
MESH_REL_DEFLECTION = 0.002
MESH_ANGULAR_DEFLECTION = 0.5
JUNCTION_PLACES = 4
DEGENERATE_PLACES = 2
SHRUNK_END_PLACES = 1
SKELETAL_PLACES = 1
# Steps of the growth test, as fractions of r.
GROWTH_STEPS = (0.5, 0.125, 0.03125)


def read_step(path):
    r = STEPControl_Reader()
    if r.ReadFile(path) != IFSelect_RetDone:
        print(f"{path}: OCCT cannot read it", file=sys.stderr)
        sys.exit(2)
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


def dist3(a, b):
    return math.sqrt(sum((a[k] - b[k]) ** 2 for k in range(3)))


# The largest accuracy a report may claim, relative to the bounding-box diagonal (as matrace's
# own verify): beyond it a ball could be anywhere in a thin wall and pass.
MAX_ACCURACY_REL_DIAGONAL = 1e-3


def separation(r, tol):
    return math.sqrt(8.0 * r * tol)


def places(touch, s, separate=None, cap=None, steps=100_000):
    """The most touch points pairwise farther apart than s, or pairwise separate(i, j) (i < j)
    when given (in the order given, a point within s of two that are not of each other would
    hide one), or `cap` when there are at least that many (the search stops there: a sheet
    mesh vertex's contacts can be a whole sphere's extrema). A search over subsets of at most
    `steps` steps; past it, the largest set found so far."""
    if separate is None:
        def separate(i, j):
            return dist3(touch[i], touch[j]) > s
    best = 0
    budget = [steps]

    def grow(chosen, start):
        nonlocal best
        best = max(best, len(chosen))
        for i in range(start, len(touch)):
            if len(chosen) + len(touch) - i <= best or budget[0] == 0:
                return
            if cap is not None and best >= cap:
                return
            budget[0] -= 1
            if all(separate(j, i) for j in chosen):
                grow(chosen + [i], i + 1)

    grow([], 0)
    return best


def finite(*values):
    for v in values:
        if isinstance(v, (list, tuple)):
            if not finite(*v):
                return False
        elif v is None or not math.isfinite(v):
            return False
    return True


class Part:
    """The part in OCCT: the shape, its shells, its faces and what each edge and vertex bounds."""

    def __init__(self, path):
        self.shape = read_step(path)
        self.shells = compound(collect(self.shape, TopAbs_SHELL))
        box = Bnd_Box()
        BRepBndLib.AddOptimal_s(self.shape, box, False, True)
        self.diagonal = box.CornerMin().Distance(box.CornerMax())
        # A coarse mesh, for the boxes alone: OCCT's distance to a shell skips the faces
        # whose boxes are farther than the best distance found, and without a mesh a face's
        # box is taken from its surface's bounds in its pcurves' range, which for a periodic
        # B-spline face came out 0.034 mm short of a point inside its trim: a touch point on
        # that face was 0.029 mm from the shell. With a mesh, the box holds the mesh's nodes
        # and is enlarged by its deflection.
        BRepMesh_IncrementalMesh(self.shape, MESH_REL_DEFLECTION * self.diagonal, False,
                                 MESH_ANGULAR_DEFLECTION, False)
        self.faces = ShapeMap()
        TopExp.MapShapes_s(self.shape, TopAbs_FACE, self.faces)
        self.gaps = {}
        self.max_gap = None
        # Each face's box, exact (`AddOptimal`): `Add`'s box of a periodic B-spline face came
        # out 0.034 mm short of a point inside its trim, and that face was then never looked
        # at there.
        self.face_boxes = []
        for i in range(1, self.faces.Extent() + 1):
            b = Bnd_Box()
            BRepBndLib.AddOptimal_s(self.faces.FindKey(i), b, False, True)
            self.face_boxes.append(b)
        self.edge_faces = ShapeListMap()
        TopExp.MapShapesAndAncestors_s(self.shape, TopAbs_EDGE, TopAbs_FACE, self.edge_faces)
        self.vertex_faces = ShapeListMap()
        TopExp.MapShapesAndAncestors_s(self.shape, TopAbs_VERTEX, TopAbs_FACE, self.vertex_faces)
        self.vertex_points = []
        # OCCT's tolerance of each vertex (its extent: at least the gap to its edges' curves).
        self.vertex_tolerances = []
        # The vertices (indices from 1) of each face (indices from 1).
        self.face_vertices = {}
        for i in range(1, self.vertex_faces.Extent() + 1):
            vertex_shape = TopoDS.Vertex(self.vertex_faces.FindKey(i))
            q = BRep_Tool.Pnt_s(vertex_shape)
            self.vertex_points.append((q.X(), q.Y(), q.Z()))
            self.vertex_tolerances.append(BRep_Tool.Tolerance_s(vertex_shape))
            for f in self.vertex_faces.FindFromIndex(i):
                self.face_vertices.setdefault(self.faces.FindIndex(f), set()).add(i)
        # Several solids (an assembly's parts often touch): a ball is checked against the
        # solid its centre is in, not against its neighbours' faces.
        self.solids = collect(self.shape, TopAbs_SOLID)
        self.solid_shells = [compound(collect(s, TopAbs_SHELL)) for s in self.solids]
        self.solid_boxes = []
        self.solid_faces = []
        for s in self.solids:
            b = Bnd_Box()
            BRepBndLib.Add_s(s, b)
            self.solid_boxes.append(b)
            self.solid_faces.append({self.faces.FindIndex(f) for f in collect(s, TopAbs_FACE)})

    def solids_holding(self, p):
        """The solids (indices) whose interior holds p, when there are several solids (parts
        may overlap a little); [None], meaning the whole shape, when there is one solid or p
        is in none."""
        if len(self.solids) < 2:
            return [None]
        inside = [
            k for k, s in enumerate(self.solids)
            if not self.solid_boxes[k].IsOut(gp_Pnt(*p))
            and BRepClass3d_SolidClassifier(s, gp_Pnt(*p), 1e-7).State() == TopAbs_IN
        ]
        return inside or [None]

    def face_gap(self, i):
        """The largest distance from face i's surface (index from 1) of its edges' 3D curves,
        sampled at 17 points each (cached)."""
        if i in self.gaps:
            return self.gaps[i]
        face = TopoDS.Face(self.faces.FindKey(i))
        surface = BRep_Tool.Surface_s(face)
        gap = 0.0
        ex = TopExp_Explorer(face, TopAbs_EDGE)
        while ex.More():
            edge = TopoDS.Edge(ex.Current())
            ex.Next()
            if BRep_Tool.Degenerated_s(edge):
                continue
            first, last = BRep_Tool.Range_s(edge)
            curve = BRep_Tool.Curve_s(edge, first, last)
            if curve is None:
                continue
            for k in range(17):
                proj = GeomAPI_ProjectPointOnSurf(curve.Value(first + (last - first) * k / 16), surface)
                if proj.NbPoints() > 0:
                    gap = max(gap, proj.LowerDistance())
        self.gaps[i] = gap
        return gap

    def faces_within(self, p, reach, solid=None):
        """The faces (indices from 1) of that solid within `reach` of `p`."""
        return [i for i, _ in self.face_distances(p, reach, solid)]

    def face_distances(self, p, reach, solid=None):
        """(index from 1, BRepExtrema_DistShapeShape from p) of every face (of that solid, if
        not None) within `reach` of `p`."""
        v = vertex(p)
        for i in self.faces_by_box(p, reach, solid):
            d = distance_within(v, self.faces.FindKey(i), reach)
            if d is not None:
                yield i, d

    def faces_by_box(self, p, reach, solid=None):
        """The faces (indices from 1) of that solid whose bounding box is within `reach` of
        `p`."""
        for i in range(1, self.faces.Extent() + 1):
            if solid is not None and i not in self.solid_faces[solid]:
                continue
            box = self.face_boxes[i - 1]
            if box.IsOut(gp_Pnt(*p)) and box_distance(box, p) > reach:
                continue
            yield i

    def gap_near(self, p, reach, solid=None):
        """The largest gap of the faces within `reach` of `p`."""
        return max((self.face_gap(i) for i in self.faces_within(p, reach, solid)), default=0.0)

    def edges_near(self, p, tol, solid=None):
        """{edge index (from 1): (its curve, the parameter of p's foot on it)} for every edge
        of the faces (of that solid) within tol of p that is itself within tol of p."""
        found = {}
        for i in self.faces_within(p, tol, solid):
            exp = TopExp_Explorer(self.faces.FindKey(i), TopAbs_EDGE)
            while exp.More():
                edge = TopoDS.Edge(exp.Current())
                exp.Next()
                k = self.edge_faces.FindIndex(edge)
                if k in found or BRep_Tool.Degenerated_s(edge):
                    continue
                first, last = BRep_Tool.Range_s(edge)
                curve = BRep_Tool.Curve_s(edge, first, last)
                if curve is None:
                    continue
                proj = GeomAPI_ProjectPointOnCurve(gp_Pnt(*p), curve, first, last)
                if proj.NbPoints() > 0 and proj.LowerDistance() <= tol:
                    found[k] = (curve, proj.LowerDistanceParameter())
        return found

    def vertex_at(self, p, tol):
        """The vertex (index from 1) within `tol` of p, or None."""
        if not finite(p):
            return None
        best = min(range(len(self.vertex_points)), key=lambda i: dist3(self.vertex_points[i], p),
                   default=None)
        if best is None or dist3(self.vertex_points[best], p) > tol:
            return None
        return best + 1

    def vertex_face_set(self, v):
        """The faces (indices from 1) of vertex v (index from 1)."""
        return {self.faces.FindIndex(f) for f in self.vertex_faces.FindFromIndex(v)}

    def largest_gap(self):
        """The largest gap of any face."""
        if self.max_gap is None:
            self.max_gap = max((self.face_gap(i) for i in range(1, self.faces.Extent() + 1)),
                               default=0.0)
        return self.max_gap

    def gap_within_reach(self, p, reach, solid=None):
        """The largest gap (above 0) of the faces no farther from `p` than `reach` plus their
        own gap: a face's surface may lie that far from its edges, and from the points near
        them; 0 when there is none."""
        g = self.largest_gap()
        if g <= 0.0:
            return 0.0
        return max((self.face_gap(i) for i, d in self.face_distances(p, reach + g, solid)
                    if self.face_gap(i) > 0.0 and d.Value() <= reach + self.face_gap(i)),
                   default=0.0)

    def neighbours(self, i):
        """Face i and the faces sharing an edge with it (indices from 1)."""
        out = {i}
        ex = TopExp_Explorer(self.faces.FindKey(i), TopAbs_EDGE)
        while ex.More():
            e = ex.Current()
            ex.Next()
            if self.edge_faces.Contains(e):
                out.update(self.faces.FindIndex(f) for f in self.edge_faces.FindFromKey(e))
        return out

    def on_surface(self, i, p, tol):
        proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*p), BRep_Tool.Surface_s(TopoDS.Face(self.faces.FindKey(i))))
        return proj.NbPoints() > 0 and proj.LowerDistance() <= tol

    def ball_solid(self, centre, r):
        """The solid a ball is checked against: of the solids holding its centre, the one
        whose boundary is nearest to being r away (None: the whole shape)."""
        ks = self.solids_holding(centre)
        if len(ks) == 1:
            return ks[0]
        return min(ks, key=lambda k: abs(self.nearest(centre, k)[0] - r))

    def nearest(self, p, k=None):
        """(distance, [(point, support type, support shape), ...]) from p to the boundary of
        solid k (None: of the whole shape)."""
        shells = self.shells if k is None else self.solid_shells[k]
        d = BRepExtrema_DistShapeShape(vertex(p), shells)
        d.Perform()
        if not d.IsDone() or d.NbSolution() == 0:
            return math.inf, []
        sols = []
        for i in range(1, d.NbSolution() + 1):
            q = d.PointOnShape2(i)
            sols.append(((q.X(), q.Y(), q.Z()), d.SupportTypeShape2(i), d.SupportOnShape2(i)))
        return d.Value(), sols

    def face_contacts(self, p, reach, solid=None, extrema=False):
        """The nearest point of every face (of that solid, if not None) within `reach` of `p`;
        with `extrema`, also every extremum of the distance from `p` on each such face's
        surface that is inside the face and within `reach` (a face touched twice by a ball,
        an elliptic wall seen from its major axis, has two: its nearest point is one)."""
        out = []
        for i, d in self.face_distances(p, reach, solid):
            for k in range(1, d.NbSolution() + 1):
                q = d.PointOnShape2(k)
                out.append((q.X(), q.Y(), q.Z()))
            if extrema:
                out += self.surface_extrema(i, p, reach)
        return out

    def axis_contacts(self, p, contacts, reach, tol, solid=None):
        """Contacts along a circle: for a centre `p` (within `tol`) on the axis of a face of
        revolution (cylinder, cone, sphere, torus, surface of revolution) within `reach`,
        each contact on that face turned round the axis; on a torus's core circle, turned round
        the core's tangent at `p` (the ball touches the tube along its meridian circle). By
        every eighth of a turn, kept when on the face (within `tol`: a fillet's face holds a
        quarter of the circle) and within `reach` of `p`. A ball centred there touches the face
        along an arc, and the extrema of the distance are not isolated (OCCT's projection
        finds none)."""
        out = []
        # The faces by their boxes: OCCT's distance from a point on a torus's core to the
        # torus's face is not always found (every point of a meridian is a solution).
        for i in self.faces_by_box(p, reach, solid):
            face = TopoDS.Face(self.faces.FindKey(i))
            surface = BRepAdaptor_Surface(face)
            axes = []
            axis = revolution_axis(surface)
            if axis is not None and gp_Lin(axis).Distance(gp_Pnt(*p)) <= tol:
                axes.append(axis)
            if surface.GetType() == GeomAbs_Torus and core_distance(surface.Torus(), p) <= tol:
                axes.append(core_tangent(surface.Torus(), p))
            for axis in axes:
                for q in contacts:
                    for k in range(1, 8):
                        turned = gp_Pnt(*q).Rotated(axis, k * math.pi / 4.0)
                        t = (turned.X(), turned.Y(), turned.Z())
                        if dist3(t, p) > reach:
                            continue
                        if distance_within(vertex(t), face, tol) is not None:
                            out.append(t)
        return out

    def surface_extrema(self, i, p, reach):
        """The extrema of the distance from `p` on face i's surface (GeomAPI_ProjectPointOnSurf)
        within `reach` of it and inside the face."""
        face = TopoDS.Face(self.faces.FindKey(i))
        proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*p), BRep_Tool.Surface_s(face))
        out = []
        for k in range(1, proj.NbPoints() + 1):
            if proj.Distance(k) > reach:
                continue
            u, v = proj.Parameters(k)
            if BRepClass_FaceClassifier(face, gp_Pnt2d(u, v), 1e-7).State() in (TopAbs_IN, TopAbs_ON):
                q = proj.Point(k)
                out.append((q.X(), q.Y(), q.Z()))
        return out

    def inside(self, p, clearance=0.0):
        """OCCT's classifier says IN. Its ray can graze an edge and say OUT for a point well
        inside (seen on a point 0.35 mm deep, IN 0.006 mm away): a point `clearance` or more
        from the boundary, so that every point within `clearance` of it is on its side, that
        is not IN is tried again at the six points half `clearance` away along the axes, and
        is inside when most of them are IN."""
        if self.state(p) == TopAbs_IN:
            return True
        if clearance <= 0.0:
            return False
        d = 0.5 * clearance
        moved = [
            tuple(p[k] + (sign * d if k == j else 0.0) for k in range(3))
            for j in range(3)
            for sign in (1.0, -1.0)
        ]
        return sum(self.state(q) == TopAbs_IN for q in moved) >= 4

    def state(self, p):
        if len(self.solids) < 2:
            return BRepClass3d_SolidClassifier(self.shape, gp_Pnt(*p), 1e-7).State()
        states = [
            BRepClass3d_SolidClassifier(s, gp_Pnt(*p), 1e-7).State()
            for k, s in enumerate(self.solids)
            if not self.solid_boxes[k].IsOut(gp_Pnt(*p))
        ]
        for want in (TopAbs_IN, TopAbs_ON):
            if want in states:
                return want
        return TopAbs_OUT

    def faces_of(self, kind, support):
        """The indices (from 1, file order) of the faces a support lies on."""
        if kind == BRepExtrema_SupportType.BRepExtrema_IsInFace:
            return [self.faces.FindIndex(support)]
        table = self.edge_faces if kind == BRepExtrema_SupportType.BRepExtrema_IsOnEdge else self.vertex_faces
        if not table.Contains(support):
            return []
        return [self.faces.FindIndex(f) for f in table.FindFromKey(support)]

    def local_contact(self, centre, kind, support, near):
        """The point of `support` (a face, edge or vertex) nearest to `centre` among its
        extrema, the one closest to `near`; None when there is none inside the support."""
        c = gp_Pnt(*centre)
        if kind == BRepExtrema_SupportType.BRepExtrema_IsVertex:
            q = BRep_Tool.Pnt_s(TopoDS.Vertex(support))
            return (q.X(), q.Y(), q.Z())
        best = None
        if kind == BRepExtrema_SupportType.BRepExtrema_IsOnEdge:
            edge = TopoDS.Edge(support)
            first, last = BRep_Tool.Range_s(edge)
            curve = BRep_Tool.Curve_s(edge, first, last)
            if curve is None:
                return None
            proj = GeomAPI_ProjectPointOnCurve(c, curve, first, last)
            for i in range(1, proj.NbPoints() + 1):
                q = proj.Point(i)
                p = (q.X(), q.Y(), q.Z())
                if best is None or dist3(p, near) < dist3(best, near):
                    best = p
            return best
        face = TopoDS.Face(support)
        surface = BRep_Tool.Surface_s(face)
        proj = GeomAPI_ProjectPointOnSurf(c, surface)
        for i in range(1, proj.NbPoints() + 1):
            u, v = proj.Parameters(i)
            inside = BRepClass_FaceClassifier(face, gp_Pnt2d(u, v), 1e-7).State()
            if inside not in (TopAbs_IN, TopAbs_ON):
                continue
            q = proj.Point(i)
            p = (q.X(), q.Y(), q.Z())
            if best is None or dist3(p, near) < dist3(best, near):
                best = p
        return best


def box_distance(box, p):
    """The distance from `p` to an axis-aligned box."""
    lo, hi = box.CornerMin(), box.CornerMax()
    d2 = 0.0
    for x, a, b in ((p[0], lo.X(), hi.X()), (p[1], lo.Y(), hi.Y()), (p[2], lo.Z(), hi.Z())):
        if x < a:
            d2 += (a - x) ** 2
        elif x > b:
            d2 += (x - b) ** 2
    return math.sqrt(d2)


def vertex(p):
    return BRepBuilderAPI_MakeVertex(gp_Pnt(*p)).Vertex()


def distance_within(v, shape, reach):
    """BRepExtrema_DistShapeShape from the vertex `v` to `shape` when it finds a point of it
    within `reach`, else None."""
    d = BRepExtrema_DistShapeShape(v, shape)
    d.Perform()
    return d if d.IsDone() and d.NbSolution() > 0 and d.Value() <= reach else None


class Checks:
    def __init__(self, tol):
        self.tol = tol
        self.checked = {}
        self.failed = {}
        self.failures = []
        self.held_to_gap = 0

    def within(self, part, error, p, reach, solid):
        """error <= tol, or <= tol plus the file's gap near p (faces within reach + error)."""
        if error <= self.tol:
            return True
        gap = part.gap_near(p, reach + error + self.tol, solid)
        ok = gap > self.tol and error <= self.tol + gap
        self.held_to_gap += ok
        return ok

    def inside(self, part, p, clearance, solid):
        """The classifier says IN, or ON where p is no farther from the boundary than the
        file's gap near it: OCCT's reader widens a gap face's tolerance to its gap, and its
        classifier answers ON for every point within it, inside or out."""
        if part.inside(p, clearance):
            return True
        if part.state(p) != TopAbs_ON:
            return False
        gap = part.gap_within_reach(p, clearance + self.tol, solid)
        ok = gap > self.tol and clearance <= gap + self.tol
        self.held_to_gap += ok
        return ok

    def record(self, check, passed, what):
        self.checked[check] = self.checked.get(check, 0) + 1
        if not passed:
            self.failed[check] = self.failed.get(check, 0) + 1
            if len(self.failures) < 200:
                self.failures.append(f"{check}: {what()}")


# The finest error a ball's separation is taken at (mm), however exact the ball: OCCT's
# extrema vouch for no less; and the same relative to the part's diagonal.
FINEST_SEPARATION_ACCURACY = 1e-7
FINEST_SEPARATION_REL_DIAGONAL = 1e-9

# Samples of an edge between two touch points at which curls_round looks for the edge bending
# round the ball.
CURL_SAMPLES = 8


def curls_round(curve, t0, t1, c, tol):
    """True when the curve bends round the ball centred at c somewhere between parameters t0
    and t1 (both included): there the second derivative of half the squared distance from c,
    |C'|^2 - (c - C).C'', is at most what the accuracy of c allows (tol |C''|), so that the
    distance along it has a maximum between two touch points (or is constant): two touch
    points there are two places however close."""
    for k in range(CURL_SAMPLES + 1):
        t = t0 + (t1 - t0) * k / CURL_SAMPLES
        q, d1, d2 = gp_Pnt(), gp_Vec(), gp_Vec()
        curve.D2(t, q, d1, d2)
        w = (c[0] - q.X(), c[1] - q.Y(), c[2] - q.Z())
        g = d1.SquareMagnitude() - (w[0] * d2.X() + w[1] * d2.Y() + w[2] * d2.Z())
        if g <= tol * d2.Magnitude():
            return True
    return False


def places_on_curling_edges(part, touch, centre, s, tol, k, cap):
    """places(touch, s), where two touch points closer than s on one edge that curls round the
    ball between them count as separate places too."""
    edges = [part.edges_near(t, tol, k) for t in touch]

    def separate(i, j):
        if dist3(touch[i], touch[j]) > s:
            return True
        return any(e in edges[j] and curls_round(curve, ti, edges[j][e][1], centre, tol)
                   for e, (curve, ti) in edges[i].items())

    return places(touch, s, separate, cap)


def shortfall_explained(part, touch, faces, s, same_ok):
    """True when every two touch points closer than s lie on two different faces that meet
    (share a vertex: a crease, a sliver between them) and not on the same faces (not both on
    one edge), or on one face where same_ok (a seam ending at a curvature limit or a pinch): the
    geometry explains why the accuracy cannot resolve them. faces[i]: the faces touch point i
    lies on."""
    for i in range(len(touch)):
        for j in range(i + 1, len(touch)):
            if dist3(touch[i], touch[j]) > s:
                continue
            # Not on the same faces (two touch points on one edge are one place there), and on
            # two faces that meet.
            meet = faces[i] != faces[j] and any(
                f != g and part.face_vertices.get(f, set()) & part.face_vertices.get(g, set())
                for f in faces[i] for g in faces[j])
            same = same_ok and bool(set(faces[i]) & set(faces[j]))
            if not (meet or same):
                return False
    return True


def distinct_faces(faces, allowed, used=()):
    """True when each touch point can be given a face of its own among those it lies on
    (faces[i]) that is in `allowed`, no face given twice."""
    if not faces:
        return True
    return any(distinct_faces(faces[1:], allowed, used + (f,))
               for f in faces[0] if f in allowed and f not in used)


def check_ball(part, checks, touched, what, centre, r, touch, need, unresolved=None):
    """unresolved: for a ball the report marks unresolved, (places it needs then, whether one
    face may hold two touch points closer than the separation, the part's vertices (indices
    from 1) at the seam's ends at convex vertices)."""
    tol = checks.tol
    ok = finite(centre, r, touch)
    checks.record("finite", ok, lambda: f"{what}: a number is not finite")
    if not ok:
        return
    point_ball = r <= tol
    k = part.ball_solid(centre, r)
    d, _ = part.nearest(centre, k)
    if not point_ball:
        checks.record("inside", checks.inside(part, centre, min(d, r), k),
                      lambda: f"{what}: centre {centre} not inside the solid")
    checks.record("distance", checks.within(part, abs(d - r), centre, r, k),
                  lambda: f"{what}: distance to boundary {d:.9g}, r = {r:.9g}")
    faces = []
    # The ball's own error (its distance's and its touch points'), for the separation below.
    own_error = abs(d - r)
    for t in touch:
        dt, sols = part.nearest(t, k)
        on = set()
        for _, kind, support in sols:
            on.update(part.faces_of(kind, support))
        own_error = max(own_error, dt)
        checks.record("touch_on_boundary", checks.within(part, dt, t, 0.0, k),
                      lambda: f"{what}: touch point {t} is {dt:.3g} mm off the boundary")
        touched.update(on)
        # On no face, within a gap of the file's: on the faces next to the nearest whose
        # surfaces it lies on (the corner of two surfaces, off the trim of one).
        if dt > tol and unresolved is not None and part.gap_near(t, dt + tol, k) > tol:
            on = {g for f in on for g in part.neighbours(f) if part.on_surface(g, t, tol)} or on
        faces.append(on)
        dc = dist3(t, centre)
        own_error = max(own_error, abs(dc - r))
        checks.record("touch_at_radius", checks.within(part, abs(dc - r), t, 0.0, k),
                      lambda: f"{what}: touch point {t} at {dc:.9g} from the centre, r = {r:.9g}")
    if not point_ball:
        # The chord at the ball's own error where that is finer than the accuracy: a touch
        # point as close to another on one smooth contact would be farther off the ball than
        # that error (by at least chord^2 / (8 r), short of osculation).
        finest = max(FINEST_SEPARATION_ACCURACY, FINEST_SEPARATION_REL_DIAGONAL * part.diagonal)
        s = separation(r, min(max(own_error, finest), max(tol, finest)))
        n = places(touch, s, cap=need)
        if n < need:
            # Closer than the separation but on one edge that curls round the ball between
            # them: two places the chord cannot tell apart and the curve's second derivative can.
            n = places_on_curling_edges(part, touch, centre, s, tol, k, need)
        # A ball marked unresolved may touch one place fewer, where its touch points closer
        # than the separation are on faces that meet; in the corner of a convex vertex its seam
        # ends at (each touch point on a face of that vertex, no two on the same), one place.
        ok = n >= need or unresolved is not None and (
            any(distinct_faces(faces, part.vertex_face_set(v)) for v in unresolved[2])
            or n >= unresolved[0] and shortfall_explained(part, touch, faces, s, unresolved[1]))
        checks.record("separated", ok,
                      lambda: f"{what}: touches {n} separate places (farther apart than {s:.3g} mm), needs {need}")


def check_mesh_vertex(part, checks, what, p):
    tol = checks.tol
    if not finite(p):
        checks.record("finite", False, lambda: f"{what}: a number is not finite")
        return
    k = part.solids_holding(p)[0]
    r, sols = part.nearest(p, k)
    checks.record("inside", checks.inside(part, p, r, k),
                  lambda: f"{what}: {p} not inside the solid")
    if not sols:
        checks.record("mesh_contacts", False, lambda: f"{what}: no nearest boundary point")
        return
    if r <= tol:
        return
    s = separation(r, tol)
    p1 = sols[0][0]
    # The contacts: every face's nearest point, and every extremum of the distance on a
    # face, within r + tol of the centre.
    contacts = [q for q, _, _ in sols] + part.face_contacts(p, r + tol, k, extrema=True)
    if places(contacts, s, cap=2) < 2:
        contacts += part.axis_contacts(p, contacts, r + tol, tol, k)
    ok = places(contacts, s, cap=2) >= 2 or growth_contact(part, p, r, p1, s, tol, k)
    # Near a file's gap, a second contact within it: a face's edge off its surface by the gap
    # is as much the boundary as the surface (the trace's balls are held to the gap likewise).
    gap = 0.0 if ok else part.gap_within_reach(p, r + tol, k)
    if gap > tol:
        near = part.face_contacts(p, r + tol + gap, k, extrema=True)
        ok = places([q for q, _, _ in sols] + near, s, cap=2) >= 2
        checks.held_to_gap += ok
    checks.record("mesh_contacts", ok,
                  lambda: f"{what}: the ball at {p} (r {r:.6g}) has no second contact: it could grow")


def revolution_axis(surface):
    """The axis (gp_Ax1) of a surface of revolution (BRepAdaptor_Surface), or None."""
    kind = surface.GetType()
    if kind == GeomAbs_Cylinder:
        return surface.Cylinder().Axis()
    if kind == GeomAbs_Cone:
        return surface.Cone().Axis()
    if kind == GeomAbs_Sphere:
        return surface.Sphere().Position().Axis()
    if kind == GeomAbs_Torus:
        return surface.Torus().Axis()
    if kind == GeomAbs_SurfaceOfRevolution:
        return surface.AxeOfRevolution()
    return None


def core_distance(torus, p):
    """The distance from `p` to a torus's core circle (gp_Torus)."""
    ax = torus.Axis()
    o, z = ax.Location(), ax.Direction()
    w = [p[0] - o.X(), p[1] - o.Y(), p[2] - o.Z()]
    h = w[0] * z.X() + w[1] * z.Y() + w[2] * z.Z()
    rho = math.sqrt(max(0.0, w[0] ** 2 + w[1] ** 2 + w[2] ** 2 - h * h))
    return math.hypot(rho - torus.MajorRadius(), h)


def core_tangent(torus, p):
    """The line through `p` along the tangent of a torus's core circle at the core's point
    nearest `p` (gp_Ax1)."""
    z = torus.Axis().Direction()
    o = torus.Axis().Location()
    w = gp_Vec(o, gp_Pnt(*p))
    radial = w - gp_Vec(z) * w.Dot(gp_Vec(z))
    return gp_Ax1(gp_Pnt(*p), gp_Dir(gp_Vec(z).Crossed(radial)))


def growth_contact(part, p, r, p1, s, tol, k=None):
    """The growth test, for a second contact on the face of the first (a face touched twice,
    a ball touching a face along a circle): step the centre away from the first contact; the
    nearest boundary point from there, or its foot from the centre on the same face, edge or
    vertex, must be a contact of the ball (at r + tol) separated from the first."""
    u = [(p[k] - p1[k]) / r for k in range(3)]
    for step in GROWTH_STEPS:
        q = tuple(p[k] + step * r * u[k] for k in range(3))
        _, qs = part.nearest(q, k)
        for near, kind, support in qs:
            for c in (near, part.local_contact(p, kind, support, near)):
                if c is not None and dist3(c, p) <= r + tol and dist3(c, p1) > s:
                    return True
    return False


def mesh_vertices(path, k):
    """About k of the mesh's distinct vertices, spread over the file, with their numbers in it
    (from 0). Many vertices can be one point (every ball of a sphere has its centre): each
    point is checked once."""
    vs, seen, n = [], set(), 0
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                v = tuple(float(x) for x in line.split()[1:4])
                if v not in seen:
                    seen.add(v)
                    vs.append((n, v))
                n += 1
    if not vs or k <= 0:
        return []
    stride = max(1, len(vs) // k)
    return vs[::stride][:k]


def check_pinch(part, checks, what, touch, tol):
    """A seam end at a pinch: two of the touch points meet at a vertex of the part (each within
    tol of it)."""
    pts = [t for t in touch if t is not None and finite(t)]
    met = any(sum(1 for t in pts if dist3(t, q) <= tol) >= 2 for q in part.vertex_points)
    checks.record("seam_ends", met, lambda: f"{what}: a pinch, but no two touch points are at a vertex "
                  f"of the part (within {tol:.3e} mm)")


def face_radii_near(part, i, t, c, r, near, place):
    """The radii of curvature of face i (index from 1) towards the centre c (1/k, k its larger
    principal curvature where positive) at its surface's point nearest t and along rays from
    there in eight directions (at OSCULATION_OFFSETS places), while the surface stays within
    `near` of the sphere of radius r about c."""
    face = TopoDS.Face(part.faces.FindKey(i))
    surface = BRep_Tool.Surface_s(face)
    proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*t), surface)
    if proj.NbPoints() == 0:
        return []
    u0, v0 = proj.LowerDistanceParameters()
    first = GeomLProp_SLProps(surface, u0, v0, 1, 1e-9)
    su, sv = first.D1U().Magnitude(), first.D1V().Magnitude()
    if not (su > 0 and sv > 0):
        return []
    sign = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    u1, u2, v1, v2 = surface.Bounds()

    def radius(u, v):
        props = GeomLProp_SLProps(surface, u, v, 2, 1e-9)
        x = props.Value()
        d = (x.X() - c[0], x.Y() - c[1], x.Z() - c[2])
        dn = math.sqrt(sum(z * z for z in d))
        if abs(dn - r) > near:
            return False
        if not (props.IsNormalDefined() and props.IsCurvatureDefined()) or not dn > 0:
            return None
        # Touched there: the face tangent to the sphere (its outward normal along the way
        # from the centre, to the angle over which a place stays within `near` of it).
        n = props.Normal()
        if sign * (n.X() * d[0] + n.Y() * d[1] + n.Z() * d[2]) / dn < math.cos(min(near / place, 0.5)):
            return None
        k = max(-sign * props.MaxCurvature(), -sign * props.MinCurvature())
        return 1.0 / k if k > 0 else None

    out = []
    for j in range(8):
        a = j * math.pi / 4
        for offset in OSCULATION_OFFSETS[0 if j == 0 else 1:]:
            step = offset * place
            u, v = u0 + math.cos(a) * step / su, v0 + math.sin(a) * step / sv
            if not (u1 <= u <= u2 and v1 <= v <= v2):
                break
            rho = radius(u, v)
            if rho is False:
                break
            if rho is not None:
                out.append(rho)
    return out


def edge_radii_near(curve, s0, c, r, near, place):
    """The radii of curvature of an edge's curve towards the centre c (1/(k N.u), u the unit
    vector to c, where positive) at parameter s0 and both ways along it (at OSCULATION_OFFSETS
    places), while it stays within `near` of the sphere of radius r about c."""
    speed = GeomLProp_CLProps(curve, s0, 1, 1e-9).D1().Magnitude()
    if not speed > 0:
        return []
    first, last = curve.FirstParameter(), curve.LastParameter()

    def radius(s):
        props = GeomLProp_CLProps(curve, s, 2, 1e-9)
        x = props.Value()
        d = (c[0] - x.X(), c[1] - x.Y(), c[2] - x.Z())
        dn = math.sqrt(sum(z * z for z in d))
        if abs(dn - r) > near:
            return False
        if not props.IsTangentDefined() or not dn > 0:
            return None
        # Touched there: square to the way to the centre (to the angle over which a place
        # stays within `near` of the sphere).
        tangent = gp_Dir()
        props.Tangent(tangent)
        if abs(tangent.X() * d[0] + tangent.Y() * d[1] + tangent.Z() * d[2]) / dn > math.sin(min(near / place, 0.5)):
            return None
        k = props.Curvature()
        if not 1e-12 < k < 1e12:
            return None
        n = gp_Dir()
        props.Normal(n)
        bend = k * (n.X() * d[0] + n.Y() * d[1] + n.Z() * d[2]) / dn
        return 1.0 / bend if bend > 0 else None

    out = []
    for sign in (-1, 1):
        for offset in OSCULATION_OFFSETS[0 if sign < 0 else 1:]:
            s = s0 + sign * offset * place / speed
            if not first <= s <= last:
                break
            rho = radius(s)
            if rho is False:
                break
            if rho is not None:
                out.append(rho)
    return out


def check_curvature_limit(part, checks, what, segment, centre, r, touch, tol):
    """A seam end at a curvature limit (`curvature_limits`): its ball osculates the boundary
    near one of its touch points -- at a face's or an edge's limit, the radii of curvature
    towards the centre of the faces (or of the edges) there, where the boundary stays within
    OSCULATION_NEAR_TOLS of the sphere, come within CURVATURE_LIMIT_TOLS of r or lie on both
    sides of it; at a vertex's, the ball touches a vertex of the part. All plus the file's gap
    near the touch point: of the faces no farther from it than the accuracy plus their own gap
    (a touch point on a face past its trim by a neighbour's gap is that far from both)."""
    touch = [t for t in touch if t is not None and finite(t)]
    if not (finite(centre, r) and touch and isinstance(segment, str)):
        checks.record("curvature_limits", False, lambda: f"{what}: no ball or touch points")
        return
    # The boundary's points nearest the centre are touch points too (the ball may osculate
    # the face it was handed towards away from the touch points listed).
    d, sols = part.nearest(centre)
    if abs(d - r) <= tol + part.largest_gap():
        touch = touch + [q for q, _, _ in sols]
    place = separation(r, tol)
    nearest = None
    for t in touch:
        gap = part.gap_within_reach(t, tol)
        reach = tol + gap
        if segment.startswith("V"):
            # A vertex within its own tolerance (OCCT's, which the reader widens to cover
            # the file's gap between the vertex and its edges' curves).
            if any(dist3(q, t) <= reach + vt and abs(dist3(q, centre) - r) <= reach + vt
                   for q, vt in zip(part.vertex_points, part.vertex_tolerances)):
                checks.record("curvature_limits", True, None)
                return
            continue
        near = OSCULATION_NEAR_TOLS * tol + gap
        allowed = CURVATURE_LIMIT_TOLS * tol + gap
        faces = [rho for i in part.faces_within(t, reach)
                 for rho in face_radii_near(part, i, t, centre, r, near, place)]
        edges = [rho for curve, s0 in part.edges_near(t, reach).values()
                 for rho in edge_radii_near(curve, s0, centre, r, near, place)]
        for radii in (faces, edges):
            if not radii:
                continue
            lo, hi = min(radii), max(radii)
            if lo - allowed <= r <= hi + allowed:
                checks.record("curvature_limits", True, None)
                return
            off = min(abs(lo - r), abs(hi - r))
            if nearest is None or off < nearest[0]:
                nearest = (off, lo, hi)
    if segment.startswith("V"):
        why = "its ball touches no vertex of the part"
    elif nearest is None:
        why = "no face or edge there bends towards its ball"
    else:
        why = (f"r {r:.6f} is no radius of curvature there (the nearest range {nearest[1]:.6f} "
               f"to {nearest[2]:.6f})")
    checks.record("curvature_limits", False, lambda: f"{what} at {segment}'s curvature limit: {why}")


def on_polyline(balls, b, tol):
    """True when ball b ([x, y, z, r]) is within tol (centre and radius) of a point of the
    polyline of balls (or of its one ball)."""
    def close(p):
        return dist3(p[:3], b[:3]) <= tol and abs(p[3] - b[3]) <= tol
    if any(close(p) for p in balls):
        return True
    for p, q in zip(balls, balls[1:]):
        d = [q[j] - p[j] for j in range(4)]
        dd = sum(x * x for x in d[:3])
        t = 0.0 if dd == 0 else max(0.0, min(1.0, sum((b[j] - p[j]) * d[j] for j in range(3)) / dd))
        if close([p[j] + t * d[j] for j in range(4)]):
            return True
    return False


def check_skeletal(part, checks, touched, k, tol, degenerate):
    """A skeletal edge at a vertex: balls on a straight line ending at a vertex of the part
    (r = 0 there), each touching that vertex alone; a free edge where a rim's sheet ends
    starts on each degenerate curve it `meets` [d, i], at its ball i or between its balls i and
    i + 1 (to 4 tol: its ball is found by emptiness, the curve's balls are located)."""
    balls = k.get("balls", [])
    what = f"skeletal edge {k.get('id')}"
    for d, i in k.get("meets", []):
        curve = degenerate[d] if isinstance(d, int) and 0 <= d < len(degenerate) else {}
        cb = (curve.get("balls") or [])[i:i + 2] if isinstance(i, int) and i >= 0 else []
        ok = bool(balls) and bool(cb) and all(finite(b[:3], b[3]) for b in cb + balls[:1]) \
            and on_polyline(cb, balls[0], 4 * tol)
        checks.record("skeletal_edges", ok, lambda: f"{what}: its first ball is not on degenerate {d} "
                      f"at its ball {i}")
    last = balls[-1] if balls else None
    at = None
    if last is not None and finite(last[:3], last[3]):
        at = min(part.vertex_points, key=lambda q: dist3(q, last[:3]), default=None)
    ok = at is not None and dist3(at, last[:3]) <= tol and abs(last[3]) <= tol
    checks.record("skeletal_edges", ok, lambda: f"{what}: does not end at a vertex of the part with r = 0")
    if at is None:
        return
    for i, b in enumerate(balls):
        check_ball(part, checks, touched, f"{what} ball {i}", b[:3], b[3], [list(at)], SKELETAL_PLACES)


def check_degenerate_ends(part, checks, touched, i, d, tol):
    """A degenerate curve traced to located ends (`degenerate_ends`): where its ball meets
    another element, the touch point is on the boundary and r from the end ball's centre;
    where it vanishes, the end ball is a vertex of the part with r = 0; a closed curve's last
    ball is a step from its first. An open end, or a curve with no ends (sampled only), fails."""
    if d.get("kind") != "curve":
        return
    balls, ends = d.get("balls", []), d.get("ends", [])
    what = f"degenerate {i}"
    closed = [e.get("kind") for e in ends if isinstance(e, dict)] == ["closed"]
    shape = bool(balls) and (closed or (len(ends) == 2 and all(
        isinstance(e, dict) and e.get("kind") != "closed" for e in ends)))
    checks.record("degenerate_ends", shape, lambda: f"{what} is not traced to two ends or round a loop")
    if not shape:
        return
    for k, e in enumerate(ends):
        b = balls[0] if k == 0 else balls[-1]
        kind = e.get("kind")
        if not finite(b[:3], b[3]):
            ok = False
        elif kind == "meets":
            t = e.get("touch")
            ok = t is not None and finite(t) and part.nearest(t)[0] <= tol \
                and abs(dist3(b[:3], t) - b[3]) <= tol
            if ok:
                touched.update(part.faces_within(t, tol))
        elif kind == "vanishes":
            ok = abs(b[3]) <= tol and any(dist3(q, b[:3]) <= tol for q in part.vertex_points)
        elif kind == "shrinks":
            ok = osculates_at(part, b, e.get("touch"), tol)
            if ok:
                touched.update(part.faces_within(e["touch"], tol))
        elif kind == "closed":
            step = max((dist3(p[:3], q[:3]) for p, q in zip(balls, balls[1:])), default=0.0)
            ok = len(balls) > 2 and dist3(b[:3], balls[0][:3]) <= 1.5 * step + tol
        else:
            ok = False
        checks.record("degenerate_ends", ok, lambda: f"{what} end {k} ({e}) is not located on the part")


def osculates_at(part, b, t, tol):
    """True when ball b (centre, r) osculates a face of the part at point t on its boundary:
    t at distance r from the centre, and on a face within tol of t, centre t - r n (n its
    outward normal at t) and 1/r its larger principal curvature there (OCCT's, signed by the
    face's orientation), to tol."""
    c, r = b[:3], b[3]
    if t is None or not finite(t) or abs(dist3(t, c) - r) > tol:
        return False
    for i in part.faces_within(t, tol):
        face = TopoDS.Face(part.faces.FindKey(i))
        surface = BRep_Tool.Surface_s(face)
        proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*t), surface)
        if proj.NbPoints() == 0:
            continue
        u, v = proj.LowerDistanceParameters()
        props = GeomLProp_SLProps(surface, u, v, 2, 1e-9)
        if not (props.IsNormalDefined() and props.IsCurvatureDefined()):
            continue
        sign = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
        n = props.Normal()
        n = (sign * n.X(), sign * n.Y(), sign * n.Z())
        # OCCT's curvatures are signed against its normal: a convex face (outward normal)
        # curves away from it, negative; towards the material is -sign * k.
        k = max(-sign * props.MaxCurvature(), -sign * props.MinCurvature())
        centre = tuple(t[j] - r * n[j] for j in range(3))
        if k > 0 and dist3(centre, c) <= tol and abs(1.0 / k - r) <= tol:
            return True
    return False


def outward_normal(face, p):
    """The unit outward normal of face (oriented in its shell) at its surface's point nearest p,
    or None where the surface has none."""
    surface = BRep_Tool.Surface_s(face)
    proj = GeomAPI_ProjectPointOnSurf(p, surface)
    if proj.NbPoints() == 0:
        return None
    u, v = proj.LowerDistanceParameters()
    props = GeomLProp_SLProps(surface, u, v, 1, 1e-9)
    if not props.IsNormalDefined():
        return None
    n = props.Normal()
    k = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    return (k * n.X(), k * n.Y(), k * n.Z())


def smooth_surfaces(part):
    """For each face (index from 1), the least face of its smooth surface: faces joined across an
    edge where their outward normals agree within SMOOTH_DEG at SMOOTH_SAMPLES points along it."""
    return joined_faces(part, False)


def joined_faces(part, reflex):
    """For each face (index from 1), the least face of the set it is in when faces are joined
    across smooth edges (see smooth_surfaces) and, with `reflex`, across reflex edges too: an
    edge whose points just off it along the difference of its two faces' outward normals, both
    ways (into each face's side of the other), are inside the solid, as at a concave corner and
    not a convex one."""
    root = list(range(part.faces.Extent() + 1))

    def find(f):
        while root[f] != f:
            root[f] = root[root[f]]
            f = root[f]
        return f

    cos_tol = math.cos(math.radians(SMOOTH_DEG))
    step = REFLEX_STEP_REL * part.diagonal
    for i in range(1, part.edge_faces.Extent() + 1):
        edge = TopoDS.Edge(part.edge_faces.FindKey(i))
        faces = []
        for f in part.edge_faces.FindFromIndex(i):
            k = part.faces.FindIndex(f)
            if k not in [g for g, _ in faces]:
                faces.append((k, TopoDS.Face(f)))
        if len(faces) != 2 or BRep_Tool.Degenerated_s(edge):
            continue
        curve = BRepAdaptor_Curve(edge)
        t0, t1 = curve.FirstParameter(), curve.LastParameter()
        smooth = True
        for s in range(SMOOTH_SAMPLES):
            p = curve.Value(t0 + (t1 - t0) * (s + 0.5) / SMOOTH_SAMPLES)
            n = [outward_normal(f, p) for _, f in faces]
            if None in n or sum(a * b for a, b in zip(n[0], n[1])) < cos_tol:
                smooth = False
                break
        joined = smooth
        if not smooth and reflex:
            p = curve.Value(0.5 * (t0 + t1))
            n = [outward_normal(f, p) for _, f in faces]
            if None not in n:
                d = [n[0][j] - n[1][j] for j in range(3)]
                at = [tuple(p.Coord(j + 1) + sign * step * d[j] for j in range(3))
                      for sign in (1.0, -1.0)]
                joined = all(part.state(q) == TopAbs_IN for q in at)
        if joined:
            a, b = find(faces[0][0]), find(faces[1][0])
            root[max(a, b)] = min(a, b)
    return [find(f) for f in range(len(root))]


def other_contact(part, face_index, uv, tol):
    """The place other than its foot where the largest ball inside the part touching face
    `face_index` (from 1) at `uv` (centre on the inward normal) touches the boundary, or None
    (no normal there, or that place within the separation of the foot: the ball osculates)."""
    face = TopoDS.Face(part.faces.FindKey(face_index))
    surface = BRep_Tool.Surface_s(face)
    props = GeomLProp_SLProps(surface, uv[0], uv[1], 1, 1e-9)
    if not props.IsNormalDefined():
        return None
    q = props.Value()
    p = (q.X(), q.Y(), q.Z())
    sign = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    n = props.Normal()
    n = (sign * n.X(), sign * n.Y(), sign * n.Z())
    solids = [k for k, faces in enumerate(part.solid_faces) if face_index in faces]
    solid = solids[0] if len(part.solids) > 1 and solids else None

    def centre(r):
        return tuple(p[j] - r * n[j] for j in range(3))

    lo, hi = 0.0, part.diagonal
    while hi - lo > SHEET_BALL_REL * part.diagonal:
        mid = 0.5 * (lo + hi)
        if part.nearest(centre(mid), solid)[0] >= mid * (1.0 - 1e-9):
            lo = mid
        else:
            hi = mid
    _, sols = part.nearest(centre(hi), solid)
    far = [q for q, _, _ in sols if dist3(q, p) > separation(lo, tol)]
    return far[0] if far else None


def reached_across_reflex_edges(part, mat, tol, surface, reached):
    """Adds to `reached` the smooth surfaces no ball touches whose sheet runs on across reflex
    edges to balls that are listed (a pocket's floor over a plate thinner than the pocket's
    walls are far apart: its balls touch the floor and the plate's bottom, then the floor's
    edge, then the wall, and the seams bounding that sheet touch the walls, not the floor). At
    the centres of an 8 x 8 grid over a face's UV bounds that are on the face, the largest ball
    inside touching it there touches one other place q; the face is reached when a listed ball
    touches a face within tol of q and a face of the face's reflex group (faces joined across
    reflex and smooth edges), q's faces not in that group."""
    group = joined_faces(part, True)
    balls = [p.get("touch", []) for s in mat.get("seams", []) for p in s.get("points", [])]
    balls += [j.get("touch", []) for j in mat.get("junctions", [])]
    ball_faces = None
    for f in range(1, part.faces.Extent() + 1):
        if surface[f] in reached:
            continue
        face = TopoDS.Face(part.faces.FindKey(f))
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        n = SHEET_SAMPLE_GRID
        for k in range(n * n):
            uv = (u0 + (u1 - u0) * (k % n + 0.5) / n, v0 + (v1 - v0) * (k // n + 0.5) / n)
            if BRepClass_FaceClassifier(face, gp_Pnt2d(*uv), 1e-9).State() != TopAbs_IN:
                continue
            q = other_contact(part, f, uv, tol)
            if q is None:
                continue
            across = {g for g in part.faces_within(q, tol) if group[g] != group[f]}
            if not across:
                continue
            if ball_faces is None:
                ball_faces = [{g for t in touch if finite(t) for g in part.faces_within(t, tol)}
                              for touch in balls]
            if any(b & across and any(group[g] == group[f] for g in b) for b in ball_faces):
                reached.add(surface[f])
                break


def check_graph(mat, checks, touched, part):
    seams, junctions = mat.get("seams", []), mat.get("junctions", [])
    n_balls = sum(len(s.get("points", [])) for s in seams) + len(junctions) + sum(
        len(d.get("balls", [])) for d in mat.get("degenerate", []))
    checks.record("nonempty", n_balls > 0, lambda: "the report has no balls")
    ends_at = [0] * len(junctions)
    # A junction where a seam of four or more contacts ends (it splits there into seams of
    # three) is not generic: its sheets, not a count of seam ends, say whether it is complete.
    non_generic = [False] * len(junctions)
    for s in seams:
        for k, e in enumerate(s.get("ends", [])):
            is_open = isinstance(e, dict) and "open" in e
            checks.record("seam_ends", not is_open, lambda: f"seam {s.get('id')} end {k} is open: {e}")
            if isinstance(e, dict) and "junction" in e:
                j = e["junction"]
                exists = isinstance(j, int) and 0 <= j < len(junctions)
                checks.record("junction_seams", exists, lambda: f"seam {s.get('id')} ends at missing junction {j}")
                if exists:
                    ends_at[j] += 1
                    at_end = s.get("segments" if k == 0 else "end_segments", [])
                    non_generic[j] = non_generic[j] or len(at_end) > 3
    for j, n in enumerate(ends_at):
        generic = len(junctions[j].get("segments", [])) == 4 and not non_generic[j]
        if generic:
            checks.record("junction_seams", n == 4, lambda: f"junction {j} (4 segments) has {n} seam ends")
    surface = smooth_surfaces(part)
    reached = {surface[f] for f in touched}
    # A face no touch point is on may still be touched by a ball at a place the report does not
    # list: within r + tol of a ball's centre (in the solid holding it; the balls are checked
    # empty on their own).
    untouched = [f for f in range(1, part.faces.Extent() + 1) if surface[f] not in reached]
    if untouched:
        balls = [p["point"] for s in seams for p in s.get("points", [])]
        balls += [list(j["point"]) + [j["radius"]] for j in junctions]
        balls += [b for d in mat.get("degenerate", []) for b in d.get("balls", [])]
        for f in untouched:
            if surface[f] in reached:
                continue
            for b in balls:
                reach = b[3] + checks.tol
                if not finite(b[:3], b[3]) or box_distance(part.face_boxes[f - 1], b[:3]) > reach:
                    continue
                solids = part.solids_holding(b[:3])
                if solids != [None] and not any(f in part.solid_faces[k] for k in solids):
                    continue
                if distance_within(vertex(b[:3]), part.faces.FindKey(f), reach) is not None:
                    reached.add(surface[f])
                    break
    if any(surface[f] not in reached for f in range(1, part.faces.Extent() + 1)):
        reached_across_reflex_edges(part, mat, checks.tol, surface, reached)
    for f in range(1, part.faces.Extent() + 1):
        checks.record("faces_touched", surface[f] in reached,
                      lambda: f"face F{f - 1} is touched by no ball (nor is a face joined to it "
                      "across smooth edges, nor does its sheet run on across its reflex edges to "
                      "balls that are)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("step")
    ap.add_argument("report")
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--tol", type=float, default=None)
    ap.add_argument("--mesh", default=None)
    ap.add_argument("--mesh-samples", type=int, default=200)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()

    part = Part(a.step)
    try:
        report = json.load(open(a.report))
        mat = report["mat"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        print(f"{a.report}: not a usable report: {e}", file=sys.stderr)
        sys.exit(2)
    # The accuracy the report claims (or 1e-6 x the diagonal), plus OCCT's own precision.
    claimed = report.get("options", {}).get("accuracy")
    if a.tol is not None:
        tol = a.tol
    elif isinstance(claimed, (int, float)) and math.isfinite(claimed) and claimed > 0:
        tol = claimed + 1e-7
    else:
        tol = 1e-6 * part.diagonal + 1e-7

    checks = Checks(tol)
    if a.tol is None:
        # A claimed accuracy that is not a small positive length would let anything pass.
        good = isinstance(claimed, (int, float)) and 0 < claimed <= MAX_ACCURACY_REL_DIAGONAL * part.diagonal
        checks.record("accuracy", good, lambda: f"the claimed accuracy {claimed!r} mm is not in (0, "
                      f"{MAX_ACCURACY_REL_DIAGONAL} x the diagonal {part.diagonal:.4f} mm]")
    touched = set()
    for j in mat.get("junctions", []):
        check_ball(part, checks, touched, f"junction {j['id']}", j["point"], j["radius"], j["touch"],
                   JUNCTION_PLACES, (JUNCTION_PLACES - 1, False, []) if j.get("unresolved") else None)
    for i, d in enumerate(mat.get("degenerate", [])):
        touch = d.get("touch", [])
        ends = d.get("ends", [])
        # The ball where the arc of contact shrinks to a vertex touches it alone.
        shrunk = {k for k, e in zip((0, len(d["balls"]) - 1), ends)
                  if len(ends) == 2 and isinstance(e, dict) and e.get("kind") == "shrinks"}
        for k, b in enumerate(d["balls"]):
            t = touch[k] if k < len(touch) else []
            need = SHRUNK_END_PLACES if k in shrunk else DEGENERATE_PLACES
            check_ball(part, checks, touched, f"degenerate {i} ball {k}", b[:3], b[3], t, need)
        check_degenerate_ends(part, checks, touched, i, d, tol)
    for k in mat.get("skeletal_edges", []):
        check_skeletal(part, checks, touched, k, tol, mat.get("degenerate", []))
    for s in mat.get("seams", []):
        pts = s["points"]
        picks = sorted(set(list(range(0, len(pts), max(1, a.every))) + [len(pts) - 1]))
        at_limit = any(isinstance(e, dict) and ("curvature_limit" in e or "pinch" in e)
                       for e in s["ends"])
        # The part's vertices at the seam's ends at convex vertices (its end balls there).
        corners = [v for end, q in zip(s["ends"], (pts[0], pts[-1]) if pts else ())
                   if isinstance(end, dict) and "vertex" in end
                   for v in [part.vertex_at(q["point"][:3], tol)] if v is not None]
        for k in picks:
            p = pts[k]
            end = s["ends"][0] if k == 0 else s["ends"][1] if k == len(pts) - 1 else None
            need = SEAM_PLACES
            if isinstance(end, dict) and "curvature_limit" in end:
                need = CURVATURE_END_PLACES
                limit = end["curvature_limit"]
                segment = limit.get("segment") if isinstance(limit, dict) else None
                check_curvature_limit(part, checks, f"seam {s['id']} point {k}", segment,
                                      p["point"][:3], p["point"][3], p["touch"], tol)
            elif isinstance(end, dict) and "pinch" in end:
                need = PINCH_END_PLACES
                check_pinch(part, checks, f"seam {s['id']} point {k}", p["touch"], tol)
            unresolved = ((CURVATURE_END_PLACES, at_limit, corners)
                          if k in s.get("unresolved", []) else None)
            check_ball(part, checks, touched, f"seam {s['id']} point {k}", p["point"][:3], p["point"][3],
                       p["touch"], need, unresolved)
    check_graph(mat, checks, touched, part)
    if a.mesh:
        for i, v in mesh_vertices(a.mesh, a.mesh_samples):
            check_mesh_vertex(part, checks, f"mesh vertex {i + 1}", v)

    failed = sum(checks.failed.values())
    if a.json:
        print(json.dumps({"tol": tol, "checked": checks.checked, "failed": checks.failed,
                          "failures": checks.failures, "held_to_gap": checks.held_to_gap},
                         indent=1, sort_keys=True))
    else:
        made = sum(checks.checked.values())
        print(f"{a.step}: {made} checks against OCCT, {failed} failed (tol {tol:.3g} mm)")
        if checks.held_to_gap:
            print(f"  {checks.held_to_gap} errors beyond the tolerance are within the file's own gaps")
        for name in sorted(checks.checked):
            print(f"  {name}: {checks.checked[name] - checks.failed.get(name, 0)}/{checks.checked[name]}")
        for f in checks.failures[:50]:
            print("  " + f)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
