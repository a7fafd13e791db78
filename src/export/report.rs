//! The JSON report, schema `matrace.report/1` (`<stem>.mat.json`).
//!
//! This module builds the `input` and `model` objects (what `matrace inspect --json` prints);
//! the `mat` and `stats` objects are added by the tracer. Everything is plain serde data so
//! the binary only serialises it.

use crate::classify::{Classification, EdgeKind, VertexKind};
use crate::model::Model;
use serde::Serialize;
use std::collections::BTreeMap;

/// The schema name written into every report.
pub const SCHEMA: &str = "matrace.report/1";

/// A report with the parts available so far.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub schema: &'static str,
    pub input: InputReport,
    pub model: ModelReport,
}

/// A report with the traced medial axis: `input`, `options`, `model`, `mat`, `stats`,
/// `outputs`.
#[derive(Clone, Debug, Serialize)]
pub struct TraceReport {
    pub schema: &'static str,
    pub input: InputReport,
    pub options: OptionsReport,
    pub model: ModelReport,
    pub mat: MatReport,
    pub stats: StatsReport,
    /// The files written beside the report (names only, in the same folder).
    pub outputs: Vec<String>,
}

/// The options and tolerances a trace ran with.
#[derive(Clone, Debug, Serialize)]
pub struct OptionsReport {
    /// Output accuracy (mm): every ball is medial to within it.
    pub accuracy: f64,
    /// Where the accuracy came from: `"1e-6 x diagonal"` (the default) or `"--tol"`.
    pub accuracy_from: String,
    /// The part's bounding-box diagonal (mm), the scale of every default tolerance.
    pub diagonal: f64,
    /// The accuracy (mm) the medial axis was computed to: `accuracy`, or the default (1e-6 ×
    /// the diagonal) where that is finer.
    pub trace_accuracy: f64,
    /// Newton residual target (mm), 1e-3 × the trace accuracy.
    pub solver_tolerance: f64,
    /// Faces meeting at less than this angle (degrees) count as tangent.
    pub angle_tol_deg: f64,
    /// Largest distance (mm) from a traced point to its seam's B-spline in `<stem>.mat.step`.
    pub fit_tolerance: f64,
    /// Grid points for the sheet mesh (0: no mesh written).
    pub mesh_samples: usize,
    /// Whether every ball was checked against the definition.
    pub verify: bool,
}

/// Wall-clock seconds per stage.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Timings {
    pub read: f64,
    pub classify: f64,
    pub trace: f64,
    pub sheets: f64,
    /// Fitting the seams and writing `<stem>.mat.step`.
    pub fit: f64,
    pub mesh: f64,
    pub picture: f64,
    pub verify: f64,
    pub total: f64,
}

/// The `mat` object: seams, junctions, sheets (by their boundaries), degenerate pieces,
/// skeletal edges and the topology check.
#[derive(Clone, Debug, Serialize)]
pub struct MatReport {
    pub seams: Vec<crate::medial::Seam>,
    pub junctions: Vec<crate::medial::Junction>,
    pub sheets: Vec<crate::medial::Sheet>,
    pub degenerate: Vec<crate::medial::Degenerate>,
    pub skeletal_edges: Vec<crate::medial::SkeletalEdge>,
    pub topology: crate::medial::Topology,
    /// The B-spline fits of the seams written to `<stem>.mat.step`, when made.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<crate::fit::FitReport>,
}

/// The `stats` object.
#[derive(Clone, Debug, Serialize)]
pub struct StatsReport {
    /// Total wall-clock seconds (read to last output), as `timings.total`.
    pub seconds: f64,
    pub timings: Timings,
    pub seams: usize,
    pub junctions: usize,
    pub sheets: usize,
    pub degenerate: usize,
    pub skeletal_edges: usize,
    pub open_ends: usize,
    /// Open seam ends by reason (`step_size_underflow`, …; see `OpenReason::kind`).
    pub open_ends_by_reason: BTreeMap<&'static str, usize>,
    /// Degenerate-curve ends not located (`mat.degenerate[].ends` of kind `open`).
    pub degenerate_open_ends: usize,
    /// The same by cause (`left_face`, …; see `DegenerateOpen::kind`).
    pub degenerate_open_ends_by_reason: BTreeMap<&'static str, usize>,
    /// Seams whose every ball touches more than three elements.
    pub non_generic_seams: usize,
    /// Seams traced in two halves that stopped one crossing apart (where the file's gap keeps
    /// a touch point from being handed on from either side), joined into one.
    pub joined_seams: usize,
    pub points: usize,
    /// Triangles in `<stem>.sheets.obj`.
    pub mesh_triangles: usize,
    /// Output accuracy used (mm).
    pub accuracy: f64,
    pub worst_residual: f64,
    pub newton_iterations: usize,
    pub corrector_failures: usize,
    /// How long the tracer took over each seam (ms), by seam id: where its time goes, and how
    /// evenly (a seam whose step collapses stands out).
    pub seam_trace_ms: Vec<f64>,
    pub skipped_vertices: Vec<usize>,
    /// Present when the trace was verified (`trace --verify`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verification: Option<crate::medial::Verification>,
}

