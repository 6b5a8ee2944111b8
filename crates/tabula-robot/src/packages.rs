//! Finding ROS packages without ROS, for `$(find pkg)` in xacro and `package://pkg/…`
//! in URDF meshes — one resolver for both, so a description that expands also finds
//! its meshes. Searched, in order: `RUST_XACRO_PACKAGE_MAP` (`pkg=/path:…`), the
//! folders given with `--package-path`, `ROS_PACKAGE_PATH`, then the folders above the
//! description file. Each folder may be a package itself, hold packages, or hold
//! folders of packages one level down (a workspace's `src/`), as `rospack` finds them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// How many folders above a description are searched for sibling packages.
const ANCESTOR_LEVELS: usize = 6;
/// How many entries of one folder are looked into for `package.xml` files.
const MAX_ENTRIES_SCANNED: usize = 4096;

/// Where packages are looked for (see the module doc for the order).
#[derive(Debug, Default)]
pub struct PackagePaths {
    /// Folders named on the command line (`--package-path`), searched before the
    /// environment's.
    pub extra: Vec<PathBuf>,
    cache: Mutex<HashMap<CacheKey, Option<PathBuf>>>,
}

/// A package name and the folder it was searched from.
type CacheKey = (String, Option<PathBuf>);

impl Clone for PackagePaths {
    fn clone(&self) -> Self {
        Self::new(self.extra.clone())
    }
}

impl PackagePaths {
    /// A resolver that also searches `extra` folders.
    pub fn new(extra: Vec<PathBuf>) -> Self {
        Self {
            extra,
            cache: Mutex::new(HashMap::new()),
        }
    }

    /// Every search root for a description at `near`, in search order (for messages).
    pub fn roots(&self, near: Option<&Path>) -> Vec<PathBuf> {
        let mut roots = self.extra.clone();
        if let Some(env) = std::env::var_os("ROS_PACKAGE_PATH") {
            roots.extend(std::env::split_paths(&env).filter(|p| !p.as_os_str().is_empty()));
        }
        if let Some(dir) = near {
            roots.extend(dir.ancestors().take(ANCESTOR_LEVELS).map(Path::to_path_buf));
        }
        roots
    }

    /// The folder of package `name`, searched from a description in folder `near`.
    pub fn find(&self, name: &str, near: Option<&Path>) -> Option<PathBuf> {
        let key = (name.to_string(), near.map(Path::to_path_buf));
        if let Ok(cache) = self.cache.lock()
            && let Some(hit) = cache.get(&key)
        {
            return hit.clone();
        }
        let found = package_map(name).or_else(|| {
            self.roots(near)
                .iter()
                .find_map(|root| package_in(root, name))
        });
        // Absolute, so that what `$(find)` returns works from any including file.
        let found = found.map(|p| std::path::absolute(&p).unwrap_or(p));
        if let Ok(mut cache) = self.cache.lock() {
            cache.insert(key, found.clone());
        }
        found
    }

