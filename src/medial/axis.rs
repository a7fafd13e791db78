//! The medial axis as traced: seams, junctions, degenerate pieces, and how each seam ends.
//!
//! These are the tracer's results and the report's `mat` object (serialised as they are).
//! Elements touched are written `F3`, `E7`, `V2` ([`Element`]).

use crate::classify::{EdgeKind, VertexKind};
use crate::medial::solver::SolveStatus;
use crate::model::Element;
use glam::DVec3;
use std::fmt;

/// One point of a seam.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SeamPoint {
    /// `[x, y, z, r]`.
    #[serde(deserialize_with = "nullable::ball")]
    pub point: [f64; 4],
    /// The touch points, one per element of the seam's `segments` (slot by slot, after any
    /// hand-over): three, or more where more elements touch every ball of the seam.
    #[serde(deserialize_with = "nullable::points")]
    pub touch: Vec<[f64; 3]>,
}

/// A node of the medial axis's graph where seams end: a junction, or a convex vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Node {
    Junction(usize),
    Vertex(usize),
}

/// How a seam ends.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SeamEnd {
    /// At a convex vertex, `r = 0`.
    Vertex(usize),
    /// At a junction.
    Junction(usize),
    /// The seam is a closed curve (both ends are its first point).
    Closed,
    /// The ball stops being maximal by curvature: it osculates `segment` (`r·κmax = 1`).
    /// The last point is where that happens to the output accuracy; a skeletal edge (the
    /// sheet's edge of centres of curvature) starts there.
    CurvatureLimit { segment: Element },
    /// Two touch points meet at vertex `vertex` of the boundary, which both their elements
    /// `segments` reach (a hole tangent to a slot's wall, a face running into an edge
    /// there): the sheet between those two elements pinches off at this ball (`r > 0`, and
    /// the ball touches two places), and the seam ends. The seam on the elements past the
    /// vertex ends at the same ball.
    Pinch {
        segments: [Element; 2],
        vertex: usize,
    },
    /// The tracer stopped without a proper end, for the reason given.
    Open(OpenReason),
}

impl SeamEnd {
    /// The graph node at this end, for a vertex or junction end.
    pub fn node(&self) -> Option<Node> {
        match *self {
            SeamEnd::Vertex(v) => Some(Node::Vertex(v)),
            SeamEnd::Junction(j) => Some(Node::Junction(j)),
            _ => None,
        }
    }
}

impl From<Node> for SeamEnd {
    fn from(node: Node) -> SeamEnd {
        match node {
            Node::Vertex(v) => SeamEnd::Vertex(v),
            Node::Junction(j) => SeamEnd::Junction(j),
        }
    }
}