impl TraceReport {
    /// The full report for a traced model, with its sheets. Timings, verification, the mesh
    /// size and the outputs are filled in by the caller as they happen.
    pub fn new(
        model: &Model,
        class: &Classification,
        mat: &crate::medial::MedialAxis,
        sheets: &crate::medial::Sheets,
        options: OptionsReport,
    ) -> TraceReport {
        let base = Report::new(model, class);
        let topology = crate::medial::verify::check_topology(mat, sheets);
        TraceReport {
            schema: SCHEMA,
            input: base.input,
            stats: StatsReport {
                seconds: 0.0,
                timings: Timings::default(),
                seams: mat.seams.len(),
                junctions: mat.junctions.len(),
                sheets: sheets.sheets.len(),
                degenerate: mat.degenerate.len(),
                skeletal_edges: mat.skeletal_edges.len(),
                open_ends: topology.open_ends,
                open_ends_by_reason: mat.open_ends_by_reason(),
                degenerate_open_ends: mat.degenerate_open_ends_by_reason().values().sum(),
                degenerate_open_ends_by_reason: mat.degenerate_open_ends_by_reason(),
                non_generic_seams: mat.stats.non_generic_seams,
                joined_seams: mat.stats.joined_seams,
                points: mat.stats.points,
                mesh_triangles: 0,
                accuracy: options.accuracy,
                worst_residual: mat.stats.worst_residual,
                newton_iterations: mat.stats.newton_iterations,
                corrector_failures: mat.stats.corrector_failures,
                seam_trace_ms: mat.seams.iter().map(|s| 1e3 * s.trace_seconds).collect(),
                skipped_vertices: mat.stats.skipped_vertices.clone(),
                verification: None,
            },
            options,
            model: base.model,
            mat: MatReport {
                seams: mat.seams.clone(),
                junctions: mat.junctions.clone(),
                sheets: sheets.sheets.clone(),
                degenerate: mat.degenerate.clone(),
                skeletal_edges: mat.skeletal_edges.clone(),
                topology,
                fit: None,
            },
            outputs: vec![],
        }
    }
}

/// What was read.
#[derive(Clone, Debug, Serialize)]
pub struct InputReport {
    pub path: String,
    pub format: String,
    /// Unit of every length in the report (always millimetres).
    pub length_unit: &'static str,
    /// The unit the file declares.
    pub file_unit: String,
    /// Millimetres per file unit (the factor applied on reading).
    pub mm_per_unit: f64,
    /// What the reader repaired or ignored, grouped (empty for a clean file).
    pub warnings: Vec<crate::model::ReadWarning>,
}

/// The B-rep and its classification.
#[derive(Clone, Debug, Serialize)]
pub struct ModelReport {
    pub solids: usize,
    /// Where an assembly places each solid (only for assemblies).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub instances: Vec<SolidInstance>,
    pub shells: usize,
    /// `[[xmin, ymin, zmin], [xmax, ymax, zmax]]`, millimetres.
    pub bbox: [[f64; 3]; 2],
    pub diagonal: f64,
    /// Each solid's volume in mm³ by the divergence theorem on its faces
    /// ([`crate::geom::volume`]); `null` where a face's region cannot be integrated.
    pub volumes: Vec<Option<f64>>,
    /// Counts by kind: `surfaces`, `edge_kinds`, `vertex_kinds`.
    pub counts: Counts,
    pub faces: Vec<FaceReport>,
    pub edges: Vec<EdgeReport>,
    pub vertices: Vec<VertexReport>,
}

/// One solid of an assembly: which brep it is and where the product structure places it.
#[derive(Clone, Debug, Serialize)]
pub struct SolidInstance {
    pub solid: usize,
    /// The `MANIFOLD_SOLID_BREP` / `BREP_WITH_VOIDS` (`step_id`).
    pub step_id: u64,
    pub name: String,
    /// The products from the root down, `/`-separated, each component with its
    /// `NEXT_ASSEMBLY_USAGE_OCCURRENCE`'s id.
    pub path: String,
}

