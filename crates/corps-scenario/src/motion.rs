//! Reference motions of a run: what the controller is asked to do, sampled every tick as
//! [`Targets`] (a CoM reference and one target per foot). Times count from the moment the
//! controller takes over; positions are relative to the robot's pose at that moment.

use crate::error::Context;
use crate::targets::positive;
pub use crate::targets::{FootTarget, PostureWave, Side, Targets};
use crate::velocity_walk::{LiveWalk, VelocitySource};
use crate::walk::{VelocitySection, WalkMotion, WalkSection};
use corps_control::tasks::Reference;
use corps_control::trajectories::{MinJerk, Sampled, Sinusoid};
use corps_model::spatial::{Motion, Se3};
use corps_sim::Terrain;
use nalgebra::{DVector, Vector3};
use serde::Deserialize;

/// `[motion]` of a scenario.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionSection {
    /// Hold the starting CoM and feet. (A struct variant with no field, so that an unknown
    /// key beside `kind = "stand"` is an error as in every other variant.)
    Stand {},
    /// CoM sinusoid about its start, `amplitude` (m, per axis) at `frequency` (Hz); the
    /// amplitude ramps in over `ramp` s (min-jerk) so the reference starts at rest.
    ComSinusoid {
        amplitude: [f64; 3],
        frequency: f64,
        #[serde(default = "one_second")]
        ramp: f64,
    },
    /// CoM down by `depth` (m) in `duration` s and back up in `duration` s (min-jerk each).
    Squat { depth: f64, duration: f64 },
    /// The CoM reference jumps by `offset` (m, world) at `at` s and holds there: a reference
    /// step, no derivative (seed 000 ch. 5's robustness case, the thesis's "10 cm on the CoM").
    ComStep { offset: [f64; 3], at: f64 },
    /// Shift the CoM over the `support` foot in `shift` s, release the other foot's contact
    /// (its force ramps to zero over the controller's contact transition), then lift it by
    /// `lift` m in `lift_duration` s, `release` s after the shift, and hold.
    OneFoot {
        support: Side,
        #[serde(default = "two_seconds")]
        shift: f64,
        #[serde(default = "release_time")]
        release: f64,
        #[serde(default = "five_centimetres")]
        lift: f64,
        #[serde(default = "one_second")]
        lift_duration: f64,
    },
    /// Walk a footstep plan (straight, stairs with `step_height`, or footholds on the terrain
    /// with `on_terrain`) with preview control.
    Walk(WalkSection),
    /// Walk by velocity commands through the MPC pattern generator.
    Velocity(VelocitySection),
    /// CoM displacement from the start read from a CSV file, rows `t, dx, dy, dz` (a natural
    /// cubic spline through them); `path` is relative to the scenario file.
    ComFile { path: std::path::PathBuf },
    /// Joints swing about their starting angle, `joints` giving each one's amplitude (rad),
    /// `sin(2π f t)` at `frequency` (Hz), the amplitude ramping in over `ramp` s (min-jerk);
    /// the CoM and feet hold. Drives the posture task's reference (TSID controllers).
    PostureSinusoid {
        joints: std::collections::BTreeMap<String, f64>,
        frequency: f64,
        #[serde(default = "one_second")]
        ramp: f64,
    },
}

impl Default for MotionSection {
    fn default() -> Self {
        MotionSection::Stand {}
    }
}

fn one_second() -> f64 {
    1.0
}
fn two_seconds() -> f64 {
    2.0
}
fn release_time() -> f64 {
    0.3
}
fn five_centimetres() -> f64 {
    0.05
}

impl MotionSection {
    /// Whether a walk can be steered live ([`crate::run::ScenarioRun::steered`]): a velocity
    /// walk with no scheduled commands.
    pub fn check_steerable(&self) -> crate::Result<()> {
        match self {
            MotionSection::Velocity(v) if v.commands.is_empty() => Ok(()),
            MotionSection::Velocity(_) => crate::error::bail!(
                "motion.commands: a steered walk takes its commands live; remove them"
            ),
            _ => crate::error::bail!(
                "motion: steering needs a velocity walk ([motion] kind = \"velocity\")"
            ),
        }
    }