/// Why the tracer stopped a seam without a proper end: every variant is an event the tracer
/// does not handle yet. Its text ([`Display`](fmt::Display)) is what reports write;
/// [`OpenReason::kind`] names the variant, for counting.
#[derive(Clone, Debug, PartialEq)]
pub enum OpenReason {
    /// The seam's tangent is undefined at its start (the Jacobian is singular there).
    SingularTangent,
    /// The tangent is undefined just after a touch point moved to another element.
    SingularTangentAfterHandover,
    /// [`crate::medial::trace::MAX_POINTS`] points and no end.
    PointBudgetExhausted,
    /// The corrector failed at every step down to the smallest step.
    StepSizeUnderflow,
    /// `r` reached 0 with no vertex within reach.
    ZeroRadiusAwayFromVertex,
    /// Two touch points on different elements came together (a degenerate seam point).
    TouchPointsCoincide,
    /// Two touch points came together just after handing `from` to `to`.
    CoincideAfterHandover { from: Element, to: Element },
    /// A touch point is handed back and forth between two elements and cannot stay on the
    /// vertex between them.
    Oscillates { from: Element, to: Element },
    /// The normal of the element is undefined at the touch point (a pole).
    UndefinedNormal { element: Element },
    /// The touch point left its face, but not near any of the face's edges.
    LeftFaceAwayFromEdges { face: Element },
    /// An edge's normal plane has no frame at the touch point.
    NoNormalFrame { edge: usize },
    /// The touch point could not be projected onto the next face.
    NotFoundOnFace { face: usize },
    /// The touch point on `element` reached an edge that is not smooth or reflex.
    ReachedEdge {
        element: Element,
        kind: EdgeKind,
        edge: usize,
    },
    /// The touch point reached the end of a reflex edge at a vertex that is not reflex or
    /// mixed.
    ReachedEdgeEnd {
        edge: usize,
        vertex_kind: VertexKind,
    },
    /// An edge's faces have no normals at the touch point.
    NoFaceNormals { edge: usize },
    /// A vertex touched by the ball has no edges.
    VertexWithoutEdges { vertex: usize },
    /// Re-solved on the new element, the hand-over gave no seam point of the same ball.
    NoSeamPointAfterHandover {
        from: Element,
        to: Element,
        status: SolveStatus,
        /// How far the centre moved (mm).
        moved: f64,
    },
    /// The boundary came closer than `r` on an element the tracer cannot touch (a vertex
    /// that is not reflex, or an edge without a normal frame there; `t`: the curve
    /// parameter on an edge).
    CloserThanR { on: Element, t: Option<f64> },
    /// An element came closer than `r`, but the four-element system has no junction on
    /// the elements.
    NoJunction { element: Element },
    /// A reason read back from a report, by its text.
    Other(String),
}

impl OpenReason {
    /// The variant's name in snake case (`step_size_underflow`): the key under which the
    /// report's `stats.open_ends_by_reason` counts it.
    pub fn kind(&self) -> &'static str {
        match self {
            OpenReason::SingularTangent => "singular_tangent",
            OpenReason::SingularTangentAfterHandover => "singular_tangent_after_handover",
            OpenReason::PointBudgetExhausted => "point_budget_exhausted",
            OpenReason::StepSizeUnderflow => "step_size_underflow",
            OpenReason::ZeroRadiusAwayFromVertex => "zero_radius_away_from_vertex",
            OpenReason::TouchPointsCoincide => "touch_points_coincide",
            OpenReason::CoincideAfterHandover { .. } => "coincide_after_handover",
            OpenReason::Oscillates { .. } => "oscillates",
            OpenReason::UndefinedNormal { .. } => "undefined_normal",
            OpenReason::LeftFaceAwayFromEdges { .. } => "left_face_away_from_edges",
            OpenReason::NoNormalFrame { .. } => "no_normal_frame",
            OpenReason::NotFoundOnFace { .. } => "not_found_on_face",
            OpenReason::ReachedEdge { .. } => "reached_edge",
            OpenReason::ReachedEdgeEnd { .. } => "reached_edge_end",
            OpenReason::NoFaceNormals { .. } => "no_face_normals",
            OpenReason::VertexWithoutEdges { .. } => "vertex_without_edges",
            OpenReason::NoSeamPointAfterHandover { .. } => "no_seam_point_after_handover",
            OpenReason::CloserThanR { .. } => "closer_than_r",
            OpenReason::NoJunction { .. } => "no_junction",
            OpenReason::Other(_) => "other",
        }
    }
}

