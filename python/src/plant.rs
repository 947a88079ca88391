//! Plants written in Python: any object with `reset(q, v, t, dt)`, `step(command)` and
//! `state()` drives a scenario run in place of corps' simulator (`corps.run(..., plant=obj)`).
//! corps reads the robot's sensors from the state it reports, with the scenario's noise.

use crate::arrays::{dvector, vector};
use crate::errors::PlantError as PyPlantError;
use corps_loop::{Command, ContactForce, PlantError};
use corps_sim::{PlantState, Push, ServoGains, StatePlant};
use nalgebra::{DVector, Vector3};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::{Arc, Mutex};

/// One control period's command, as a Python plant receives it.
#[pyclass(name = "Command", module = "corps", frozen)]
pub struct PyCommand {
    /// `torque`, `position` or `velocity`.
    #[pyo3(get)]
    kind: &'static str,
    /// Joint torques (N·m, size na) for `torque`.
    #[pyo3(get)]
    torque: Option<Py<PyArray1<f64>>>,
    /// The full configuration whose joint part is the position target (size nq; the base part
    /// is ignored) for `position`.
    #[pyo3(get)]
    q_ref: Option<Py<PyArray1<f64>>>,
    /// Joint velocity targets (rad/s, size na) for `position` and `velocity`.
    #[pyo3(get)]
    v_ref: Option<Py<PyArray1<f64>>>,
}

#[pymethods]
impl PyCommand {
    fn __repr__(&self) -> String {
        format!("corps.Command(kind='{}')", self.kind)
    }
}

impl PyCommand {
    fn new(py: Python<'_>, c: &Command) -> Self {
        let arr = |x: &DVector<f64>| Some(dvector(py, x).unbind());
        match c {
            Command::Torque(t) => Self {
                kind: "torque",
                torque: arr(t),
                q_ref: None,
                v_ref: None,
            },
            Command::Position { q_ref, v_ref } => Self {
                kind: "position",
                torque: None,
                q_ref: arr(q_ref),
                v_ref: arr(v_ref),
            },
            Command::Velocity(v) => Self {
                kind: "velocity",
                torque: None,
                q_ref: None,
                v_ref: arr(v),
            },
        }
    }
}

/// The first Python exception a plant raised, to re-raise from `corps.run`.
pub type Raised = Arc<Mutex<Option<PyErr>>>;

/// A Python object as a [`StatePlant`].
pub struct PythonPlant {
    object: Py<PyAny>,
    nq: usize,
    nv: usize,
    raised: Raised,
}

impl PythonPlant {
    /// `object` as a plant; its sizes are the first state's, given to `reset`.
    pub fn new(object: Py<PyAny>, raised: Raised) -> Self {
        Self {
            object,
            nq: 0,
            nv: 0,
            raised,
        }
    }

    /// A Python exception as the loop's plant error; the exception itself is kept.
    fn failed(&self, method: &str, e: PyErr) -> PlantError {
        let message = format!("plant.{method}(): {e}");
        if let Ok(mut slot) = self.raised.lock() {
            slot.get_or_insert(e);
        }
        PlantError::Failed(message)
    }

    /// A broken protocol as a `corps.PlantError`.
    fn protocol(&self, method: &str, what: String) -> PlantError {
        self.failed(
            method,
            PyPlantError::new_err(format!("plant.{method}(): {what}")),
        )
    }
}

