//! numpy in and out. Inputs are read in place when they are contiguous float64 arrays (the
//! usual case) and converted once otherwise (lists, integer arrays, strided views); outputs
//! are new arrays that own their memory (never views of a `Data` that the next call
//! overwrites).

use nalgebra::{Dim, Matrix, RawStorage};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1};
use pyo3::prelude::*;
use std::borrow::Cow;

/// A vector argument: anything numpy can turn into a 1-D float64 array.
pub type VectorArg<'py> = PyArrayLike1<'py, f64, AllowTypeChange>;

/// The argument's values, borrowed when it is a contiguous float64 array.
pub fn slice<'a>(x: &'a VectorArg<'_>) -> Cow<'a, [f64]> {
    match x.as_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(x.as_array().iter().copied().collect()),
    }
}

/// A new 1-D array with `values`.
pub fn vector<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, values)
}

/// A new C-ordered 2-D array with the entries of a (column-major) nalgebra matrix.
pub fn matrix<'py, R: Dim, C: Dim, S: RawStorage<f64, R, C>>(
    py: Python<'py>,
    m: &Matrix<f64, R, C, S>,
) -> Bound<'py, PyArray2<f64>> {
    let (rows, cols) = m.shape();
    let array = numpy::ndarray::Array2::from_shape_fn((rows, cols), |(r, c)| m[(r, c)]);
    PyArray2::from_owned_array(py, array)
}

/// A new 1-D array with the entries of a vector.
pub fn dvector<'py>(py: Python<'py>, x: &nalgebra::DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    vector(py, x.as_slice())
}

/// The 4 × 4 homogeneous matrix of a placement.
pub fn homogeneous<'py>(
    py: Python<'py>,
    m: &corps_model::spatial::Se3,
) -> Bound<'py, PyArray2<f64>> {
    let mut h = nalgebra::Matrix4::identity();
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(&m.rotation);
    h.fixed_view_mut::<3, 1>(0, 3).copy_from(&m.translation);
    matrix(py, &h)
}
