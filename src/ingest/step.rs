//! STEP (ISO 10303-21) ingestion into our [`Model`].
//!
//! The file is parsed into ruststep's AST by [`super::p21`] (points and directions kept
//! compact), patched where truck misreads it ([`super::records`]), put into truck's table
//! (the common records as holders built here, the rest through truck's reader), and then
//! walked by hand: `MANIFOLD_SOLID_BREP` / `BREP_WITH_VOIDS` →
//! `CLOSED_SHELL` / `ORIENTED_CLOSED_SHELL` → `ADVANCED_FACE` (or `ORIENTED_FACE`) →
//! `FACE_BOUND` → `EDGE_LOOP` / `VERTEX_LOOP` → `ORIENTED_EDGE` → `EDGE_CURVE` → `VERTEX_POINT`.
//! Only the geometry (surfaces, edge curves) is converted by truck, one entity at a time, so a
//! conversion that fails is an error naming that entity instead of a face that silently
//! disappears. Lengths are converted to millimetres and assembly placements applied to the
//! geometry itself.

use super::domain::{align_loops, face_domain, loop_uv};
use super::p21::{self, Item, PointKind};
use super::records::{self, as_bool, as_ref, as_refs, params, LengthUnit, Mat4, Records};
use crate::error::{Error, Result};
use crate::model::*;
use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::{FxHashMap as HashMap, FxHashSet};
use std::path::{Path, PathBuf};
use truck_geometry::prelude::Point3;
use truck_stepio::r#in::ruststep::ast::{EntityInstance, Name, Parameter, Record};
use truck_stepio::r#in::ruststep::tables::{IntoOwned, PlaceHolder};
use truck_stepio::r#in::{
    Axis2Placement3dHolder, CartesianPointHolder, CircleHolder, CylindricalSurfaceHolder,
    DirectionHolder, EdgeCurveHolder, LineHolder, PlaneHolder, SurfaceAnyHolder, Table,
    VectorHolder, VertexPointHolder,
};

/// Files larger than this are refused before parsing (the parser keeps the whole structure in
/// memory, several times the file size).
pub const MAX_FILE_BYTES: u64 = 512 * 1024 * 1024;

/// Reads STEP text already in memory; `path` is used in messages and the report.
pub fn read_model_from_bytes(path: &Path, bytes: &[u8]) -> Result<Model> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(model_err(path, "file is empty"));
    }
    let text = std::str::from_utf8(bytes).map_err(|e| Error::Syntax {
        path: path.into(),
        reason: format!("not text (invalid UTF-8 at byte {})", e.valid_up_to()),
    })?;
    let head = text.trim_start_matches('\u{feff}').trim_start();
    if !head.starts_with("ISO-10303-21") {
        return Err(Error::Syntax {
            path: path.into(),
            reason: "does not start with ISO-10303-21; (not a STEP file)".into(),
        });
    }
    if !text.contains("END-ISO-10303-21") {
        return Err(Error::Syntax {
            path: path.into(),
            reason: "no END-ISO-10303-21; (file truncated?)".into(),
        });
    }
    let mut exchange = p21::parse(text, MAX_NESTING).map_err(|e| Error::Syntax {
        path: path.into(),
        reason: e.to_string(),
    })?;
    if exchange.data.is_empty() {
        return Err(Error::Syntax {
            path: path.into(),
            reason: "no DATA section".into(),
        });
    }
    records::patch_for_truck(&mut exchange.data);
    let recs = Records::new(&exchange.data);
    if let Some((id, entity, reason)) = records::check_acyclic(&recs) {
        return Err(entity_err(path, id, entity, reason));
    }
    if let Some((id, entity, reason)) = records::check_bspline_degrees(&recs) {
        return Err(entity_err(path, id, entity, reason));
    }
    if let Some((id, entity, reason)) = records::check_knots(&recs) {
        return Err(entity_err(path, id, entity, reason));
    }
    let mut table = Table::default();
    let mut undecodable: HashMap<u64, String> = HashMap::default();
    let contexts = records::definitional_contexts(&recs);
    // What truck does not read it keeps as text, formatted with `Debug` (8 % of reading the
    // NIST parts, whose styling entities are a large part of the file), and the topology is
    // walked here: both are skipped, but for the contexts of definitional representations,
    // which truck looks up among its text records.
    let to_push: Vec<&Item> = exchange
        .data
        .iter()
        .flat_map(|s| &s.entities)
        .filter(|item| match item {
            Item::Instance(EntityInstance::Simple { id, record }) => {
                records::truck_converts(&record.name) || contexts.contains(id)
            }
            Item::Instance(EntityInstance::Complex { .. }) | Item::Point(_) => true,
        })
        .collect();
    reserve_table(&mut table, &to_push);
    for item in to_push {
        let inst = match item {
            Item::Point(p) => {
                push_point(&mut table, p);
                continue;
            }
            Item::Instance(EntityInstance::Simple { id, record })
                if push_direct(&mut table, *id, record) =>
            {
                continue;
            }
            Item::Instance(inst) => inst,
        };
        match guarded(|| table.push_instance(inst)) {
            Ok(Ok(())) => {}
            Ok(Err(e)) => {
                undecodable.insert(records::instance_id(inst), first_line(&e.to_string()));
            }
            Err(p) => {
                undecodable.insert(records::instance_id(inst), format!("reader panicked: {p}"));
            }
        }
    }
    cone_angles_in_radians(&mut table, &recs);
    Ingest {
        path: path.into(),
        recs: &recs,
        table: &table,
        undecodable: &undecodable,
        model: Model {
            source: SourceInfo {
                path: path.display().to_string(),
                format: "step".into(),
                file_unit: "mm".into(),
                mm_per_unit: 1.0,
            },
            solids: vec![],
            shells: vec![],
            faces: vec![],
            edges: vec![],
            vertices: vec![],
            bbox: (DVec3::ZERO, DVec3::ZERO),
        },
        edge_map: HashMap::default(),
        vertex_map: HashMap::default(),
    }
    .run()
}

