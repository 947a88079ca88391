//! `corps model inspect` and `corps model eval`.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use corps_model::*;
use corps_scenario::default_robot::load_model;
use nalgebra::{DMatrix, Matrix3xX, Matrix6xX};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(Subcommand)]
pub enum ModelCommand {
    /// Print sizes, mass, joints with limits, frames and reference configurations.
    Inspect {
        #[command(flatten)]
        robot: RobotArgs,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate dynamics at the states of a JSON file and print JSON (M, h, g, RNEA, ABA, CoM,
    /// its Jacobian, A_G, h_G and, per frame, placement, LOCAL_WORLD_ALIGNED Jacobian and
    /// classical acceleration). Missing v, a or tau default to zero.
    Eval {
        #[command(flatten)]
        robot: RobotArgs,
        /// Input: {"frames": [names], "states": [{"q": [...], "v": [...], "a": [...], "tau": [...]}]}
        #[arg(long)]
        states: PathBuf,
    },
}

#[derive(Args)]
pub struct RobotArgs {
    /// URDF file (default: TALOS talos_reduced, embedded).
    #[arg(long)]
    urdf: Option<PathBuf>,
    /// SRDF file with reference configurations (group_state).
    #[arg(long)]
    srdf: Option<PathBuf>,
    /// Weld the root link to the world instead of adding a free-flyer.
    #[arg(long)]
    fixed_base: bool,
}

pub fn run(cmd: ModelCommand) -> Result<()> {
    match cmd {
        ModelCommand::Inspect { robot, json } => {
            let model = load_model(
                robot.urdf.as_deref(),
                robot.srdf.as_deref(),
                robot.fixed_base,
            )?;
            if json {
                corps::stdout::print(&format!(
                    "{}\n",
                    serde_json::to_string_pretty(&inspect_json(&model))?
                ))
            } else {
                corps::stdout::print(&inspect_text(&model))
            }
        }
        ModelCommand::Eval { robot, states } => {
            let model = load_model(
                robot.urdf.as_deref(),
                robot.srdf.as_deref(),
                robot.fixed_base,
            )?;
            let text = std::fs::read_to_string(&states)
                .with_context(|| format!("reading {}", states.display()))?;
            let input: EvalInput = serde_json::from_str(&text)
                .with_context(|| format!("parsing {}", states.display()))?;
            let out = evaluate(&model, &input)?;
            corps::stdout::print(&format!("{}\n", serde_json::to_string(&out)?))
        }
    }
}

fn fmt_limit(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.4}")
    } else if x > 0.0 {
        "inf".into()
    } else {
        "-inf".into()
    }
}

/// Human-readable description of a model.
pub fn inspect_text(model: &Model) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "robot {}: nq = {}, nv = {}, total mass = {:.4} kg",
        model.name,
        model.nq,
        model.nv,
        model.total_mass()
    );
    let _ = writeln!(s, "\njoints ({}):", model.njoints());
    let _ = writeln!(
        s,
        "  {:<3} {:<26} {:<11} {:>4} {:>4} {:>9} {:>9} {:>8} {:>8}",
        "#", "name", "type", "q", "v", "lower", "upper", "vel", "effort"
    );
    for (i, j) in model.joints.iter().enumerate() {
        let (lo, hi, vel, eff) = if j.nq() == 1 {
            (
                fmt_limit(model.lower_position_limit[j.idx_q]),
                fmt_limit(model.upper_position_limit[j.idx_q]),
                fmt_limit(model.velocity_limit[j.idx_v]),
                fmt_limit(model.effort_limit[j.idx_v]),
            )
        } else {
            ("-".into(), "-".into(), "-".into(), "-".into())
        };
        let _ = writeln!(
            s,
            "  {:<3} {:<26} {:<11} {:>4} {:>4} {:>9} {:>9} {:>8} {:>8}",
            i,
            j.name,
            j.kind.short_name(),
            j.idx_q,
            j.idx_v,
            lo,
            hi,
            vel,
            eff
        );
    }
    let _ = writeln!(s, "\nframes ({}):", model.frames.len());
    for f in &model.frames {
        let parent = f
            .parent_joint
            .map_or("universe".to_string(), |p| model.joints[p].name.clone());
        let _ = writeln!(s, "  {:<36} {:<12} on {}", f.name, f.kind.as_str(), parent);
    }
    let _ = writeln!(
        s,
        "\nreference configurations ({}):",
        model.reference_configurations.len()
    );
    for (name, _) in &model.reference_configurations {
        let _ = writeln!(s, "  {name}");
    }
    let _ = writeln!(s, "\ncollision shapes: {}", model.collisions.len());
    s
}

fn inspect_json(model: &Model) -> serde_json::Value {
    let joints: Vec<_> = model
        .joints
        .iter()
        .map(|j| {
            serde_json::json!({
                "name": j.name, "type": j.kind.short_name(), "idx_q": j.idx_q, "idx_v": j.idx_v,
                "nq": j.nq(), "nv": j.nv(),
                "parent": j.parent.map(|p| model.joints[p].name.clone()),
                "lower": finite_or_null(&model.lower_position_limit.as_slice()[j.idx_q..j.idx_q + j.nq()]),
                "upper": finite_or_null(&model.upper_position_limit.as_slice()[j.idx_q..j.idx_q + j.nq()]),
                "velocity": finite_or_null(&model.velocity_limit.as_slice()[j.idx_v..j.idx_v + j.nv()]),
                "effort": finite_or_null(&model.effort_limit.as_slice()[j.idx_v..j.idx_v + j.nv()]),
            })
        })
        .collect();
    let frames: Vec<_> = model
        .frames
        .iter()
        .map(|f| {
            serde_json::json!({"name": f.name, "type": f.kind.as_str(),
            "parent_joint": f.parent_joint.map(|p| model.joints[p].name.clone())})
        })
        .collect();
    let configs: BTreeMap<_, _> = model
        .reference_configurations
        .iter()
        .map(|(n, q)| (n.clone(), q.as_slice().to_vec()))
        .collect();
    serde_json::json!({"name": model.name, "nq": model.nq, "nv": model.nv, "mass": model.total_mass(),
        "joints": joints, "frames": frames, "reference_configurations": configs})
}