/// Counts by kind (keys sorted, so reports are stable).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Counts {
    pub faces: usize,
    pub edges: usize,
    pub vertices: usize,
    pub surfaces: BTreeMap<&'static str, usize>,
    pub edge_kinds: BTreeMap<&'static str, usize>,
    pub vertex_kinds: BTreeMap<&'static str, usize>,
}

#[derive(Clone, Debug, Serialize)]
pub struct FaceReport {
    pub id: usize,
    /// The id of the entity in the file: `#123` in STEP, the DE number in IGES.
    #[serde(rename = "step_id")]
    pub source_id: u64,
    pub surface: &'static str,
    pub shell: usize,
    /// Loops bounding the face (vertex loops included).
    pub loops: usize,
    /// True when `Su × Sv` points into the material (the outward normal is its negative).
    pub reversed: bool,
}

#[derive(Clone, Debug, Serialize)]
pub struct EdgeReport {
    pub id: usize,
    /// The id of the entity in the file: `#123` in STEP, the DE number in IGES.
    #[serde(rename = "step_id")]
    pub source_id: u64,
    pub curve: &'static str,
    pub vertices: [usize; 2],
    pub faces: Vec<usize>,
    pub kind: EdgeKind,
    /// Smallest and largest interior dihedral angle along the edge, degrees.
    pub angle_deg: [f64; 2],
}

#[derive(Clone, Debug, Serialize)]
pub struct VertexReport {
    pub id: usize,
    /// The id of the entity in the file: `#123` in STEP, the DE number in IGES.
    #[serde(rename = "step_id")]
    pub source_id: u64,
    pub point: [f64; 3],
    pub kind: VertexKind,
}

/// The kind of an edge curve, as the report names it.
pub fn curve_kind(curve: &crate::model::Curve3D) -> &'static str {
    use crate::model::Curve3D as C;
    use truck_stepio::r#in::alias::Conic3D;
    match curve {
        C::Line(_) => "line",
        C::Polyline(_) => "polyline",
        C::Conic(Conic3D::Ellipse(_)) => "ellipse",
        C::Conic(Conic3D::Hyperbola(_)) => "hyperbola",
        C::Conic(Conic3D::Parabola(_)) => "parabola",
        C::BSplineCurve(_) => "bspline",
        C::NurbsCurve(_) => "nurbs",
        C::PCurve(_) => "pcurve",
    }
}

impl Report {
    /// The `input` and `model` parts of the report for a model and its classification.
    pub fn new(model: &Model, class: &Classification) -> Report {
        let (lo, hi) = model.bounding_box();
        let mut counts = Counts {
            faces: model.faces.len(),
            edges: model.edges.len(),
            vertices: model.vertices.len(),
            ..Counts::default()
        };
        let faces = model
            .faces
            .iter()
            .enumerate()
            .map(|(id, f)| {
                let surface = crate::geom::surface_kind(&f.surface);
                *counts.surfaces.entry(surface).or_default() += 1;
                FaceReport {
                    id,
                    source_id: f.source_id,
                    surface,
                    shell: f.shell,
                    loops: f.loops.len(),
                    reversed: f.sign < 0.0,
                }
            })
            .collect();
        for k in [EdgeKind::Convex, EdgeKind::Reflex, EdgeKind::Smooth] {
            counts.edge_kinds.insert(k.name(), 0);
        }
        for k in [
            VertexKind::Convex,
            VertexKind::Reflex,
            VertexKind::Mixed,
            VertexKind::Crease,
            VertexKind::Smooth,
        ] {
            counts.vertex_kinds.insert(k.name(), 0);
        }
        let edges = model
            .edges
            .iter()
            .zip(&class.edges)
            .enumerate()
            .map(|(id, (e, c))| {
                *counts.edge_kinds.entry(c.kind.name()).or_default() += 1;
                EdgeReport {
                    id,
                    source_id: e.source_id,
                    curve: curve_kind(&e.curve),
                    vertices: e.vertices,
                    faces: e.faces.clone(),
                    kind: c.kind,
                    angle_deg: [c.angle_range_deg.0, c.angle_range_deg.1],
                }
            })
            .collect();
        let vertices = model
            .vertices
            .iter()
            .zip(&class.vertices)
            .enumerate()
            .map(|(id, (v, k))| {
                *counts.vertex_kinds.entry(k.name()).or_default() += 1;
                VertexReport {
                    id,
                    source_id: v.source_id,
                    point: v.point.to_array(),
                    kind: *k,
                }
            })
            .collect();
        Report {
            schema: SCHEMA,
            input: InputReport {
                path: model.source.path.clone(),
                format: model.source.format.clone(),
                length_unit: "mm",
                file_unit: model.source.file_unit.clone(),
                mm_per_unit: model.source.mm_per_unit,
                warnings: model.source.warnings.clone(),
            },
            model: ModelReport {
                solids: model.solids.len(),
                instances: model
                    .solids
                    .iter()
                    .enumerate()
                    .filter_map(|(k, s)| {
                        Some(SolidInstance {
                            solid: k,
                            step_id: s.source_id,
                            name: s.name.clone(),
                            path: s.instance.clone()?,
                        })
                    })
                    .collect(),
                shells: model.shells.len(),
                bbox: [lo.to_array(), hi.to_array()],
                diagonal: (hi - lo).length(),
                volumes: crate::geom::solid_volumes(model),
                counts,
                faces,
                edges,
                vertices,
            },
        }
    }
}

