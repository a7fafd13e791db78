//! Text of the picture: page coordinates with one decimal, lengths in mm for labels,
//! polylines as SVG attributes, XML escaping and plurals. Every number goes through these,
//! so the output is deterministic byte for byte.

use glam::DVec2;
use std::fmt::Write as _;

/// A number with at most one decimal, without a trailing `.0` or a negative zero.
pub(super) fn num(x: f64) -> String {
    let r = (x * 10.0).round() / 10.0;
    // A non-finite number (a NaN from bad geometry) would make the file invalid SVG.
    if r == 0.0 || !r.is_finite() {
        return "0".into();
    }
    let s = format!("{r:.1}");
    s.strip_suffix(".0").map(str::to_owned).unwrap_or(s)
}

/// SVG `points` of a polyline: `x,y x,y …`.
pub(super) fn points_attr(pts: &[DVec2]) -> String {
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
pub(super) fn path_data(pts: &[DVec2]) -> String {
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
pub(super) fn mm(x: f64) -> String {
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

/// `s` with the characters XML reserves in text and attributes escaped.
pub(super) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `x` with `decimals` decimals, trailing zeros (and then a trailing point) dropped, without
/// a negative zero: the labels of the colour bar.
pub(super) fn fixed_decimals(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
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
}

/// `n` and `noun`, in the plural unless `n` is 1 (`vertex` → `vertices`).
pub(super) fn plural(n: usize, noun: &str) -> String {
    match (n, noun) {
        (1, _) => format!("1 {noun}"),
        (_, "vertex") => format!("{n} vertices"),
        _ => format!("{n} {noun}s"),
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::picture;
    use super::*;

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
}
