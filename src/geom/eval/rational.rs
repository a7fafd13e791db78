//! The rational quotient rule (Piegl & Tiller, *The NURBS Book*, A4.2 for curves, A4.4 for
//! surfaces): from the homogeneous derivatives `A = w·S` and the weight's, the derivatives of
//! `S = A/w` up to order 2, `Su = (Au − wu·S)/w`, `Suv = (Auv − wuv·S − wu·Sv − wv·Su)/w`, ….
//! NURBS curves and surfaces use it, and so does a projective placement matrix.

use super::derivs::SurfaceDerivs;
use glam::DVec4;

/// Piegl & Tiller A4.2 up to order 2: from `A = w·C` and `w` with their derivatives, returns
/// `C`, `C′ = (A′ − w′C)/w`, `C″ = (A″ − 2w′C′ − w″C)/w`.
#[inline]
pub(super) fn rational_curve<V>(a: [V; 3], w: [f64; 3]) -> (V, V, V)
where
    V: Copy + std::ops::Sub<Output = V> + std::ops::Mul<f64, Output = V>,
{
    let inv = 1.0 / w[0];
    let c = a[0] * inv;
    let c1 = (a[1] - c * w[1]) * inv;
    let c2 = (a[2] - c1 * (2.0 * w[1]) - c * w[2]) * inv;
    (c, c1, c2)
}

/// Piegl & Tiller A4.4 up to order 2. `h` holds the homogeneous `[A, Au, Av, Auu, Auv, Avv]`
/// with the weight in `w`.
#[inline]
pub(super) fn rational_surface(h: &[DVec4; 6]) -> SurfaceDerivs {
    let a = |k: usize| h[k].truncate();
    let w = |k: usize| h[k].w;
    let inv = 1.0 / w(0);
    let p = a(0) * inv;
    let su = (a(1) - p * w(1)) * inv;
    let sv = (a(2) - p * w(2)) * inv;
    let suu = (a(3) - su * (2.0 * w(1)) - p * w(3)) * inv;
    let suv = (a(4) - su * w(2) - sv * w(1) - p * w(4)) * inv;
    let svv = (a(5) - sv * (2.0 * w(2)) - p * w(5)) * inv;
    SurfaceDerivs {
        p,
        su,
        sv,
        suu,
        suv,
        svv,
    }
}