/// Puts a compact point or direction into truck's table: the holder truck's reader makes of
/// its record (`push_instance`), without the record or the deserializer.
fn push_point(table: &mut Table, p: &p21::CompactPoint) {
    let (label, coords) = (p.label.clone(), p.coords().to_vec());
    match p.kind {
        PointKind::CartesianPoint => {
            let holder = CartesianPointHolder {
                label,
                coordinates: coords,
            };
            table.cartesian_point.insert(p.id, holder);
        }
        PointKind::Direction => {
            let holder = DirectionHolder {
                label,
                direction_ratios: coords,
            };
            table.direction.insert(p.id, holder);
        }
    }
}

/// Puts the most common geometry and vertex records into truck's table when they are in
/// their usual form (a string label, `#id` references, reals, `.T.`/`.F.`): the holder
/// truck's reader makes of the record (`push_instance`, through serde), built directly.
/// False for any other record or form, which goes through truck's reader.
fn push_direct(table: &mut Table, id: u64, record: &Record) -> bool {
    let label = |q: &Parameter| match q {
        Parameter::String(s) => Some(s.clone()),
        _ => None,
    };
    fn r<T>(q: &Parameter) -> Option<PlaceHolder<T>> {
        as_ref(q).map(|id| PlaceHolder::Ref(Name::Entity(id)))
    }
    fn opt_r<T>(q: &Parameter) -> Option<Option<PlaceHolder<T>>> {
        match q {
            Parameter::NotProvided => Some(None),
            _ => r(q).map(Some),
        }
    }
    let real = |q: &Parameter| match q {
        Parameter::Real(x) => Some(*x),
        _ => None,
    };
    /// Puts the holder, if the record gave one, under `id`.
    fn put<H>(map: &mut std::collections::HashMap<u64, H>, id: u64, holder: Option<H>) -> bool {
        holder.map(|h| map.insert(id, h)).is_some()
    }
    match (record.name.as_str(), params(record)) {
        ("VECTOR", [l, o, m]) => {
            let holder = || {
                Some(VectorHolder {
                    label: label(l)?,
                    orientation: r(o)?,
                    magnitude: real(m)?,
                })
            };
            put(&mut table.vector, id, holder())
        }
        ("AXIS2_PLACEMENT_3D", [l, loc, axis, x]) => {
            let holder = || {
                Some(Axis2Placement3dHolder {
                    label: label(l)?,
                    location: r(loc)?,
                    axis: opt_r(axis)?,
                    ref_direction: opt_r(x)?,
                })
            };
            put(&mut table.axis2_placement_3d, id, holder())
        }
        ("LINE", [l, pnt, dir]) => {
            let holder = || {
                Some(LineHolder {
                    label: label(l)?,
                    pnt: r(pnt)?,
                    dir: r(dir)?,
                })
            };
            put(&mut table.line, id, holder())
        }
        ("CIRCLE", [l, position, radius]) => {
            let holder = || {
                Some(CircleHolder {
                    label: label(l)?,
                    position: r(position)?,
                    radius: real(radius)?,
                })
            };
            put(&mut table.circle, id, holder())
        }
        ("PLANE", [l, position]) => {
            let holder = || {
                Some(PlaneHolder {
                    label: label(l)?,
                    position: r(position)?,
                })
            };
            put(&mut table.plane, id, holder())
        }
        ("CYLINDRICAL_SURFACE", [l, position, radius]) => {
            let holder = || {
                Some(CylindricalSurfaceHolder {
                    label: label(l)?,
                    position: r(position)?,
                    radius: real(radius)?,
                })
            };
            put(&mut table.cylindrical_surface, id, holder())
        }
        ("VERTEX_POINT", [l, point]) => {
            let holder = || {
                Some(VertexPointHolder {
                    label: label(l)?,
                    vertex_geometry: r(point)?,
                })
            };
            put(&mut table.vertex_point, id, holder())
        }
        ("EDGE_CURVE", [l, start, end, geometry, sense]) => {
            let holder = || {
                Some(EdgeCurveHolder {
                    label: label(l)?,
                    edge_start: r(start)?,
                    edge_end: r(end)?,
                    edge_geometry: r(geometry)?,
                    same_sense: as_bool(sense)?,
                })
            };
            put(&mut table.edge_curve, id, holder())
        }
        _ => false,
    }
}

/// truck takes a cone's semi-angle in radians whatever the file's plane-angle unit: the
/// angles in its table are converted.
fn cone_angles_in_radians(table: &mut Table, recs: &Records) {
    let angle = records::plane_angle_factor(recs);
    if angle != 1.0 {
        for cone in table.conical_surface.values_mut() {
            cone.semi_angle *= angle;
        }
    }
}