impl fmt::Display for OpenReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OpenReason::SingularTangent => write!(f, "singular tangent"),
            OpenReason::SingularTangentAfterHandover => {
                write!(f, "singular tangent after a hand-over")
            }
            OpenReason::PointBudgetExhausted => write!(f, "point budget exhausted"),
            OpenReason::StepSizeUnderflow => write!(f, "step size underflow"),
            OpenReason::ZeroRadiusAwayFromVertex => {
                write!(f, "radius reached zero away from a vertex")
            }
            OpenReason::TouchPointsCoincide => {
                write!(f, "two touch points coincide (a degenerate seam point)")
            }
            OpenReason::CoincideAfterHandover { from, to } => {
                write!(f, "two touch points coincide after handing {from} to {to}")
            }
            OpenReason::Oscillates { from, to } => write!(
                f,
                "touch point oscillates between {from} and {to} and cannot stay on a vertex"
            ),
            OpenReason::UndefinedNormal { element } => {
                write!(f, "touch point on {element} at an undefined normal")
            }
            OpenReason::LeftFaceAwayFromEdges { face } => {
                write!(f, "touch point left {face} away from its edges")
            }
            OpenReason::NoNormalFrame { edge } => write!(f, "no normal frame on E{edge}"),
            OpenReason::NotFoundOnFace { face } => write!(f, "touch point not found on F{face}"),
            OpenReason::ReachedEdge {
                element,
                kind,
                edge,
            } => write!(f, "touch point on {element} reached {kind:?} edge E{edge}"),
            OpenReason::ReachedEdgeEnd { edge, vertex_kind } => write!(
                f,
                "touch point reached the end of reflex edge E{edge} at a {vertex_kind:?} vertex"
            ),
            OpenReason::NoFaceNormals { edge } => write!(f, "no face normals on E{edge}"),
            OpenReason::VertexWithoutEdges { vertex } => {
                write!(f, "vertex V{vertex} has no edges")
            }
            OpenReason::NoSeamPointAfterHandover {
                from,
                to,
                status,
                moved,
            } => write!(
                f,
                "no seam point after handing {from} to {to} (corrector {status:?}, centre moved {moved:.2e} mm)"
            ),
            OpenReason::CloserThanR { on, t } => {
                // Written as the distance query's feature prints in Rust's debug form.
                match (on, t) {
                    (Element::Face(i), _) => write!(f, "Face({i})"),
                    (Element::Edge(i), Some(t)) => write!(f, "Edge({i}, {t:?})"),
                    (Element::Edge(i), None) => write!(f, "Edge({i})"),
                    (Element::Vertex(i), _) => write!(f, "Vertex({i})"),
                }?;
                write!(f, " comes closer than r (vertex segments are not traced yet)")
            }
            OpenReason::NoJunction { element } => write!(
                f,
                "{element} comes closer than r, but no junction with it on the segments"
            ),
            OpenReason::Other(text) => write!(f, "{text}"),
        }
    }
}

impl serde::Serialize for OpenReason {
    /// As its text.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for OpenReason {
    /// From its text, as [`OpenReason::Other`].
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<OpenReason, D::Error> {
        <String as serde::Deserialize>::deserialize(d).map(OpenReason::Other)
    }
}

/// A seam: a curve of ball centres touching three elements (more at a non-generic seam).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Seam {
    pub id: usize,
    /// Index of the solid in the model.
    pub solid: usize,
    /// The three elements at the first point (a face twice when the ball touches it in two
    /// places); more at a non-generic seam, whose every ball they all touch (the seam from a
    /// square pyramid's apex: four faces), in their order round the seam.
    pub segments: Vec<Element>,
    pub ends: [SeamEnd; 2],
    /// The elements at the last point (after any hand-over), slot by slot as `segments`.
    pub end_segments: Vec<Element>,
    pub points: Vec<SeamPoint>,
    /// Where a touch point moves to another element, in the order of the points.
    pub handovers: Vec<Handover>,
    /// The points whose touch points make fewer separate places than a seam point needs at
    /// the accuracy (see [`crate::medial::verify::unresolved_points`]): exact seam points whose
    /// third contact the accuracy cannot tell from another (a shallow crease, a sliver face,
    /// a face near its curvature limit). Verification holds them to two places (one in the
    /// corner of a convex vertex the seam ends at).
    #[serde(default)]
    pub unresolved: Vec<usize>,
    /// How long the tracer took over this seam (s): not part of the medial axis, so not in
    /// the report's seam (the report's `stats.seam_trace_ms` lists them, by seam).
    #[serde(skip)]
    pub trace_seconds: f64,
}