    /// Checks the values; the error names the key.
    pub fn check(&self) -> Result<(), String> {
        match self {
            MotionSection::Stand {} => Ok(()),
            MotionSection::Walk(w) => w.check(),
            MotionSection::Velocity(v) => v.check(),
            MotionSection::ComFile { .. } => Ok(()),
            MotionSection::PostureSinusoid {
                joints,
                frequency,
                ramp,
            } => {
                if let Some((j, a)) = joints.iter().find(|(_, a)| !a.is_finite()) {
                    return Err(format!("motion.joints.{j} = {a}: must be finite"));
                }
                if joints.is_empty() {
                    return Err("motion.joints: name at least one joint".into());
                }
                positive("frequency", *frequency)?;
                positive("ramp", *ramp)
            }
            MotionSection::ComSinusoid {
                amplitude,
                frequency,
                ramp,
            } => {
                if amplitude.iter().any(|a| !a.is_finite()) {
                    return Err("motion.amplitude: must be finite".into());
                }
                positive("frequency", *frequency)?;
                positive("ramp", *ramp)
            }
            MotionSection::Squat { depth, duration } => {
                if !depth.is_finite() {
                    return Err("motion.depth: must be finite".into());
                }
                positive("duration", *duration)
            }
            MotionSection::ComStep { offset, at } => {
                if offset.iter().any(|a| !a.is_finite()) {
                    return Err("motion.offset: must be finite".into());
                }
                if !(*at >= 0.0 && at.is_finite()) {
                    return Err("motion.at: must be a time ≥ 0 s".into());
                }
                Ok(())
            }
            MotionSection::OneFoot {
                shift,
                release,
                lift,
                lift_duration,
                ..
            } => {
                positive("shift", *shift)?;
                positive("release", *release)?;
                positive("lift_duration", *lift_duration)?;
                if !lift.is_finite() || *lift < 0.0 {
                    return Err(format!("motion.lift = {lift}: must be ≥ 0"));
                }
                Ok(())
            }
        }
    }
}

/// A motion anchored at the robot's CoM and soles when the controller takes over.
pub struct MotionPlan {
    section: MotionSection,
    com0: Vector3<f64>,
    feet0: [Se3; 2],
    walk: Option<WalkMotion>,
    /// A velocity walk steered live, planned as it is sampled.
    live: Option<LiveWalk>,
    com_file: Option<Sampled>,
    /// Per actuated joint, the posture sinusoid's amplitude.
    posture_amplitude: Option<std::sync::Arc<DVector<f64>>>,
}

/// A min-jerk ramp from 0 to 1 over `duration` s: its value and two derivatives at `t`.
fn ramp_in(t: f64, duration: f64) -> (f64, f64, f64) {
    let r = MinJerk {
        start: DVector::zeros(1),
        end: DVector::from_element(1, 1.0),
        t0: 0.0,
        duration,
    }
    .sample(t);
    (r.pos[0], r.vel[0], r.acc[0])
}

/// Where the robot stands when the controller takes over: its CoM and soles.
#[derive(Clone, Copy, Debug)]
pub struct Handover {
    pub com: Vector3<f64>,
    pub feet: [Se3; 2],
}

/// The run's control period and length (s).
#[derive(Clone, Copy, Debug)]
pub struct Timeline {
    pub dt: f64,
    pub duration: f64,
}