fn finite_or_null(x: &[f64]) -> Vec<Option<f64>> {
    x.iter().map(|v| v.is_finite().then_some(*v)).collect()
}

/// Input of `corps model eval`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvalInput {
    #[serde(default)]
    frames: Vec<String>,
    states: Vec<EvalState>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EvalState {
    q: Vec<f64>,
    v: Option<Vec<f64>>,
    a: Option<Vec<f64>>,
    tau: Option<Vec<f64>>,
}

#[derive(Serialize)]
pub struct EvalOutput {
    nq: usize,
    nv: usize,
    mass: f64,
    results: Vec<EvalResult>,
}

#[derive(Serialize)]
#[allow(non_snake_case)]
struct EvalResult {
    M: Vec<Vec<f64>>,
    nle: Vec<f64>,
    g: Vec<f64>,
    rnea: Vec<f64>,
    aba: Vec<f64>,
    com: Vec<f64>,
    Jcom: Vec<Vec<f64>>,
    Ag: Vec<Vec<f64>>,
    hg: Vec<f64>,
    frames: BTreeMap<String, FrameResult>,
}

#[derive(Serialize)]
#[allow(non_snake_case)]
struct FrameResult {
    translation: Vec<f64>,
    rotation: Vec<Vec<f64>>,
    J_lwa: Vec<Vec<f64>>,
    classical_acc_lwa: Vec<f64>,
}

fn rows_dyn(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}
fn rows6(m: &Matrix6xX<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}
fn rows3(m: &Matrix3xX<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

/// Evaluates every state of `input`.
pub fn evaluate(model: &Model, input: &EvalInput) -> Result<EvalOutput> {
    let frame_ids: Vec<(String, usize)> = input
        .frames
        .iter()
        .map(|n| Ok((n.clone(), model.frame_id(n)?)))
        .collect::<corps_model::Result<_>>()?;
    let mut data = Data::new(model);
    let mut jac = Matrix6xX::zeros(model.nv);
    let zeros = vec![0.0; model.nv];
    let mut results = Vec::with_capacity(input.states.len());
    for (k, s) in input.states.iter().enumerate() {
        let ctx = || format!("state {k}");
        let v = s.v.as_deref().unwrap_or(&zeros);
        let a = s.a.as_deref().unwrap_or(&zeros);
        let tau = s.tau.as_deref().unwrap_or(&zeros);
        let q = s.q.as_slice();
        let m = crba(model, &mut data, q).with_context(ctx)?.clone();
        let nle = nonlinear_effects(model, &mut data, q, v)
            .with_context(ctx)?
            .as_slice()
            .to_vec();
        let g = generalized_gravity(model, &mut data, q)
            .with_context(ctx)?
            .as_slice()
            .to_vec();
        let tau_rnea = rnea(model, &mut data, q, v, a)
            .with_context(ctx)?
            .as_slice()
            .to_vec();
        let ddq = aba(model, &mut data, q, v, tau)
            .with_context(ctx)?
            .as_slice()
            .to_vec();
        let hg = compute_centroidal_momentum(model, &mut data, q, v).with_context(ctx)?;
        let (com, jcom, ag) = (
            data.com.as_slice().to_vec(),
            rows3(&data.jcom),
            rows6(&data.ag),
        );
        forward_kinematics(model, &mut data, q, v, a).with_context(ctx)?;
        compute_joint_jacobians(model, &mut data, q).with_context(ctx)?;
        let mut frames = BTreeMap::new();
        for (name, fid) in &frame_ids {
            let place = frame_placement(model, &data, *fid)?;
            frame_jacobian(
                model,
                &data,
                *fid,
                ReferenceFrame::LocalWorldAligned,
                &mut jac,
            )?;
            let acc = frame_classical_acceleration(
                model,
                &data,
                *fid,
                ReferenceFrame::LocalWorldAligned,
            )?;
            frames.insert(
                name.clone(),
                FrameResult {
                    translation: place.translation.as_slice().to_vec(),
                    rotation: place
                        .rotation
                        .row_iter()
                        .map(|r| r.iter().copied().collect())
                        .collect(),
                    J_lwa: rows6(&jac),
                    classical_acc_lwa: acc.to_vector().as_slice().to_vec(),
                },
            );
        }
        results.push(EvalResult {
            M: rows_dyn(&m),
            nle,
            g,
            rnea: tau_rnea,
            aba: ddq,
            com,
            Jcom: jcom,
            Ag: ag,
            hg: hg.to_vector().as_slice().to_vec(),
            frames,
        });
    }
    if results.is_empty() {
        bail!("no states in the input");
    }
    Ok(EvalOutput {
        nq: model.nq,
        nv: model.nv,
        mass: model.total_mass(),
        results,
    })
}