/// Sizes truck's tables for the entities most files are made of, which would otherwise grow
/// by rehashing (truck's maps hash with SipHash).
fn reserve_table(table: &mut Table, items: &[&Item]) {
    let mut n = [0usize; 9];
    for item in items {
        let k = match item {
            Item::Point(p) => match p.kind {
                PointKind::CartesianPoint => 0,
                PointKind::Direction => 1,
            },
            Item::Instance(EntityInstance::Simple { record, .. }) => match record.name.as_str() {
                "CARTESIAN_POINT" => 0,
                "DIRECTION" => 1,
                "VECTOR" => 2,
                "AXIS2_PLACEMENT_3D" => 3,
                "LINE" => 4,
                "CIRCLE" => 5,
                "B_SPLINE_CURVE_WITH_KNOTS" => 6,
                "VERTEX_POINT" => 7,
                "EDGE_CURVE" => 8,
                _ => continue,
            },
            Item::Instance(EntityInstance::Complex { .. }) => continue,
        };
        n[k] += 1;
    }
    table.cartesian_point.reserve(n[0]);
    table.direction.reserve(n[1]);
    table.vector.reserve(n[2]);
    table.axis2_placement_3d.reserve(n[3]);
    table.line.reserve(n[4]);
    table.circle.reserve(n[5]);
    table.b_spline_curve_with_knots.reserve(n[6]);
    table.vertex_point.reserve(n[7]);
    table.edge_curve.reserve(n[8]);
}

/// Deepest list nesting accepted. AP203/AP214 need at most 4 or 5 (a rational B-spline
/// surface's weights: a list of lists inside a complex instance).
pub const MAX_NESTING: usize = 64;

/// Runs `f`, turning a panic into an error message (truck panics on some bad data).
pub(crate) fn guarded<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    crate::panic_guard::catch(f)
}

fn first_line(s: &str) -> String {
    let line = s.lines().next().unwrap_or("").trim();
    if line.len() > 200 {
        format!("{}…", &line[..line.floor_char_boundary(200)])
    } else {
        line.to_string()
    }
}

fn model_err(path: &Path, reason: impl Into<String>) -> Error {
    Error::Model {
        path: path.into(),
        reason: reason.into(),
    }
}

fn entity_err(path: &Path, id: u64, entity: impl Into<String>, reason: impl Into<String>) -> Error {
    Error::Entity {
        path: path.into(),
        id,
        entity: entity.into(),
        reason: reason.into(),
    }
}

/// One solid to build: its brep entity and where it is placed.
struct SolidJob {
    brep: u64,
    unit: LengthUnit,
    placement: Mat4,
}

struct Ingest<'a> {
    path: PathBuf,
    recs: &'a Records<'a>,
    table: &'a Table,
    undecodable: &'a HashMap<u64, String>,
    model: Model,
    /// (EDGE_CURVE id, placement index) → edge index.
    edge_map: HashMap<(u64, usize), usize>,
    /// (VERTEX_POINT id, placement index) → vertex index.
    vertex_map: HashMap<(u64, usize), usize>,
}

