//! The STEP topology walk from each solid down to its vertices, into the [`Model`].
//!
//! From each solid (`MANIFOLD_SOLID_BREP` / `BREP_WITH_VOIDS`, once per placement of its
//! representation) through `CLOSED_SHELL` / `ORIENTED_CLOSED_SHELL` → `ADVANCED_FACE` (or
//! `ORIENTED_FACE`) → `FACE_BOUND` → `EDGE_LOOP` / `VERTEX_LOOP` → `ORIENTED_EDGE` →
//! `EDGE_CURVE` → `VERTEX_POINT`.
//!
//! Lengths are converted to millimetres and assembly placements applied to the geometry
//! itself; an edge or vertex shared by faces of one placed solid is one model edge or vertex.
//! Each shell must be closed: every edge used by exactly two of its faces, every loop
//! connected end to start.

use super::error::model_err;
use super::p21::PointKind;
use super::placement::{placements, representation_links, representations, Representation};
use super::records::{as_bool, as_ref, as_refs, as_string, params};
use super::source::Source;
use super::units::{all_length_units, context_length_unit, LengthUnit};
use crate::error::Result;
use crate::ingest::domain::EMPTY_DOMAIN;
use crate::ingest::transform::{apply, Mat4, IDENTITY};
use crate::model::*;
use glam::DVec3;
use rustc_hash::FxHashMap as HashMap;

