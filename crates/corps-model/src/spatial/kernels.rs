//! Explicit fixed-size products for the hot paths. nalgebra's generic small-matrix products go
//! through loops that LLVM does not fully unroll; these spell every term out (measured: CRBA
//! on TALOS spent most of its time in those loops before).

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// `A v`.
#[inline(always)]
pub fn m3v(a: &Matrix3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let c = &a.data.0;
    Vector3::new(
        c[0][0] * v.x + c[1][0] * v.y + c[2][0] * v.z,
        c[0][1] * v.x + c[1][1] * v.y + c[2][1] * v.z,
        c[0][2] * v.x + c[1][2] * v.y + c[2][2] * v.z,
    )
}

/// `Aᵀ v`.
#[inline(always)]
pub fn m3tv(a: &Matrix3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let c = &a.data.0;
    Vector3::new(
        c[0][0] * v.x + c[0][1] * v.y + c[0][2] * v.z,
        c[1][0] * v.x + c[1][1] * v.y + c[1][2] * v.z,
        c[2][0] * v.x + c[2][1] * v.y + c[2][2] * v.z,
    )
}

/// `A B`.
#[inline(always)]
pub fn m3m3(a: &Matrix3<f64>, b: &Matrix3<f64>) -> Matrix3<f64> {
    let bc = &b.data.0;
    let c0 = m3v(a, &Vector3::new(bc[0][0], bc[0][1], bc[0][2]));
    let c1 = m3v(a, &Vector3::new(bc[1][0], bc[1][1], bc[1][2]));
    let c2 = m3v(a, &Vector3::new(bc[2][0], bc[2][1], bc[2][2]));
    Matrix3::from_data(nalgebra::ArrayStorage([
        [c0.x, c0.y, c0.z],
        [c1.x, c1.y, c1.z],
        [c2.x, c2.y, c2.z],
    ]))
}

/// `R S Rᵀ` for a symmetric S.
#[inline(always)]
pub fn rotate_symmetric(r: &Matrix3<f64>, s: &Matrix3<f64>) -> Matrix3<f64> {
    let rs = m3m3(r, s);
    // (R S) Rᵀ: entry (i, j) = row i of RS · row j of R.
    let a = &rs.data.0;
    let b = &r.data.0;
    let e = |i: usize, j: usize| a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
    let (xx, xy, xz, yy, yz, zz) = (e(0, 0), e(0, 1), e(0, 2), e(1, 1), e(1, 2), e(2, 2));
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

/// `Y v` for a 6 × 6 matrix.
#[inline(always)]
pub fn m6v(y: &Matrix6<f64>, v: &Vector6<f64>) -> Vector6<f64> {
    let c = &y.data.0;
    let mut out = [0.0; 6];
    for (k, col) in c.iter().enumerate() {
        let vk = v[k];
        for (o, x) in out.iter_mut().zip(col.iter()) {
            *o += x * vk;
        }
    }
    Vector6::from(out)
}

/// `Y += X` for 6 × 6 matrices.
#[inline(always)]
pub fn m6_add_assign(y: &mut Matrix6<f64>, x: &Matrix6<f64>) {
    for (a, b) in y.data.0.iter_mut().zip(x.data.0.iter()) {
        for (p, q) in a.iter_mut().zip(b.iter()) {
            *p += q;
        }
    }
}

/// `Y −= u uᵀ s` (the rank-1 update of the articulated-body algorithm).
#[inline(always)]
pub fn m6_rank1_sub(y: &mut Matrix6<f64>, u: &Vector6<f64>, s: f64) {
    for (j, col) in y.data.0.iter_mut().enumerate() {
        let uj = u[j] * s;
        for (i, x) in col.iter_mut().enumerate() {
            *x -= u[i] * uj;
        }
    }
}