impl Ingest<'_> {
    fn err(&self, id: u64, reason: impl Into<String>) -> Error {
        entity_err(&self.path, id, self.recs.name(id), reason)
    }

    /// Parameter `k` of entity `id`'s record, read by `read`; `what` names it in the error.
    fn param<T>(
        &self,
        id: u64,
        params: &[Parameter],
        k: usize,
        read: impl Fn(&Parameter) -> Option<T>,
        what: &str,
    ) -> Result<T> {
        params
            .get(k)
            .and_then(read)
            .ok_or_else(|| self.err(id, what.to_string()))
    }

    fn run(mut self) -> Result<Model> {
        let jobs = self.solid_jobs()?;
        if jobs.is_empty() {
            let shells = self
                .recs
                .ids_in_order()
                .filter(|id| self.recs.is(*id, "OPEN_SHELL") || self.recs.is(*id, "CLOSED_SHELL"))
                .count();
            let what = if shells > 0 {
                format!("no solid (MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS); {shells} shell(s) not part of a solid")
            } else {
                "no solid (MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS) in the file".to_string()
            };
            return Err(model_err(&self.path, what));
        }
        // Units must agree: the model has one unit (we report it); geometry is in mm anyway.
        self.model.source.file_unit = jobs[0].unit.name.clone();
        self.model.source.mm_per_unit = jobs[0].unit.mm;
        for (k, job) in jobs.iter().enumerate() {
            self.build_solid(k, job)?;
        }
        self.check_everything_used()?;
        self.renumber_in_file_order();
        self.compute_domains()?;
        self.model.bbox = crate::geom::model_bounding_box(&self.model);
        Ok(self.model)
    }

    /// Finds every solid, its representation's length unit, and its placements.
    fn solid_jobs(&self) -> Result<Vec<SolidJob>> {
        let recs = self.recs;
        let breps: Vec<u64> = recs
            .ids_in_order()
            .filter(|id| {
                recs.simple(*id)
                    .is_some_and(|r| r.name == "MANIFOLD_SOLID_BREP" || r.name == "BREP_WITH_VOIDS")
            })
            .collect();
        let reps = records::representations(recs);
        let links =
            records::representation_links(recs).map_err(|(id, reason)| self.err(id, reason))?;
        let fallback_unit = || -> Result<LengthUnit> {
            let units = records::all_length_units(recs);
            let mut ok: Vec<LengthUnit> = vec![];
            for u in units {
                let u = u.map_err(|e| model_err(&self.path, e))?;
                if !ok.contains(&u) {
                    ok.push(u);
                }
            }
            match ok.len() {
                0 => Ok(LengthUnit::mm()),
                1 => Ok(ok.remove(0)),
                _ => Err(model_err(
                    &self.path,
                    "several length units and no representation context says which applies",
                )),
            }
        };
        let mut jobs = Vec::new();
        for brep in breps {
            let holders: Vec<&records::Representation> =
                reps.iter().filter(|r| r.items.contains(&brep)).collect();
            if holders.is_empty() {
                jobs.push(SolidJob {
                    brep,
                    unit: fallback_unit()?,
                    placement: records::IDENTITY,
                });
                continue;
            }
            let rep = holders[0];
            let unit = match rep
                .context
                .and_then(|c| records::context_length_unit(recs, c))
            {
                Some(Ok(u)) => u,
                Some(Err(e)) => return Err(self.err(rep.context.unwrap_or(rep.id), e)),
                None => fallback_unit()?,
            };
            for placement in records::placements(rep.id, &links) {
                jobs.push(SolidJob {
                    brep,
                    unit: unit.clone(),
                    placement,
                });
            }
        }
        if let Some(first) = jobs.first() {
            if let Some(other) = jobs
                .iter()
                .find(|j| (j.unit.mm - first.unit.mm).abs() > 1e-12 * first.unit.mm)
            {
                return Err(model_err(
                    &self.path,
                    format!(
                        "solids in different length units ({} and {}) are not supported",
                        first.unit.name, other.unit.name
                    ),
                ));
            }
        }
        Ok(jobs)
    }

    fn build_solid(&mut self, instance: usize, job: &SolidJob) -> Result<()> {
        let recs = self.recs;
        let rec = recs
            .simple(job.brep)
            .expect("brep id came from the records");
        let p = params(rec);
        let name = p.first().map(records::as_string).unwrap_or_default();
        let outer = self.param(job.brep, p, 1, as_ref, "outer shell missing")?;
        let voids = if rec.name == "BREP_WITH_VOIDS" {
            self.param(job.brep, p, 2, as_refs, "void shell list unreadable")?
        } else {
            vec![]
        };
        // Length scaling then placement: x_world = P · (s · x_file).
        let s = job.unit.mm;
        let mut m = job.placement;
        for row in m.iter_mut().take(3) {
            row[3] *= s;
            for cell in row.iter_mut().take(3) {
                *cell *= s;
            }
        }
        // The translation of a placement is in file units too.
        let solid = self.model.solids.len();
        self.model.solids.push(Solid {
            source_id: job.brep,
            name,
            shells: vec![],
        });
        for (k, shell) in std::iter::once(outer).chain(voids).enumerate() {
            let idx = self.build_shell(shell, solid, k > 0, instance, &m)?;
            self.model.solids[solid].shells.push(idx);
        }
        Ok(())
    }

    fn build_shell(
        &mut self,
        id: u64,
        solid: usize,
        is_void: bool,
        instance: usize,
        m: &Mat4,
    ) -> Result<usize> {
        let recs = self.recs;
        let rec = recs
            .simple(id)
            .ok_or_else(|| self.err(id, "expected a shell"))?;
        let (shell_id, orientation) = match rec.name.as_str() {
            "CLOSED_SHELL" => (id, true),
            "ORIENTED_CLOSED_SHELL" => {
                let p = params(rec);
                let inner = self.param(id, p, 2, as_ref, "shell element missing")?;
                let o = self.param(id, p, 3, as_bool, "orientation missing")?;
                (inner, o)
            }
            "OPEN_SHELL" | "ORIENTED_OPEN_SHELL" => {
                return Err(self.err(id, "open shell: the solid is not closed"))
            }
            _ => return Err(self.err(id, "expected CLOSED_SHELL")),
        };
        let srec = recs
            .simple(shell_id)
            .filter(|r| r.name == "CLOSED_SHELL")
            .ok_or_else(|| self.err(shell_id, "expected CLOSED_SHELL"))?;
        let faces = self.param(shell_id, params(srec), 1, as_refs, "face list unreadable")?;
        if faces.is_empty() {
            return Err(self.err(shell_id, "shell has no faces"));
        }
        let shell = self.model.shells.len();
        self.model.shells.push(Shell {
            source_id: shell_id,
            solid,
            is_void,
            faces: vec![],
        });
        let shell_sign = if orientation { 1.0 } else { -1.0 };
        let first_edge = self.model.edges.len();
        for face in faces {
            let f = self.build_face(face, shell, shell_sign, instance, m)?;
            self.model.shells[shell].faces.push(f);
        }
        // Closedness: every edge of the shell is used exactly twice, once each way.
        for e in first_edge..self.model.edges.len() {
            let edge = &self.model.edges[e];
            if edge.faces.len() != 2 {
                return Err(self.err(
                    edge.source_id,
                    format!(
                        "edge used by {} face(s) of shell #{shell_id}; a closed shell uses each edge twice (open shell?)",
                        edge.faces.len()
                    ),
                ));
            }
        }
        Ok(shell)
    }

    fn build_face(
        &mut self,
        id: u64,
        shell: usize,
        shell_sign: f64,
        instance: usize,
        m: &Mat4,
    ) -> Result<usize> {
        let recs = self.recs;
        let rec = recs
            .simple(id)
            .ok_or_else(|| self.err(id, "expected a face"))?;
        let (face_id, face_sign) = match rec.name.as_str() {
            "ADVANCED_FACE" | "FACE_SURFACE" => (id, 1.0),
            "ORIENTED_FACE" => {
                let p = params(rec);
                let inner = self.param(id, p, 2, as_ref, "face element missing")?;
                let o = p.get(3).and_then(as_bool).unwrap_or(true);
                (inner, if o { 1.0 } else { -1.0 })
            }
            _ => return Err(self.err(id, "expected ADVANCED_FACE")),
        };
        let frec = recs
            .simple(face_id)
            .filter(|r| r.name == "ADVANCED_FACE" || r.name == "FACE_SURFACE")
            .ok_or_else(|| self.err(face_id, "expected ADVANCED_FACE"))?;
        let p = params(frec);
        let bounds = self.param(face_id, p, 1, as_refs, "bounds unreadable")?;
        let geometry = self.param(face_id, p, 2, as_ref, "surface missing")?;
        let same_sense = self.param(face_id, p, 3, as_bool, "same_sense missing")?;
        let surface = self.convert_surface(geometry, m)?;
        let index = self.model.faces.len();
        let mut loops = Vec::new();
        let mut outer = None;
        for b in bounds {
            let brec = recs
                .simple(b)
                .ok_or_else(|| self.err(b, "expected FACE_BOUND"))?;
            if brec.name != "FACE_BOUND" && brec.name != "FACE_OUTER_BOUND" {
                return Err(self.err(b, "expected FACE_BOUND"));
            }
            let bp = params(brec);
            let lp = self.param(b, bp, 1, as_ref, "loop missing")?;
            let orientation = self.param(b, bp, 2, as_bool, "orientation missing")?;
            if brec.name == "FACE_OUTER_BOUND" {
                outer = Some(loops.len());
            }
            loops.push(self.build_loop(lp, orientation, index, instance, m)?);
        }
        let sign = shell_sign * face_sign * if same_sense { 1.0 } else { -1.0 };
        self.model.faces.push(Face {
            source_id: face_id,
            shell,
            surface,
            sign,
            same_sense,
            loops,
            outer,
            domain: UvDomain {
                u: (0.0, 0.0),
                v: (0.0, 0.0),
                u_period: None,
                v_period: None,
            },
        });
        Ok(index)
    }

    fn build_loop(
        &mut self,
        id: u64,
        orientation: bool,
        face: usize,
        instance: usize,
        m: &Mat4,
    ) -> Result<Loop> {
        let recs = self.recs;
        let rec = recs
            .simple(id)
            .ok_or_else(|| self.err(id, "expected EDGE_LOOP"))?;
        match rec.name.as_str() {
            "VERTEX_LOOP" => {
                let v = self.param(id, params(rec), 1, as_ref, "vertex missing")?;
                let vi = self.vertex(v, instance, m)?;
                Ok(Loop {
                    source_id: id,
                    edges: vec![],
                    vertex: Some(vi),
                    uv: vec![],
                })
            }
            "EDGE_LOOP" => {
                let oes = self.param(id, params(rec), 1, as_refs, "edge list unreadable")?;
                if oes.is_empty() {
                    return Err(self.err(id, "empty edge loop"));
                }
                let mut edges = Vec::with_capacity(oes.len());
                for oe in oes {
                    let orec = recs
                        .simple(oe)
                        .ok_or_else(|| self.err(oe, "expected ORIENTED_EDGE"))?;
                    let (ec, forward) = match orec.name.as_str() {
                        "ORIENTED_EDGE" => {
                            let op = params(orec);
                            let ec = self.param(oe, op, 3, as_ref, "edge element missing")?;
                            let o = self.param(oe, op, 4, as_bool, "orientation missing")?;
                            (ec, o)
                        }
                        "EDGE_CURVE" => (oe, true),
                        _ => return Err(self.err(oe, "expected ORIENTED_EDGE")),
                    };
                    let e = self.edge(ec, instance, m)?;
                    self.model.edges[e].faces.push(face);
                    edges.push(OrientedEdge { edge: e, forward });
                }
                if !orientation {
                    edges.reverse();
                    for e in &mut edges {
                        e.forward = !e.forward;
                    }
                }
                // The loop must be connected end to start.
                for k in 0..edges.len() {
                    let a = edges[k];
                    let b = edges[(k + 1) % edges.len()];
                    let end = self.model.edges[a.edge].vertices[usize::from(a.forward)];
                    let start = self.model.edges[b.edge].vertices[usize::from(!b.forward)];
                    if end != start {
                        return Err(self.err(id, "edges of the loop do not connect end to start"));
                    }
                }
                Ok(Loop {
                    source_id: id,
                    edges,
                    vertex: None,
                    uv: vec![],
                })
            }
            "POLY_LOOP" => Err(self.err(id, "POLY_LOOP (faceted B-rep) is not supported")),
            _ => Err(self.err(id, "expected EDGE_LOOP or VERTEX_LOOP")),
        }
    }

    fn vertex(&mut self, id: u64, instance: usize, m: &Mat4) -> Result<usize> {
        if let Some(&v) = self.vertex_map.get(&(id, instance)) {
            return Ok(v);
        }
        let recs = self.recs;
        let rec = recs
            .simple(id)
            .filter(|r| r.name == "VERTEX_POINT")
            .ok_or_else(|| self.err(id, "expected VERTEX_POINT"))?;
        let pid = self.param(id, params(rec), 1, as_ref, "point missing")?;
        let c = recs
            .coordinates(pid, PointKind::CartesianPoint)
            .ok_or_else(|| self.err(pid, "expected CARTESIAN_POINT"))?;
        if c.len() != 3 || c.iter().any(|x| !x.is_finite()) {
            return Err(self.err(pid, "needs three finite coordinates"));
        }
        let point = records::apply(m, DVec3::new(c[0], c[1], c[2]));
        let v = self.model.vertices.len();
        self.model.vertices.push(Vertex {
            source_id: id,
            point,
        });
        self.vertex_map.insert((id, instance), v);
        Ok(v)
    }

    fn edge(&mut self, id: u64, instance: usize, m: &Mat4) -> Result<usize> {
        if let Some(&e) = self.edge_map.get(&(id, instance)) {
            return Ok(e);
        }
        let recs = self.recs;
        let rec = recs
            .simple(id)
            .filter(|r| r.name == "EDGE_CURVE")
            .ok_or_else(|| self.err(id, "expected EDGE_CURVE"))?;
        let p = params(rec);
        let v0 = self.param(id, p, 1, as_ref, "start vertex missing")?;
        let v1 = self.param(id, p, 2, as_ref, "end vertex missing")?;
        let geometry = self.param(id, p, 3, as_ref, "curve missing")?;
        let a = self.vertex(v0, instance, m)?;
        let b = self.vertex(v1, instance, m)?;
        let curve = self.convert_edge_curve(id, geometry, m)?;
        let range = self.edge_range(id, &curve, a, b)?;
        let e = self.model.edges.len();
        self.model.edges.push(Edge {
            source_id: id,
            curve,
            range,
            vertices: [a, b],
            faces: vec![],
        });
        self.edge_map.insert((id, instance), e);
        Ok(e)
    }

    /// The parameter interval of `curve` between the edge's vertices; truck trims lines and
    /// conics to the vertices, B-splines keep their own range (check it, project if needed).
    fn edge_range(&self, id: u64, curve: &Curve3D, a: usize, b: usize) -> Result<(f64, f64)> {
        use truck_geometry::prelude::{ParametricCurve, SearchNearestParameter};
        let (t0, t1) = match curve {
            // An unclamped (periodic-style) knot vector is only valid between the p-th and
            // the (m−p)-th knot; truck reports the whole knot range, where the curve is
            // undefined.
            Curve3D::BSplineCurve(c) => valid_knot_range(c.knot_vec(), c.degree()),
            Curve3D::NurbsCurve(c) => valid_knot_range(c.knot_vec(), c.degree()),
            _ => None,
        }
        .or_else(|| guarded(|| curve.try_range_tuple()).ok().flatten())
        .ok_or_else(|| self.err(id, "edge curve is unbounded"))?;
        let pa = self.model.vertices[a].point;
        let pb = self.model.vertices[b].point;
        let at = |t: f64| {
            let q = curve.subs(t);
            DVec3::new(q.x, q.y, q.z)
        };
        let scale = 1.0 + pa.abs().max_element().max(pb.abs().max_element());
        let tol = 1e-6 * scale;
        if at(t0).distance(pa) <= tol && at(t1).distance(pb) <= tol {
            return Ok((t0, t1));
        }
        // Project the vertices (hint: the nearer end).
        let proj = |p: DVec3, hint: f64| {
            guarded(|| curve.search_nearest_parameter(Point3::new(p.x, p.y, p.z), Some(hint), 100))
                .ok()
                .flatten()
        };
        let s0 = proj(pa, t0);
        let s1 = proj(pb, t1);
        match (s0, s1) {
            (Some(s0), Some(s1))
                if at(s0).distance(pa) <= 1e-4 * scale && at(s1).distance(pb) <= 1e-4 * scale =>
            {
                if a == b || (s1 - s0).abs() < 1e-12 {
                    Ok((t0, t1))
                } else {
                    Ok((s0, s1))
                }
            }
            _ => Err(self.err(
                id,
                format!(
                    "the edge's vertices are not on its curve (distance {:.3e} mm and {:.3e} mm)",
                    at(t0).distance(pa),
                    at(t1).distance(pb)
                ),
            )),
        }
    }

    fn undecodable(&self, id: u64) -> Option<Error> {
        self.undecodable
            .get(&id)
            .map(|reason| self.err(id, format!("cannot be read: {reason}")))
    }

    /// Runs a truck conversion for entity `id`: its error becomes `failure: …`, a panic
    /// inside truck `reader panicked: …`.
    fn with_truck<T>(
        &self,
        id: u64,
        failure: &str,
        f: impl FnOnce() -> std::result::Result<T, String>,
    ) -> Result<T> {
        match guarded(f) {
            Ok(Ok(x)) => Ok(x),
            Ok(Err(e)) => Err(self.err(id, format!("{failure}: {e}"))),
            Err(p) => Err(self.err(id, format!("reader panicked: {p}"))),
        }
    }

    fn convert_surface(&self, id: u64, m: &Mat4) -> Result<Surface> {
        if let Some(e) = self.undecodable(id) {
            return Err(e);
        }
        let known = [
            "PLANE",
            "CYLINDRICAL_SURFACE",
            "CONICAL_SURFACE",
            "SPHERICAL_SURFACE",
            "TOROIDAL_SURFACE",
            "B_SPLINE_SURFACE_WITH_KNOTS",
            "BEZIER_SURFACE",
            "UNIFORM_SURFACE",
            "QUASI_UNIFORM_SURFACE",
            "SURFACE_OF_LINEAR_EXTRUSION",
            "SURFACE_OF_REVOLUTION",
            "RATIONAL_B_SPLINE_SURFACE",
        ];
        if !known.iter().any(|k| self.recs.is(id, k)) {
            return Err(self.err(id, "unsupported surface type"));
        }
        let table = self.table;
        let surface = self.with_truck(id, "cannot be converted", || {
            let any = PlaceHolder::<SurfaceAnyHolder>::Ref(Name::Entity(id))
                .into_owned(table)
                .map_err(|e| first_line(&e.to_string()))?;
            Surface::try_from(&any).map_err(|e| first_line(&e.to_string()))
        })?;
        Ok(records::placed(surface, m))
    }

    fn convert_edge_curve(&self, id: u64, geometry: u64, m: &Mat4) -> Result<Curve3D> {
        if let Some(e) = self.undecodable(id).or_else(|| self.undecodable(geometry)) {
            return Err(e);
        }
        let known = [
            "LINE",
            "CIRCLE",
            "ELLIPSE",
            "B_SPLINE_CURVE_WITH_KNOTS",
            "BEZIER_CURVE",
            "UNIFORM_CURVE",
            "QUASI_UNIFORM_CURVE",
            "RATIONAL_B_SPLINE_CURVE",
            "POLYLINE",
            "SURFACE_CURVE",
            "SEAM_CURVE",
            "HYPERBOLA",
            "PARABOLA",
        ];
        if !known.iter().any(|k| self.recs.is(geometry, k)) {
            return Err(self.err(geometry, "unsupported curve type"));
        }
        let table = self.table;
        let curve = self.with_truck(id, "curve cannot be converted", || {
            let ec = PlaceHolder::<EdgeCurveHolder>::Ref(Name::Entity(id))
                .into_owned(table)
                .map_err(|e| first_line(&e.to_string()))?;
            ec.parse_curve3d().map_err(|e| first_line(&e.to_string()))
        })?;
        if matches!(curve, Curve3D::PCurve(_)) {
            return Err(self.err(id, "edge has only a pcurve, no 3D curve"));
        }
        Ok(records::placed(curve, m))
    }

    /// Compares what the file defines with what the model holds: every `ADVANCED_FACE`,
    /// `EDGE_CURVE` and `VERTEX_POINT` in the file must belong to a solid.
    fn check_everything_used(&self) -> Result<()> {
        let used_faces: FxHashSet<u64> = self.model.faces.iter().map(|f| f.source_id).collect();
        let used_edges: FxHashSet<u64> = self.model.edges.iter().map(|e| e.source_id).collect();
        let used_vertices: FxHashSet<u64> =
            self.model.vertices.iter().map(|v| v.source_id).collect();
        for id in self.recs.ids_in_order() {
            let Some(rec) = self.recs.simple(id) else {
                continue;
            };
            let lost = match rec.name.as_str() {
                "ADVANCED_FACE" | "FACE_SURFACE" => !used_faces.contains(&id),
                "EDGE_CURVE" => !used_edges.contains(&id),
                "VERTEX_POINT" => !used_vertices.contains(&id),
                _ => false,
            };
            if lost {
                return Err(self.err(id, "defined in the file but not part of any solid"));
            }
        }
        Ok(())
    }

    /// Faces, edges and vertices numbered in the order the file defines them (then by
    /// placement instance).
    fn renumber_in_file_order(&mut self) {
        let recs = self.recs;
        let m = &mut self.model;
        // Instance of an entity = order of first creation among copies with the same id.
        let key_f: Vec<(usize, usize)> = order_keys(m.faces.iter().map(|f| f.source_id), recs);
        let key_e: Vec<(usize, usize)> = order_keys(m.edges.iter().map(|e| e.source_id), recs);
        let key_v: Vec<(usize, usize)> = order_keys(m.vertices.iter().map(|v| v.source_id), recs);
        let perm_f = permutation(&key_f);
        let perm_e = permutation(&key_e);
        let perm_v = permutation(&key_v);
        // new_of[old] = new index
        let inv = |perm: &[usize]| {
            let mut inv = vec![0; perm.len()];
            for (new, &old) in perm.iter().enumerate() {
                inv[old] = new;
            }
            inv
        };
        let (nf, ne, nv) = (inv(&perm_f), inv(&perm_e), inv(&perm_v));
        m.faces = perm_f.iter().map(|&o| m.faces[o].clone()).collect();
        m.edges = perm_e.iter().map(|&o| m.edges[o].clone()).collect();
        m.vertices = perm_v.iter().map(|&o| m.vertices[o]).collect();
        for s in &mut m.shells {
            for f in &mut s.faces {
                *f = nf[*f];
            }
        }
        for f in &mut m.faces {
            for l in &mut f.loops {
                for oe in &mut l.edges {
                    oe.edge = ne[oe.edge];
                }
                if let Some(v) = &mut l.vertex {
                    *v = nv[*v];
                }
            }
        }
        for e in &mut m.edges {
            for v in &mut e.vertices {
                *v = nv[*v];
            }
            for f in &mut e.faces {
                *f = nf[*f];
            }
        }
    }

    fn compute_domains(&mut self) -> Result<()> {
        // Faces are independent: their loops are projected in parallel (results are the same
        // whatever the thread count), then the first error in face order is reported.
        let m = &self.model;
        let uvs: Vec<LoopsUv> = (0..m.faces.len())
            .into_par_iter()
            .map(|fi| {
                m.faces[fi]
                    .loops
                    .iter()
                    .map(|l| loop_uv(m, fi, l).map_err(|reason| (l.source_id, reason)))
                    .collect()
            })
            .collect();
        for (fi, uv) in uvs.into_iter().enumerate() {
            let uv =
                uv.map_err(|(id, reason)| entity_err(&self.path, id, self.recs.name(id), reason))?;
            let m = &mut self.model;
            for (l, uv) in m.faces[fi].loops.iter_mut().zip(uv) {
                l.uv = uv;
            }
            align_loops(&mut m.faces[fi]);
            let (domain, outer) = face_domain(m, &m.faces[fi]);
            m.faces[fi].domain = domain;
            if m.faces[fi].outer.is_none() {
                m.faces[fi].outer = outer;
            }
        }
        Ok(())
    }
}