impl MotionPlan {
    /// The motion of `robot` from `handover` over `timeline` and `terrain`; files are read
    /// relative to `base_dir`. With `steering`, a velocity motion takes its commands from it
    /// as the run goes instead of its schedule (which must then be empty).
    pub fn new(
        robot: &corps_robot::Robot,
        section: MotionSection,
        handover: Handover,
        timeline: Timeline,
        base_dir: &std::path::Path,
        terrain: &Terrain,
        steering: Option<Box<dyn VelocitySource>>,
    ) -> crate::Result<Self> {
        let Timeline { dt, duration } = timeline;
        let Handover {
            com: com0,
            feet: feet0,
        } = handover;
        let com_file = match &section {
            MotionSection::ComFile { path } => {
                let path = base_dir.join(path);
                let text = std::fs::read_to_string(&path)
                    .with_context(|| format!("motion.path: reading {}", path.display()))?;
                let s = Sampled::from_csv(&text)
                    .with_context(|| format!("motion.path: {}", path.display()))?;
                if s.sample(0.0).pos.len() != 3 {
                    crate::error::bail!(
                        "motion.path: {}: rows must be `t, dx, dy, dz`",
                        path.display()
                    );
                }
                Some(s)
            }
            _ => None,
        };
        // CoM height above the soles at the handover.
        let com_height = com0.z - (feet0[0].translation.z + feet0[1].translation.z) / 2.0;
        let mut live = None;
        if steering.is_some() {
            section.check_steerable()?;
        }
        let walk = match (&section, steering) {
            (MotionSection::Velocity(v), Some(source)) => {
                live = Some(LiveWalk::new(
                    robot, source, v.release, &feet0, com_height, dt,
                )?);
                None
            }
            // (Steering is None below: the check above refused it for other motions.)
            (MotionSection::Walk(w), _) => {
                Some(WalkMotion::new(w, &feet0, &com0, dt, duration, terrain)?)
            }
            (MotionSection::Velocity(v), None) => Some(WalkMotion::velocity(
                robot, v, &feet0, com_height, dt, duration,
            )?),
            _ => None,
        };
        let posture_amplitude = match &section {
            MotionSection::PostureSinusoid { joints, .. } => {
                let model = &robot.model;
                let first = model.first_actuated();
                let mut a = DVector::zeros(model.nv - first);
                for (name, amplitude) in joints {
                    let joint = model.joints.iter().find(|j| &j.name == name);
                    match joint {
                        Some(j) if j.nv() == 1 && j.idx_v >= first => {
                            a[j.idx_v - first] = *amplitude
                        }
                        Some(_) => crate::error::bail!(
                            "motion.joints.{name}: not a one-dof actuated joint"
                        ),
                        None => crate::error::bail!("motion.joints.{name}: no such joint"),
                    }
                }
                Some(std::sync::Arc::new(a))
            }
            _ => None,
        };
        Ok(Self {
            section,
            com0,
            feet0,
            walk,
            live,
            com_file,
            posture_amplitude,
        })
    }

    /// The walk, when the motion is one.
    pub fn walk(&self) -> Option<&WalkMotion> {
        self.walk.as_ref()
    }

    /// The walk, to correct it before the run.
    pub fn walk_mut(&mut self) -> Option<&mut WalkMotion> {
        self.walk.as_mut()
    }

    /// The targets at rest at the starting pose.
    pub fn initial_targets(&self) -> Targets {
        Targets::at_rest(&self.com0, &self.feet0)
    }

    /// The live walk's MPC failures (periods where it held the previous sample) and the
    /// first one; None without a live walk.
    pub fn live_failures(&self) -> Option<(usize, Option<&str>)> {
        self.live.as_ref().map(LiveWalk::failures)
    }

    /// Writes the targets at time `t` (s since the handover) into `out`.
    pub fn sample(&mut self, t: f64, out: &mut Targets) {
        let c0 = DVector::from_column_slice(self.com0.as_slice());
        match &self.section {
            MotionSection::Stand {} => {}
            MotionSection::PostureSinusoid {
                frequency, ramp, ..
            } => {
                let (k, dk, ddk) = ramp_in(t, *ramp);
                let w = std::f64::consts::TAU * frequency;
                let (sin, cos) = (w * t).sin_cos();
                // s = k(t) sin(ωt): the product rule gives the derivatives.
                let wave = [
                    k * sin,
                    dk * sin + k * w * cos,
                    ddk * sin + 2.0 * dk * w * cos - k * w * w * sin,
                ];
                out.posture = self.posture_amplitude.as_ref().map(|a| PostureWave {
                    amplitude: a.clone(),
                    wave,
                });
            }
            MotionSection::Walk(_) | MotionSection::Velocity(_) => {
                if let Some(w) = &mut self.live {
                    w.sample(t, out);
                } else if let Some(w) = &self.walk {
                    w.sample(t, out);
                }
            }
            MotionSection::ComFile { .. } => {
                if let Some(f) = &self.com_file {
                    let r = f.sample(t);
                    out.com = Reference {
                        pos: &c0 + r.pos,
                        vel: r.vel,
                        acc: r.acc,
                    };
                }
            }
            MotionSection::ComStep { offset, at } => {
                let mut pos = c0.clone();
                if t >= *at {
                    for k in 0..3 {
                        pos[k] += offset[k];
                    }
                }
                out.com = Reference::constant(pos);
            }
            MotionSection::ComSinusoid {
                amplitude,
                frequency,
                ramp,
            } => {
                let sine = Sinusoid {
                    center: c0.clone(),
                    amplitude: DVector::from_column_slice(amplitude),
                    frequency: *frequency,
                };
                let s = sine.sample(t);
                let (k, dk, ddk) = ramp_in(t, *ramp);
                // c = c0 + k(t)(s − c0): the product rule gives the derivatives.
                let d = &s.pos - &c0;
                out.com = Reference {
                    pos: &c0 + &d * k,
                    vel: &s.vel * k + &d * dk,
                    acc: &s.acc * k + &s.vel * (2.0 * dk) + &d * ddk,
                };
            }
            MotionSection::Squat { depth, duration } => {
                let mut low = c0.clone();
                low[2] -= depth;
                out.com = if t < *duration {
                    MinJerk {
                        start: c0,
                        end: low,
                        t0: 0.0,
                        duration: *duration,
                    }
                    .sample(t)
                } else {
                    MinJerk {
                        start: low,
                        end: c0,
                        t0: *duration,
                        duration: *duration,
                    }
                    .sample(t)
                };
            }
            MotionSection::OneFoot {
                support,
                shift,
                release,
                lift,
                lift_duration,
            } => {
                let stance = self.feet0[support.index()].translation;
                let mut over = c0.clone();
                over[0] = stance.x;
                over[1] = stance.y;
                out.com = MinJerk {
                    start: c0,
                    end: over,
                    t0: 0.0,
                    duration: *shift,
                }
                .sample(t);
                let swing = 1 - support.index();
                let foot = &mut out.feet[swing];
                foot.in_contact = t < *shift;
                foot.supporting = t < shift + release;
                let start = self.feet0[swing].translation;
                let r = MinJerk {
                    start: DVector::from_column_slice(start.as_slice()),
                    end: DVector::from_column_slice((start + Vector3::z() * *lift).as_slice()),
                    t0: shift + release,
                    duration: *lift_duration,
                }
                .sample(t);
                let v3 = |x: &DVector<f64>| Vector3::new(x[0], x[1], x[2]);
                foot.reference.placement.translation = v3(&r.pos);
                foot.reference.velocity = Motion::new(v3(&r.vel), Vector3::zeros());
                foot.reference.acceleration = Motion::new(v3(&r.acc), Vector3::zeros());
            }
        }
    }
}

