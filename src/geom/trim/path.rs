//! Whether a straight UV path leaves a face and comes back: it crosses the face's trimming
//! loops at least twice. The loops are cut into runs of segments with their UV boxes
//! ([`LoopChunks`]) so that a test reads only the runs near the path.

use crate::model::Face;
use glam::DVec2;

/// A face's trimming loops cut into runs of [`LoopChunks::RUN`] polygon segments, each with
/// its UV bounding box, so a path test reads only the runs near the path.
#[derive(Clone, Debug, Default)]
pub struct LoopChunks {
    /// `(loop, first segment, end segment, min, max)`.
    runs: Vec<(usize, usize, usize, DVec2, DVec2)>,
    /// The box of all the runs.
    lo: DVec2,
    hi: DVec2,
}

impl LoopChunks {
    /// Segments per run.
    pub const RUN: usize = 16;

    /// The runs of `face`'s loops.
    pub fn new(face: &Face) -> LoopChunks {
        let mut runs = vec![];
        for (k, l) in face.loops.iter().enumerate() {
            let poly = l.outline();
            let n = poly.len();
            let mut start = 0;
            while start < n {
                let end = (start + Self::RUN).min(n);
                let (mut lo, mut hi) =
                    (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
                for i in start..=end {
                    let p = poly[i % n];
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
                runs.push((k, start, end, lo, hi));
                start = end;
            }
        }
        let lo = runs
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |m, r| m.min(r.3));
        let hi = runs
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |m, r| m.max(r.4));
        LoopChunks { runs, lo, hi }
    }
}

/// True when the straight UV path from `a` to `b` leaves `face` and comes back: it crosses its
/// trimming loops at least twice. A touch point that steps over a hole (or a notch of the outline)
/// lands inside the face again, and [`contains`](super::contains) alone would not see that it left.
/// (One crossing is no exit: a path from a point on the boundary — after a hand-over — may cross
/// the sampled loop polygon once where it cuts the exact curve's chord.) On a periodic face the
/// loops live in unwrapped coordinates, and the path may be a period or more away from them
/// (the tracer's parameters run on round a cylinder): each copy of the path shifted by whole
/// periods onto the loops' box is tested alone. (A path over the notch where a plate joins a
/// half cylinder, on the CAx-IF's tail turbine, was not tested at all.) Faces without loops
/// are not tested. `chunks` are the face's [`LoopChunks`].
pub fn path_crosses_loops(face: &Face, chunks: &LoopChunks, a: DVec2, b: DVec2) -> bool {
    if a == b || chunks.runs.is_empty() {
        return false;
    }
    let (lo, hi) = (a.min(b), a.max(b));
    // The whole periods `k` by which the path's extent [lo, hi] shifted overlaps the loops'
    // [clo, chi]; just 0 when not periodic; `None` (nothing tested) for an absurd span.
    let shifts = |period: Option<f64>, lo: f64, hi: f64, clo: f64, chi: f64| match period {
        Some(p) if p > 0.0 && p.is_finite() => {
            let first = ((clo - hi) / p).ceil();
            let last = ((chi - lo) / p).floor();
            // A path is shorter than a period, and loops span a few at most.
            (first.is_finite() && last.is_finite() && last - first <= 4.0)
                .then_some(first as i64..=last as i64)
        }
        _ => Some(0..=0),
    };
    let (Some(su), Some(sv)) = (
        shifts(face.domain.u_period, lo.x, hi.x, chunks.lo.x, chunks.hi.x),
        shifts(face.domain.v_period, lo.y, hi.y, chunks.lo.y, chunks.hi.y),
    ) else {
        return false;
    };
    let (pu, pv) = (
        face.domain.u_period.unwrap_or(0.0),
        face.domain.v_period.unwrap_or(0.0),
    );
    su.into_iter().any(|ku| {
        sv.clone().any(|kv| {
            let shift = DVec2::new(ku as f64 * pu, kv as f64 * pv);
            crosses_twice(face, chunks, a + shift, b + shift)
        })
    })
}