impl Seam {
    /// The point at end `end` (0: the first, else the last) and the elements touched there.
    pub fn at_end(&self, end: usize) -> (Option<&SeamPoint>, &[Element]) {
        match end {
            0 => (self.points.first(), &self.segments),
            _ => (self.points.last(), &self.end_segments),
        }
    }

    /// True when either end is [`SeamEnd::Open`].
    pub fn is_open(&self) -> bool {
        self.ends.iter().any(|e| matches!(e, SeamEnd::Open(_)))
    }
}

/// A touch point passing from one element to the next along a seam (over a smooth edge, onto
/// or off a reflex edge).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Handover {
    /// Index of the seam point where it happens (on both elements).
    pub point: usize,
    pub from: Element,
    pub to: Element,
}

/// A junction: a ball touching four elements (more at a non-generic junction).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Junction {
    pub id: usize,
    /// Index of the solid in the model.
    pub solid: usize,
    #[serde(deserialize_with = "nullable::point")]
    pub point: [f64; 3],
    #[serde(deserialize_with = "nullable::number")]
    pub radius: f64,
    pub segments: Vec<Element>,
    #[serde(deserialize_with = "nullable::points")]
    pub touch: Vec<[f64; 3]>,
    /// True when the touch points make fewer than four separate places at the accuracy (two
    /// of them on elements that meet, closer than `√(8·r·a)`): verification holds it to three.
    #[serde(default)]
    pub unresolved: bool,
}

/// What a degenerate piece's centres form.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DegenerateKind {
    /// The centres move along a curve: the sheet between the elements has collapsed to it
    /// (a cylinder's axis, a torus's core circle).
    Curve,
    /// One centre: the ball touches all around (a sphere's centre).
    Point,
}

impl DegenerateKind {
    /// `"curve"` or `"point"`, as reports write it.
    pub fn as_str(&self) -> &'static str {
        match self {
            DegenerateKind::Curve => "curve",
            DegenerateKind::Point => "point",
        }
    }
}

/// A degenerate piece of the medial axis (a cylinder's axis, a sphere's centre, a torus's
/// core circle): maximal balls that touch `segments` along a continuum, found by sampling.
/// Its centres are not traced as seams; `balls` are the sampled ones, each verified maximal.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Degenerate {
    pub solid: usize,
    pub kind: DegenerateKind,
    pub segments: Vec<Element>,
    /// Sampled balls `[x, y, z, r]`.
    #[serde(deserialize_with = "nullable::balls")]
    pub balls: Vec<[f64; 4]>,
    /// Two touch points of each ball (one on each of `segments`), in the order of `balls`
    /// (missing in reports made before they were recorded).
    #[serde(default, deserialize_with = "nullable::pairs")]
    pub touch: Vec<[[f64; 3]; 2]>,
    /// How a traced curve ends at its first and its last ball (or that it closes on itself:
    /// one [`DegenerateEnd::Closed`]). Empty for a point, and for a curve only sampled.
    #[serde(default)]
    pub ends: Vec<DegenerateEnd>,
    /// A traced curve's balls touch their segments all round (a circle: a cylinder's axis, a
    /// torus's core), not along an arc only (a fillet's axis, where a sheet ends freely).
    #[serde(default)]
    pub around: bool,
}

