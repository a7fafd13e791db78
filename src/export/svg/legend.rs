//! The legend column (the colour bar of the seam radius, the symbols, the scale bar of the
//! orthographic views) and the title block along the bottom (the part, the model's counts,
//! the medial axis's counts, the accuracy).

use super::colour::{
    colour, nice_floor, ticks, RadiusScale, COLOUR_LEVELS, DEGENERATE_COLOUR, EDGE_GREYS,
    SKELETAL_COLOUR,
};
use super::layout::{Layout, Rect};
use super::panels::draw_scale_bar;
use super::text::{escape, fixed_decimals, mm, num, plural};
use crate::medial::{DegenerateKind, MedialAxis};
use crate::model::Model;
use std::fmt::Write as _;

/// The legend column of `lay`: the colour bar of `radius` (or a note that there are no seams),
/// the symbols with their counts in `mat`, and the scale bar of the orthographic views.
pub(super) fn draw_legend(
    s: &mut String,
    mat: &MedialAxis,
    radius: Option<RadiusScale>,
    lay: &Layout,
) {
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
    let bar = Rect {
        x,
        y: r.y + 62.0,
        w: 20.0,
        h: 300.0,
    };
    match radius {
        Some(rs) => draw_colour_bar(s, rs, bar),
        None => {
            let _ = writeln!(
                s,
                r##"<text x="{}" y="{}" font-size="11" fill="#707070">no seams traced</text>"##,
                num(bar.x),
                num(bar.y + 14.0)
            );
        }
    }
    let y = draw_symbols(s, mat, x, bar.y + bar.h + 40.0);
    draw_scale_bar(
        s,
        lay.panels[0].scale,
        x,
        y + 44.0,
        "front, top, right views",
        false,
    );
    s.push_str("</g>\n");
}

/// The colour bar of `rs` in `bar`: one swatch per level, the range's ends and round values
/// between them marked.
fn draw_colour_bar(s: &mut String, rs: RadiusScale, bar: Rect) {
    let (bx, by, bw, bh) = (bar.x, bar.y, bar.w, bar.h);
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
            fixed_decimals(v, decimals + usize::from(end)),
            y = num(y)
        );
    }
    s.push_str("</g>\n");
}

/// The symbols of the picture with their counts in `mat`, from `y` down at `x`; returns the
/// y of the last.
fn draw_symbols(s: &mut String, mat: &MedialAxis, x: f64, mut y: f64) -> f64 {
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
    y += 24.0;
    item(
        s,
        y,
        line(y, SKELETAL_COLOUR, "1.6", r#" stroke-dasharray="2 3""#),
        format!("skeletal edge ({})", mat.skeletal_edges.len()),
    );
    y += 22.0;
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
    y
}

/// The title block along the bottom of the page.
pub(super) fn draw_title_block(
    s: &mut String,
    model: &Model,
    mat: &MedialAxis,
    title: &str,
    accuracy: Option<f64>,
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
                accuracy
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{has_class, picture};

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
}
