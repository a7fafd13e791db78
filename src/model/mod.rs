//! Our own B-rep model: solids → shells → faces → loops → oriented edges → vertices.
//!
//! Geometry is truck's exact geometry (`Surface`, `Curve3D`), already converted to
//! millimetres and placed by any assembly transform, so nothing downstream needs to know about
//! units or placements. Topology is ours, because truck's `Shell`/`Face` cannot represent
//! periodic faces and loses STEP ids (`docs/truck.md`).
//!
//! Conventions:
//! - Every entity keeps the id it has in the file (`source_id`): the STEP instance id
//!   (`#123`), or the IGES directory-entry number.
//! - Faces, edges and vertices are numbered in the order the file defines their entities.
//! - A face's outward normal (pointing **out of the material**) is
//!   `sign · (Su × Sv) / ‖Su × Sv‖` with `sign` = [`Face::sign`]; the sign folds in the
//!   surface's `same_sense`, an `ORIENTED_FACE`, and a void shell's orientation.
//! - An edge's curve runs from `vertices[0]` to `vertices[1]` over `range`.

mod element;
pub mod tolerances;
pub mod warnings;

pub use element::Element;
use glam::DVec3;
pub use tolerances::Tolerances;
pub use truck_stepio::r#in::alias::{Curve3D, Surface};
pub use warnings::{ReadWarning, Warnings};

/// What the model was read from.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SourceInfo {
    /// The file, as given.
    pub path: String,
    /// `"step"` or `"iges"`.
    pub format: String,
    /// The length unit the file declares, as named there (`"mm"`, `"cm"`, `"m"`, `"inch"`, …).
    pub file_unit: String,
    /// Millimetres per file unit; every coordinate in the model has been multiplied by it.
    pub mm_per_unit: f64,
    /// What the reader repaired or ignored (empty for a clean file).
    pub warnings: Vec<ReadWarning>,
}

/// A whole part: one or more solids.
#[derive(Clone, Debug)]
pub struct Model {
    pub source: SourceInfo,
    pub solids: Vec<Solid>,
    pub shells: Vec<Shell>,
    pub faces: Vec<Face>,
    pub edges: Vec<Edge>,
    pub vertices: Vec<Vertex>,
    /// Axis-aligned bounding box `(min, max)`, computed once on reading (see
    /// [`crate::geom::model_bounding_box`]).
    pub bbox: (DVec3, DVec3),
}

/// A solid: its outer shell first, then its void shells.
#[derive(Clone, Debug)]
pub struct Solid {
    pub source_id: u64,
    pub name: String,
    /// Where an assembly places it: the products from the root down, `/`-separated.
    pub instance: Option<String>,
    pub shells: Vec<usize>,
}

/// A closed shell.
#[derive(Clone, Debug)]
pub struct Shell {
    pub source_id: u64,
    pub solid: usize,
    /// True for the inner boundary of a void (`BREP_WITH_VOIDS`).
    pub is_void: bool,
    pub faces: Vec<usize>,
}

/// The UV rectangle a face's trimming loops cover, with periodic unwrapping resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvDomain {
    pub u: (f64, f64),
    pub v: (f64, f64),
    /// Period of the surface in u, if it is periodic (cylinder, cone, sphere, torus, revolution).
    pub u_period: Option<f64>,
    /// Period of the surface in v, if it is periodic (torus).
    pub v_period: Option<f64>,
}

impl UvDomain {
    /// True when `uv` lies in the rectangle (an angle taken modulo its period), to a
    /// relative 1e-9 of the rectangle's size. A point of the surface outside it is not on
    /// the face; one inside may still be outside the face's trim.
    pub fn contains(&self, uv: (f64, f64)) -> bool {
        let within = |x: f64, r: (f64, f64), period: Option<f64>| {
            let tol = 1e-9 * (r.1 - r.0).abs().max(1.0);
            match period {
                Some(p) if p > 0.0 => {
                    let x = r.0 + (x - r.0).rem_euclid(p);
                    x <= r.1 + tol || x - p >= r.0 - tol
                }
                _ => x >= r.0 - tol && x <= r.1 + tol,
            }
        };
        within(uv.0, self.u, self.u_period) && within(uv.1, self.v, self.v_period)
    }
}

/// A face: an exact surface trimmed by loops.
#[derive(Clone, Debug)]
pub struct Face {
    pub source_id: u64,
    pub shell: usize,
    pub surface: Surface,
    /// `+1.0` when `Su × Sv` points out of the material, `-1.0` otherwise.
    pub sign: f64,
    /// The `ADVANCED_FACE`'s `same_sense`: the loops have the face on their left when seen
    /// against `Su × Sv` if true, against `−(Su × Sv)` if false (orientation of the loops,
    /// not of the material; that is `sign`).
    pub same_sense: bool,
    pub loops: Vec<Loop>,
    /// Index into `loops` of the outer loop, when the face has one (a full sphere has none).
    pub outer: Option<usize>,
    pub domain: UvDomain,
}

