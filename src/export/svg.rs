//! The picture `<stem>.mat.svg`: the part's edges and its medial axis from three orthographic
//! views and one isometric view, for a design review.
//!
//! Layout (a 1400 × 1000 user-unit page, `viewBox` so it scales): a 2 × 2 grid of panels in
//! **third-angle projection** — TOP above FRONT, RIGHT to the right of FRONT, the ISOMETRIC
//! view in the free corner — a legend column on the right (colour bar of the seam radius,
//! symbols, scale bar) and a title block along the bottom (file, counts, accuracy).
//!
//! Views, with `(u, v)` the picture's right and up directions and the viewer on the `toward`
//! side:
//! - FRONT: `u = x`, `v = z`, seen from −y (looking along +y);
//! - TOP: `u = x`, `v = y`, seen from +z (looking along −z);
//! - RIGHT: `u = y`, `v = z`, seen from +x (looking along −x);
//! - ISOMETRIC: seen from `(1, −1, 1)`, `u = (1, 1, 0)/√2`, `v = (−1, 1, 2)/√6`, so the front
//!   (−y), right (+x) and top (+z) faces of the part are the visible ones.
//!
//! Model `v` (z or y) points up in the picture: SVG's y axis is flipped. The three
//! orthographic views share one scale and are centred in their cells; the grid's columns and
//! rows are sized to what the views need (at least [`MIN_SPLIT`] each), and the cells of a
//! column share their x, those of a row their y, so FRONT and TOP line up in x and FRONT and
//! RIGHT in z, as a drawing must. The isometric view is fitted to its cell at its own scale
//! and carries its own scale bar.
//!
//! The picture is a wireframe (the medial axis is inside the part, so hidden-line removal
//! would hide exactly what the picture is for). As a depth cue each part edge is grey by its
//! mean depth in the view — near edges dark, far edges light — and everything is drawn far
//! to near. Tangent (smooth) edges are drawn thinner. Curved faces also get their outlines
//! (silhouettes: where the normal is perpendicular to the view), found by marching squares on
//! `n · toward` over a grid of each face and placed on the exact surface, so a cylinder,
//! sphere or torus looks like one. An outline point lies on the surface, but where along the
//! surface it sits comes from linear interpolation on a [`SILHOUETTE_GRID`]² grid: close
//! enough to see, not a tolerance, and an outline loop smaller than a grid cell may be missed.
//! Seam edges of periodic faces (a cylinder's parameter seam) are not drawn.
//!
//! Curves are sampled from the exact geometry: lines by their ends, polylines by their
//! vertices, other curves by recursive midpoint subdivision until the curve is within a
//! fraction of a pixel of its chords; every polyline is then thinned per view by
//! Douglas–Peucker to [`SvgOptions::px_tol`] (D. Douglas, T. Peucker, "Algorithms for the
//! reduction of the number of points required to represent a digitized line or its
//! caricature", *The Canadian Cartographer* 10(2), 1973). The seam radius is quantised to
//! [`COLOUR_LEVELS`] levels of viridis; a seam is split into runs whose levels stay within one
//! of each other, each drawn in its middle level and thinned on its own, so thinning never
//! moves a colour by more than one level. Coordinates are written with one decimal (0.1 px):
//! the output is deterministic, byte for byte, for the same input.

use crate::classify::{Classification, EdgeKind};
use crate::error::Result;
use crate::geom::{eval_curve, eval_surface, surface_kind};
use crate::medial::{DegenerateKind, MedialAxis};
use crate::model::Model;
use glam::{DVec2, DVec3};
use std::fmt::Write as _;
use std::path::Path;
use truck_stepio::r#in::alias::Curve3D;

/// Page width in SVG user units (px at 100 %).
pub const PAGE_WIDTH: f64 = 1400.0;
/// Page height in SVG user units.
pub const PAGE_HEIGHT: f64 = 1000.0;
/// Default thinning tolerance: points within this distance (px) of the drawn chord are dropped.
pub const DEFAULT_PX_TOL: f64 = 0.25;
/// Default largest number of junctions whose ids are written in the isometric view.
pub const DEFAULT_MAX_JUNCTION_LABELS: usize = 30;
/// Number of distinct seam colours (the radius range is quantised to this many levels).
pub const COLOUR_LEVELS: usize = 24;
/// Largest depth of the midpoint subdivision of a curved edge (2^12 pieces per interval at
/// most).
const MAX_SUBDIVISION_DEPTH: u32 = 12;

const MARGIN: f64 = 12.0;
const LEGEND_WIDTH: f64 = 230.0;
const TITLE_HEIGHT: f64 = 92.0;
const LABEL_BAND: f64 = 24.0;
/// Smallest share of the grid's width or height a column or row of panels gets.
pub const MIN_SPLIT: f64 = 0.4;
const INSET: f64 = 16.0;
const DEGENERATE_COLOUR: &str = "#d0109a";
const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";
/// Greys of a part edge from near to far.
const EDGE_GREYS: [&str; 4] = ["#262626", "#555555", "#858585", "#b0b0b0"];

/// Options of [`render_svg`].
#[derive(Clone, Debug)]
pub struct SvgOptions {
    /// The part's name in the title block (empty: the file name of the model's source).
    pub title: String,
    /// The trace's output accuracy (mm), written in the title block when known.
    pub accuracy: Option<f64>,
    /// Thinning tolerance in px: polyline points this close to the drawn chord are dropped.
    pub px_tol: f64,
    /// Junction ids are written in the isometric view when there are at most this many.
    pub max_junction_labels: usize,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            title: String::new(),
            accuracy: None,
            px_tol: DEFAULT_PX_TOL,
            max_junction_labels: DEFAULT_MAX_JUNCTION_LABELS,
        }
    }
}

/// A direction of view: the picture's right (`u`) and up (`v`) axes in model space, and the
/// direction toward the viewer.
#[derive(Clone, Copy, Debug)]
struct View {
    name: &'static str,
    /// What the view looks along, for the panel label.
    note: &'static str,
    u: DVec3,
    v: DVec3,
    toward: DVec3,
}

const FRONT: View = View {
    name: "FRONT",
    note: "looking along +y",
    u: DVec3::X,
    v: DVec3::Z,
    toward: DVec3::NEG_Y,
};
const TOP: View = View {
    name: "TOP",
    note: "looking along \u{2212}z",
    u: DVec3::X,
    v: DVec3::Y,
    toward: DVec3::Z,
};
const RIGHT: View = View {
    name: "RIGHT",
    note: "looking along \u{2212}x",
    u: DVec3::Y,
    v: DVec3::Z,
    toward: DVec3::X,
};

fn isometric() -> View {
    View {
        name: "ISOMETRIC",
        note: "from (1, \u{2212}1, 1)",
        u: DVec3::new(1.0, 1.0, 0.0).normalize(),
        v: DVec3::new(-1.0, 1.0, 2.0).normalize(),
        toward: DVec3::new(1.0, -1.0, 1.0).normalize(),
    }
}

/// A rectangle on the page.
#[derive(Clone, Copy, Debug)]
struct Rect {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

/// One view placed on the page: model point → page point.
#[derive(Clone, Copy, Debug)]
struct Panel {
    view: View,
    cell: Rect,
    /// px per mm.
    scale: f64,
    /// `(u, v)` of the model's bounding-box centre, drawn at `origin`.
    centre: DVec2,
    origin: DVec2,
    /// Depth (along `toward`) of the nearest and farthest bounding-box corner.
    depth_range: (f64, f64),
}

impl Panel {
    fn page_point(&self, p: DVec3) -> DVec2 {
        let (u, v) = (p.dot(self.view.u), p.dot(self.view.v));
        DVec2::new(
            self.origin.x + (u - self.centre.x) * self.scale,
            self.origin.y - (v - self.centre.y) * self.scale,
        )
    }

    fn depth(&self, p: DVec3) -> f64 {
        p.dot(self.view.toward)
    }