    /// `package://pkg/rest` as a path, or an error naming every folder searched.
    pub fn resolve_url(&self, url: &str, near: Option<&Path>) -> Result<PathBuf, String> {
        let rest = url.strip_prefix("package://").unwrap_or(url);
        let (pkg, inner) = rest.split_once('/').unwrap_or((rest, ""));
        match self.find(pkg, near) {
            Some(dir) => Ok(dir.join(inner)),
            None => Err(format!(
                "package `{pkg}` not found (searched RUST_XACRO_PACKAGE_MAP, {}; add its \
                 folder with --package-path or ROS_PACKAGE_PATH)",
                self.roots(near)
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }
}

/// `RUST_XACRO_PACKAGE_MAP`'s entry for `name` (the xacro-rs convention this project
/// documented first).
fn package_map(name: &str) -> Option<PathBuf> {
    let map = std::env::var("RUST_XACRO_PACKAGE_MAP").ok()?;
    map.split(':').find_map(|entry| {
        let (k, v) = entry.split_once('=')?;
        (k.trim() == name && Path::new(v.trim()).is_dir()).then(|| PathBuf::from(v.trim()))
    })
}

/// Package `name` at `root`: the root itself, `root/name`, or a folder one or two levels
/// down whose manifest names it (directory names may differ, `pkg-master`; a workspace's
/// `src/` holds repositories that hold packages). Hidden folders and the system's
/// (`/proc`, `/sys`, `/dev`) are not entered; at most [`MAX_ENTRIES_SCANNED`] folders
/// are looked into per root.
fn package_in(root: &Path, name: &str) -> Option<PathBuf> {
    if is_package_named(root, name) {
        return Some(root.to_path_buf());
    }
    let direct = root.join(name);
    if direct.is_dir() {
        return Some(direct);
    }
    let mut budget = MAX_ENTRIES_SCANNED;
    let mut level = vec![root.to_path_buf()];
    for _depth in 0..2 {
        let mut next = Vec::new();
        for dir in &level {
            for sub in subfolders(dir, &mut budget) {
                if manifest_name(&sub).as_deref() == Some(name) {
                    return Some(sub);
                }
                next.push(sub);
            }
        }
        level = next;
    }
    None
}

/// The folders in `dir` worth searching, counted against `budget`.
fn subfolders(dir: &Path, budget: &mut usize) -> Vec<PathBuf> {
    if matches!(dir.to_str(), Some("/proc" | "/sys" | "/dev")) {
        return Vec::new();
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for e in entries.flatten() {
        if *budget == 0 {
            break;
        }
        *budget -= 1;
        let hidden = e.file_name().to_string_lossy().starts_with('.');
        if !hidden && e.file_type().is_ok_and(|t| t.is_dir()) {
            out.push(e.path());
        }
    }
    out
}

/// True when `dir` is package `name`: its manifest says so, or it has none and its
/// folder is called so.
fn is_package_named(dir: &Path, name: &str) -> bool {
    match manifest_name(dir) {
        Some(n) => n == name,
        None => dir.file_name().is_some_and(|n| n == name),
    }
}

/// The `<name>` of `dir/package.xml` (or the `name` attribute of a rosbuild
/// `manifest.xml`'s package), read from at most 64 KiB.
pub fn manifest_name(dir: &Path) -> Option<String> {
    let text = read_small(&dir.join("package.xml"))?;
    let start = text.find("<name>")? + "<name>".len();
    let end = text[start..].find("</name>")? + start;
    Some(text[start..end].trim().to_string())
}

fn read_small(path: &Path) -> Option<String> {
    use std::io::Read;
    let meta = std::fs::metadata(path).ok()?;
    if !meta.is_file() {
        return None;
    }
    let mut text = String::new();
    std::fs::File::open(path)
        .ok()?
        .take(64 << 10)
        .read_to_string(&mut text)
        .ok()?;
    Some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packages_are_found_by_manifest_name_beside_and_above() {
        let tmp = std::env::temp_dir().join(format!("tabula-pkg-{}", std::process::id()));
        let ws = tmp.join("ws/src");
        std::fs::create_dir_all(ws.join("arm_description-master/urdf")).unwrap();
        std::fs::create_dir_all(ws.join("hand/meshes")).unwrap();
        std::fs::write(
            ws.join("arm_description-master/package.xml"),
            "<package><name>arm_description</name></package>",
        )
        .unwrap();
        std::fs::write(
            ws.join("hand/package.xml"),
            "<package><name> hand </name></package>",
        )
        .unwrap();
        let paths = PackagePaths::default();
        let near = ws.join("arm_description-master/urdf");
        assert_eq!(
            paths.find("arm_description", Some(&near)),
            Some(ws.join("arm_description-master"))
        );
        assert_eq!(paths.find("hand", Some(&near)), Some(ws.join("hand")));
        assert_eq!(
            paths.resolve_url("package://hand/meshes/a.stl", Some(&near)),
            Ok(ws.join("hand/meshes/a.stl"))
        );
        let err = paths
            .resolve_url("package://nowhere/a.stl", Some(&near))
            .unwrap_err();
        assert!(
            err.contains("`nowhere`") && err.contains("--package-path"),
            "{err}"
        );
        let extra = PackagePaths::new(vec![ws.clone()]);
        assert_eq!(extra.find("hand", None), Some(ws.join("hand")));
        std::fs::remove_dir_all(&tmp).ok();
    }
}