/// One face's loops in UV, or the failing loop's id and the reason.
type LoopsUv = std::result::Result<Vec<Vec<glam::DVec2>>, (u64, String)>;

/// `[k_p, k_{m−p}]` of a knot vector of degree `p` (m + 1 knots).
fn valid_knot_range(knots: &truck_geometry::prelude::KnotVec, degree: usize) -> Option<(f64, f64)> {
    let m = knots.len();
    (m > 2 * degree + 1).then(|| (knots[degree], knots[m - degree - 1]))
}

fn order_keys(ids: impl Iterator<Item = u64>, recs: &Records) -> Vec<(usize, usize)> {
    let mut seen: HashMap<u64, usize> = HashMap::default();
    ids.map(|id| {
        let k = seen.entry(id).or_insert(0);
        let inst = *k;
        *k += 1;
        (inst, recs.position(id))
    })
    .collect()
}

fn permutation(keys: &[(usize, usize)]) -> Vec<usize> {
    let mut perm: Vec<usize> = (0..keys.len()).collect();
    perm.sort_by_key(|&i| keys[i]);
    perm
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A compact point or direction gives truck's table the holder truck's own reader makes
    /// of the full record, for every form the parser keeps compact.
    #[test]
    fn compact_points_make_truck_s_holders() {
        let text = "ISO-10303-21;HEADER;ENDSEC;DATA;
            #1=CARTESIAN_POINT('',(1.,-2.5,3.E1));
            #2=CARTESIAN_POINT('a''b',(0.5,-0.));
            #3=CARTESIAN_POINT('x',(7.));
            #4=DIRECTION('',(0.,0.,1.));
            #5=DIRECTION('d',(1.E-300,-1.));
            ENDSEC;END-ISO-10303-21;";
        let parsed = p21::parse(text, 8).expect("parses");
        let (mut ours, mut truck) = (Table::default(), Table::default());
        for item in &parsed.data[0].entities {
            let Item::Point(p) = item else {
                panic!("{item:?} is not compact")
            };
            push_point(&mut ours, p);
            truck
                .push_instance(&item.to_instance())
                .expect("truck reads it");
        }
        assert_eq!(ours.cartesian_point.len(), 3);
        assert_eq!(ours.direction.len(), 2);
        assert_eq!(ours.cartesian_point, truck.cartesian_point);
        assert_eq!(ours.direction, truck.direction);
    }

    /// Every record `push_direct` takes, in every sample and real-world file, gives the
    /// holder truck's reader makes of it; it takes nearly all records of its kinds.
    #[test]
    fn direct_holders_are_truck_s_on_every_file() {
        let (mut direct, mut kinds) = (0, 0);
        for f in p21::tests::corpus_step_files() {
            let text = std::fs::read_to_string(&f).unwrap();
            let mut parsed = p21::parse(&text, MAX_NESTING).unwrap();
            records::patch_for_truck(&mut parsed.data);
            let (mut ours, mut truck) = (Table::default(), Table::default());
            for item in &parsed.data[0].entities {
                let Item::Instance(inst @ EntityInstance::Simple { id, record }) = item else {
                    continue;
                };
                let kind = [
                    "VECTOR",
                    "AXIS2_PLACEMENT_3D",
                    "LINE",
                    "CIRCLE",
                    "PLANE",
                    "CYLINDRICAL_SURFACE",
                    "VERTEX_POINT",
                    "EDGE_CURVE",
                ]
                .contains(&record.name.as_str());
                kinds += usize::from(kind);
                if push_direct(&mut ours, *id, record) {
                    assert!(kind, "{f:?} #{id}");
                    direct += 1;
                    truck
                        .push_instance(inst)
                        .unwrap_or_else(|e| panic!("{f:?} #{id}: {e}"));
                }
            }
            assert_eq!(ours.vector, truck.vector, "{f:?}");
            assert_eq!(ours.axis2_placement_3d, truck.axis2_placement_3d, "{f:?}");
            assert_eq!(ours.line, truck.line, "{f:?}");
            assert_eq!(ours.circle, truck.circle, "{f:?}");
            assert_eq!(ours.plane, truck.plane, "{f:?}");
            assert_eq!(ours.cylindrical_surface, truck.cylindrical_surface, "{f:?}");
            assert_eq!(ours.vertex_point, truck.vertex_point, "{f:?}");
            assert_eq!(ours.edge_curve, truck.edge_curve, "{f:?}");
        }
        assert!(kinds > 5000, "{kinds}");
        assert!(direct * 100 >= kinds * 95, "{direct} of {kinds}");
    }

    /// Other forms go through truck's reader: an integer where a real is expected, an
    /// unknown enumeration, a typed value where a reference is expected, a parameter too
    /// many, a label left out.
    #[test]
    fn unusual_forms_are_left_to_truck() {
        let text = "ISO-10303-21;HEADER;ENDSEC;DATA;
            #1=VECTOR('',#2,2);
            #3=EDGE_CURVE('',#4,#5,#6,.U.);
            #7=LINE('',#8,LENGTH_MEASURE(1.));
            #9=PLANE('',#10,#11);
            #12=VERTEX_POINT($,#13);
            ENDSEC;END-ISO-10303-21;";
        let parsed = p21::parse(text, 8).expect("parses");
        let mut table = Table::default();
        for item in &parsed.data[0].entities {
            let Item::Instance(EntityInstance::Simple { id, record }) = item else {
                panic!("{item:?}")
            };
            assert!(!push_direct(&mut table, *id, record), "#{id}");
        }
    }

    /// A cone's semi-angle in degrees reaches truck in radians; in a file in radians it is
    /// left as it is.
    #[test]
    fn cone_angles_reach_truck_in_radians() {
        let cone = "#1=CARTESIAN_POINT('',(0.,0.,0.));
            #2=DIRECTION('',(0.,0.,1.));
            #3=DIRECTION('',(1.,0.,0.));
            #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);
            #5=CONICAL_SURFACE('',#4,2.,30.);
            #8=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));";
        let degree = "#6=(CONVERSION_BASED_UNIT('DEGREE',#7)NAMED_UNIT(*)PLANE_ANGLE_UNIT());
            #7=PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925),#8);";
        for (units, expected) in [("", 30.0), (degree, 30.0 * 0.0174532925)] {
            let text =
                format!("ISO-10303-21;HEADER;ENDSEC;DATA;{cone}{units}ENDSEC;END-ISO-10303-21;");
            let parsed = p21::parse(&text, 8).expect("parses");
            let recs = Records::new(&parsed.data);
            let mut table = Table::default();
            for item in &parsed.data[0].entities {
                table
                    .push_instance(&item.to_instance())
                    .expect("truck reads it");
            }
            cone_angles_in_radians(&mut table, &recs);
            assert_eq!(table.conical_surface[&5].semi_angle, expected, "{units}");
        }
    }
}