/// How a degenerate curve ends (see [`Degenerate::ends`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum DegenerateEnd {
    /// The ball touches another element there besides its continuum, at `touch`: where the
    /// curve meets the rest of the medial axis (the apex of a cylinder cap's cone of balls),
    /// or, where `osculates` (the ball touches that element along a continuum too: a
    /// capsule's hemispherical cap), where it ends freely.
    Meets {
        element: Element,
        #[serde(deserialize_with = "nullable::point")]
        touch: [f64; 3],
        osculates: bool,
    },
    /// The ball shrinks to nothing at a vertex (a cone's apex): the last ball is the vertex,
    /// `r = 0`.
    Vanishes { vertex: usize },
    /// The arc its balls touch their face along shrinks to a point, at `touch` on `element`
    /// (a round cut off obliquely by a wall: the arc narrows to the vertex where the cut
    /// meets the round's tangent line, or to the point of the cut's edge, an ellipse, that
    /// reaches farthest along the curve). The last ball osculates the face there (centre
    /// `P − n/κ1`, `r = 1/κ1`, `n` the outward normal and `κ1` the larger principal
    /// curvature) and touches it at that point only: a free end.
    Shrinks {
        element: Element,
        #[serde(deserialize_with = "nullable::point")]
        touch: [f64; 3],
    },
    /// The curve closes on itself (a torus's core circle).
    Closed,
    /// Not located: the continuation stopped for `reason` (its text), of kind `cause`.
    Open {
        reason: String,
        /// What stopped it, for counting (`stats.degenerate_open_ends_by_reason`); a report
        /// written before causes were recorded reads back as `other`.
        #[serde(default)]
        cause: DegenerateOpen,
    },
}

impl DegenerateEnd {
    /// An open end of kind `cause`, with its text.
    pub fn open(cause: DegenerateOpen, reason: impl Into<String>) -> DegenerateEnd {
        DegenerateEnd::Open {
            reason: reason.into(),
            cause,
        }
    }
}

/// Why a degenerate curve's end was not located: each is an event the continuation does not
/// handle yet. The report writes it in snake case (`left_face`, …), which
/// `stats.degenerate_open_ends_by_reason` counts.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum DegenerateOpen {
    /// The centre's direction is undefined at the ball the curve was sampled at.
    NoDirection,
    /// The ball budget ran out with no end.
    BallBudget,
    /// The hand-over budget ran out with no end.
    HandoverBudget,
    /// The curve turned too much at every step down to the smallest.
    TurnsEveryStep,
    /// The corrector failed at every step down to the smallest.
    CorrectorFailed,
    /// The two touch points came within one place of each other (the continuum is too
    /// short for the accuracy).
    TouchPointsMeet,
    /// The balls stopped touching a continuum (the sheet opens again).
    SheetOpens,
    /// No boundary was found near the ball.
    NoBoundary,
    /// A touch point left its face, and no face beside it carries the continuum on.
    LeftFace,
    /// The ball stopped being empty, but no other element touches it.
    NoToucher,
    /// `r` reached 0 with no vertex within reach.
    ZeroRadiusAwayFromVertex,
    /// Read back from a report that does not say.
    #[default]
    Other,
}

impl DegenerateOpen {
    /// The name the report counts it under.
    pub fn kind(&self) -> &'static str {
        match self {
            DegenerateOpen::NoDirection => "no_direction",
            DegenerateOpen::BallBudget => "ball_budget",
            DegenerateOpen::HandoverBudget => "handover_budget",
            DegenerateOpen::TurnsEveryStep => "turns_every_step",
            DegenerateOpen::CorrectorFailed => "corrector_failed",
            DegenerateOpen::TouchPointsMeet => "touch_points_meet",
            DegenerateOpen::SheetOpens => "sheet_opens",
            DegenerateOpen::NoBoundary => "no_boundary",
            DegenerateOpen::LeftFace => "left_face",
            DegenerateOpen::NoToucher => "no_toucher",
            DegenerateOpen::ZeroRadiusAwayFromVertex => "zero_radius_away_from_vertex",
            DegenerateOpen::Other => "other",
        }
    }
}

