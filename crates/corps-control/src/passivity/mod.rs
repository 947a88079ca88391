//! Passivity by a global energy tank (seed 000 ch. 5, §3.18 of its digest): the stacked task
//! energy `S = ½ Eᵀ Λ K_P E` ([`StackedTaskEnergy`]), the tank `E_tank = ½ s²` with its three
//! valves ([`EnergyTank`]), and the power they give the inverse-dynamics QP: the valves scale
//! every reference by βγ and the QP keeps `Ḣ ≤ −q̇_jᵀτ` (see
//! [`crate::formulation::PassiveInverseDynamics`]).

mod stacked_energy;
mod tank;

pub use stacked_energy::{StackedTaskEnergy, TaskPower};
pub use tank::{smooth_step, EnergyTank, TankParams, Valves};
