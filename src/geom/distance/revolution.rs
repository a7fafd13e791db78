//! Surfaces of revolution for the nearest-point search: the axis and the profile's samples
//! in cylindrical coordinates, from which a descent to the foot of a point starts in the plane
//! through the axis and the point (see `face::other_basin_feet`).

use crate::model::Face;
use glam::DVec3;

/// Samples of a surface of revolution's profile searched for starts in [`Profile::starts`],
/// and how many of their local minima start a descent.
const PROFILE_SAMPLES: usize = 64;
const PROFILE_MINIMA: usize = 3;

/// A surface of revolution as its axis and its profile's samples in cylindrical coordinates,
/// for the starts of the descent to a foot ([`Profile::starts`]); the `Boundary` caches it.
#[derive(Clone, Debug)]
pub(crate) struct Profile {
    /// Whether the angle is the `u` parameter (else `v`).
    angle_is_u: bool,
    centre: DVec3,
    /// Unit vectors: the axis, and the directions of the angles 0 and a quarter turn.
    axis: DVec3,
    e1: DVec3,
    e2: DVec3,
    /// Per sample: the profile parameter, and its point's height along the axis, distance
    /// from it and azimuth at angle 0.
    samples: Vec<(f64, f64, f64, f64)>,
    /// The longest chord between neighbouring samples (in a plane through the axis): the
    /// foot is within half of it of a sample.
    spacing: f64,
}

impl Profile {
    /// The profile of `face`'s surface of revolution; `None` where the face has not exactly
    /// one periodic direction or no parallel is a proper circle. The axis, and the angle's
    /// origin and sense, come from three points of one parallel (the angle is the periodic
    /// parameter, linear in the turn).
    pub(crate) fn new(face: &Face) -> Option<Profile> {
        if crate::geom::surface_kind(&face.surface) != "revolution" {
            return None;
        }
        let d = &face.domain;
        let (angle_is_u, (w0, w1)) = match (d.u_period, d.v_period) {
            (Some(_), None) => (true, d.v),
            (None, Some(_)) => (false, d.u),
            _ => return None,
        };
        let at = |angle: f64, w: f64| {
            if angle_is_u {
                crate::geom::surface_point(&face.surface, angle, w)
            } else {
                crate::geom::surface_point(&face.surface, w, angle)
            }
        };
        let quarter = std::f64::consts::FRAC_PI_2;
        // The parallel through the middle of the profile's range, or failing that a quarter
        // of the way along (a profile may touch the axis).
        let (centre, e1, e2) = [0.5, 0.25, 0.75].into_iter().find_map(|f| {
            let w = w0 + f * (w1 - w0);
            let (a, b, c) = (at(0.0, w), at(quarter, w), at(2.0 * quarter, w));
            let centre = 0.5 * (a + c);
            let (e1, e2) = (a - centre, b - centre);
            let rho2 = e1.length_squared();
            (rho2 > 1e-18 * (1.0 + centre.length_squared())
                && (e2.length_squared() - rho2).abs() <= 1e-6 * rho2
                && e1.dot(e2).abs() <= 1e-6 * rho2)
                .then(|| (centre, e1.normalize(), e2.normalize()))
        })?;
        let axis = e1.cross(e2);
        let samples = (0..=PROFILE_SAMPLES)
            .map(|k| w0 + (w1 - w0) * k as f64 / PROFILE_SAMPLES as f64)
            .filter_map(|w| {
                let q = at(0.0, w) - centre;
                let h = q.dot(axis);
                let radial = q - axis * h;
                let az = radial.dot(e2).atan2(radial.dot(e1));
                q.is_finite().then_some((w, h, radial.length(), az))
            })
            .collect::<Vec<_>>();
        let spacing = samples
            .windows(2)
            .map(|w| ((w[1].1 - w[0].1).powi(2) + (w[1].2 - w[0].2).powi(2)).sqrt())
            .fold(0.0, f64::max);
        Some(Profile {
            angle_is_u,
            centre,
            axis,
            e1,
            e2,
            samples,
            spacing,
        })
    }

    /// Starts for the descent to the foot of `p`, each with the least distance to `p` a foot
    /// from there may have (the sample's, less half the samples' spacing): in the
    /// plane through the axis and `p` (on `p`'s side and across the axis), at the profile's
    /// samples nearest `p` there (their local minima, nearest first: a B-spline profile's
    /// parameter may run fast over one span, so the nearest sample is not always in the
    /// foot's basin).
    pub(crate) fn starts(&self, p: DVec3) -> Vec<((f64, f64), f64)> {
        let q = p - self.centre;
        let h = q.dot(self.axis);
        let radial = q - self.axis * h;
        let (r, theta) = (
            radial.length(),
            radial.dot(self.e2).atan2(radial.dot(self.e1)),
        );
        let mut out = vec![];
        for (side, turn) in [(1.0, 0.0), (-1.0, std::f64::consts::PI)] {
            // Squared distance from p to the sample turned into p's half-plane (or across).
            let dist: Vec<f64> = self
                .samples
                .iter()
                .map(|&(_, hs, rs, _)| (h - hs).powi(2) + (r - side * rs).powi(2))
                .collect();
            let mut minima: Vec<usize> = (0..dist.len())
                .filter(|&k| {
                    (k == 0 || dist[k - 1] >= dist[k])
                        && (k + 1 == dist.len() || dist[k + 1] >= dist[k])
                })
                .collect();
            minima.sort_by(|&a, &b| dist[a].total_cmp(&dist[b]));
            for k in minima.into_iter().take(PROFILE_MINIMA) {
                let (w, _, _, az) = self.samples[k];
                let angle = theta + turn - az;
                let uv = if self.angle_is_u {
                    (angle, w)
                } else {
                    (w, angle)
                };
                // Less half the spacing: a nearer foot has a sample within that of it.
                out.push((uv, dist[k].sqrt() - 0.5 * self.spacing));
            }
        }
        out
    }
}
