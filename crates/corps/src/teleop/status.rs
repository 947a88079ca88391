//! What teleoperation shows and reports as the run goes: the velocity the robot achieves, its
//! steps, its pose and the controller's time, computed from the run's rows and true state by a
//! row sink; it also paces the run to real time and applies a key script.

use super::keys::{KeyAction, TimedKey};
use corps_loop::Truth;
use corps_scenario::run::RowSink;
use corps_scenario::teleop::VelocityPad;
use corps_scenario::velocity_walk::LiveVelocity;
use corps_scenario::ScenarioError;
use corps_walk::mpc::VelocityCommand;
use corps_walk::pose::wrap_angle;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The window over which the achieved velocity is averaged (s): about two steps of seed
/// 002's gait (1.2 s each), so that the sway within a step averages out.
pub const VELOCITY_WINDOW: f64 = 2.4;

/// A foot is loaded above this fraction of the robot's standing weight and unloaded below
/// half of it; it changes between stance and swing once the new state has held [`HOLD`] s
/// (shorter touches are scuffs and landing bounces), and a step is a swing ending in stance.
const LOADED: f64 = 0.1;
const HOLD: f64 = 0.1;

/// The base's planar pose: x, y (m, world) and yaw (rad).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
}

/// A snapshot for the display and the final report.
#[derive(Clone, Debug, Default)]
pub struct Status {
    /// Simulated time since the handover (s).
    pub t: f64,
    pub commanded: VelocityCommand,
    /// Achieved (v_x, v_y) in the base's heading frame (m/s, the heading halfway through the
    /// window, so that turning shows no sideways speed) and yaw rate (rad/s), averaged over
    /// [`VELOCITY_WINDOW`].
    pub achieved: [f64; 3],
    /// Touchdowns of either foot since the handover.
    pub steps: usize,
    pub start: Pose,
    pub pose: Pose,
    /// Heading change since the start (rad), unwrapped: two turns are 4π.
    pub turned: f64,
    /// The last control tick's time and the longest so far (µs).
    pub tick_us: f64,
    pub tick_us_max: f64,
    /// Simulated over wall time since the start (1 when paced and keeping up).
    pub realtime_factor: f64,
    /// Recent (t, commanded v_x, achieved v_x, commanded v_y, achieved v_y), one per
    /// [`PUBLISH_EVERY`] ticks.
    pub history: Vec<[f64; 5]>,
}

impl Status {
    /// Distance (m) from the start, and the heading change (rad, unwrapped).
    pub fn travelled(&self) -> (f64, f64) {
        let d = (self.pose.x - self.start.x).hypot(self.pose.y - self.start.y);
        (d, self.turned)
    }
}

