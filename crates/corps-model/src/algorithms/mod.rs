//! Rigid-body algorithms: free functions over an immutable [`crate::Model`] and a
//! [`crate::Data`] workspace, one algorithm per file.

pub mod aba;
pub mod all_terms;
pub mod centroidal;
pub mod cholesky;
pub mod coriolis;
pub mod crba;
pub mod energy;
pub mod jacobians;
pub mod kinematics;
pub mod minverse;
pub mod operational_space;
pub mod rnea;