    /// 0 at the nearest bounding-box corner, 1 at the farthest.
    fn farness(&self, p: DVec3) -> f64 {
        let (near, far) = self.depth_range;
        if near - far > 0.0 {
            ((near - self.depth(p)) / (near - far)).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

/// The four panels: FRONT, TOP, RIGHT, ISOMETRIC.
struct Layout {
    panels: [Panel; 4],
    legend: Rect,
    title: Rect,
}

fn corners(bbox: (DVec3, DVec3)) -> [DVec3; 8] {
    let (lo, hi) = bbox;
    std::array::from_fn(|k| {
        DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// `(u range, v range, centre, depth range)` of the bounding box in a view.
fn extent(view: &View, bbox: (DVec3, DVec3)) -> (DVec2, DVec2, (f64, f64)) {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    for c in corners(bbox) {
        let q = DVec2::new(c.dot(view.u), c.dot(view.v));
        lo = lo.min(q);
        hi = hi.max(q);
        let d = c.dot(view.toward);
        near = near.max(d);
        far = far.min(d);
    }
    (hi - lo, (lo + hi) * 0.5, (near, far))
}

fn layout(bbox: (DVec3, DVec3)) -> Layout {
    let grid_w = PAGE_WIDTH - 3.0 * MARGIN - LEGEND_WIDTH;
    let grid_h = PAGE_HEIGHT - 3.0 * MARGIN - TITLE_HEIGHT;
    // Split the grid where the orthographic views need it: the left column holds x (TOP,
    // FRONT), the right one y (RIGHT); the top row holds y (TOP), the bottom one z (FRONT,
    // RIGHT). Each column and row keeps at least MIN_SPLIT of the grid, so a flat part still
    // leaves the isometric view room. Cells of one column share their x, cells of one row
    // their y, so the views stay aligned.
    let size = (bbox.1 - bbox.0).max(DVec3::splat(1e-9));
    let split = |a: f64, b: f64| (a / (a + b)).clamp(MIN_SPLIT, 1.0 - MIN_SPLIT);
    let cw = [
        split(size.x, size.y) * grid_w,
        (1.0 - split(size.x, size.y)) * grid_w,
    ];
    let rh = [
        split(size.y, size.z) * grid_h,
        (1.0 - split(size.y, size.z)) * grid_h,
    ];
    let cell = |col: usize, row: usize| Rect {
        x: MARGIN + if col == 0 { 0.0 } else { cw[0] },
        y: MARGIN + if row == 0 { 0.0 } else { rh[0] },
        w: cw[col],
        h: rh[row],
    };
    // Third-angle: TOP above FRONT, RIGHT right of FRONT, ISOMETRIC in the free corner.
    let views = [FRONT, TOP, RIGHT, isometric()];
    let cells = [cell(0, 1), cell(0, 0), cell(1, 1), cell(1, 0)];
    let fit = |size: DVec2, c: Rect| {
        let size = size.max(DVec2::splat(1e-9));
        let (aw, ah) = (c.w - 2.0 * INSET, c.h - LABEL_BAND - 2.0 * INSET);
        (aw / size.x).min(ah / size.y)
    };
    let extents = views.map(|v| extent(&v, bbox));
    let ortho = (0..3)
        .map(|k| fit(extents[k].0, cells[k]))
        .fold(f64::INFINITY, f64::min);
    let panels = std::array::from_fn(|k| {
        let c = cells[k];
        Panel {
            view: views[k],
            cell: c,
            scale: if k < 3 { ortho } else { fit(extents[k].0, c) },
            centre: extents[k].1,
            origin: DVec2::new(c.x + c.w / 2.0, c.y + LABEL_BAND + (c.h - LABEL_BAND) / 2.0),
            depth_range: extents[k].2,
        }
    });
    Layout {
        panels,
        legend: Rect {
            x: PAGE_WIDTH - MARGIN - LEGEND_WIDTH,
            y: MARGIN,
            w: LEGEND_WIDTH,
            h: grid_h,
        },
        title: Rect {
            x: MARGIN,
            y: PAGE_HEIGHT - MARGIN - TITLE_HEIGHT,
            w: PAGE_WIDTH - 2.0 * MARGIN,
            h: TITLE_HEIGHT,
        },
    }
}

/// Samples an edge's exact curve over `range` so that the polyline is within `tol` (mm) of
/// the curve: lines by their ends, polylines by their vertices, others by midpoint
/// subdivision from 16 equal intervals (32 for a closed edge).
fn sample_curve(curve: &Curve3D, range: (f64, f64), closed: bool, tol: f64) -> Vec<DVec3> {
    let at = |t: f64| eval_curve(curve, t).p;
    let (t0, t1) = range;
    match curve {
        Curve3D::Line(_) => vec![at(t0), at(t1)],
        Curve3D::Polyline(_) => {
            let (a, b) = (t0.min(t1), t0.max(t1));
            let mut ts = vec![a];
            let mut k = a.floor() + 1.0;
            while k < b {
                ts.push(k);
                k += 1.0;
            }
            ts.push(b);
            if t0 > t1 {
                ts.reverse();
            }
            ts.into_iter().map(at).collect()
        }
        _ => {
            let n = if closed { 32 } else { 16 };
            let mut out = vec![at(t0)];
            for k in 0..n {
                let a = t0 + (t1 - t0) * k as f64 / n as f64;
                let b = t0 + (t1 - t0) * (k + 1) as f64 / n as f64;
                subdivide(&at, (a, at(a)), (b, at(b)), tol, 0, &mut out);
            }
            out
        }
    }
}

fn subdivide(
    at: &impl Fn(f64) -> DVec3,
    a: (f64, DVec3),
    b: (f64, DVec3),
    tol: f64,
    depth: u32,
    out: &mut Vec<DVec3>,
) {
    let tm = 0.5 * (a.0 + b.0);
    let m = at(tm);
    if depth < MAX_SUBDIVISION_DEPTH && distance_to_segment(m, a.1, b.1) > tol {
        subdivide(at, a, (tm, m), tol, depth + 1, out);
        subdivide(at, (tm, m), b, tol, depth + 1, out);
    } else {
        out.push(b.1);
    }
}

fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * s).distance(p)
}

fn distance_to_segment_2d(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * s).distance(p)
}

/// Grid size (per parameter direction) of the silhouette search on a curved face.
pub const SILHOUETTE_GRID: usize = 48;

/// A curved face sampled on a grid over its UV domain, for silhouettes.
struct FaceGrid {
    face: usize,
    u: (f64, f64),
    v: (f64, f64),
    /// Unit normals (orientation irrelevant) at the `(n + 1)²` nodes, row by row in v.
    normals: Vec<DVec3>,
}

/// Grids of every non-planar face (a plane has no silhouette).
fn face_grids(model: &Model) -> Vec<FaceGrid> {
    let n = SILHOUETTE_GRID;
    model
        .faces
        .iter()
        .enumerate()
        .filter(|(_, f)| surface_kind(&f.surface) != "plane")
        .map(|(i, f)| {
            let (u, v) = (f.domain.u, f.domain.v);
            let mut normals = Vec::with_capacity((n + 1) * (n + 1));
            for j in 0..=n {
                for k in 0..=n {
                    let (a, b) = (grid_at(u, k, n), grid_at(v, j, n));
                    let d = eval_surface(&f.surface, a, b);
                    normals.push(d.su.cross(d.sv).normalize_or_zero());
                }
            }
            FaceGrid {
                face: i,
                u,
                v,
                normals,
            }
        })
        .collect()
}

/// `x` moved at most 1e-9 of the range into `range`.
fn nudge_inside(x: f64, range: (f64, f64)) -> f64 {
    let (lo, hi) = (range.0.min(range.1), range.0.max(range.1));
    let e = 1e-9 * (hi - lo);
    x.clamp(lo + e, hi - e)
}

fn grid_at(range: (f64, f64), k: usize, n: usize) -> f64 {
    range.0 + (range.1 - range.0) * k as f64 / n as f64
}

/// The silhouettes (contour generators: where the surface normal is perpendicular to the
/// view direction) of the curved faces in `view`, as 3D polylines on the exact surfaces.
///
/// Marching squares on `n · toward` over each face's grid: a crossing is placed on a grid
/// edge by linear interpolation, evaluated on the surface, and kept when it lies in the
/// trimmed face; crossings are chained through the cells into polylines. A face seen
/// exactly edge-on (a cylinder along its axis) has `n · toward = 0` everywhere and no
/// silhouette apart from its boundary edges.
fn silhouettes(model: &Model, grids: &[FaceGrid], view: &View) -> Vec<Vec<DVec3>> {
    let n = SILHOUETTE_GRID;
    let node = |k: usize, j: usize| j * (n + 1) + k;
    // The view direction tilted by ~1e-7 rad, so that no grid node lies exactly on a
    // silhouette (where `n · toward = 0` the sign test cannot tell on which side of a node
    // the silhouette passes: a sphere's meridian u = 0 in the front view was lost).
    let toward = (view.toward + DVec3::new(3.1e-8, 7.3e-8, 5.9e-8)).normalize();
    let mut out = vec![];
    for grid in grids {
        let face = &model.faces[grid.face];
        let g: Vec<f64> = grid.normals.iter().map(|q| q.dot(toward)).collect();
        if g.iter().all(|x| x.abs() < 1e-6) {
            continue;
        }
        // Crossing on the grid edge `key`: 2·node for the edge to the next u, 2·node + 1
        // for the edge to the next v.
        let mut crossing: Vec<Option<DVec3>> = vec![None; 2 * (n + 1) * (n + 1)];
        for j in 0..=n {
            for k in 0..=n {
                let a = node(k, j);
                for (dir, (k2, j2)) in [(0, (k + 1, j)), (1, (k, j + 1))] {
                    if k2 > n || j2 > n {
                        continue;
                    }
                    let b = node(k2, j2);
                    if (g[a] > 0.0) == (g[b] > 0.0) {
                        continue;
                    }
                    let t = g[a] / (g[a] - g[b]);
                    let uv = DVec2::new(
                        grid_at(grid.u, k, n)
                            + t * (grid_at(grid.u, k2, n) - grid_at(grid.u, k, n)),
                        grid_at(grid.v, j, n)
                            + t * (grid_at(grid.v, j2, n) - grid_at(grid.v, j, n)),
                    );
                    // A crossing on the domain's border (a sphere's meridian u = 0) is
                    // tested a hair inside it: the trimming test may leave the border out.
                    let inner = DVec2::new(nudge_inside(uv.x, grid.u), nudge_inside(uv.y, grid.v));
                    if crate::geom::trim::contains(face, inner) {
                        crossing[2 * a + dir] =
                            Some(crate::geom::surface_point(&face.surface, uv.x, uv.y));
                    }
                }
            }
        }
        // Segments through the cells, as pairs of edge keys.
        let mut links: Vec<Vec<usize>> = vec![vec![]; crossing.len()];
        for j in 0..n {
            for k in 0..n {
                let sides = [
                    2 * node(k, j),
                    2 * node(k, j) + 1,
                    2 * node(k, j + 1),
                    2 * node(k + 1, j) + 1,
                ];
                let hit: Vec<usize> = sides
                    .into_iter()
                    .filter(|&e| crossing[e].is_some())
                    .collect();
                for pair in hit.chunks_exact(2) {
                    links[pair[0]].push(pair[1]);
                    links[pair[1]].push(pair[0]);
                }
            }
        }
        // Chains: from the ends first, then what is left (closed loops).
        let mut used = vec![false; crossing.len()];
        let starts = (0..links.len())
            .filter(|&e| links[e].len() == 1)
            .chain(0..links.len());
        for start in starts {
            if used[start] || links[start].is_empty() {
                continue;
            }
            let mut chain = vec![];
            let mut at = start;
            loop {
                used[at] = true;
                chain.push(crossing[at].unwrap());
                match links[at].iter().find(|&&e| !used[e]) {
                    Some(&next) => at = next,
                    None => {
                        if links[at].contains(&start) && chain.len() > 2 {
                            chain.push(crossing[start].unwrap());
                        }
                        break;
                    }
                }
            }
            if chain.len() >= 2 {
                out.push(chain);
            }
        }
    }
    out
}

/// Douglas–Peucker thinning: the points of `pts` farther than `tol` from the chords of the
/// kept points, with both ends always kept.
fn thin(pts: &[DVec2], tol: f64) -> Vec<DVec2> {
    if pts.len() <= 2 {
        return pts.to_vec();
    }
    let mut keep = vec![false; pts.len()];
    keep[0] = true;
    keep[pts.len() - 1] = true;
    let mut stack = vec![(0, pts.len() - 1)];
    while let Some((i, j)) = stack.pop() {
        let mut worst = (0.0, 0);
        for k in i + 1..j {
            let d = distance_to_segment_2d(pts[k], pts[i], pts[j]);
            if d > worst.0 {
                worst = (d, k);
            }
        }
        if worst.0 > tol {
            keep[worst.1] = true;
            stack.push((i, worst.1));
            stack.push((worst.1, j));
        }
    }
    pts.iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(*p))
        .collect()
}

/// A number with at most one decimal, without a trailing `.0` or a negative zero.
fn num(x: f64) -> String {
    let r = (x * 10.0).round() / 10.0;
    // A non-finite number (a NaN from bad geometry) would make the file invalid SVG.
    if r == 0.0 || !r.is_finite() {
        return "0".into();
    }
    let s = format!("{r:.1}");
    s.strip_suffix(".0").map(str::to_owned).unwrap_or(s)
}

fn points_attr(pts: &[DVec2]) -> String {
    let mut s = String::with_capacity(pts.len() * 12);
    for (k, p) in pts.iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{},{}", num(p.x), num(p.y));
    }
    s
}

/// SVG path data of a polyline: `M x y L x y x y …`.
fn path_data(pts: &[DVec2]) -> String {
    let mut s = String::with_capacity(pts.len() * 12);
    for (k, p) in pts.iter().enumerate() {
        let _ = match k {
            0 => write!(s, "M{} {}", num(p.x), num(p.y)),
            1 => write!(s, "L{} {}", num(p.x), num(p.y)),
            _ => write!(s, " {} {}", num(p.x), num(p.y)),
        };
    }
    s
}

/// A length in mm for a label: about four significant digits, no trailing zeros.
fn mm(x: f64) -> String {
    let a = x.abs();
    let decimals = if a == 0.0 || a >= 100.0 {
        1
    } else if a >= 10.0 {
        2
    } else if a >= 1.0 {
        3
    } else {
        4
    };
    let s = format!("{x:.decimals$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// viridis (matplotlib's perceptually uniform map, S. van der Walt & N. Smith, 2015) at nine
/// stops, interpolated linearly in sRGB.
const VIRIDIS: [[u8; 3]; 9] = [
    [0x44, 0x01, 0x54],
    [0x47, 0x2d, 0x7b],
    [0x3b, 0x52, 0x8b],
    [0x2c, 0x72, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x28, 0xae, 0x80],
    [0x5e, 0xc9, 0x62],
    [0xad, 0xdc, 0x30],
    [0xfd, 0xe7, 0x25],
];
/// The part of viridis used: its last, light-yellow tenth is too faint on white.
const VIRIDIS_END: f64 = 0.9;

/// The colour of `t ∈ [0, 1]` (small radius dark blue, large radius yellow-green).
fn colour(t: f64) -> String {
    let x = t.clamp(0.0, 1.0) * VIRIDIS_END * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let c: [u8; 3] = std::array::from_fn(|k| {
        let (a, b) = (VIRIDIS[i][k] as f64, VIRIDIS[i + 1][k] as f64);
        (a + (b - a) * f).round() as u8
    });
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The radius range coloured, `(lo, hi)` with `hi > lo`.
#[derive(Clone, Copy, Debug)]
struct RadiusScale {
    lo: f64,
    hi: f64,
}

impl RadiusScale {
    fn of(mat: &MedialAxis) -> Option<RadiusScale> {
        let rs = mat
            .seams
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.point[3]))
            .chain(mat.junctions.iter().map(|j| j.radius))
            .filter(|r| r.is_finite());
        let (lo, hi) = rs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r), b.max(r))
        });
        if lo > hi {
            return None;
        }
        let hi = if hi - lo > 1e-12 * hi.abs().max(1.0) {
            hi
        } else {
            lo + hi.abs().max(1.0) * 1e-3
        };
        Some(RadiusScale { lo, hi })
    }

    fn t(&self, r: f64) -> f64 {
        ((r - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
    }

    /// The quantised colour level of `r`.
    fn level(&self, r: f64) -> usize {
        ((self.t(r) * COLOUR_LEVELS as f64) as usize).min(COLOUR_LEVELS - 1)
    }

    fn level_colour(level: usize) -> String {
        colour((level as f64 + 0.5) / COLOUR_LEVELS as f64)
    }
}

/// The largest of 1, 2, 5 × 10ᵏ not above `x`.
fn nice_floor(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|v| *v <= x * (1.0 + 1e-12))
        .unwrap_or(p)
}

