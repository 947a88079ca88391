//! Where a description and the files it names are read from: the disk, or the copies built
//! into the library (TALOS, iCub and simple_humanoid with their gains files), so that corps
//! runs from any directory.

use std::path::{Component, Path, PathBuf};

/// The built-in robots: name and the description's path in [`EMBEDDED`].
pub const BUILT_IN: [(&str, &str); 6] = [
    ("talos", "robots/talos_data/talos.toml"),
    (
        "talos_flexible_hip",
        "robots/talos_data/talos_flexible_hip.toml",
    ),
    ("icub", "robots/icub_description/icub.toml"),
    (
        "icub_backpacked",
        "robots/icub_description/icub_backpacked.toml",
    ),
    (
        "icub_parallel_legs",
        "robots/icub_description/icub_parallel_legs.toml",
    ),
    (
        "simple_humanoid",
        "robots/simple_humanoid_description/simple_humanoid.toml",
    ),
];

macro_rules! embed {
    ($($path:literal),* $(,)?) => {
        &[$(($path, include_str!(concat!("../../../", $path)))),*]
    };
}

/// Files built into the library, by their path in the repository.
pub const EMBEDDED: &[(&str, &str)] = embed!(
    "robots/talos_data/talos.toml",
    "robots/talos_data/talos_flexible_hip.toml",
    "robots/talos_data/robots/talos_reduced_box.urdf",
    "robots/talos_data/srdf/talos.srdf",
    "config/talos/tsid_torque.toml",
    "config/talos/tsid_torque_walk.toml",
    "config/talos/passive_torque.toml",
    "config/talos/passive_torque_walk.toml",
    "config/talos/tsid_torque_force.toml",
    "config/talos/tsid_position.toml",
    "config/talos/ik_position.toml",
    "config/talos/walk_mpc.toml",
    "config/talos/actuators/elbow.toml",
    "config/talos/tsid_torque_posture_fail.toml",
    "config/talos/tsid_torque_posture_success.toml",
    "config/talos/passive_torque_posture_fail.toml",
    "robots/icub_description/icub.toml",
    "robots/icub_description/icub_backpacked.toml",
    "robots/icub_description/icub_parallel_legs.toml",
    "robots/icub_description/robots/icub.urdf",
    "robots/icub_description/srdf/icub.srdf",
    "config/icub/tsid_torque.toml",
    "config/icub/soft_tasks.toml",
    "config/icub/soft_tasks_fsm1.toml",
    "robots/simple_humanoid_description/simple_humanoid.toml",
    "robots/simple_humanoid_description/urdf/simple_humanoid.urdf",
    "robots/simple_humanoid_description/srdf/simple_humanoid.srdf",
    "config/simple_humanoid/tsid_torque.toml",
);

/// A place files are read from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FileSource {
    /// The file system.
    Disk,
    /// [`EMBEDDED`].
    BuiltIn,
}

impl FileSource {
    /// The text of `path`, or an error message naming it.
    pub fn read(&self, path: &Path) -> Result<String, String> {
        match self {
            FileSource::Disk => std::fs::read_to_string(path)
                .map_err(|e| format!("cannot read {}: {e}", path.display())),
            FileSource::BuiltIn => {
                let key = normalize(path);
                EMBEDDED
                    .iter()
                    .find(|(p, _)| Path::new(p) == key)
                    .map(|(_, text)| text.to_string())
                    .ok_or_else(|| format!("{} is not built in", key.display()))
            }
        }
    }

    /// How `path` is shown in messages.
    pub fn show(&self, path: &Path) -> String {
        match self {
            FileSource::Disk => path.display().to_string(),
            FileSource::BuiltIn => format!("built-in {}", normalize(path).display()),
        }
    }
}

/// `path` with `.` and `a/..` removed (built-in paths are relative to the repository).
pub fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_paths_resolve_through_parent_directories() {
        let p = Path::new("robots/talos_data/../../config/talos/tsid_torque.toml");
        assert!(FileSource::BuiltIn.read(p).unwrap().contains("[com]"));
        assert!(FileSource::BuiltIn
            .read(Path::new("robots/nowhere.toml"))
            .unwrap_err()
            .contains("not built in"));
    }
}