/// True when the straight UV path from `a` to `b` crosses `face`'s loop polygons (as they are,
/// unwrapped) at least twice. A segment spanning most of a period is not crossed: it closes a
/// loop that goes once round a periodic face (a hole's circle, with no seam edge), back over
/// the whole loop, where a path crossing the loop once would cross it twice.
fn crosses_twice(face: &Face, chunks: &LoopChunks, a: DVec2, b: DVec2) -> bool {
    let wraps = |p: DVec2, q: DVec2| {
        let spans = |d: f64, period: Option<f64>| period.is_some_and(|t| d.abs() > 0.9 * t);
        spans(q.x - p.x, face.domain.u_period) || spans(q.y - p.y, face.domain.v_period)
    };
    let (lo, hi) = (a.min(b), a.max(b));
    let cross = |o: DVec2, x: DVec2, y: DVec2| (x - o).perp_dot(y - o);
    let mut crossings = 0;
    for &(k, start, end, rlo, rhi) in &chunks.runs {
        if rhi.cmplt(lo).any() || rlo.cmpgt(hi).any() {
            continue;
        }
        let uv = face.loops[k].outline();
        let n = uv.len();
        for i in start..end {
            let (p, q) = (uv[i], uv[(i + 1) % n]);
            if p.max(q).cmplt(lo).any() || p.min(q).cmpgt(hi).any() || wraps(p, q) {
                continue;
            }
            let (d1, d2) = (cross(a, b, p), cross(a, b, q));
            let (d3, d4) = (cross(p, q, a), cross(p, q, b));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                crossings += 1;
                if crossings >= 2 {
                    return true;
                }
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::trim::contains;
    use crate::testing::geometry::{face_where, uv_of};
    use crate::testing::sample;
    use glam::DVec3;

    /// A path over a hole leaves the face and comes back (two crossings); a path inside the
    /// plate, or one that only reaches into a hole, is not an exit-and-return.
    #[test]
    fn path_over_a_hole_crosses_the_loops() {
        let m = sample("plate_with_holes.step");
        let top = face_where(&m, |p| (p.z - 10.0).abs() < 1e-9);
        let face = &m.faces[top];
        let uv = |x: f64, y: f64| uv_of(face, DVec3::new(x, y, 10.0));
        let chunks = LoopChunks::new(face);
        let path_crosses_loops =
            |face: &Face, a: DVec2, b: DVec2| path_crosses_loops(face, &chunks, a, b);
        // Over the r = 5 hole at (15, 25), both ends on the plate.
        assert!(contains(face, uv(8.0, 25.0)) && contains(face, uv(22.0, 25.0)));
        assert!(path_crosses_loops(face, uv(8.0, 25.0), uv(22.0, 25.0)));
        // Beside it, and from the plate into the hole (that one `contains` catches).
        assert!(!path_crosses_loops(face, uv(8.0, 35.0), uv(22.0, 35.0)));
        assert!(!path_crosses_loops(face, uv(8.0, 25.0), uv(15.0, 25.0)));
        assert!(!path_crosses_loops(face, uv(8.0, 25.0), uv(8.0, 25.0)));
    }

    /// On a periodic face the loops are tested against the path shifted by whole periods: a
    /// half cylinder of a hub split at its top and bottom, with the notch a plate 2 mm thick
    /// cuts into it (z from −1 to 1 at x from −40 to 0). A step over the notch leaves the face
    /// and comes back, wherever the path's parameters are counted from; beside the notch it
    /// does not. (Periodic faces were not tested: the step over the notch went unseen.)
    #[test]
    fn path_over_a_notch_of_a_periodic_face_crosses_the_loops() {
        let m = sample("trace/plate_through_a_split_hub.step");
        let half = face_where(&m, |p| {
            p.y > -1e-9 && (p.y * p.y + p.z * p.z - 36.0 * 36.0).abs() < 1e-6
        });
        let face = &m.faces[half];
        let period = face.domain.u_period.expect("a cylinder is periodic");
        let y = (36.0f64 * 36.0 - 9.0).sqrt();
        let uv = |x: f64, z: f64| uv_of(face, DVec3::new(x, y, z));
        let chunks = LoopChunks::new(face);
        let (below, above) = (uv(-23.0, -3.0), uv(-23.0, 3.0));
        assert!(contains(face, below) && contains(face, above));
        for k in [-1.0, 0.0, 1.0, 2.0] {
            let shift = DVec2::new(k * period, 0.0);
            assert!(
                path_crosses_loops(face, &chunks, below + shift, above + shift),
                "over the notch, shifted by {k} periods"
            );
            // Beyond the plate's end (x < −40) the wall has no notch.
            let (a, b) = (uv(-50.0, -3.0) + shift, uv(-50.0, 3.0) + shift);
            assert!(
                !path_crosses_loops(face, &chunks, a, b),
                "beside the notch, {k} periods"
            );
        }
    }
}