/// About `n` round values inside `[lo, hi]`.
fn ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = nice_floor((hi - lo) / n as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// Renders the picture of `model` and its medial axis `mat` as an SVG document.
pub fn render_svg(
    model: &Model,
    class: &Classification,
    mat: &MedialAxis,
    opts: &SvgOptions,
) -> String {
    let lay = layout(model.bbox);
    let radius = RadiusScale::of(mat);
    let max_scale = lay.panels.iter().map(|p| p.scale).fold(0.0, f64::max);
    let curve_tol = 0.5 * opts.px_tol / max_scale.max(1e-12);
    let edges: Vec<Vec<DVec3>> = model
        .edges
        .iter()
        .map(|e| {
            // A seam edge (a cylinder's or sphere's parameter seam) is no edge of the part's
            // shape; the outlines show the face instead.
            if e.is_seam() {
                vec![]
            } else {
                sample_curve(&e.curve, e.range, e.is_closed(), curve_tol)
            }
        })
        .collect();
    let grids = face_grids(model);

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT}" font-size="12">"#,
        w = num(PAGE_WIDTH),
        h = num(PAGE_HEIGHT)
    );
    let title = if opts.title.is_empty() {
        Path::new(&model.source.path)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    } else {
        opts.title.clone()
    };
    let _ = writeln!(s, "<title>{} — medial axis</title>", escape(&title));
    // The seam colours, one class per level.
    s.push_str("<defs><style>");
    for l in 0..COLOUR_LEVELS {
        let _ = write!(s, ".c{l}{{stroke:{}}}", RadiusScale::level_colour(l));
    }
    s.push_str("</style></defs>\n");
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    for (k, panel) in lay.panels.iter().enumerate() {
        let outlines = silhouettes(model, &grids, &panel.view);
        draw_panel(
            &mut s,
            class,
            mat,
            &edges,
            &outlines,
            panel,
            radius,
            opts,
            k == 3,
        );
    }
    draw_legend(&mut s, mat, radius, &lay);
    draw_title_block(&mut s, model, mat, &title, opts, &lay);
    s.push_str("</svg>\n");
    s
}