impl StatePlant for PythonPlant {
    fn reset(&mut self, q: &[f64], v: &[f64], t: f64, dt: f64) -> Result<(), PlantError> {
        (self.nq, self.nv) = (q.len(), v.len());
        Python::attach(|py| {
            let args = (vector(py, q), vector(py, v), t, dt);
            self.object.call_method1(py, "reset", args).map(|_| ())
        })
        .map_err(|e| self.failed("reset", e))
    }

    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        Python::attach(|py| {
            let c = Py::new(py, PyCommand::new(py, command))?;
            self.object.call_method1(py, "step", (c,)).map(|_| ())
        })
        .map_err(|e| self.failed("step", e))
    }

    fn servo_gains(&mut self, gains: &ServoGains) -> Result<(), PlantError> {
        let has = Python::attach(|py| self.object.bind(py).hasattr("servo"))
            .map_err(|e| self.failed("servo", e))?;
        if !has {
            return Ok(());
        }
        Python::attach(|py| {
            let integral = gains.integral.as_ref().map(|i| vector(py, i.ki.as_slice()));
            let args = (
                vector(py, gains.kp.as_slice()),
                vector(py, gains.kd.as_slice()),
                integral,
            );
            self.object.call_method1(py, "servo", args).map(|_| ())
        })
        .map_err(|e| self.failed("servo", e))
    }

    fn push(&mut self, push: &Push) -> Result<(), PlantError> {
        let has = Python::attach(|py| self.object.bind(py).hasattr("push"))
            .map_err(|e| self.failed("push", e))?;
        if !has {
            return Err(self.protocol(
                "push",
                format!(
                    "the scenario pushes '{}' and the plant has no push() method",
                    push.frame
                ),
            ));
        }
        Python::attach(|py| {
            let args = (
                push.frame.clone(),
                push.start,
                push.duration,
                vector(py, &push.force),
                vector(py, &push.torque),
            );
            self.object.call_method1(py, "push", args).map(|_| ())
        })
        .map_err(|e| self.failed("push", e))
    }

    fn state(&mut self, out: &mut PlantState) -> Result<(), PlantError> {
        Python::attach(|py| -> Result<(), PlantError> {
            let s = self
                .object
                .call_method0(py, "state")
                .map_err(|e| self.failed("state", e))?;
            let s = s
                .bind(py)
                .cast::<PyDict>()
                .map_err(|_| self.protocol("state", "must return a dict".into()))?;
            let get = |key: &str| -> Result<Option<Bound<'_, PyAny>>, PlantError> {
                s.get_item(key).map_err(|e| self.failed("state", e))
            };
            let need = |key: &str| -> Result<Bound<'_, PyAny>, PlantError> {
                get(key)?.ok_or_else(|| self.protocol("state", format!("no '{key}' in the dict")))
            };
            out.time = need("t")?
                .extract::<f64>()
                .map_err(|_| self.protocol("state", "'t' must be a number (s)".into()))?;
            read_vector(self, &need("q")?, "q", self.nq, &mut out.q)?;
            read_vector(self, &need("v")?, "v", self.nv, &mut out.v)?;
            out.applied_torques.fill(0.0);
            if let Some(tau) = get("tau")? {
                let tau = tau
                    .extract::<PyArrayLike1<'_, f64, AllowTypeChange>>()
                    .map_err(|_| self.protocol("state", "'tau' must be a 1-D array".into()))?;
                let tau = tau.as_array();
                let actuated = self.nv.checked_sub(6);
                if tau.len() != self.nv && Some(tau.len()) != actuated {
                    return Err(self.protocol(
                        "state",
                        format!(
                            "'tau' has size {}, expected nv = {} (or nv - 6 with a free-flyer)",
                            tau.len(),
                            self.nv
                        ),
                    ));
                }
                let first = self.nv - tau.len();
                for (k, x) in tau.iter().enumerate() {
                    out.applied_torques[first + k] = *x;
                }
            }
            out.contacts.clear();
            if let Some(c) = get("contacts")? {
                let c = c
                    .extract::<PyArrayLike2<'_, f64, AllowTypeChange>>()
                    .map_err(|_| {
                        self.protocol("state", "'contacts' must be a (k, 7) array".into())
                    })?;
                let c = c.as_array();
                if c.ncols() != 7 && c.nrows() > 0 {
                    return Err(self.protocol(
                        "state",
                        format!(
                            "'contacts' rows are [joint, px, py, pz, fx, fy, fz], got {} columns",
                            c.ncols()
                        ),
                    ));
                }
                for row in c.rows() {
                    let joint = row[0];
                    if !(joint >= 0.0 && joint.fract() == 0.0) {
                        return Err(
                            self.protocol("state", format!("a contact's joint index is {joint}"))
                        );
                    }
                    out.contacts.push(ContactForce {
                        joint: joint as usize,
                        position: Vector3::new(row[1], row[2], row[3]),
                        force: Vector3::new(row[4], row[5], row[6]),
                    });
                }
            }
            Ok(())
        })
    }
}

fn read_vector(
    plant: &PythonPlant,
    x: &Bound<'_, PyAny>,
    name: &str,
    size: usize,
    out: &mut DVector<f64>,
) -> Result<(), PlantError> {
    let x = x
        .extract::<PyArrayLike1<'_, f64, AllowTypeChange>>()
        .map_err(|_| plant.protocol("state", format!("'{name}' must be a 1-D array")))?;
    let x = x.as_array();
    if x.len() != size {
        return Err(plant.protocol(
            "state",
            format!("'{name}' has size {}, expected {size}", x.len()),
        ));
    }
    for (o, v) in out.iter_mut().zip(x.iter()) {
        *o = *v;
    }
    Ok(())
}
