//! The task stack every formulation solves: named tasks with a priority level and a weight,
//! added, re-weighted and removed at run time. A weight change is a minimum-jerk ramp over
//! the time the caller gives (zero: at once), so that a weighted task enters and leaves the QP
//! without a jump in the command; a removal ramps the weight to zero, then drops the task.
//! Where a formulation makes a level an equality (the inverse dynamics' priority 0), the
//! weight does not enter it: such a task holds fully until it leaves the stack.

use crate::error::{ControlError, Result};
use crate::tasks::{Task, TaskLevel};
use corps_model::min_jerk::min_jerk;
use std::any::Any;

/// A weight moving from `from` to `to` over [t0, t0 + duration].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ramp {
    t0: f64,
    duration: f64,
    from: f64,
    to: f64,
    remove_at_end: bool,
}

/// A task of the stack.
pub struct TaskEntry {
    pub name: String,
    /// 0 is the highest priority. What a level means is the formulation's: the weighted
    /// inverse dynamics makes level 0 equalities and level 1 costs; the hierarchical IK
    /// solves each level in strict priority.
    pub priority: usize,
    /// The weight now (inside its level).
    pub weight: f64,
    pub task: Box<dyn Task>,
    ramp: Option<Ramp>,
}

/// Named tasks of one level of derivation (acceleration or velocity).
pub struct TaskStack {
    level: TaskLevel,
    /// The lowest priority the formulation solves (None: any).
    max_priority: Option<usize>,
    entries: Vec<TaskEntry>,
    /// Changes whenever a task is added or removed or changes priority (formulations that
    /// size their problem per structure rebuild then).
    structure: u64,
}

/// A weight that is finite and ≥ 0, a finite start time and a finite, non-negative duration.
fn check_ramp(name: &str, weight: Option<f64>, t: f64, duration: f64) -> Result<()> {
    let bad = |reason: String| {
        Err(ControlError::Config {
            name: format!("task '{name}'"),
            reason,
        })
    };
    if let Some(w) = weight.filter(|w| !(*w >= 0.0 && w.is_finite())) {
        return bad(format!("weight must be finite and ≥ 0, got {w}"));
    }
    if !(t.is_finite() && duration >= 0.0 && duration.is_finite()) {
        return bad(format!(
            "a ramp needs a finite time and a finite duration ≥ 0, got t = {t}, duration = {duration}"
        ));
    }
    Ok(())
}

fn no_task(name: &str) -> ControlError {
    ControlError::Config {
        name: format!("task '{name}'"),
        reason: "no such task in the stack".into(),
    }
}

impl TaskStack {
    /// An empty stack of `level` tasks.
    pub fn new(level: TaskLevel) -> Self {
        Self {
            level,
            max_priority: None,
            entries: Vec::new(),
            structure: 0,
        }
    }

    /// An empty stack whose priorities go from 0 to `max` (a formulation of `max + 1`
    /// levels): a task beyond is refused when it is added or moved.
    pub fn with_max_priority(level: TaskLevel, max: usize) -> Self {
        Self {
            max_priority: Some(max),
            ..Self::new(level)
        }
    }

    fn check_priority(&self, name: &str, priority: usize) -> Result<()> {
        match self.max_priority {
            Some(max) if priority > max => Err(ControlError::Config {
                name: format!("task '{name}'"),
                reason: format!(
                    "priority {priority}: this formulation solves priorities 0 to {max}"
                ),
            }),
            _ => Ok(()),
        }
    }

    /// Adds `task` as `name` at `priority` with `weight`, at once.
    pub fn add(&mut self, name: &str, task: impl Task, priority: usize, weight: f64) -> Result<()> {
        self.add_boxed(name, Box::new(task), priority, weight)
    }

    /// [`TaskStack::add`] for a boxed task.
    pub fn add_boxed(
        &mut self,
        name: &str,
        task: Box<dyn Task>,
        priority: usize,
        weight: f64,
    ) -> Result<()> {
        let bad = |reason: String| ControlError::Config {
            name: format!("task '{name}'"),
            reason,
        };
        if self.index(name).is_some() {
            return Err(bad("a task of that name is already in the stack".into()));
        }
        if task.level() != self.level {
            return Err(bad(format!(
                "a {:?}-level task in a {:?}-level stack",
                task.level(),
                self.level
            )));
        }
        if !(weight >= 0.0 && weight.is_finite()) {
            return Err(bad(format!("weight must be finite and ≥ 0, got {weight}")));
        }
        self.check_priority(name, priority)?;
        self.entries.push(TaskEntry {
            name: name.into(),
            priority,
            weight,
            task,
            ramp: None,
        });
        self.structure += 1;
        Ok(())
    }

