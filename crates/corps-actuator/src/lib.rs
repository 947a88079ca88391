//! Joint actuators (seed 000 ch. 3): the single-joint drive model of the TALOS elbow
//! ([`elbow`], Eq 3.1–3.5), read from an actuator description file ([`description`]); its
//! thermal model and identification ([`thermal`], Eq 3.6–3.8); and the current-limiting
//! iLQR that keeps the motor current under its limit with exponential barriers
//! ([`current_ocp`], [`ilqr`], [`mpc`], §3.13).

pub mod barrier;
pub mod butterworth;
mod csv_rows;
pub mod current_ocp;
pub mod description;
pub mod elbow;
mod error;
pub mod excitation;
pub mod identification;
pub mod ilqr;
pub mod mpc;
pub mod records;
pub mod simulated_joint;
pub mod thermal;

pub use description::ActuatorDescription;
pub use error::ActuatorError;
