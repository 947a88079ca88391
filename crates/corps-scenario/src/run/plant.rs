//! The plant of a scenario run: corps' simulator, or a plant that computes its own physics
//! (another engine, a Python class) read through corps' sensors from the settled state on.

use corps_loop::{Command, Plant, PlantError, Sensed};
use corps_sim::{ExternalPlant, SimulatedRobot, StatePlant, WithHiddenJoints};
use nalgebra::DVector;

/// Either plant, dispatched without a virtual call on the simulator's path.
// One plant per run, moved once: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
pub enum RunPlant {
    Simulated(SimulatedRobot),
    /// The simulator on a model with joints the controllers do not see.
    Hidden(WithHiddenJoints<SimulatedRobot>),
    External(ExternalPlant<Box<dyn StatePlant>>),
}

impl RunPlant {
    /// Ticks whose next step was prepared on a second thread.
    pub fn overlapped_ticks(&self) -> u64 {
        match self {
            RunPlant::Simulated(p) => p.overlap_counts().0,
            RunPlant::Hidden(p) => p.inner().overlap_counts().0,
            RunPlant::External(_) => 0,
        }
    }

    /// The true configuration at the end of the run.
    pub fn final_configuration(self) -> Result<DVector<f64>, PlantError> {
        match self {
            RunPlant::Simulated(p) => Ok(p.into_simulator()?.q().clone_owned()),
            RunPlant::Hidden(p) => {
                let map = p.map().clone();
                let sim = p.into_inner().into_simulator()?;
                let mut q = DVector::zeros(map.rigid_nq());
                map.narrow_q(sim.q().as_slice(), q.as_mut_slice());
                Ok(q)
            }
            RunPlant::External(p) => Ok(p.last_state().q.clone()),
        }
    }
}

impl Plant for RunPlant {
    fn sensed(&self) -> Sensed {
        match self {
            RunPlant::Simulated(p) => p.sensed(),
            RunPlant::Hidden(p) => p.sensed(),
            RunPlant::External(p) => p.sensed(),
        }
    }
    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        match self {
            RunPlant::Simulated(p) => p.sense(out),
            RunPlant::Hidden(p) => p.sense(out),
            RunPlant::External(p) => p.sense(out),
        }
    }
    fn complete(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        match self {
            RunPlant::Simulated(p) => p.complete(out),
            RunPlant::Hidden(p) => p.complete(out),
            RunPlant::External(p) => p.complete(out),
        }
    }
    fn prepare(&mut self) {
        match self {
            RunPlant::Simulated(p) => p.prepare(),
            RunPlant::Hidden(p) => p.prepare(),
            RunPlant::External(p) => p.prepare(),
        }
    }
    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        match self {
            RunPlant::Simulated(p) => p.step(command),
            RunPlant::Hidden(p) => p.step(command),
            RunPlant::External(p) => p.step(command),
        }
    }
}
