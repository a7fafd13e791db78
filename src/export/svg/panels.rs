//! One view of the picture: its frame and label, the part's edges and outlines grey by
//! depth, the degenerate pieces, the seams coloured by radius, the junctions (with their ids
//! in the isometric view when there are few), the model axes, and scale bars.
//!
//! The picture is a wireframe (the medial axis is inside the part, so hidden-line removal
//! would hide exactly what the picture is for). As a depth cue each part edge is grey by its
//! mean depth in the view — near edges dark, far edges light — and everything is drawn far
//! to near. Tangent (smooth) edges are drawn thinner. A seam is split into runs whose colour
//! levels stay within one of each other, each drawn in its middle level and thinned on its
//! own, so thinning never moves a colour by more than one level.

use super::colour::{
    colour, nice_floor, RadiusScale, DEGENERATE_COLOUR, EDGE_GREYS, SKELETAL_COLOUR,
};
use super::layout::Panel;
use super::sampling::thin;
use super::text::{escape, mm, num, path_data, points_attr};
use crate::classify::{Classification, EdgeKind};
use crate::medial::MedialAxis;
use glam::{DVec2, DVec3};
use std::fmt::Write as _;

/// What every panel shows, and how finely.
pub(super) struct Scene<'a> {
    pub(super) class: &'a Classification,
    pub(super) mat: &'a MedialAxis,
    /// The part's edges, sampled (empty for the edges not drawn).
    pub(super) edges: &'a [Vec<DVec3>],
    /// The radius range coloured; `None` when there are no seams.
    pub(super) radius: Option<RadiusScale>,
    /// Thinning tolerance (px).
    pub(super) px_tol: f64,
    /// Junction ids are written in the isometric view when there are at most this many.
    pub(super) max_junction_labels: usize,
}

/// Draws one view of `scene`, with the curved faces' `outlines` in that view.
pub(super) fn draw_panel(
    s: &mut String,
    scene: &Scene,
    outlines: &[Vec<DVec3>],
    panel: &Panel,
    is_iso: bool,
) {
    let (mat, c) = (scene.mat, panel.cell);
    let id = panel.view.name.to_ascii_lowercase();
    let _ = writeln!(s, r#"<g class="view" id="view-{id}">"#);
    draw_label(s, panel);
    draw_edges(s, scene.class, scene.edges, outlines, panel, scene.px_tol);
    if !mat.degenerate.is_empty() {
        draw_degenerates(s, mat, panel, scene.px_tol);
    }
    if !mat.skeletal_edges.is_empty() {
        draw_skeletal(s, mat, panel);
    }
    if let Some(rs) = scene.radius {
        draw_seams(s, mat, panel, rs, scene.px_tol);
        draw_junctions(s, mat, panel, rs);
        if is_iso && !mat.junctions.is_empty() && mat.junctions.len() <= scene.max_junction_labels {
            draw_junction_labels(s, mat, panel);
        }
    }
    if is_iso {
        draw_scale_bar(s, panel.scale, c.x + c.w - 20.0, c.y + c.h - 22.0, "", true);
    }
    draw_axes(s, panel);
    s.push_str("</g>\n");
}

/// The panel's frame, and the view's name with what it looks along.
fn draw_label(s: &mut String, panel: &Panel) {
    let c = panel.cell;
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
}

/// Part edges, grey by mean depth, in groups from far to near; tangent edges thinner.
/// Silhouettes of curved faces are drawn as edges (after the edges, numbered on).
fn draw_edges(
    s: &mut String,
    class: &Classification,
    edges: &[Vec<DVec3>],
    outlines: &[Vec<DVec3>],
    panel: &Panel,
    px_tol: f64,
) {
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
            let _ = writeln!(s, r#"<path d="{}"/>"#, path_data(&thin(&px, px_tol)));
        }
        s.push_str("</g>\n");
    }
}

/// Degenerate pieces: magenta, dashed through the centres, a diamond and the ball's outline
/// at each sampled ball (at the two ends of a traced curve).
fn draw_degenerates(s: &mut String, mat: &MedialAxis, panel: &Panel, px_tol: f64) {
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
                points_attr(&thin(&centres, px_tol))
            );
        }
        let marked: Vec<usize> = if d.ends.is_empty() || d.balls.is_empty() {
            (0..d.balls.len()).collect()
        } else {
            let mut ends = vec![0, d.balls.len() - 1];
            ends.dedup();
            ends
        };
        for (b, q) in marked.iter().map(|&i| (&d.balls[i], &centres[i])) {
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

/// The seams, far to near, each in runs of equal colour.
fn draw_seams(s: &mut String, mat: &MedialAxis, panel: &Panel, rs: RadiusScale, px_tol: f64) {
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
        draw_seam(s, mat, i, panel, rs, px_tol);
    }
    s.push_str("</g>\n");
}

/// The skeletal edges: dotted straight lines from their seams' ends to their vertices.
fn draw_skeletal(s: &mut String, mat: &MedialAxis, panel: &Panel) {
    let _ = writeln!(
        s,
        r#"<g class="skeletal-edges" fill="none" stroke="{SKELETAL_COLOUR}" stroke-width="1.6" stroke-dasharray="2 3" stroke-linecap="round">"#
    );
    for k in &mat.skeletal_edges {
        let (Some(a), Some(b)) = (k.balls.first(), k.balls.last()) else {
            continue;
        };
        let (p, q) = (
            panel.page_point(DVec3::new(a[0], a[1], a[2])),
            panel.page_point(DVec3::new(b[0], b[1], b[2])),
        );
        let _ = writeln!(
            s,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}"><title>skeletal edge {} ({} {}) to V{} · r {}–0 mm</title></line>"#,
            num(p.x),
            num(p.y),
            num(q.x),
            num(q.y),
            k.id,
            k.segments[0],
            k.segments[1],
            k.vertex,
            mm(a[3])
        );
    }
    s.push_str("</g>\n");
}

/// The junctions as dots in the colour of their radius.
fn draw_junctions(s: &mut String, mat: &MedialAxis, panel: &Panel, rs: RadiusScale) {
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
}

/// One seam, in runs of equal colour (a dot when it has one point), with its radius range
/// in its title.
fn draw_seam(
    s: &mut String,
    mat: &MedialAxis,
    i: usize,
    panel: &Panel,
    rs: RadiusScale,
    px_tol: f64,
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
            path_data(&thin(&px[start..=end], px_tol))
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
pub(super) fn draw_scale_bar(
    s: &mut String,
    scale: f64,
    x: f64,
    y: f64,
    caption: &str,
    right: bool,
) {
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{count, has_class, views};
    use super::super::{render_svg, SvgOptions};
    use crate::export::svg::COLOUR_LEVELS;
    use crate::medial::SeamEnd;

    #[test]
    fn a_seam_from_a_corner_runs_from_the_darkest_to_the_lightest_colour() {
        let (m, c, mat) = crate::testing::traced("box.step");
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
    fn degenerate_pieces_are_drawn_and_a_part_without_seams_says_so() {
        let (m, c, mat) = crate::testing::traced("cylinder.step");
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
}