impl corps_loop::ReferenceSource<Targets> for MotionPlan {
    fn sample(&mut self, t: f64, out: &mut Targets) {
        MotionPlan::sample(self, t, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(section: MotionSection) -> MotionPlan {
        let foot = |y: f64| Se3::new(nalgebra::Matrix3::identity(), Vector3::new(0.0, y, 0.0));
        let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
        MotionPlan::new(
            &talos,
            section,
            Handover {
                com: Vector3::new(0.0, 0.0, 0.88),
                feet: [foot(0.1), foot(-0.1)],
            },
            Timeline {
                dt: 1e-3,
                duration: 10.0,
            },
            std::path::Path::new("."),
            &Terrain::default(),
            None,
        )
        .unwrap()
    }

    #[test]
    fn the_sinusoid_starts_at_rest_and_reaches_its_amplitude() {
        let mut p = plan(MotionSection::ComSinusoid {
            amplitude: [0.0, 0.03, 0.0],
            frequency: 0.5,
            ramp: 1.0,
        });
        let mut out = p.initial_targets();
        p.sample(0.0, &mut out);
        assert!(out.com.vel.norm() < 1e-12 && out.com.acc.norm() < 1e-12);
        p.sample(2.5, &mut out); // sin(2π·0.5·2.5) = 1
        assert!((out.com.pos[1] - 0.03).abs() < 1e-12);
    }

    #[test]
    fn one_foot_releases_then_lifts_the_swing_foot() {
        let mut p = plan(MotionSection::OneFoot {
            support: Side::Left,
            shift: 2.0,
            release: 0.3,
            lift: 0.05,
            lift_duration: 1.0,
        });
        let mut out = p.initial_targets();
        p.sample(1.0, &mut out);
        assert!(out.feet[1].in_contact);
        p.sample(2.1, &mut out);
        assert!(!out.feet[1].in_contact);
        assert!(out.feet[1].reference.placement.translation.z.abs() < 1e-12);
        p.sample(4.0, &mut out);
        assert!((out.feet[1].reference.placement.translation.z - 0.05).abs() < 1e-12);
        assert!((out.com.pos[1] - 0.1).abs() < 1e-12);
        assert!(out.feet[0].in_contact);
    }

    #[test]
    fn bad_values_name_their_key() {
        let e = MotionSection::Squat {
            depth: 0.1,
            duration: 0.0,
        }
        .check()
        .unwrap_err();
        assert!(e.contains("motion.duration"), "{e}");
    }
}