/// The solids of the file, with their shells, faces, loops, edges and vertices in the order
/// the walk meets them (numbered in file order later); the loops have no UV polygon yet.
pub fn build_solids(src: &Source) -> Result<Model> {
    let mut walk = Walk {
        src,
        model: Model {
            source: SourceInfo {
                path: src.path.display().to_string(),
                format: "step".into(),
                file_unit: "mm".into(),
                mm_per_unit: 1.0,
                warnings: vec![],
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
    };
    let jobs = walk.solid_jobs()?;
    if jobs.is_empty() {
        let recs = src.recs;
        let shells = recs
            .ids_in_order()
            .filter(|id| recs.is(*id, "OPEN_SHELL") || recs.is(*id, "CLOSED_SHELL"))
            .count();
        // An assembly whose parts are in files of their own (AP214's external references:
        // a `DOCUMENT_FILE` named for each, as CATIA V5 writes an assembly's parts): say so
        // and name them, for the user to read those files.
        let external: Vec<String> = recs
            .ids_in_order()
            .filter_map(|id| recs.simple(id))
            .filter(|r| r.name == "DOCUMENT_FILE")
            .filter_map(|r| params(r).first().map(as_string))
            .filter(|name| !name.trim().is_empty())
            .collect();
        let what = if shells > 0 {
            format!("no solid (MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS); {shells} shell(s) not part of a solid")
        } else if !external.is_empty() {
            format!(
                "no solid (MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS) in the file: its parts are \
                 in other files it refers to ({}), which are not read; read those files",
                external.join(", ")
            )
        } else {
            "no solid (MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS) in the file".to_string()
        };
        return Err(model_err(src.path, what));
    }
    // Units must agree: the model has one unit (we report it); geometry is in mm anyway.
    walk.model.source.file_unit = jobs[0].unit.name.clone();
    walk.model.source.mm_per_unit = jobs[0].unit.mm;
    for (k, job) in jobs.iter().enumerate() {
        walk.build_solid(k, job)?;
    }
    Ok(walk.model)
}

/// One solid to build: its brep entity and where it is placed.
struct SolidJob {
    brep: u64,
    unit: LengthUnit,
    placement: Mat4,
    /// Where an assembly places it: the product path.
    path: Option<String>,
    /// For a closed shell read from a `SHELL_BASED_SURFACE_MODEL` (`brep` is the model): the
    /// shell.
    shell: Option<u64>,
}

/// The walk's state: the model so far, and what each (entity, placement) became.
struct Walk<'a> {
    src: &'a Source<'a>,
    model: Model,
    /// (EDGE_CURVE id, placement index) → edge index.
    edge_map: HashMap<(u64, usize), usize>,
    /// (VERTEX_POINT id, placement index) → vertex index.
    vertex_map: HashMap<(u64, usize), usize>,
}

impl Walk<'_> {
    /// Finds every solid, its representation's length unit, and its placements.
    fn solid_jobs(&self) -> Result<Vec<SolidJob>> {
        let recs = self.src.recs;
        // One pass over the records for the solids, the assembly's occurrences and whether
        // anything is mapped in.
        let (mut breps, mut nauos, mut mapped_items) = (Vec::new(), Vec::new(), false);
        for id in recs.ids_in_order() {
            let Some(r) = recs.simple(id) else { continue };
            match r.name.as_str() {
                "MANIFOLD_SOLID_BREP" | "BREP_WITH_VOIDS" => breps.push(id),
                "NEXT_ASSEMBLY_USAGE_OCCURRENCE" => nauos.extend(super::assembly::nauo(id, r)),
                "MAPPED_ITEM" => mapped_items = true,
                _ => {}
            }
        }
        if breps.is_empty() {
            return self.surface_model_jobs();
        }
        let reps = representations(recs);
        let brep_set: rustc_hash::FxHashSet<u64> = breps.iter().copied().collect();
        let is_brep = |id: u64| brep_set.contains(&id);
        let placed = super::assembly::placed_solids(recs, &is_brep, nauos)
            .map_err(|(id, reason)| self.src.err(id, reason))?;
        match placed {
            Some(placed) if !placed.is_empty() => return self.assembly_jobs(&breps, &reps, placed),
            Some(_) => {
                if let Some(&first) = breps.first() {
                    self.src.warn(
                        "assembly",
                        first,
                        "an assembly whose product structure places no solid",
                        "every solid read where its own representations place it",
                    );
                }
            }
            None => {}
        }
        let links = representation_links(recs, &reps, mapped_items)
            .map_err(|(id, reason)| self.src.err(id, reason))?;
        let mut jobs = Vec::new();
        for brep in breps {
            let holders: Vec<&Representation> =
                reps.iter().filter(|r| r.items.contains(&brep)).collect();
            if holders.is_empty() {
                jobs.push(SolidJob {
                    brep,
                    unit: self.file_unit()?,
                    placement: IDENTITY,
                    path: None,
                    shell: None,
                });
                continue;
            }
            let rep = holders[0];
            let unit = self.unit_of(rep.context, rep.id)?;
            for placement in placements(rep.id, &links) {
                jobs.push(SolidJob {
                    brep,
                    unit: unit.clone(),
                    placement,
                    path: None,
                    shell: None,
                });
            }
        }
        same_unit(self.src, &jobs)?;
        Ok(jobs)
    }

    /// With no solid in the file: the closed shells of its `SHELL_BASED_SURFACE_MODEL`s, each
    /// read as a solid with a warning (in its representation's unit; not placed). A shell
    /// that is not closed is refused when it is walked.
    fn surface_model_jobs(&self) -> Result<Vec<SolidJob>> {
        let recs = self.src.recs;
        let reps = representations(recs);
        let mut jobs = Vec::new();
        for id in recs.ids_in_order() {
            let Some(rec) = recs
                .simple(id)
                .filter(|r| r.name == "SHELL_BASED_SURFACE_MODEL")
            else {
                continue;
            };
            let shells = self
                .src
                .param(id, params(rec), 1, as_refs, "shell list unreadable")?;
            let context = reps
                .iter()
                .find(|r| r.items.contains(&id))
                .and_then(|r| r.context);
            let unit = self.unit_of(context, id)?;
            for shell in shells {
                self.src.warn(
                    "surface_model",
                    shell,
                    "no solid in the file: a shell of a SHELL_BASED_SURFACE_MODEL",
                    "read as a solid (it must be closed)",
                );
                jobs.push(SolidJob {
                    brep: id,
                    unit: unit.clone(),
                    placement: IDENTITY,
                    path: None,
                    shell: Some(shell),
                });
            }
        }
        same_unit(self.src, &jobs)?;
        Ok(jobs)
    }

    /// The length unit of a representation `rep` (or a surface model) whose context is
    /// `context`: the context's, else the file's ([`Self::file_unit`]); an unreadable unit
    /// is an error naming the context.
    fn unit_of(&self, context: Option<u64>, rep: u64) -> Result<LengthUnit> {
        match context.and_then(|c| context_length_unit(self.src.recs, c)) {
            Some(Ok(u)) => Ok(u),
            Some(Err(e)) => Err(self.src.err(context.unwrap_or(rep), e)),
            None => self.file_unit(),
        }
    }

    /// The length unit for a solid whose representation's context names none: the file's one
    /// length unit (mm when it declares none); several are an error.
    fn file_unit(&self) -> Result<LengthUnit> {
        let mut ok: Vec<LengthUnit> = vec![];
        for u in all_length_units(self.src.recs) {
            let u = u.map_err(|e| model_err(self.src.path, e))?;
            if !ok.contains(&u) {
                ok.push(u);
            }
        }
        match ok.len() {
            0 => Ok(LengthUnit::mm()),
            1 => Ok(ok.remove(0)),
            _ => Err(model_err(
                self.src.path,
                "several length units and no representation context says which applies",
            )),
        }
    }

    /// The jobs of an assembly: one per solid the product structure places; solids it does
    /// not reach are left out with a warning.
    fn assembly_jobs(
        &self,
        breps: &[u64],
        reps: &[Representation],
        placed: Vec<super::assembly::Placed>,
    ) -> Result<Vec<SolidJob>> {
        let mut jobs = Vec::with_capacity(placed.len());
        for p in &placed {
            let context = reps.iter().find(|r| r.id == p.rep).and_then(|r| r.context);
            let unit = self.unit_of(context, p.rep)?;
            jobs.push(SolidJob {
                brep: p.brep,
                unit,
                placement: p.placement,
                path: Some(p.path.clone()),
                shell: None,
            });
        }
        let mut unplaced: Vec<u64> = placed.iter().filter_map(|p| p.unplaced).collect();
        unplaced.sort_unstable();
        unplaced.dedup();
        for nauo in unplaced {
            self.src.warn(
                "assembly",
                nauo,
                "component that no CONTEXT_DEPENDENT_SHAPE_REPRESENTATION places",
                "placed in its assembly's coordinates (no transformation)",
            );
        }
        for &brep in breps {
            if !placed.iter().any(|p| p.brep == brep) {
                self.src.warn(
                    "assembly",
                    brep,
                    "solid the assembly's product structure does not use",
                    "ignored",
                );
            }
        }
        same_unit(self.src, &jobs)?;
        Ok(jobs)
    }
}

