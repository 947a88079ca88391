//! Finding a URDF's mesh files: `package://name/path` resolved against a search path
//! (`CORPS_PACKAGE_PATH`, as ROS_PACKAGE_PATH: directories holding packages; then `robots/`
//! and `../shared/robots/example-robot-data/` from the working directory), plain paths as
//! they are.

use std::path::PathBuf;

/// The directories that hold packages, in search order.
pub fn search_path() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::env::var_os("CORPS_PACKAGE_PATH")
        .map(|v| std::env::split_paths(&v).collect())
        .unwrap_or_default();
    dirs.push(PathBuf::from("robots"));
    dirs.push(PathBuf::from("../shared/robots/example-robot-data"));
    dirs
}

/// The file `uri` names, if it exists.
pub fn resolve(uri: &str, dirs: &[PathBuf]) -> Option<PathBuf> {
    let path = uri.strip_prefix("file://").unwrap_or(uri);
    if let Some(rest) = path.strip_prefix("package://") {
        let (package, inner) = rest.split_once('/')?;
        let mut candidates: Vec<PathBuf> =
            dirs.iter().map(|d| d.join(package).join(inner)).collect();
        // example-robot-data's own URDFs name `package://example-robot-data/robots/<robot>/…`,
        // which a copy of its robots' folders holds as `<robot>/…`.
        if let ("example-robot-data", Some(robot)) = (package, inner.strip_prefix("robots/")) {
            candidates.extend(dirs.iter().map(|d| d.join(robot)));
        }
        return candidates.into_iter().find(|p| p.is_file());
    }
    let p = PathBuf::from(path);
    p.is_file().then_some(p)
}

/// MIME type of a mesh file, by extension (what Foxglove's model primitive reads).
pub fn media_type(path: &std::path::Path) -> Option<&'static str> {
    match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
        "stl" => Some("model/stl"),
        "dae" => Some("model/vnd.collada+xml"),
        "glb" => Some("model/gltf-binary"),
        _ => None,
    }
}