#[allow(clippy::too_many_arguments)]
fn draw_panel(
    s: &mut String,
    class: &Classification,
    mat: &MedialAxis,
    edges: &[Vec<DVec3>],
    outlines: &[Vec<DVec3>],
    panel: &Panel,
    radius: Option<RadiusScale>,
    opts: &SvgOptions,
    is_iso: bool,
) {
    let c = panel.cell;
    let id = panel.view.name.to_ascii_lowercase();
    let _ = writeln!(s, r#"<g class="view" id="view-{id}">"#);
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#c8c8c8" stroke-width="1"/>"##,
        num(c.x + 3.0),
        num(c.y + 3.0),
        num(c.w - 6.0),
        num(c.h - 6.0)
    );
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{}" font-size="14" font-weight="bold" fill="#202020">{}<tspan dx="10" font-weight="normal" font-size="11" fill="#707070">{}</tspan></text>"##,
        num(c.x + 12.0),
        num(c.y + 21.0),
        panel.view.name,
        panel.view.note
    );

    // Part edges, grey by mean depth, in groups from far to near; tangent edges thinner.
    // Silhouettes of curved faces are drawn as edges (after the edges, numbered on).
    let mut groups: Vec<Vec<usize>> = vec![vec![]; 2 * EDGE_GREYS.len()];
    let lines: Vec<&Vec<DVec3>> = edges.iter().chain(outlines).collect();
    for (i, pts) in lines.iter().enumerate() {
        if pts.len() < 2 {
            continue;
        }
        let far = pts.iter().map(|p| panel.farness(*p)).sum::<f64>() / pts.len().max(1) as f64;
        let level = ((far * EDGE_GREYS.len() as f64) as usize).min(EDGE_GREYS.len() - 1);
        let smooth = class
            .edges
            .get(i)
            .is_some_and(|e| e.kind == EdgeKind::Smooth);
        groups[2 * (EDGE_GREYS.len() - 1 - level) + usize::from(!smooth)].push(i);
    }
    for (g, members) in groups.iter().enumerate() {
        if members.is_empty() {
            continue;
        }
        let smooth = g % 2 == 0;
        let _ = writeln!(
            s,
            r#"<g class="edges{}" fill="none" stroke="{}" stroke-width="{}" stroke-linecap="round" stroke-linejoin="round">"#,
            if smooth { " smooth" } else { "" },
            EDGE_GREYS[EDGE_GREYS.len() - 1 - g / 2],
            if smooth { "0.6" } else { "1.1" }
        );
        for &i in members {
            let px: Vec<DVec2> = lines[i].iter().map(|p| panel.page_point(*p)).collect();
            let _ = writeln!(s, r#"<path d="{}"/>"#, path_data(&thin(&px, opts.px_tol)));
        }
        s.push_str("</g>\n");
    }

    // Degenerate pieces: magenta, dashed through the sampled centres, a diamond at each
    // centre and the ball's outline.
    if !mat.degenerate.is_empty() {
        let _ = writeln!(
            s,
            r#"<g class="degenerates" fill="none" stroke="{DEGENERATE_COLOUR}">"#
        );
        for (k, d) in mat.degenerate.iter().enumerate() {
            let _ = writeln!(
                s,
                r#"<g class="degenerate" data-kind="{}">"#,
                escape(d.kind.as_str())
            );
            let _ = writeln!(
                s,
                "<title>degenerate {} {k} ({}): {} ball(s), r {}</title>",
                escape(d.kind.as_str()),
                escape(
                    &d.segments
                        .iter()
                        .map(|e| e.to_string())
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
                d.balls.len(),
                d.balls
                    .first()
                    .map(|b| mm(b[3]) + " mm")
                    .unwrap_or_default()
            );
            let centres: Vec<DVec2> = d
                .balls
                .iter()
                .map(|b| panel.page_point(DVec3::new(b[0], b[1], b[2])))
                .collect();
            if centres.len() >= 2 {
                let _ = writeln!(
                    s,
                    r#"<polyline points="{}" stroke-width="1.8" stroke-dasharray="6 3"/>"#,
                    points_attr(&thin(&centres, opts.px_tol))
                );
            }
            for (b, q) in d.balls.iter().zip(&centres) {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{}" cy="{}" r="{}" stroke-width="0.6" stroke-dasharray="3 3" opacity="0.7"/>"#,
                    num(q.x),
                    num(q.y),
                    num(b[3] * panel.scale)
                );
                let _ = writeln!(
                    s,
                    r#"<path d="M{} {}l4 4-4 4-4-4z" fill="{DEGENERATE_COLOUR}" stroke="none"/>"#,
                    num(q.x),
                    num(q.y - 4.0)
                );
            }
            s.push_str("</g>\n");
        }
        s.push_str("</g>\n");
    }

    // Seams, far to near, in runs of equal colour.
    if let Some(rs) = radius {
        let mut order: Vec<(f64, usize)> = mat
            .seams
            .iter()
            .enumerate()
            .map(|(i, seam)| {
                let d = seam
                    .points
                    .iter()
                    .map(|p| panel.farness(DVec3::new(p.point[0], p.point[1], p.point[2])))
                    .sum::<f64>()
                    / seam.points.len().max(1) as f64;
                (d, i)
            })
            .collect();
        order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let _ = writeln!(
            s,
            r#"<g class="seams" fill="none" stroke-width="2.2" stroke-linecap="round" stroke-linejoin="round">"#
        );
        for (_, i) in order {
            draw_seam(s, mat, i, panel, rs, opts);
        }
        s.push_str("</g>\n");

        let _ = writeln!(
            s,
            r##"<g class="junctions" stroke="#000000" stroke-width="0.9">"##
        );
        // Smaller dots when there are many, so that they do not hide the seams.
        let dot = if mat.junctions.len() > 40 {
            "2.8"
        } else {
            "3.6"
        };
        for j in &mat.junctions {
            let q = panel.page_point(DVec3::from_array(j.point));
            let _ = writeln!(
                s,
                r#"<circle class="junction" cx="{}" cy="{}" r="{dot}" fill="{}"><title>junction {} · r {} mm</title></circle>"#,
                num(q.x),
                num(q.y),
                colour(rs.t(j.radius)),
                j.id,
                mm(j.radius)
            );
        }
        s.push_str("</g>\n");
        if is_iso && !mat.junctions.is_empty() && mat.junctions.len() <= opts.max_junction_labels {
            draw_junction_labels(s, mat, panel);
        }
    }
    if is_iso {
        draw_scale_bar(s, panel.scale, c.x + c.w - 20.0, c.y + c.h - 22.0, "", true);
    }
    draw_axes(s, panel);
    s.push_str("</g>\n");
}