/// Solids in different length units are refused: the model has one unit.
fn same_unit(src: &Source, jobs: &[SolidJob]) -> Result<()> {
    let Some(first) = jobs.first() else {
        return Ok(());
    };
    match jobs
        .iter()
        .find(|j| (j.unit.mm - first.unit.mm).abs() > 1e-12 * first.unit.mm)
    {
        Some(other) => Err(model_err(
            src.path,
            format!(
                "solids in different length units ({} and {}) are not supported",
                first.unit.name, other.unit.name
            ),
        )),
        None => Ok(()),
    }
}

impl Walk<'_> {
    fn build_solid(&mut self, instance: usize, job: &SolidJob) -> Result<()> {
        let recs = self.src.recs;
        let rec = recs
            .simple(job.brep)
            .expect("brep id came from the records");
        let p = params(rec);
        let name = p.first().map(as_string).unwrap_or_default();
        let outer = match job.shell {
            Some(shell) => shell,
            None => self
                .src
                .param(job.brep, p, 1, as_ref, "outer shell missing")?,
        };
        let voids = if rec.name == "BREP_WITH_VOIDS" {
            self.src
                .param(job.brep, p, 2, as_refs, "void shell list unreadable")?
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
            instance: job.path.clone(),
            shells: vec![],
        });
        let open_allowed = job.shell.is_some();
        for (k, shell) in std::iter::once(outer).chain(voids).enumerate() {
            let idx = self.build_shell(shell, solid, k > 0, open_allowed, instance, &m)?;
            self.model.solids[solid].shells.push(idx);
        }
        Ok(())
    }

    fn build_shell(
        &mut self,
        id: u64,
        solid: usize,
        is_void: bool,
        open_allowed: bool,
        instance: usize,
        m: &Mat4,
    ) -> Result<usize> {
        let recs = self.src.recs;
        let rec = recs
            .simple(id)
            .ok_or_else(|| self.src.err(id, "expected a shell"))?;
        let (shell_id, orientation) = match rec.name.as_str() {
            "CLOSED_SHELL" => (id, true),
            "OPEN_SHELL" if open_allowed => (id, true),
            "ORIENTED_CLOSED_SHELL" => {
                let p = params(rec);
                let inner = self.src.param(id, p, 2, as_ref, "shell element missing")?;
                let o = self.src.param(id, p, 3, as_bool, "orientation missing")?;
                (inner, o)
            }
            "OPEN_SHELL" | "ORIENTED_OPEN_SHELL" => {
                return Err(self.src.err(id, "open shell: the solid is not closed"))
            }
            _ => return Err(self.src.err(id, "expected CLOSED_SHELL")),
        };
        let srec = recs
            .simple(shell_id)
            .filter(|r| r.name == "CLOSED_SHELL" || (open_allowed && r.name == "OPEN_SHELL"))
            .ok_or_else(|| self.src.err(shell_id, "expected CLOSED_SHELL"))?;
        let faces = self
            .src
            .param(shell_id, params(srec), 1, as_refs, "face list unreadable")?;
        if faces.is_empty() {
            return Err(self.src.err(shell_id, "shell has no faces"));
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
                return Err(self.src.err(
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
        let recs = self.src.recs;
        let rec = recs
            .simple(id)
            .ok_or_else(|| self.src.err(id, "expected a face"))?;
        let (face_id, face_sign) = match rec.name.as_str() {
            "ADVANCED_FACE" | "FACE_SURFACE" => (id, 1.0),
            "ORIENTED_FACE" => {
                let p = params(rec);
                let inner = self.src.param(id, p, 2, as_ref, "face element missing")?;
                let o = p.get(3).and_then(as_bool).unwrap_or(true);
                (inner, if o { 1.0 } else { -1.0 })
            }
            _ => return Err(self.src.err(id, "expected ADVANCED_FACE")),
        };
        let frec = recs
            .simple(face_id)
            .filter(|r| r.name == "ADVANCED_FACE" || r.name == "FACE_SURFACE")
            .ok_or_else(|| self.src.err(face_id, "expected ADVANCED_FACE"))?;
        let p = params(frec);
        let bounds = self
            .src
            .param(face_id, p, 1, as_refs, "bounds unreadable")?;
        let geometry = self.src.param(face_id, p, 2, as_ref, "surface missing")?;
        let same_sense = self
            .src
            .param(face_id, p, 3, as_bool, "same_sense missing")?;
        let surface = self.src.convert_surface(geometry, m)?;
        let index = self.model.faces.len();
        let mut loops = Vec::new();
        let mut outer = None;
        for b in bounds {
            let brec = recs
                .simple(b)
                .ok_or_else(|| self.src.err(b, "expected FACE_BOUND"))?;
            if brec.name != "FACE_BOUND" && brec.name != "FACE_OUTER_BOUND" {
                return Err(self.src.err(b, "expected FACE_BOUND"));
            }
            let bp = params(brec);
            let lp = self.src.param(b, bp, 1, as_ref, "loop missing")?;
            let orientation = self.src.param(b, bp, 2, as_bool, "orientation missing")?;
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
            domain: EMPTY_DOMAIN,
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
        let recs = self.src.recs;
        let rec = recs
            .simple(id)
            .ok_or_else(|| self.src.err(id, "expected EDGE_LOOP"))?;
        match rec.name.as_str() {
            "VERTEX_LOOP" => {
                let v = self
                    .src
                    .param(id, params(rec), 1, as_ref, "vertex missing")?;
                let vi = self.vertex(v, instance, m)?;
                Ok(Loop {
                    source_id: id,
                    edges: vec![],
                    vertex: Some(vi),
                    uv: vec![],
                    uv_counts: vec![],
                    outline: vec![],
                    gap_mm: 0.0,
                })
            }
            "EDGE_LOOP" => {
                let oes = self
                    .src
                    .param(id, params(rec), 1, as_refs, "edge list unreadable")?;
                if oes.is_empty() {
                    return Err(self.src.err(id, "empty edge loop"));
                }
                let mut edges = Vec::with_capacity(oes.len());
                for oe in oes {
                    let orec = recs
                        .simple(oe)
                        .ok_or_else(|| self.src.err(oe, "expected ORIENTED_EDGE"))?;
                    let (ec, forward) = match orec.name.as_str() {
                        "ORIENTED_EDGE" => {
                            let op = params(orec);
                            let ec = self.src.param(oe, op, 3, as_ref, "edge element missing")?;
                            let o = self.src.param(oe, op, 4, as_bool, "orientation missing")?;
                            (ec, o)
                        }
                        "EDGE_CURVE" => (oe, true),
                        _ => return Err(self.src.err(oe, "expected ORIENTED_EDGE")),
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
                        return Err(self
                            .src
                            .err(id, "edges of the loop do not connect end to start"));
                    }
                }
                Ok(Loop {
                    source_id: id,
                    edges,
                    vertex: None,
                    uv: vec![],
                    uv_counts: vec![],
                    outline: vec![],
                    gap_mm: 0.0,
                })
            }
            "POLY_LOOP" => Err(self
                .src
                .err(id, "POLY_LOOP (faceted B-rep) is not supported")),
            _ => Err(self.src.err(id, "expected EDGE_LOOP or VERTEX_LOOP")),
        }
    }

    fn vertex(&mut self, id: u64, instance: usize, m: &Mat4) -> Result<usize> {
        if let Some(&v) = self.vertex_map.get(&(id, instance)) {
            return Ok(v);
        }
        let recs = self.src.recs;
        let rec = recs
            .simple(id)
            .filter(|r| r.name == "VERTEX_POINT")
            .ok_or_else(|| self.src.err(id, "expected VERTEX_POINT"))?;
        let pid = self
            .src
            .param(id, params(rec), 1, as_ref, "point missing")?;
        let c = recs
            .coordinates(pid, PointKind::CartesianPoint)
            .ok_or_else(|| self.src.err(pid, "expected CARTESIAN_POINT"))?;
        if c.len() != 3 || c.iter().any(|x| !x.is_finite()) {
            return Err(self.src.err(pid, "needs three finite coordinates"));
        }
        let point = apply(m, DVec3::new(c[0], c[1], c[2]));
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
        let recs = self.src.recs;
        let rec = recs
            .simple(id)
            .filter(|r| r.name == "EDGE_CURVE")
            .ok_or_else(|| self.src.err(id, "expected EDGE_CURVE"))?;
        let p = params(rec);
        let v0 = self.src.param(id, p, 1, as_ref, "start vertex missing")?;
        let v1 = self.src.param(id, p, 2, as_ref, "end vertex missing")?;
        let geometry = self.src.param(id, p, 3, as_ref, "curve missing")?;
        let a = self.vertex(v0, instance, m)?;
        let b = self.vertex(v1, instance, m)?;
        let curve = self.src.convert_edge_curve(id, geometry, m)?;
        let ends = (self.model.vertices[a].point, self.model.vertices[b].point);
        let range = self.src.edge_range(id, &curve, ends, a == b)?;
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
}
