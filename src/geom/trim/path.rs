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
        LoopChunks { runs }
    }
}

/// True when the straight UV path from `a` to `b` leaves `face` and comes back: it crosses its
/// trimming loops at least twice. A touch point that steps over a hole (or a notch of the outline)
/// lands inside the face again, and [`contains`](super::contains) alone would not see that it left.
/// (One crossing is no exit: a path from a point on the boundary — after a hand-over — may cross
/// the sampled loop polygon once where it cuts the exact curve's chord.) Periodic faces are not
/// tested (their loops live in unwrapped coordinates), nor faces without loops. `chunks` are the
/// face's [`LoopChunks`].
pub fn path_crosses_loops(face: &Face, chunks: &LoopChunks, a: DVec2, b: DVec2) -> bool {
    if face.domain.u_period.is_some() || face.domain.v_period.is_some() || a == b {
        return false;
    }
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
            if p.max(q).cmplt(lo).any() || p.min(q).cmpgt(hi).any() {
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
}