fn draw_seam(
    s: &mut String,
    mat: &MedialAxis,
    i: usize,
    panel: &Panel,
    rs: RadiusScale,
    opts: &SvgOptions,
) {
    let seam = &mat.seams[i];
    let (rlo, rhi) = seam
        .points
        .iter()
        .map(|p| p.point[3])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r), b.max(r))
        });
    let _ = writeln!(
        s,
        r#"<g class="seam" data-seam="{}"><title>seam {} · r {}–{} mm · {} points</title>"#,
        seam.id,
        seam.id,
        mm(rlo),
        mm(rhi),
        seam.points.len()
    );
    let px: Vec<DVec2> = seam
        .points
        .iter()
        .map(|p| panel.page_point(DVec3::new(p.point[0], p.point[1], p.point[2])))
        .collect();
    if px.len() == 1 {
        let _ = write!(
            s,
            r#"<circle cx="{}" cy="{}" r="1.5" fill="{}" stroke="none"/>"#,
            num(px[0].x),
            num(px[0].y),
            colour(rs.t(seam.points[0].point[3]))
        );
    }
    // Segment k joins points k and k + 1 and takes the level of its mean radius; a run of
    // segments whose levels stay within one of its first is drawn in its middle level.
    let level = |k: usize| rs.level(0.5 * (seam.points[k].point[3] + seam.points[k + 1].point[3]));
    let mut start = 0;
    while start + 1 < px.len() {
        let first = level(start);
        let (mut lo, mut hi) = (first, first);
        let mut end = start + 1;
        while end + 1 < px.len() && level(end).abs_diff(first) <= 1 {
            lo = lo.min(level(end));
            hi = hi.max(level(end));
            end += 1;
        }
        let _ = write!(
            s,
            r#"<path class="c{}" d="{}"/>"#,
            (lo + hi).div_ceil(2),
            path_data(&thin(&px[start..=end], opts.px_tol))
        );
        start = end;
    }
    s.push_str("</g>\n");
}

/// Junction ids beside their dots, skipping a label that would overlap one already placed.
fn draw_junction_labels(s: &mut String, mat: &MedialAxis, panel: &Panel) {
    let _ = writeln!(
        s,
        r##"<g class="junction-labels" font-size="10" fill="#303030">"##
    );
    let mut placed: Vec<DVec2> = vec![];
    for j in &mat.junctions {
        let q = panel.page_point(DVec3::from_array(j.point)) + DVec2::new(5.0, -5.0);
        if placed
            .iter()
            .any(|p| (p.x - q.x).abs() < 22.0 && (p.y - q.y).abs() < 11.0)
        {
            continue;
        }
        placed.push(q);
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}">J{}</text>"#,
            num(q.x),
            num(q.y),
            j.id
        );
    }
    s.push_str("</g>\n");
}

/// The model axes as seen in the panel, in the top right corner (inside the label band and
/// the inset above the drawing, so it never covers the part).
fn draw_axes(s: &mut String, panel: &Panel) {
    let o = DVec2::new(panel.cell.x + panel.cell.w - 42.0, panel.cell.y + 28.0);
    let _ = writeln!(
        s,
        r##"<g class="axes" stroke="#606060" stroke-width="1" fill="#606060" font-size="10">"##
    );
    for (name, axis) in [("x", DVec3::X), ("y", DVec3::Y), ("z", DVec3::Z)] {
        let d = DVec2::new(axis.dot(panel.view.u), -axis.dot(panel.view.v));
        if d.length() < 0.2 {
            continue;
        }
        let e = o + d * 14.0;
        let t = o + d * 21.0;
        let _ = writeln!(
            s,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}"/><text x="{}" y="{}" stroke="none" text-anchor="middle" dominant-baseline="central">{name}</text>"#,
            num(o.x),
            num(o.y),
            num(e.x),
            num(e.y),
            num(t.x),
            num(t.y)
        );
    }
    s.push_str("</g>\n");
}

/// A scale bar of a round length 50–130 px long, labelled above its middle; its left end at
/// `x`, or its right end when `right` is set.
fn draw_scale_bar(s: &mut String, scale: f64, x: f64, y: f64, caption: &str, right: bool) {
    let len = nice_floor(130.0 / scale);
    let w = len * scale;
    let x = if right { x - w } else { x };
    let _ = writeln!(
        s,
        r##"<g class="scale-bar" font-size="11" fill="#202020"><rect x="{}" y="{}" width="{}" height="5" fill="#202020"/><rect x="{}" y="{}" width="{}" height="5" fill="#ffffff" stroke="#202020" stroke-width="0.8"/><text x="{}" y="{}" text-anchor="middle">{} mm</text>{}</g>"##,
        num(x),
        num(y),
        num(w / 2.0),
        num(x + w / 2.0),
        num(y),
        num(w / 2.0),
        num(x + w / 2.0),
        num(y - 4.0),
        mm(len),
        if caption.is_empty() {
            String::new()
        } else {
            format!(
                r##"<text x="{}" y="{}" font-size="10" fill="#606060">{}</text>"##,
                num(x),
                num(y + 17.0),
                escape(caption)
            )
        }
    );
}