/// A skeletal edge: a free edge of a sheet, where the sheet ends because the two touch points
/// of its balls have met. The tracer finds them where a seam ends with two touch points on
/// one part of the boundary (faces and the reflex edges joining them) met at a vertex of it:
/// the balls touching only that vertex, centres on the straight line from it through the
/// seam's last centre, `r` from that ball's down to 0 at the vertex (each inside the last, so
/// each empty). The sheet of those two elements ends along it. And where a rim's sheet
/// narrows to nothing at the rim's vertex (its two faces tangent there, two rounds meeting in
/// a mitre; or the rim over a round that ends against a wall), it ends along the same kind of
/// line, the balls tangent to the boundary at the vertex, from the largest of them that is
/// empty (or the one on a degenerate curve below it) down to the vertex: a free edge, with
/// no `starts`.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SkeletalEdge {
    pub id: usize,
    /// Index of the solid in the model.
    pub solid: usize,
    /// The seam ends it starts from: `[seam, end]` (end 0 or 1), one ball (two seams meet
    /// there where the ball pinches two sheets).
    pub starts: Vec<[usize; 2]>,
    /// The two elements whose touch points meet at `vertex`.
    pub segments: [Element; 2],
    /// The vertex it ends at, `r = 0`.
    pub vertex: usize,
    /// A free edge where a rim's sheet ends (no seam starts it): the degenerate curves its
    /// first ball lies on, `[degenerate index, k]`: at that curve's ball `k` or between its
    /// balls `k` and `k + 1` (see [`ball_on_polyline`]). Empty for an edge started by seams,
    /// and for one whose first ball is on nothing known (its sheet's boundary is then open
    /// there).
    #[serde(default)]
    pub meets: Vec<[usize; 2]>,
    /// Balls `[x, y, z, r]` from the seam's end to the vertex.
    #[serde(deserialize_with = "nullable::balls")]
    pub balls: Vec<[f64; 4]>,
}

/// Where ball `(c, r)` lies on the polyline of `balls` `[x, y, z, r]` (centre and radius
/// within `near` of a point of one of its segments, or of its one ball): the index of the
/// ball starting that segment (the last ball's own index where it is that ball).
pub fn ball_on_polyline(balls: &[[f64; 4]], c: DVec3, r: f64, near: f64) -> Option<usize> {
    let at = |b: &[f64; 4]| (DVec3::new(b[0], b[1], b[2]), b[3]);
    let close = |(p, s): (DVec3, f64)| p.distance(c) <= near && (s - r).abs() <= near;
    if let Some(k) = balls.iter().position(|b| close(at(b))) {
        return Some(k);
    }
    balls.windows(2).position(|w| {
        let ((p, rp), (q, rq)) = (at(&w[0]), at(&w[1]));
        let t = along_chord(c, p, q);
        close((p.lerp(q, t), rp + t * (rq - rp)))
    })
}

/// Where on the segment `[a, b]` the point nearest `p` is: its parameter in `[0, 1]` (0 for a
/// segment of no length).
pub(crate) fn along_chord(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Counters of a trace.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct TraceStats {
    pub points: usize,
    pub newton_iterations: usize,
    /// Steps retried at half the length (corrector failed or the seam turned too much).
    pub corrector_failures: usize,
    /// Largest `‖F‖∞` over the output points (mm).
    pub worst_residual: f64,
    /// Vertices where more than three faces meet, not started from (non-generic starts).
    pub skipped_vertices: Vec<usize>,
    /// Seeds that did not refine to a valid seam point, or lay on a seam already traced.
    pub skipped_seeds: usize,
    /// Seams traced a second time from their other end, and dropped.
    pub duplicate_seams: usize,
    /// Seams traced in two halves that stopped at one place from both sides (a crossing the
    /// file's gap or tilt keeps either half from passing), joined into one.
    pub joined_seams: usize,
    /// Seams whose every ball touches more than three elements (non-generic seams).
    pub non_generic_seams: usize,
}

/// The traced medial axis of a model (every solid's).
#[derive(Clone, Debug, serde::Serialize)]
pub struct MedialAxis {
    pub seams: Vec<Seam>,
    pub junctions: Vec<Junction>,
    /// Degenerate parts of the medial axis met while seeding: balls touching a face along a
    /// curve or all over, whose centres form a curve or a point instead of a sheet.
    pub degenerate: Vec<Degenerate>,
    /// The sheets' free edges found so far (those at vertices).
    pub skeletal_edges: Vec<SkeletalEdge>,
    pub stats: TraceStats,
}

impl MedialAxis {
    /// Open seam ends counted by [`OpenReason::kind`].
    pub fn open_ends_by_reason(&self) -> std::collections::BTreeMap<&'static str, usize> {
        let mut counts = std::collections::BTreeMap::new();
        for s in &self.seams {
            for e in &s.ends {
                if let SeamEnd::Open(why) = e {
                    *counts.entry(why.kind()).or_insert(0) += 1;
                }
            }
        }
        counts
    }

    /// Open degenerate-curve ends counted by [`DegenerateOpen::kind`].
    pub fn degenerate_open_ends_by_reason(
        &self,
    ) -> std::collections::BTreeMap<&'static str, usize> {
        let mut counts = std::collections::BTreeMap::new();
        for d in &self.degenerate {
            for e in &d.ends {
                if let DegenerateEnd::Open { cause, .. } = e {
                    *counts.entry(cause.kind()).or_insert(0) += 1;
                }
            }
        }
        counts
    }
}

