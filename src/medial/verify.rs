//! Self-verification of a traced medial axis against the definition, and the check of its
//! topology (`docs/design.md`, verification).
//!
//! For every seam point and junction: the nearest point of its solid's boundary of the centre (exact
//! trimmed-face distance through the boundary BVH) is at distance `r` — nothing is closer, so
//! the ball is maximal in the global sense — and every reported touch point lies on the
//! boundary at distance `r` from the centre. The figures are the worst absolute errors (mm).

use super::axis::{MedialAxis, SeamEnd};
use super::sheets::{Sheets, SolidEuler};
use crate::geom::Boundary;
use crate::model::Model;
use glam::DVec3;

/// Worst errors over a traced medial axis.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Verification {
    /// Balls checked (seam points and junctions).
    pub balls: usize,
    /// Worst `|d(B, ∂Ω) − r|`.
    pub worst_distance_error: f64,
    /// Worst `|‖t − B‖ − r|` over touch points.
    pub worst_touch_error: f64,
    /// Worst distance of a touch point from the boundary.
    pub worst_touch_off_boundary: f64,
    /// Where the worst of the three errors is: `seam S point K` or `junction J`.
    pub worst_at: Option<String>,
}

impl Verification {
    /// The largest of the three errors.
    pub fn worst(&self) -> f64 {
        self.worst_distance_error
            .max(self.worst_touch_error)
            .max(self.worst_touch_off_boundary)
    }
}

/// Checks every seam point and junction of `mat` against `model`'s boundary.
pub fn verify(model: &Model, boundary: &Boundary, mat: &MedialAxis) -> Verification {
    let mut v = Verification::default();
    // Distance to the boundary of one solid (each solid has its own medial axis).
    let nearest = |p: DVec3, solid: usize| {
        boundary
            .nearest_face_where(model, p, |f| model.solid_of_face(f) == solid)
            .map_or(f64::INFINITY, |(_, h)| h.distance)
    };
    let mut ball =
        |at: &dyn Fn() -> String, solid: usize, centre: DVec3, r: f64, touch: &[[f64; 3]]| {
            v.balls += 1;
            let before = v.worst();
            let d = nearest(centre, solid);
            v.worst_distance_error = v.worst_distance_error.max((d - r).abs());
            for t in touch {
                let t = DVec3::from_array(*t);
                v.worst_touch_error = v.worst_touch_error.max((t.distance(centre) - r).abs());
                let off = nearest(t, solid);
                v.worst_touch_off_boundary = v.worst_touch_off_boundary.max(off);
            }
            if v.worst() > before {
                v.worst_at = Some(at());
            }
        };
    for s in &mat.seams {
        for (k, p) in s.points.iter().enumerate() {
            ball(
                &|| format!("seam {} point {k}", s.id),
                s.solid,
                DVec3::new(p.point[0], p.point[1], p.point[2]),
                p.point[3],
                &p.touch,
            );
        }
    }
    for (i, d) in mat.degenerate.iter().enumerate() {
        for (k, b) in d.balls.iter().enumerate() {
            ball(
                &|| format!("degenerate {i} ball {k}"),
                d.solid,
                DVec3::new(b[0], b[1], b[2]),
                b[3],
                &[],
            );
        }
    }
    for j in &mat.junctions {
        ball(
            &|| format!("junction {}", j.id),
            j.solid,
            DVec3::from_array(j.point),
            j.radius,
            &j.touch,
        );
    }
    v
}

/// Consistency of the seam–junction graph, and the Euler characteristic of each solid next to
/// its medial axis's (which must be equal: the medial axis is a deformation retract of the
/// solid).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Topology {
    /// Junctions plus convex vertices where seams end.
    pub graph_nodes: usize,
    /// Seams (a closed seam counts as one edge with one node of its own).
    pub graph_edges: usize,
    /// Seam ends that are not a vertex, a junction, a closed loop or a curvature limit.
    pub open_ends: usize,
    /// Generic junctions (4 segments) that do not have exactly 4 seam ends, and seam ends
    /// naming a junction that does not exist: both would be tracer bugs.
    pub inconsistencies: Vec<String>,
    /// Per solid: `V − E + F` of the B-rep and `V − E + Σ χ(sheet)` of its medial axis.
    pub euler: Vec<SolidEuler>,
    /// Sheet-boundary arc ends that could not be paired at a node (tracer gaps).
    pub unpaired: Vec<String>,
}

/// Checks the seam–junction graph of `mat`, and takes the Euler characteristics and the
/// unpaired sheet-boundary ends from its `sheets`.
pub fn check_topology(mat: &MedialAxis, sheets: &Sheets) -> Topology {
    let mut ends_at = vec![0usize; mat.junctions.len()];
    let mut vertices = std::collections::BTreeSet::new();
    let mut inconsistencies = vec![];
    let mut open_ends = 0;
    let mut closed = 0;
    for s in &mat.seams {
        for e in &s.ends {
            match e {
                SeamEnd::Junction(j) if *j < ends_at.len() => ends_at[*j] += 1,
                SeamEnd::Junction(j) => {
                    inconsistencies.push(format!("seam {} ends at missing junction {j}", s.id))
                }
                SeamEnd::Vertex(v) => {
                    vertices.insert(*v);
                }
                SeamEnd::Open(_) => open_ends += 1,
                SeamEnd::Closed => closed += 1,
                SeamEnd::CurvatureLimit { .. } => {}
            }
        }
    }
    for (j, n) in ends_at.iter().enumerate() {
        if mat.junctions[j].segments.len() == 4 && *n != 4 {
            inconsistencies.push(format!("junction {j} (4 segments) has {n} seam ends"));
        }
    }
    Topology {
        graph_nodes: mat.junctions.len() + vertices.len() + closed / 2,
        graph_edges: mat.seams.len(),
        open_ends,
        inconsistencies,
        euler: sheets.solids.clone(),
        unpaired: sheets.unpaired.clone(),
    }
}