fn draw_legend(s: &mut String, mat: &MedialAxis, radius: Option<RadiusScale>, lay: &Layout) {
    let r = lay.legend;
    let x = r.x + 14.0;
    let _ = writeln!(s, r#"<g class="legend">"#);
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#c8c8c8"/>"##,
        num(r.x + 3.0),
        num(r.y + 3.0),
        num(r.w - 6.0),
        num(r.h - 6.0)
    );
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{}" font-size="14" font-weight="bold" fill="#202020">MEDIAL AXIS</text>"##,
        num(x),
        num(r.y + 26.0)
    );
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{}" font-size="12" fill="#202020">seam ball radius r (mm)</text>"##,
        num(x),
        num(r.y + 50.0)
    );
    // Colour bar: vertical, small radii at the bottom.
    let (bx, by, bw, bh) = (x, r.y + 62.0, 20.0, 300.0);
    match radius {
        Some(rs) => {
            let _ = writeln!(s, r#"<g class="colour-bar">"#);
            for l in 0..COLOUR_LEVELS {
                let h = bh / COLOUR_LEVELS as f64;
                let _ = writeln!(
                    s,
                    r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{}"/>"#,
                    num(bx),
                    num(by + bh - (l + 1) as f64 * h),
                    num(bw),
                    num(h + 0.4),
                    RadiusScale::level_colour(l)
                );
            }
            let _ = writeln!(
                s,
                r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#404040" stroke-width="0.8"/>"##,
                num(bx),
                num(by),
                num(bw),
                num(bh)
            );
            let y_of = |v: f64| by + bh - rs.t(v) * bh;
            // Round ticks with as many decimals as their step needs; the range's ends with
            // one more, so that a narrow range (4 to 4.004 mm) reads as such.
            let step = nice_floor((rs.hi - rs.lo) / 5.0);
            let decimals = (-step.log10()).ceil().clamp(0.0, 6.0) as usize;
            let label = |v: f64, d: usize| {
                let s = format!("{v:.d$}");
                let s = if s.contains('.') {
                    s.trim_end_matches('0').trim_end_matches('.')
                } else {
                    &s
                };
                if s == "-0" {
                    "0".to_owned()
                } else {
                    s.to_owned()
                }
            };
            let mut marks = vec![(rs.lo, true), (rs.hi, true)];
            for t in ticks(rs.lo, rs.hi, 5) {
                // Skip round ticks crowding the range's ends.
                if (y_of(t) - y_of(rs.lo)).abs() > 16.0 && (y_of(t) - y_of(rs.hi)).abs() > 16.0 {
                    marks.push((t, false));
                }
            }
            for (v, end) in marks {
                let y = y_of(v);
                let _ = writeln!(
                    s,
                    r##"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#404040" stroke-width="0.8"/><text x="{}" y="{}" font-size="11" fill="#202020"{}>{}</text>"##,
                    num(bx + bw),
                    num(bx + bw + 5.0),
                    num(bx + bw + 8.0),
                    num(y + 4.0),
                    if end { r#" font-weight="bold""# } else { "" },
                    label(v, decimals + usize::from(end)),
                    y = num(y)
                );
            }
            s.push_str("</g>\n");
        }
        None => {
            let _ = writeln!(
                s,
                r##"<text x="{}" y="{}" font-size="11" fill="#707070">no seams traced</text>"##,
                num(bx),
                num(by + 14.0)
            );
        }
    }

    // Symbols.
    let mut y = by + bh + 40.0;
    let item = |s: &mut String, y: f64, symbol: String, text: String| {
        let _ = writeln!(
            s,
            r##"{symbol}<text x="{}" y="{}" font-size="11" fill="#202020">{}</text>"##,
            num(x + 40.0),
            num(y + 4.0),
            escape(&text)
        );
    };
    let line = |y: f64, stroke: &str, width: &str, dash: &str| {
        format!(
            r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{stroke}" stroke-width="{width}"{dash}/>"#,
            num(x),
            num(x + 30.0),
            y = num(y)
        )
    };
    let mid = colour(0.5);
    item(
        s,
        y,
        line(y, &mid, "2.2", ""),
        format!("seam, coloured by r ({})", mat.seams.len()),
    );
    y += 20.0;
    item(
        s,
        y,
        format!(
            r##"<circle cx="{}" cy="{}" r="3.6" fill="{}" stroke="#000000" stroke-width="0.9"/>"##,
            num(x + 15.0),
            num(y),
            mid
        ),
        format!("junction ({})", mat.junctions.len()),
    );
    y += 20.0;
    item(
        s,
        y,
        format!(
            r#"{}<path d="M{} {}l4 4-4 4-4-4z" fill="{DEGENERATE_COLOUR}"/>"#,
            line(y, DEGENERATE_COLOUR, "1.8", r#" stroke-dasharray="6 3""#),
            num(x + 15.0),
            num(y - 4.0)
        ),
        format!(
            "degenerate curve ({})",
            mat.degenerate
                .iter()
                .filter(|d| d.kind == DegenerateKind::Curve)
                .count()
        ),
    );
    y += 20.0;
    item(
        s,
        y,
        format!(
            r#"<circle cx="{}" cy="{}" r="8" fill="none" stroke="{DEGENERATE_COLOUR}" stroke-width="0.6" stroke-dasharray="3 3"/><path d="M{} {}l4 4-4 4-4-4z" fill="{DEGENERATE_COLOUR}"/>"#,
            num(x + 15.0),
            num(y),
            num(x + 15.0),
            num(y - 4.0)
        ),
        format!(
            "degenerate point ({})",
            mat.degenerate
                .iter()
                .filter(|d| d.kind != DegenerateKind::Curve)
                .count()
        ),
    );
    y += 16.0;
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{}" font-size="10" fill="#707070">dashed circle: its maximal ball</text>"##,
        num(x + 40.0),
        num(y + 4.0)
    );
    y += 26.0;
    item(
        s,
        y,
        line(y, EDGE_GREYS[0], "1.1", ""),
        "edge or outline, near side".into(),
    );
    y += 20.0;
    item(
        s,
        y,
        line(y, EDGE_GREYS[3], "1.1", ""),
        "edge or outline, far side".into(),
    );
    y += 20.0;
    item(
        s,
        y,
        line(y, EDGE_GREYS[0], "0.6", ""),
        "tangent edge".into(),
    );
    y += 44.0;
    draw_scale_bar(
        s,
        lay.panels[0].scale,
        x,
        y,
        "front, top, right views",
        false,
    );
    s.push_str("</g>\n");
}

fn draw_title_block(
    s: &mut String,
    model: &Model,
    mat: &MedialAxis,
    title: &str,
    opts: &SvgOptions,
    lay: &Layout,
) {
    let r = lay.title;
    let (lo, hi) = model.bbox;
    let size = hi - lo;
    let open = mat.seams.iter().filter(|s| s.is_open()).count();
    let curves = mat
        .degenerate
        .iter()
        .filter(|d| d.kind == DegenerateKind::Curve)
        .count();
    let cells: [(&str, f64, Vec<String>); 4] = [
        (
            "PART",
            0.34,
            vec![
                title.to_owned(),
                format!("{} × {} × {} mm", mm(size.x), mm(size.y), mm(size.z)),
            ],
        ),
        (
            "MODEL",
            0.2,
            vec![
                format!(
                    "{} · {}",
                    plural(model.solids.len(), "solid"),
                    plural(model.faces.len(), "face")
                ),
                format!(
                    "{} · {}",
                    plural(model.edges.len(), "edge"),
                    plural(model.vertices.len(), "vertex")
                ),
            ],
        ),
        (
            "MEDIAL AXIS",
            0.24,
            vec![
                format!("{} seams ({open} open)", mat.seams.len()),
                format!(
                    "{} junctions · {} degenerate ({} curve, {} point)",
                    mat.junctions.len(),
                    mat.degenerate.len(),
                    curves,
                    mat.degenerate.len() - curves
                ),
            ],
        ),
        (
            "ACCURACY",
            0.22,
            vec![
                opts.accuracy
                    .map(|a| format!("{a:.1e} mm"))
                    .unwrap_or_else(|| "not given".into()),
                format!("worst residual {:.1e} mm", mat.stats.worst_residual),
            ],
        ),
    ];
    let _ = writeln!(s, r##"<g class="title-block" fill="#202020">"##);
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#404040" stroke-width="1.2"/>"##,
        num(r.x + 3.0),
        num(r.y),
        num(r.w - 6.0),
        num(r.h - 26.0)
    );
    let mut cx = r.x + 3.0;
    for (k, (caption, frac, lines)) in cells.iter().enumerate() {
        let w = frac * (r.w - 6.0);
        if k > 0 {
            let _ = writeln!(
                s,
                r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#404040" stroke-width="0.8"/>"##,
                num(r.y),
                num(r.y + r.h - 26.0),
                x = num(cx)
            );
        }
        let _ = writeln!(
            s,
            r##"<text x="{}" y="{}" font-size="9" fill="#707070" letter-spacing="0.5">{caption}</text>"##,
            num(cx + 8.0),
            num(r.y + 13.0)
        );
        for (i, line) in lines.iter().enumerate() {
            let big = k == 0 && i == 0;
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" font-size="{}"{}>{}</text>"#,
                num(cx + 8.0),
                num(r.y + 32.0 + 19.0 * i as f64),
                if big { 15 } else { 12 },
                if big { r#" font-weight="bold""# } else { "" },
                escape(line)
            );
        }
        cx += w;
    }
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{}" font-size="11" fill="#505050">Third-angle projection · dimensions in mm · wireframe, far edges lighter · matrace {}</text>"##,
        num(r.x + 11.0),
        num(r.y + r.h - 8.0),
        env!("CARGO_PKG_VERSION")
    );
    s.push_str("</g>\n");
}

/// `n` and `noun`, in the plural unless `n` is 1 (`vertex` → `vertices`).
fn plural(n: usize, noun: &str) -> String {
    match (n, noun) {
        (1, _) => format!("1 {noun}"),
        (_, "vertex") => format!("{n} vertices"),
        _ => format!("{n} {noun}s"),
    }
}