    /// Adds `task` with its weight rising from 0 to `weight` over `duration` s from `t`.
    pub fn add_smoothly(
        &mut self,
        name: &str,
        task: impl Task,
        priority: usize,
        weight: f64,
        t: f64,
        duration: f64,
    ) -> Result<()> {
        check_ramp(name, Some(weight), t, duration)?;
        self.add(name, task, priority, 0.0)?;
        self.set_weight(name, weight, t, duration)
    }

    /// Moves the weight of `name` to `weight` over `duration` s from `t` (0: at once).
    pub fn set_weight(&mut self, name: &str, weight: f64, t: f64, duration: f64) -> Result<()> {
        check_ramp(name, Some(weight), t, duration)?;
        let k = self.index(name).ok_or_else(|| no_task(name))?;
        let e = &mut self.entries[k];
        if duration > 0.0 {
            e.ramp = Some(Ramp {
                t0: t,
                duration,
                from: e.weight,
                to: weight,
                remove_at_end: false,
            });
        } else {
            e.weight = weight;
            e.ramp = None;
        }
        Ok(())
    }

    /// Removes `name` at once and returns it.
    pub fn remove(&mut self, name: &str) -> Result<Box<dyn Task>> {
        let k = self.index(name).ok_or_else(|| no_task(name))?;
        self.structure += 1;
        Ok(self.entries.remove(k).task)
    }

    /// Ramps the weight of `name` to 0 over `duration` s from `t`, then removes it.
    pub fn remove_smoothly(&mut self, name: &str, t: f64, duration: f64) -> Result<()> {
        check_ramp(name, None, t, duration)?;
        if duration <= 0.0 {
            return self.remove(name).map(|_| ());
        }
        let k = self.index(name).ok_or_else(|| no_task(name))?;
        let e = &mut self.entries[k];
        e.ramp = Some(Ramp {
            t0: t,
            duration,
            from: e.weight,
            to: 0.0,
            remove_at_end: true,
        });
        Ok(())
    }

    /// Moves `name` to `priority`.
    pub fn set_priority(&mut self, name: &str, priority: usize) -> Result<()> {
        let k = self.index(name).ok_or_else(|| no_task(name))?;
        self.check_priority(name, priority)?;
        if self.entries[k].priority != priority {
            self.entries[k].priority = priority;
            self.structure += 1;
        }
        Ok(())
    }

    /// Advances the weight ramps to time `t` and drops the tasks whose removal ended.
    pub fn update(&mut self, t: f64) {
        if !t.is_finite() {
            return;
        }
        let before = self.entries.len();
        self.entries.retain_mut(|e| {
            let Some(r) = e.ramp else { return true };
            let [s, _, _] = min_jerk((t - r.t0) / r.duration);
            e.weight = r.from + (r.to - r.from) * s;
            if t >= r.t0 + r.duration {
                e.weight = r.to;
                e.ramp = None;
                return !r.remove_at_end;
            }
            true
        });
        if self.entries.len() != before {
            self.structure += 1;
        }
    }

    /// Position of `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.entries.iter().position(|e| e.name == name)
    }

    pub fn contains(&self, name: &str) -> bool {
        self.index(name).is_some()
    }

    /// The task `name` as its concrete type (to set its reference or gains).
    pub fn task<T: Task>(&self, name: &str) -> Option<&T> {
        let e = &self.entries[self.index(name)?];
        (e.task.as_ref() as &dyn Any).downcast_ref()
    }

    /// The task `name` as its concrete type, mutably.
    pub fn task_mut<T: Task>(&mut self, name: &str) -> Option<&mut T> {
        let k = self.index(name)?;
        (self.entries[k].task.as_mut() as &mut dyn Any).downcast_mut()
    }

    /// The current weight of `name`.
    pub fn weight(&self, name: &str) -> Option<f64> {
        self.index(name).map(|k| self.entries[k].weight)
    }

    /// The tasks in the order they were added.
    pub fn entries(&self) -> &[TaskEntry] {
        &self.entries
    }

    /// The tasks, mutably (to compute their rows).
    pub fn entries_mut(&mut self) -> &mut [TaskEntry] {
        &mut self.entries
    }

    /// A number that changes whenever the stack's structure does.
    pub fn structure(&self) -> u64 {
        self.structure
    }

    /// Which derivative the tasks constrain.
    pub fn level(&self) -> TaskLevel {
        self.level
    }
}
