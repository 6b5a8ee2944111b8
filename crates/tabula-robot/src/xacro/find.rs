//! `$(find pkg)` for xacro-rs, answered by the project's one package resolver
//! ([`crate::packages::PackagePaths`]) so that xacro and `package://` meshes agree.

use crate::packages::PackagePaths;
use std::cell::RefCell;
use std::error::Error;
use std::path::{Path, PathBuf};
use xacro_rs::extensions::ExtensionHandler;

/// The `find` extension; searches from the folder of the file being expanded.
pub struct FindPackage {
    pub packages: PackagePaths,
    pub current_dir: RefCell<Option<PathBuf>>,
}

impl ExtensionHandler for FindPackage {
    fn resolve(&self, command: &str, args_raw: &str) -> Result<Option<String>, Box<dyn Error>> {
        if command != "find" {
            return Ok(None);
        }
        let name = args_raw.trim();
        if name.is_empty() || name.contains(char::is_whitespace) {
            return Err(format!("$(find) takes one package name, got `{name}`").into());
        }
        let near = self.current_dir.borrow().clone();
        self.packages
            .resolve_url(name, near.as_deref())
            .map(|p| Some(p.display().to_string().trim_end_matches('/').to_string()))
            .map_err(Into::into)
    }

    fn on_file_change(&self, current_file: Option<&Path>) {
        *self.current_dir.borrow_mut() = current_file.and_then(Path::parent).map(Path::to_path_buf);
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