/// Writes `svg` to `path` atomically: into a temporary file in the same folder, then renamed
/// over `path`, so a reader never sees a half-written picture.
pub fn write_svg(path: &Path, svg: &str) -> Result<()> {
    super::write_atomic(path, svg.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medial::{trace, SeamEnd, TraceOptions};

    fn traced(name: &str) -> (Model, Classification, MedialAxis) {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("samples")
            .join(name);
        let m = crate::ingest::read_model(&p).unwrap();
        let c = crate::classify(&m, &Default::default());
        let mat = trace(&m, &c, &TraceOptions::for_model(&m));
        (m, c, mat)
    }

    fn picture(name: &str) -> String {
        let (m, c, mat) = traced(name);
        render_svg(&m, &c, &mat, &SvgOptions::default())
    }

    fn has_class(n: &roxmltree::Node, class: &str) -> bool {
        n.attribute("class")
            .is_some_and(|c| c.split_whitespace().any(|w| w == class))
    }

    fn count(n: roxmltree::Node, tag: &str, class: &str) -> usize {
        n.descendants()
            .filter(|d| d.has_tag_name(tag) && has_class(d, class))
            .count()
    }

    fn views<'a>(doc: &'a roxmltree::Document) -> Vec<roxmltree::Node<'a, 'a>> {
        doc.descendants()
            .filter(|n| n.has_tag_name("g") && has_class(n, "view"))
            .collect()
    }

    #[test]
    fn box_picture_is_xml_with_every_seam_and_junction_in_every_view() {
        let (m, c, mat) = traced("box.step");
        assert_eq!((mat.seams.len(), mat.junctions.len()), (12, 4));
        let svg = render_svg(&m, &c, &mat, &SvgOptions::default());
        let doc = roxmltree::Document::parse(&svg).expect("the picture is well-formed XML");
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert_eq!(root.attribute("viewBox"), Some("0 0 1400 1000"));
        let vs = views(&doc);
        let ids: Vec<_> = vs.iter().filter_map(|v| v.attribute("id")).collect();
        assert_eq!(
            ids,
            ["view-front", "view-top", "view-right", "view-isometric"]
        );
        for v in &vs {
            assert_eq!(count(*v, "g", "seam"), 12, "{:?}", v.attribute("id"));
            assert_eq!(
                count(*v, "circle", "junction"),
                4,
                "{:?}",
                v.attribute("id")
            );
            // Every seam has at least one drawn piece, coloured by a level class.
            for seam in v
                .descendants()
                .filter(|n| n.has_tag_name("g") && has_class(n, "seam"))
            {
                let pieces: Vec<_> = seam.children().filter(|n| n.has_tag_name("path")).collect();
                assert!(!pieces.is_empty());
                for p in pieces {
                    let class = p.attribute("class").unwrap();
                    let level: usize = class.strip_prefix('c').unwrap().parse().unwrap();
                    assert!(level < COLOUR_LEVELS, "{class}");
                }
            }
            // 12 part edges.
            let edges = v
                .descendants()
                .filter(|n| n.has_tag_name("g") && has_class(n, "edges"))
                .flat_map(|g| g.children().filter(|n| n.has_tag_name("path")))
                .count();
            assert_eq!(edges, 12);
        }
        // The colour bar: one swatch per level, labelled 0 and 10 mm (box 60 × 40 × 20:
        // seams from the corners at r = 0 to the junctions at r = 10).
        let bar = doc
            .descendants()
            .find(|n| has_class(n, "colour-bar"))
            .expect("colour bar");
        assert_eq!(
            bar.children().filter(|n| n.has_tag_name("rect")).count(),
            COLOUR_LEVELS + 1
        );
        let labels: Vec<_> = bar
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text())
            .collect();
        assert!(
            labels.contains(&"0") && labels.contains(&"10"),
            "{labels:?}"
        );
        let title = doc
            .descendants()
            .find(|n| has_class(n, "title-block"))
            .unwrap();
        let text: String = title
            .descendants()
            .filter_map(|n| n.text())
            .collect::<Vec<_>>()
            .join("|");
        assert!(text.contains("box.step"), "{text}");
        assert!(text.contains("12 seams (0 open)"), "{text}");
        assert!(text.contains("4 junctions · 0 degenerate"), "{text}");
        assert!(text.contains("6 faces"), "{text}");
    }

    #[test]
    fn a_seam_from_a_corner_runs_from_the_darkest_to_the_lightest_colour() {
        let (m, c, mat) = traced("box.step");
        let svg = render_svg(&m, &c, &mat, &SvgOptions::default());
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let seam = &mat.seams[0];
        assert!(
            matches!(seam.ends[0], SeamEnd::Vertex(_)),
            "{:?}",
            seam.ends
        );
        assert!(
            matches!(seam.ends[1], SeamEnd::Junction(_)),
            "{:?}",
            seam.ends
        );
        let g = doc
            .descendants()
            .find(|n| has_class(n, "seam") && n.attribute("data-seam") == Some("0"))
            .unwrap();
        let levels: Vec<usize> = g
            .children()
            .filter(|n| n.has_tag_name("path"))
            .map(|p| p.attribute("class").unwrap()[1..].parse().unwrap())
            .collect();
        assert!(levels.len() >= 3, "{levels:?}");
        assert!(levels[0] <= 1, "{levels:?}");
        assert!(*levels.last().unwrap() >= COLOUR_LEVELS - 2, "{levels:?}");
        assert!(levels.windows(2).all(|w| w[0] <= w[1]), "{levels:?}");
    }

    #[test]
    fn colour_bar_labels_are_distinct_on_a_narrow_radius_range() {
        // The revolved ring's two seams have r within 4…4.004 mm: four significant digits
        // would label several ticks alike.
        let svg = picture("scad_rotate_extrude.step");
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let bar = doc
            .descendants()
            .find(|n| has_class(n, "colour-bar"))
            .unwrap();
        let labels: Vec<&str> = bar
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text())
            .collect();
        assert!(labels.len() >= 4, "{labels:?}");
        let distinct: std::collections::BTreeSet<&str> = labels.iter().copied().collect();
        assert_eq!(distinct.len(), labels.len(), "{labels:?}");
    }

    #[test]
    fn views_are_third_angle_aligned_with_model_up_pointing_up() {
        let bbox = (DVec3::ZERO, DVec3::new(60.0, 40.0, 20.0));
        let lay = layout(bbox);
        let [front, top, right, iso] = lay.panels;
        // Third angle: TOP above FRONT, RIGHT to the right of FRONT.
        assert!(top.cell.y + top.cell.h <= front.cell.y + 1e-9);
        assert!((top.cell.x - front.cell.x).abs() < 1e-9);
        assert!(front.cell.x + front.cell.w <= right.cell.x + 1e-9);
        assert!((right.cell.y - front.cell.y).abs() < 1e-9);
        // One scale for the orthographic views.
        assert_eq!(front.scale, top.scale);
        assert_eq!(front.scale, right.scale);
        let p = DVec3::new(10.0, 30.0, 5.0);
        let q = DVec3::new(50.0, 5.0, 15.0);
        let (fp, fq) = (front.page_point(p), front.page_point(q));
        // FRONT: x to the right, z up (SVG y down), y is depth.
        assert!((fq.x - fp.x - 40.0 * front.scale).abs() < 1e-9);
        assert!((fp.y - fq.y - 10.0 * front.scale).abs() < 1e-9);
        assert_eq!(
            front.page_point(p),
            front.page_point(p + DVec3::new(0.0, 17.0, 0.0))
        );
        // TOP: x to the right, y up; aligned with FRONT in x.
        let (tp, tq) = (top.page_point(p), top.page_point(q));
        assert!((tp.x - fp.x).abs() < 1e-9 && (tq.x - fq.x).abs() < 1e-9);
        assert!((tq.y - tp.y - 25.0 * top.scale).abs() < 1e-9);
        // RIGHT: y to the right, z up; aligned with FRONT in z.
        let (rp, rq) = (right.page_point(p), right.page_point(q));
        assert!((rp.y - fp.y).abs() < 1e-9 && (rq.y - fq.y).abs() < 1e-9);
        assert!((rp.x - rq.x - 25.0 * right.scale).abs() < 1e-9);
        // ISOMETRIC: x goes right and down, y right and up, z straight up.
        let o = iso.page_point(DVec3::ZERO);
        let dx = iso.page_point(DVec3::X) - o;
        let dy = iso.page_point(DVec3::Y) - o;
        let dz = iso.page_point(DVec3::Z) - o;
        assert!(dx.x > 0.0 && dx.y > 0.0, "{dx}");
        assert!(dy.x > 0.0 && dy.y < 0.0, "{dy}");
        assert!(dz.x.abs() < 1e-9 && dz.y < 0.0, "{dz}");
        assert!((dx.length() - dy.length()).abs() < 1e-9);
        // The whole part lies in each panel's drawing area, below the label band.
        for panel in lay.panels {
            let c = panel.cell;
            for k in corners(bbox) {
                let q = panel.page_point(k);
                assert!(q.x >= c.x + INSET - 1e-6 && q.x <= c.x + c.w - INSET + 1e-6);
                assert!(q.y >= c.y + LABEL_BAND + INSET - 1e-6);
                assert!(q.y <= c.y + c.h - INSET + 1e-6, "{} {q}", panel.view.name);
            }
        }
    }

    #[test]
    fn the_picture_is_deterministic() {
        let (m, c, mat) = traced("filleted_box.step");
        let a = render_svg(&m, &c, &mat, &SvgOptions::default());
        let b = render_svg(&m, &c, &mat.clone(), &SvgOptions::default());
        assert_eq!(a, b);
        let (m2, c2, mat2) = traced("filleted_box.step");
        assert_eq!(a, render_svg(&m2, &c2, &mat2, &SvgOptions::default()));
    }

    #[test]
    fn page_coordinates_have_at_most_one_decimal() {
        let svg = picture("plate_with_holes.step");
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let mut seen = 0;
        for n in doc.descendants() {
            for a in ["d", "points", "cx", "cy", "x", "y"] {
                let Some(v) = n.attribute(a) else { continue };
                for tok in v.split(|ch: char| !(ch.is_ascii_digit() || ch == '.' || ch == '-')) {
                    if let Some((_, frac)) = tok.split_once('.') {
                        assert!(frac.len() <= 1, "{a}=\"{v}\"");
                    }
                    seen += 1;
                }
            }
        }
        assert!(seen > 1000, "{seen}");
        assert_eq!(num(-0.04), "0");
        assert_eq!(num(12.0), "12");
        assert_eq!(num(-3.26), "-3.3");
    }

    #[test]
    fn circles_are_sampled_to_the_tolerance_and_lines_by_their_ends() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/plate_with_holes.step");
        let m = crate::ingest::read_model(&p).unwrap();
        let tol = 0.01;
        let (mut circles, mut lines) = (0, 0);
        for e in &m.edges {
            let pts = sample_curve(&e.curve, e.range, e.is_closed(), tol);
            match e.curve {
                Curve3D::Line(_) => {
                    assert_eq!(pts.len(), 2);
                    lines += 1;
                }
                _ => {
                    circles += 1;
                    assert!(pts.len() >= 17, "{}", pts.len());
                    // Between consecutive samples the curve stays within tol of the chord.
                    let n = pts.len() - 1;
                    let (t0, t1) = e.range;
                    for k in 0..4 * n {
                        let t = t0 + (t1 - t0) * (k as f64 + 0.5) / (4 * n) as f64;
                        let q = eval_curve(&e.curve, t).p;
                        let d = pts
                            .windows(2)
                            .map(|w| distance_to_segment(q, w[0], w[1]))
                            .fold(f64::INFINITY, f64::min);
                        assert!(d <= tol * 1.01, "{d}");
                    }
                }
            }
        }
        assert!(circles > 0 && lines > 0, "{circles} {lines}");
    }

    #[test]
    fn a_cylinder_has_two_straight_outlines_from_the_side_and_none_along_its_axis() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/cylinder.step");
        let m = crate::ingest::read_model(&p).unwrap();
        let (lo, hi) = m.bbox;
        let r = 0.5 * (hi.x - lo.x);
        let grids = face_grids(&m);
        assert_eq!(grids.len(), 1, "one curved face");
        // Seen along its axis (z) the side face is edge-on: no outline.
        assert!(silhouettes(&m, &grids, &TOP).is_empty());
        // From the front: the generators at x = ±r, y = 0, over the whole height.
        let lines = silhouettes(&m, &grids, &FRONT);
        assert_eq!(lines.len(), 2, "{lines:?}");
        let mut xs = vec![];
        for line in &lines {
            for q in line {
                assert!((q.x.abs() - r).abs() < 1e-3 * r, "{q}");
                assert!(q.y.abs() < 1e-3 * r, "{q}");
            }
            let (zlo, zhi) = line
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
                    (a.min(q.z), b.max(q.z))
                });
            assert!((zlo - lo.z).abs() < 1e-6 && (zhi - hi.z).abs() < 1e-6);
            xs.push(line[0].x.signum());
        }
        xs.sort_by(f64::total_cmp);
        assert_eq!(xs, [-1.0, 1.0]);
    }

    #[test]
    fn a_sphere_has_a_closed_outline_in_every_view() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/sphere.step");
        let m = crate::ingest::read_model(&p).unwrap();
        let (lo, hi) = m.bbox;
        let (c, r) = (0.5 * (lo + hi), 0.5 * (hi.x - lo.x));
        let grids = face_grids(&m);
        for view in [FRONT, TOP, RIGHT, isometric()] {
            let lines = silhouettes(&m, &grids, &view);
            // The great circle perpendicular to the view, in one or two pieces (a meridian
            // outline is cut at the poles), all on the sphere and in its plane.
            let n: usize = lines.iter().map(|l| l.len()).sum();
            assert!(n > SILHOUETTE_GRID, "{} {n}", view.name);
            for q in lines.iter().flatten() {
                assert!(((*q - c).length() - r).abs() < 1e-6 * r, "{q}");
                assert!(
                    (*q - c).dot(view.toward).abs() < 2e-3 * r,
                    "{} {q}",
                    view.name
                );
            }
            // It goes all around: points in every quadrant of the view.
            let quadrants: std::collections::BTreeSet<(bool, bool)> = lines
                .iter()
                .flatten()
                .map(|q| ((*q - c).dot(view.u) > 0.0, (*q - c).dot(view.v) > 0.0))
                .collect();
            assert_eq!(quadrants.len(), 4, "{}", view.name);
        }
    }

    #[test]
    fn thinning_keeps_the_ends_and_every_point_off_the_chord() {
        let line: Vec<DVec2> = (0..100)
            .map(|k| DVec2::new(k as f64, 2.0 * k as f64))
            .collect();
        assert_eq!(thin(&line, 0.25), vec![line[0], line[99]]);
        let arc: Vec<DVec2> = (0..=200)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / 200.0;
                DVec2::new(100.0 * a.cos(), 100.0 * a.sin())
            })
            .collect();
        let kept = thin(&arc, 0.25);
        assert!(kept.len() > 10 && kept.len() < 60, "{}", kept.len());
        assert_eq!((kept[0], *kept.last().unwrap()), (arc[0], arc[200]));
        for p in &arc {
            let d = kept
                .windows(2)
                .map(|w| distance_to_segment_2d(*p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.25 + 1e-12, "{d}");
        }
    }

    #[test]
    fn degenerate_pieces_are_drawn_and_a_part_without_seams_says_so() {
        let (m, c, mat) = traced("cylinder.step");
        assert!(mat.seams.is_empty() && !mat.degenerate.is_empty());
        let svg = render_svg(&m, &c, &mat, &SvgOptions::default());
        let doc = roxmltree::Document::parse(&svg).unwrap();
        for v in views(&doc) {
            assert_eq!(count(v, "g", "degenerate"), mat.degenerate.len());
            assert_eq!(count(v, "g", "seam"), 0);
        }
        assert!(svg.contains("no seams traced"));
        // Part lines: from the front the two circles (seen edge-on) and the two outlines; from
        // the top the two circles. The seam edge of the side face is not drawn.
        assert_eq!(m.edges.iter().filter(|e| e.is_seam()).count(), 1);
        let lines = |id: &str| {
            let v = views(&doc)
                .into_iter()
                .find(|v| v.attribute("id") == Some(id))
                .unwrap();
            v.descendants()
                .filter(|n| n.has_tag_name("g") && has_class(n, "edges"))
                .flat_map(|g| g.children().filter(|n| n.has_tag_name("path")))
                .count()
        };
        assert_eq!(lines("view-front"), 4);
        assert_eq!(lines("view-top"), 2);
        assert!(!svg.contains("colour-bar"));
        assert!(svg.contains(&format!("degenerate curve ({})", mat.degenerate.len())));
    }

    #[test]
    fn viridis_ends_and_radius_levels() {
        assert_eq!(colour(0.0), "#440154");
        assert_ne!(colour(1.0), "#fde725", "the faint yellow end is not used");
        let rs = RadiusScale { lo: 2.0, hi: 8.0 };
        assert_eq!(rs.level(2.0), 0);
        assert_eq!(rs.level(8.0), COLOUR_LEVELS - 1);
        assert_eq!(rs.level(5.0), COLOUR_LEVELS / 2);
        assert_eq!(ticks(0.0, 10.0, 5), [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(nice_floor(140.0 / 7.3), 10.0);
    }

    #[test]
    fn write_svg_replaces_the_file_and_names_it_on_failure() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.mat.svg");
        write_svg(&path, "<svg/>").unwrap();
        write_svg(&path, "<svg></svg>").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "<svg></svg>");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file left behind");
        let bad = dir.path().join("missing").join("b.mat.svg");
        let e = write_svg(&bad, "<svg/>").unwrap_err();
        assert!(e.to_string().contains("b.mat.svg"), "{e}");
        assert_eq!(e.path(), bad);
    }
}
