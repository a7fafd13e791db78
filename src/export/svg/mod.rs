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

mod colour;
mod layout;
mod legend;
mod panels;
mod sampling;
mod silhouettes;
#[cfg(test)]
mod test_support;
mod text;

pub use colour::COLOUR_LEVELS;
pub use layout::{MIN_SPLIT, PAGE_HEIGHT, PAGE_WIDTH};
pub use silhouettes::SILHOUETTE_GRID;

use crate::classify::Classification;
use crate::error::Result;
use crate::medial::MedialAxis;
use crate::model::Model;
use colour::RadiusScale;
use glam::DVec3;
use layout::layout;
use legend::{draw_legend, draw_title_block};
use panels::{draw_panel, Scene};
use sampling::sample_curve;
use silhouettes::{face_grids, silhouettes};
use std::fmt::Write as _;
use std::path::Path;
use text::{escape, num};

/// Default thinning tolerance: points within this distance (px) of the drawn chord are dropped.
pub const DEFAULT_PX_TOL: f64 = 0.25;
/// Default largest number of junctions whose ids are written in the isometric view.
pub const DEFAULT_MAX_JUNCTION_LABELS: usize = 30;

/// Curves are sampled to this fraction of the thinning tolerance (at the largest scale).
const SAMPLING_TOL_REL_PX_TOL: f64 = 0.5;

const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

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
    let curve_tol = SAMPLING_TOL_REL_PX_TOL * opts.px_tol / max_scale.max(1e-12);
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
    let scene = Scene {
        class,
        mat,
        edges: &edges,
        radius,
        px_tol: opts.px_tol,
        max_junction_labels: opts.max_junction_labels,
    };

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
        draw_panel(&mut s, &scene, &outlines, panel, k == 3);
    }
    draw_legend(&mut s, mat, radius, &lay);
    draw_title_block(&mut s, model, mat, &title, opts.accuracy, &lay);
    s.push_str("</svg>\n");
    s
}

/// Writes `svg` to `path` atomically: into a temporary file in the same folder, then renamed
/// over `path`, so a reader never sees a half-written picture.
pub fn write_svg(path: &Path, svg: &str) -> Result<()> {
    crate::export::atomic::write_atomic(path, svg.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::test_support::{count, has_class, views};
    use super::*;

    #[test]
    fn box_picture_is_xml_with_every_seam_and_junction_in_every_view() {
        let (m, c, mat) = crate::testing::traced("box.step");
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
    fn the_picture_is_deterministic() {
        let (m, c, mat) = crate::testing::traced("filleted_box.step");
        let a = render_svg(&m, &c, &mat, &SvgOptions::default());
        let b = render_svg(&m, &c, &mat.clone(), &SvgOptions::default());
        assert_eq!(a, b);
        let (m2, c2, mat2) = crate::testing::traced("filleted_box.step");
        assert_eq!(a, render_svg(&m2, &c2, &mat2, &SvgOptions::default()));
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
