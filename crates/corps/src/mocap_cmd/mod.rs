//! `corps mocap`: motion capture of an operator (seed 001 ch. 6) — `retarget` maps a clip onto
//! a robot through a mapping file and writes what the robot would be asked to do (joints,
//! waist height, steps) with plots beside the operator's; `send` plays a clip on the live
//! stream's UDP protocol in real time.

mod plots;

use anyhow::{anyhow, Context, Result};
use clap::{Args, Subcommand};
use corps_mocap::bvh::Bvh;
use corps_mocap::replay::{retarget_clip, Retargeted};
use corps_mocap::retarget::Mapping;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Subcommand)]
pub enum MocapCommand {
    /// Retarget a clip (BVH) onto the robot of a mapping file: joints.csv, steps.csv,
    /// joints.png (operator vs robot angles, Fig 6.10), steps.png (step lengths, Fig 6.12).
    Retarget(RetargetArgs),
    /// Play a clip (BVH) in real time on the live stream's protocol (UDP, one frame a
    /// datagram: `TIME V1 … VN`) to a receiver.
    Send(SendArgs),
}

#[derive(Args)]
pub struct RetargetArgs {
    /// The operator's clip (BVH).
    pub clip: PathBuf,
    /// The mapping file (TOML: robot, skeleton landmarks, joint groups, step ranges).
    #[arg(long, default_value = "config/icub/retargeting.toml")]
    pub mapping: PathBuf,
    /// Output directory (default out/mocap/<clip name>_<robot>).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

#[derive(Args)]
pub struct SendArgs {
    /// The clip (BVH) to play.
    pub clip: PathBuf,
    /// The receiver's address (HOST:PORT).
    #[arg(long)]
    pub to: String,
    /// Playback speed (1: the clip's own rate).
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
}

pub fn run(cmd: MocapCommand) -> Result<()> {
    match cmd {
        MocapCommand::Retarget(args) => retarget(args),
        MocapCommand::Send(args) => send(args),
    }
}

fn send(args: SendArgs) -> Result<()> {
    let bvh = Bvh::read(&args.clip).map_err(|e| anyhow!("{e}"))?;
    let frames =
        corps_mocap::stream::send_clip(&bvh, &args.to, args.speed, &crate::interrupt::FLAG)
            .map_err(|e| anyhow!("{e}"))?;
    crate::stdout::print(&format!(
        "sent {frames} of {} frames of {} to {}\n",
        bvh.frames(),
        args.clip.display(),
        args.to
    ))
}

fn retarget(args: RetargetArgs) -> Result<()> {
    let bvh = Bvh::read(&args.clip).map_err(|e| anyhow!("{e}"))?;
    let mapping = Mapping::read(&args.mapping).map_err(|e| anyhow!("{e}"))?;
    let r = retarget_clip(&mapping, &bvh).map_err(|e| anyhow!("{e}"))?;
    let clip_name = args
        .clip
        .file_stem()
        .map_or("clip".into(), |s| s.to_string_lossy().into_owned());
    let out = args
        .output
        .unwrap_or_else(|| Path::new("out/mocap").join(format!("{clip_name}_{}", r.robot)));
    // Everything is computed before the first file is written.
    let joints_csv = joints_csv(&r);
    let steps_csv = steps_csv(&r);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    crate::output::write_atomic(&out, "joints.csv", joints_csv.as_bytes())?;
    crate::output::write_atomic(&out, "steps.csv", steps_csv.as_bytes())?;
    plots::joints(&out.join("joints.png"), &clip_name, &r)?;
    plots::steps(&out.join("steps.png"), &clip_name, &r, &mapping)?;
    crate::stdout::print(&summary(&r, &clip_name, &out))
}

/// `time`, then per mapped joint `operator_<joint>` and `<joint>` (rad), then `waist_height`.
fn joints_csv(r: &Retargeted) -> String {
    let mut s = String::from("time");
    for j in &r.joints {
        let _ = write!(s, ",operator_{0},{0}", j.name);
    }
    s.push_str(",waist_height\n");
    for k in 0..r.time.len() {
        let _ = write!(s, "{}", r.time[k]);
        for i in 0..r.joints.len() {
            let _ = write!(s, ",{},{}", r.operator[k][i], r.clipped[k][i]);
        }
        let _ = writeln!(s, ",{}", r.waist[k]);
    }
    s
}

/// One row per operator step, in body coordinates at rest (m).
fn steps_csv(r: &Retargeted) -> String {
    let mut s = String::from(
        "step,foot,start,end,operator_dx,operator_dy,operator_length,operator_height,robot_dx,robot_dy,robot_length,robot_height,clipped\n",
    );
    for (k, st) in r.steps.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            k + 1,
            if st.foot == 0 { "left" } else { "right" },
            st.start,
            st.end,
            st.human_travel.x,
            st.human_travel.y,
            st.human_travel.norm(),
            st.human_height,
            st.robot_travel.x,
            st.robot_travel.y,
            st.robot_travel.norm(),
            st.robot_height,
            st.clipped
        );
    }
    s
}

/// Per mapped joint: the RMS and largest |operator − robot| (deg) the joint limits cause.
pub fn clipping_error(r: &Retargeted) -> Vec<(f64, f64)> {
    (0..r.joints.len())
        .map(|i| {
            let e: Vec<f64> = (r.operator.iter().zip(&r.clipped))
                .map(|(o, c)| (o[i] - c[i]).abs().to_degrees())
                .collect();
            let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len().max(1) as f64).sqrt();
            (rms, e.iter().copied().fold(0.0, f64::max))
        })
        .collect()
}

fn summary(r: &Retargeted, clip: &str, out: &Path) -> String {
    let duration = r.time.last().copied().unwrap_or(0.0);
    let mut s = format!(
        "{clip} onto {}: {} frames ({duration:.2} s), {} joints mapped\n  waist at rest: operator {:.3} m, robot {:.3} m (ratio {:.3}); robot waist {:.3}–{:.3} m\n  operator steps: {} ({} clipped to the robot's range)\n",
        r.robot,
        r.time.len(),
        r.joints.len(),
        r.waist_rest_human,
        r.waist_rest_robot,
        r.waist_rest_robot / r.waist_rest_human,
        r.waist.iter().copied().fold(f64::INFINITY, f64::min),
        r.waist.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        r.steps.len(),
        r.steps.iter().filter(|s| s.clipped).count(),
    );
    let errors = clipping_error(r);
    let clipped: Vec<String> = (r.joints.iter().zip(&r.joint_clippings).zip(&errors))
        .filter(|((_, n), _)| **n > 0)
        .map(|((j, n), (_, max))| format!("{} {n} frames (≤ {max:.1}°)", j.name))
        .collect();
    let _ = writeln!(
        s,
        "  joint limits: {}",
        if clipped.is_empty() {
            "never reached".to_string()
        } else {
            format!("clipped {}", clipped.join(", "))
        }
    );
    let _ = writeln!(
        s,
        "wrote {}, {}, {}, {}",
        out.join("joints.csv").display(),
        out.join("steps.csv").display(),
        out.join("joints.png").display(),
        out.join("steps.png").display()
    );
    s
}
