//! The picture's colours: viridis for the seam radius, quantised to [`COLOUR_LEVELS`]
//! levels over the radius range of the part ([`RadiusScale`]), the greys of the part's edges,
//! the colour of degenerate pieces, and the round values (ticks) of the colour bar and the
//! scale bars.

use crate::medial::MedialAxis;

/// Number of distinct seam colours (the radius range is quantised to this many levels).
pub const COLOUR_LEVELS: usize = 24;

/// The colour of degenerate pieces (magenta).
pub(super) const DEGENERATE_COLOUR: &str = "#d0109a";
/// The colour of skeletal edges (a sheet's free edge: dotted, in orange).
pub(super) const SKELETAL_COLOUR: &str = "#e07000";

/// Greys of a part edge from near to far.
pub(super) const EDGE_GREYS: [&str; 4] = ["#262626", "#555555", "#858585", "#b0b0b0"];

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
pub(super) fn colour(t: f64) -> String {
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
pub(super) struct RadiusScale {
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl RadiusScale {
    pub(super) fn of(mat: &MedialAxis) -> Option<RadiusScale> {
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

    pub(super) fn t(&self, r: f64) -> f64 {
        ((r - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
    }

    /// The quantised colour level of `r`.
    pub(super) fn level(&self, r: f64) -> usize {
        ((self.t(r) * COLOUR_LEVELS as f64) as usize).min(COLOUR_LEVELS - 1)
    }

    pub(super) fn level_colour(level: usize) -> String {
        colour((level as f64 + 0.5) / COLOUR_LEVELS as f64)
    }
}

/// The largest of 1, 2, 5 × 10ᵏ not above `x`.
pub(super) fn nice_floor(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|v| *v <= x * (1.0 + 1e-12))
        .unwrap_or(p)
}

/// About `n` round values inside `[lo, hi]`.
pub(super) fn ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = nice_floor((hi - lo) / n as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