/// A human-readable table of the `input` and `model` parts (what `matrace inspect` prints).
pub fn render_table(r: &Report) -> String {
    use std::fmt::Write;
    let m = &r.model;
    let mut s = String::new();
    let kinds = |map: &BTreeMap<&'static str, usize>| {
        map.iter()
            .filter(|(_, n)| **n > 0)
            .map(|(k, n)| format!("{n} {k}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(s, "{}", r.input.path);
    let _ = writeln!(
        s,
        "  format {}  file unit {} ({} mm)  lengths below in mm",
        r.input.format, r.input.file_unit, r.input.mm_per_unit
    );
    let _ = writeln!(
        s,
        "  solids {}  shells {}  faces {}  edges {}  vertices {}",
        m.solids, m.shells, m.counts.faces, m.counts.edges, m.counts.vertices
    );
    let _ = writeln!(
        s,
        "  bbox [{:.4}, {:.4}, {:.4}] .. [{:.4}, {:.4}, {:.4}]  diagonal {:.4}",
        m.bbox[0][0],
        m.bbox[0][1],
        m.bbox[0][2],
        m.bbox[1][0],
        m.bbox[1][1],
        m.bbox[1][2],
        m.diagonal
    );
    let volumes: Vec<String> = m
        .volumes
        .iter()
        .map(|v| v.map_or("unknown".to_string(), |v| format!("{v:.4}")))
        .collect();
    let _ = writeln!(s, "  volume {} mm³ (by solid)", volumes.join(", "));
    for w in &r.input.warnings {
        let _ = writeln!(
            s,
            "  warning ({}): {}",
            w.kind,
            crate::model::warnings::summary_line(std::slice::from_ref(w))
        );
    }
    let _ = writeln!(s, "  surfaces: {}", kinds(&m.counts.surfaces));
    let _ = writeln!(s, "  edges:    {}", kinds(&m.counts.edge_kinds));
    let _ = writeln!(s, "  vertices: {}", kinds(&m.counts.vertex_kinds));
    let _ = writeln!(
        s,
        "\nFaces\n  {:>5} {:>8} {:<11} {:>5} {:>5} {:>8}",
        "id", "step", "surface", "shell", "loops", "normal"
    );
    for f in &m.faces {
        let _ = writeln!(
            s,
            "  {:>5} {:>8} {:<11} {:>5} {:>5} {:>8}",
            format!("F{}", f.id),
            format!("#{}", f.source_id),
            f.surface,
            f.shell,
            f.loops,
            if f.reversed { "-Su×Sv" } else { "+Su×Sv" }
        );
    }
    let _ = writeln!(
        s,
        "\nEdges\n  {:>5} {:>8} {:<9} {:>11} {:>13} {:<7} {:>17}",
        "id", "step", "curve", "vertices", "faces", "kind", "angle° min..max"
    );
    for e in &m.edges {
        let faces: Vec<String> = e.faces.iter().map(|f| format!("F{f}")).collect();
        let _ = writeln!(
            s,
            "  {:>5} {:>8} {:<9} {:>11} {:>13} {:<7} {:>8.2}..{:<8.2}",
            format!("E{}", e.id),
            format!("#{}", e.source_id),
            e.curve,
            format!("V{}-V{}", e.vertices[0], e.vertices[1]),
            faces.join(","),
            e.kind.name(),
            e.angle_deg[0],
            e.angle_deg[1]
        );
    }
    let _ = writeln!(
        s,
        "\nVertices\n  {:>5} {:>8} {:<7} point",
        "id", "step", "kind"
    );
    for v in &m.vertices {
        let _ = writeln!(
            s,
            "  {:>5} {:>8} {:<7} ({:.6}, {:.6}, {:.6})",
            format!("V{}", v.id),
            format!("#{}", v.source_id),
            v.kind.name(),
            v.point[0],
            v.point[1],
            v.point[2]
        );
    }
    s
}
