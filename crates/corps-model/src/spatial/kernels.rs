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

/// `Y += ᵏXᵢᵀ X ᵏXᵢ`: a symmetric 6 × 6 inertia X in frame i added to Y in frame k, where frame i
/// sits at `p` with axes `r` in k (the motion transform ᵏXᵢ⁻¹ = [[Rᵀ, −Rᵀ[p]×], [0, Rᵀ]]).
/// Linear-first blocks [[A, B], [Bᵀ, C]]: rotated A = R A Rᵀ, B = R B Rᵀ, C = R C Rᵀ, then
/// moved by p: A' = A, B' = B − A[p]×, C' = C − Bᵀ[p]× + [p]×B' (Featherstone, RBDA Eq. 2.66).
#[inline(always)]
pub fn m6_transformed_add(
    y: &mut Matrix6<f64>,
    x: &Matrix6<f64>,
    r: &Matrix3<f64>,
    p: &Vector3<f64>,
) {
    let xc = &x.data.0;
    let block = |row: usize, col: usize| Matrix3::from_fn(|i, j| xc[col + j][row + i]);
    let a = rotate_symmetric(r, &block(0, 0));
    let mut b = m3m3(&m3m3(r, &block(0, 3)), &r.transpose());
    let mut c = rotate_symmetric(r, &block(3, 3));
    // Many joints share their parent's origin (p = 0: nothing to move). Otherwise row k of
    // M[p]× is (row k of M) × p and column k of [p]×M is p × (column k of M).
    if *p != Vector3::zeros() {
        let row_cross = |m: &Matrix3<f64>, k: usize| {
            let (x, y, z) = (m[(k, 0)], m[(k, 1)], m[(k, 2)]);
            [y * p.z - z * p.y, z * p.x - x * p.z, x * p.y - y * p.x]
        };
        let b2 = Matrix3::from_fn(|i, j| b[(i, j)] - row_cross(&a, i)[j]);
        let bt = b.transpose();
        let pb2 = Matrix3::from_columns(&[
            p.cross(&b2.column(0)),
            p.cross(&b2.column(1)),
            p.cross(&b2.column(2)),
        ]);
        c = Matrix3::from_fn(|i, j| c[(i, j)] - row_cross(&bt, i)[j] + pb2[(i, j)]);
        b = b2;
    }
    let yc = &mut y.data.0;
    for col in 0..3 {
        for row in 0..3 {
            yc[col][row] += a[(row, col)];
            yc[col + 3][row] += b[(row, col)];
            yc[col][row + 3] += b[(col, row)];
            yc[col + 3][row + 3] += c[(row, col)];
        }
    }
}
