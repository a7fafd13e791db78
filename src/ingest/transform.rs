//! 4×4 transforms shared by the STEP and IGES readers.
//!
//! Row-major matrices acting on column vectors, for unit scaling, assembly placements and
//! IGES transformation matrices, and the geometry moved by them.

use glam::DVec3;
use truck_geometry::prelude::{Matrix4, Transformed};

/// A 4×4 rigid (or scaling) transform, row-major, acting on column vectors.
pub type Mat4 = [[f64; 4]; 4];

/// The identity transform.
pub const IDENTITY: Mat4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// Matrix product `a · b`.
pub fn mat_mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

/// `m` applied to the point `p`.
pub fn apply(m: &Mat4, p: DVec3) -> DVec3 {
    let a = [p.x, p.y, p.z, 1.0];
    let r = |i: usize| (0..4).map(|k| m[i][k] * a[k]).sum::<f64>();
    DVec3::new(r(0), r(1), r(2))
}

/// Geometry moved by the placement `m` (mm scaling and assembly transform).
pub fn placed<T: Transformed<Matrix4>>(mut geometry: T, m: &Mat4) -> T {
    if *m != IDENTITY {
        geometry.transform_by(to_matrix4(m));
    }
    geometry
}

/// `m` as truck's (cgmath's) matrix.
pub fn to_matrix4(m: &Mat4) -> Matrix4 {
    // cgmath matrices are column-major: Matrix4::new takes columns.
    Matrix4::new(
        m[0][0], m[1][0], m[2][0], m[3][0], m[0][1], m[1][1], m[2][1], m[3][1], m[0][2], m[1][2],
        m[2][2], m[3][2], m[0][3], m[1][3], m[2][3], m[3][3],
    )
}

/// Inverse of a rigid transform (rotation + translation).
pub fn rigid_inverse(a: &Mat4) -> Mat4 {
    let mut m = IDENTITY;
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = a[j][i];
        }
    }
    for row in m.iter_mut().take(3) {
        row[3] = -(0..3).map(|k| row[k] * a[k][3]).sum::<f64>();
    }
    m
}