/// The planar pose of a free-flyer base from `q` (x, y, z, quaternion x, y, z, w).
fn base_pose(q: &[f64]) -> Pose {
    let (x, y, z, w) = (q[3], q[4], q[5], q[6]);
    Pose {
        x: q[0],
        y: q[1],
        yaw: (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
    }
}

/// Column indices the status reads.
struct Columns {
    t: usize,
    fz: [usize; 2],
    tick_us: usize,
}

/// The row sink of a teleoperated run.
pub struct TeleopSink {
    columns: Columns,
    dt: f64,
    input: Arc<LiveVelocity>,
    shared: Arc<Mutex<Status>>,
    status: Status,
    /// Base poses of the last [`VELOCITY_WINDOW`] (a ring of `window` entries, one per tick).
    poses: Vec<(f64, Pose)>,
    window: usize,
    ticks: usize,
    weight: Option<f64>,
    /// Each foot in stance (else swinging), and since when the other state has held.
    stance: [bool; 2],
    pending: [Option<f64>; 2],
    /// Real-time pacing: the wall clock when simulated time 0 was due.
    pace: Option<Instant>,
    wall_start: Instant,
    /// A key script and the index of its next key.
    script: Vec<TimedKey>,
    next_key: usize,
    pad: VelocityPad,
    quit: &'static AtomicBool,
}

/// How often (control ticks) the display's copy and history are refreshed: 20 Hz at 1 kHz.
pub const PUBLISH_EVERY: usize = 50;
const HISTORY: usize = 400;

impl TeleopSink {
    /// A sink for a run with `columns` at period `dt`, steering `input`: paced to real time
    /// when `realtime`, applying the keys of `script` at their times (with `pad`), raising
    /// `quit` at a scripted quit.
    pub fn new(
        columns: &[String],
        dt: f64,
        input: Arc<LiveVelocity>,
        realtime: bool,
        script: Vec<TimedKey>,
        pad: VelocityPad,
        quit: &'static AtomicBool,
    ) -> anyhow::Result<Self> {
        let find = |name: &str| crate::output::column(columns, name);
        let window = (VELOCITY_WINDOW / dt).round() as usize + 1;
        Ok(Self {
            columns: Columns {
                t: find("t")?,
                fz: [find("left_foot_fz")?, find("right_foot_fz")?],
                tick_us: find("tick_us")?,
            },
            dt,
            input,
            shared: Arc::new(Mutex::new(Status::default())),
            status: Status {
                history: Vec::with_capacity(HISTORY),
                ..Default::default()
            },
            poses: Vec::with_capacity(window),
            window,
            ticks: 0,
            weight: None,
            stance: [true; 2],
            pending: [None; 2],
            pace: realtime.then(Instant::now),
            wall_start: Instant::now(),
            script,
            next_key: 0,
            pad,
            quit,
        })
    }

    /// The status as the display reads it.
    pub fn shared(&self) -> Arc<Mutex<Status>> {
        self.shared.clone()
    }

    /// The status at the end of the run.
    pub fn finish(&self) -> Status {
        let mut s = self.status.clone();
        s.commanded = self.input.get();
        s
    }

    fn apply_keys(&mut self, t: f64) {
        while let Some(k) = self.script.get(self.next_key).filter(|k| k.t <= t + 1e-9) {
            match k.action {
                KeyAction::Pad(a) => self.input.set(self.pad.apply(a)),
                KeyAction::Quit => self.quit.store(true, Ordering::SeqCst),
            }
            self.next_key += 1;
        }
    }

    fn count_steps(&mut self, t: f64, row: &[f64]) {
        let fz = self.columns.fz.map(|c| row[c]);
        let weight = *self.weight.get_or_insert(fz[0] + fz[1]);
        for (k, f) in fz.into_iter().enumerate() {
            let other = if self.stance[k] {
                f < 0.5 * LOADED * weight
            } else {
                f > LOADED * weight
            };
            if !other {
                self.pending[k] = None;
                continue;
            }
            let since = *self.pending[k].get_or_insert(t);
            if t - since >= HOLD - 1e-9 {
                self.stance[k] = !self.stance[k];
                self.pending[k] = None;
                if self.stance[k] {
                    self.status.steps += 1;
                }
            }
        }
    }

    fn pace(&mut self, t: f64) {
        let Some(start) = self.pace else { return };
        let due = start + Duration::from_secs_f64(t.max(0.0));
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        } else if now - due > Duration::from_millis(250) {
            // Too slow to keep up: drift instead of rushing to catch up.
            self.pace = Some(now - Duration::from_secs_f64(t.max(0.0)));
        }
    }
}

impl RowSink for TeleopSink {
    fn row(&mut self, _index: usize, row: &[f64]) -> Result<(), ScenarioError> {
        let t = row[self.columns.t];
        self.status.t = t;
        self.apply_keys(t);
        self.count_steps(t, row);
        let tick = row[self.columns.tick_us];
        self.status.tick_us = tick;
        self.status.tick_us_max = self.status.tick_us_max.max(tick);
        self.pace(t + self.dt);
        Ok(())
    }

    fn state(&mut self, _index: usize, truth: &Truth) -> Result<(), ScenarioError> {
        let pose = base_pose(truth.q.as_slice());
        let t = self.status.t;
        if self.ticks == 0 {
            self.status.start = pose;
        } else {
            self.status.turned += wrap_angle(pose.yaw - self.status.pose.yaw);
        }
        self.status.pose = pose;
        let n = self.window;
        if self.poses.len() < n {
            self.poses.push((t, pose));
        } else {
            self.poses[self.ticks % n] = (t, pose);
        }
        let (t0, p0) = if self.poses.len() < n {
            self.poses[0]
        } else {
            self.poses[(self.ticks + 1) % n]
        };
        if t > t0 {
            let span = t - t0;
            let turn = wrap_angle(pose.yaw - p0.yaw);
            let (s, c) = (p0.yaw + 0.5 * turn).sin_cos();
            let (dx, dy) = (pose.x - p0.x, pose.y - p0.y);
            self.status.achieved = [
                (c * dx + s * dy) / span,
                (-s * dx + c * dy) / span,
                turn / span,
            ];
        }
        self.ticks += 1;
        if self.ticks.is_multiple_of(PUBLISH_EVERY) {
            self.status.commanded = self.input.get();
            let wall = self.wall_start.elapsed().as_secs_f64();
            self.status.realtime_factor = if wall > 0.0 { t / wall } else { 0.0 };
            let c = self.status.commanded;
            let a = self.status.achieved;
            if self.status.history.len() == HISTORY {
                self.status.history.remove(0);
            }
            self.status.history.push([t, c.vx, a[0], c.vy, a[1]]);
            if let Ok(mut shared) = self.shared.lock() {
                shared.clone_from(&self.status);
            }
        }
        Ok(())
    }
}