/// Reading numbers back from a report, where serde_json writes a NaN as `null`: a `null`
/// reads as NaN again (so that verification fails on it instead of the reading).
mod nullable {
    use serde::{Deserialize, Deserializer};

    /// A number, or an array or vector of them, read with `null` as NaN.
    pub(super) struct N<T>(pub(super) T);

    impl<'de> Deserialize<'de> for N<f64> {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            Ok(N(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN)))
        }
    }

    macro_rules! arrays {
        ($($k:literal)*) => {$(
            impl<'de, T> Deserialize<'de> for N<[T; $k]>
            where
                N<T>: Deserialize<'de>,
            {
                fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                    let a = <[N<T>; $k]>::deserialize(d)?;
                    Ok(N(a.map(|n| n.0)))
                }
            }
        )*};
    }
    arrays!(2 3 4);

    impl<'de, T> Deserialize<'de> for N<Vec<T>>
    where
        N<T>: Deserialize<'de>,
    {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let v = Vec::<N<T>>::deserialize(d)?;
            Ok(N(v.into_iter().map(|n| n.0).collect()))
        }
    }

    macro_rules! readers {
        ($($name:ident: $t:ty),*) => {$(
            /// For `#[serde(deserialize_with = ...)]` on a field of this type.
            pub(super) fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<$t, D::Error> {
                N::<$t>::deserialize(d).map(|n| n.0)
            }
        )*};
    }
    readers!(
        number: f64,
        point: [f64; 3],
        ball: [f64; 4],
        points: Vec<[f64; 3]>,
        balls: Vec<[f64; 4]>,
        pairs: Vec<[[f64; 3]; 2]>
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Open degenerate ends are counted by cause; an end read back from a report written
    /// before causes were recorded counts as `other`, and a cause survives the round trip.
    #[test]
    fn degenerate_open_ends_are_counted_by_cause() {
        let old: DegenerateEnd =
            serde_json::from_str(r#"{"kind": "open", "reason": "made up"}"#).unwrap();
        let left = DegenerateEnd::open(DegenerateOpen::LeftFace, "a touch point left F3");
        let back: DegenerateEnd =
            serde_json::from_str(&serde_json::to_string(&left).unwrap()).unwrap();
        assert_eq!(back, left);
        let curve = |ends: Vec<DegenerateEnd>| Degenerate {
            solid: 0,
            kind: DegenerateKind::Curve,
            segments: vec![Element::Face(0), Element::Face(0)],
            balls: vec![],
            touch: vec![],
            ends,
            around: false,
        };
        let mat = MedialAxis {
            seams: vec![],
            junctions: vec![],
            degenerate: vec![
                curve(vec![left.clone(), left]),
                curve(vec![old, DegenerateEnd::Closed]),
            ],
            skeletal_edges: vec![],
            stats: TraceStats::default(),
        };
        let counts: Vec<(&str, usize)> = mat.degenerate_open_ends_by_reason().into_iter().collect();
        assert_eq!(counts, [("left_face", 2), ("other", 1)]);
    }
}