/// A trimming loop: a cycle of oriented edges, or a single vertex (`VERTEX_LOOP`, e.g. a pole).
#[derive(Clone, Debug)]
pub struct Loop {
    pub source_id: u64,
    pub edges: Vec<OrientedEdge>,
    /// Set for a `VERTEX_LOOP`; `edges` is then empty.
    pub vertex: Option<usize>,
    /// The loop as a closed polygon in the face's (unwrapped) UV space, densely sampled from
    /// the exact edge curves; used for inside/outside tests of the trimmed face.
    pub uv: Vec<glam::DVec2>,
    /// How many points of `uv` each edge has, in the order of `edges`: sample `k` of `n` is
    /// at `t0 + (t1 − t0)·k/n` in the loop's direction, and each edge's first sample is its
    /// start. Empty for a vertex loop, and before the reader has built `uv`.
    pub uv_counts: Vec<usize>,
    /// The polygon the inside tests walk, when it is not `uv` itself (empty then): `uv` with
    /// each pole given two points. A pole is one point of the surface but a segment of its
    /// UV domain; the loop reaches it along one meridian and leaves along another, and with
    /// one point there one of the two chords would cut across the face (see
    /// [`crate::ingest::domain::pole_outline`]).
    pub outline: Vec<glam::DVec2>,
    /// The largest distance (mm) of the loop's edge curves and vertices from the face's
    /// surface, as the reader measured it while sampling `uv` (0 for a vertex loop on it):
    /// where exporters write edges that follow one face and not the other, the face's
    /// boundary is defined only to this.
    pub gap_mm: f64,
}

impl Face {
    /// The largest distance (mm) of the face's edges and vertices from its surface
    /// ([`Loop::gap_mm`] over its loops).
    pub fn gap_mm(&self) -> f64 {
        self.loops.iter().map(|l| l.gap_mm).fold(0.0, f64::max)
    }
}

impl Loop {
    /// The closed polygon that bounds the loop's region in UV: [`Loop::outline`] when the
    /// reader made one, else [`Loop::uv`].
    pub fn outline(&self) -> &[glam::DVec2] {
        if self.outline.is_empty() {
            &self.uv
        } else {
            &self.outline
        }
    }

    /// True when `uv` is laid out on the edges as `uv_counts` says (the reader has built it).
    pub fn uv_counts_match(&self) -> bool {
        self.uv_counts.len() == self.edges.len()
            && self.uv_counts.iter().sum::<usize>() == self.uv.len()
    }
}

/// An edge used in a loop, in the edge's direction (`forward`) or against it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OrientedEdge {
    pub edge: usize,
    pub forward: bool,
}

/// An edge: an exact 3D curve between two vertices.
#[derive(Clone, Debug)]
pub struct Edge {
    pub source_id: u64,
    pub curve: Curve3D,
    /// Parameter interval of `curve` from `vertices[0]` to `vertices[1]`.
    pub range: (f64, f64),
    pub vertices: [usize; 2],
    /// Faces using the edge, in order of first use (two for a manifold edge; a seam edge of a
    /// periodic face lists that face twice).
    pub faces: Vec<usize>,
}

/// A vertex.
#[derive(Clone, Copy, Debug)]
pub struct Vertex {
    pub source_id: u64,
    pub point: DVec3,
}

impl Edge {
    /// True when both ends are the same vertex (a full circle, a seam of a closed surface).
    pub fn is_closed(&self) -> bool {
        self.vertices[0] == self.vertices[1]
    }

    /// True when the edge is a seam: the same face on both sides.
    pub fn is_seam(&self) -> bool {
        self.faces.len() == 2 && self.faces[0] == self.faces[1]
    }
}

impl Model {
    /// Face `f` and the faces sharing an edge with it (none but `f` when the model has no
    /// face `f`).
    pub fn faces_next_to(&self, f: usize) -> Vec<usize> {
        let mut out = vec![f];
        for oe in self
            .faces
            .get(f)
            .iter()
            .flat_map(|face| &face.loops)
            .flat_map(|l| &l.edges)
        {
            for &g in self.edges.get(oe.edge).map_or(&[][..], |e| &e.faces[..]) {
                if !out.contains(&g) {
                    out.push(g);
                }
            }
        }
        out
    }

    /// Axis-aligned bounding box `(min, max)` of the model, from vertices and sampled edges
    /// and faces (exact for planar parts, a close inner estimate for curved ones).
    pub fn bounding_box(&self) -> (DVec3, DVec3) {
        self.bbox
    }

    /// Length of the bounding-box diagonal: the scale all default tolerances derive from.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        (hi - lo).length()
    }

    /// The solid face `f` bounds.
    pub fn solid_of_face(&self, f: usize) -> usize {
        self.shells[self.faces[f].shell].solid
    }
}
