//! TALOS' walking settings for tests and benchmarks (the library holds no robot's numbers).
#![allow(dead_code)]

use corps_walk::lipm::Lipm;
use corps_walk::mpc::MpcParams;
use corps_walk::preview_control::PreviewParams;
use corps_walk::FootGeometry;

/// TALOS' CoM height on jrl-walkgen (`:comheight 0.876681`, seed 002 §4.4).
pub const TALOS_COM_HEIGHT: f64 = 0.876681;

/// TALOS' sole about the ankle projection: `lxp = 0.10`, `lxn = 0.11`, `lyp = lyn = 0.069`
/// (seed 000 §2, from talos-torque-control `balance_ctrl_sim_conf.py`).
pub const TALOS_SOLE: FootGeometry = FootGeometry {
    front: 0.10,
    back: 0.11,
    left: 0.069,
    right: 0.069,
};

/// Kajita's preview control on TALOS' pendulum (`g = 9.81`, seed 002 §4.4).
pub fn talos_preview() -> PreviewParams {
    PreviewParams {
        lipm: Lipm {
            com_height: TALOS_COM_HEIGHT,
            gravity: 9.81,
        },
        ..PreviewParams::kajita2003()
    }
}

/// The MPC on TALOS: `config/talos/walk_mpc.toml`.
pub fn talos_mpc() -> MpcParams {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../config/talos/walk_mpc.toml"
    );
    let text = std::fs::read_to_string(path).expect("config/talos/walk_mpc.toml");
    toml::from_str(&text).expect("TALOS' MPC settings parse")
}
