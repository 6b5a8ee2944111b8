//! A look at every file a xacro expansion will read, before xacro-rs reads it: the
//! crate reads includes and `load_yaml` files whole, with no size check, so an include
//! of `/dev/zero` or of a 10 GB file would exhaust memory. Paths are resolved as far as
//! they can be without evaluating (`$(find)`, `$(arg)` with the given or default
//! values); each one that resolves must be a regular file within the robot size limit.
//! Paths built from properties are left to the expansion, whose time and memory are
//! watched.

use crate::packages::PackagePaths;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use tabula_geom::input::{Format, read_text};

/// How many distinct files one description may include.
const MAX_FILES: usize = 1000;

/// What the look found wrong, as one sentence.
pub type IncludeProblem = String;

/// Walks the includes of `top` (already read as `text`).
pub fn check(
    top: &Path,
    text: &str,
    args: &[(String, String)],
    packages: &PackagePaths,
) -> Result<(), IncludeProblem> {
    let mut args: HashMap<String, String> = args.iter().cloned().collect();
    let mut seen = HashSet::new();
    let mut queue = vec![(top.to_path_buf(), text.to_string())];
    while let Some((file, text)) = queue.pop() {
        for (name, default) in arg_defaults(&text) {
            args.entry(name).or_insert(default);
        }
        let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
        for raw in referenced_files(&text) {
            let Some(path) = resolve(&raw, &dir, &args, packages) else {
                continue;
            };
            if path.to_string_lossy().contains('*') || !seen.insert(path.clone()) {
                continue;
            }
            if seen.len() > MAX_FILES {
                return Err(format!("more than {MAX_FILES} included files"));
            }
            let meta = std::fs::metadata(&path);
            if meta.as_ref().is_ok_and(|m| !m.is_file()) {
                return Err(format!(
                    "`{}` (included by {}) is not a regular file",
                    path.display(),
                    file.display()
                ));
            }
            if meta.is_err() {
                continue; // xacro-rs names the missing file itself
            }
            let body = read_text(&path, Format::Robot).map_err(|e| e.to_string())?;
            if is_xml(&path) {
                queue.push((path, body));
            }
        }
    }
    Ok(())
}

fn is_xml(path: &Path) -> bool {
    !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"))
}

/// `filename` of `<xacro:include>` elements and the string argument of `load_yaml(…)`.
fn referenced_files(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find(":include") {
        let tag_end = rest[i..].find('>').map_or(rest.len(), |e| i + e);
        let tag = &rest[i..tag_end];
        if let Some(v) = attribute(tag, "filename") {
            out.push(v);
        }
        rest = &rest[tag_end.min(rest.len())..];
        if rest.is_empty() {
            break;
        }
    }
    let mut rest = text;
    while let Some(i) = rest.find("load_yaml(") {
        let after = &rest[i + "load_yaml(".len()..];
        let quote = after.trim_start().chars().next();
        if let Some(q @ ('\'' | '"')) = quote {
            let body = &after.trim_start()[1..];
            if let Some(end) = body.find(q) {
                out.push(body[..end].to_string());
            }
        }
        rest = after;
    }
    out
}

/// `<xacro:arg name="…" default="…"/>` pairs.
fn arg_defaults(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find(":arg ") {
        let tag_end = rest[i..].find('>').map_or(rest.len(), |e| i + e);
        let tag = &rest[i..tag_end];
        if let (Some(n), Some(d)) = (attribute(tag, "name"), attribute(tag, "default")) {
            out.push((n, d));
        }
        rest = &rest[tag_end.min(rest.len())..];
    }
    out
}

fn attribute(tag: &str, name: &str) -> Option<String> {
    let mut rest = tag;
    while let Some(i) = rest.find(name) {
        let before_ok = i == 0 || rest.as_bytes()[i - 1].is_ascii_whitespace();
        let after = rest[i + name.len()..].trim_start();
        if before_ok && let Some(value) = after.strip_prefix('=') {
            let value = value.trim_start();
            let q = value.chars().next()?;
            let body = &value[1..];
            return body.find(q).map(|e| body[..e].to_string());
        }
        rest = &rest[i + name.len()..];
    }
    None
}

/// `raw` with `$(find)` and `$(arg)` substituted, relative to `dir`; `None` when it
/// still holds an expression only the expansion can evaluate.
fn resolve(
    raw: &str,
    dir: &Path,
    args: &HashMap<String, String>,
    packages: &PackagePaths,
) -> Option<PathBuf> {
    let mut s = raw.trim().to_string();
    for _ in 0..16 {
        let Some(start) = s.find("$(") else { break };
        let end = s[start..].find(')')? + start;
        let inner = s[start + 2..end].trim().to_string();
        let (verb, arg) = inner.split_once(char::is_whitespace)?;
        let value = match verb {
            "find" => packages.find(arg.trim(), Some(dir))?.display().to_string(),
            "arg" => args.get(arg.trim())?.clone(),
            _ => return None,
        };
        s.replace_range(start..=end, &value);
    }
    if s.contains("$(") || s.contains("${") || s.is_empty() {
        return None;
    }
    let p = PathBuf::from(s);
    Some(if p.is_relative() { dir.join(p) } else { p })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn includes_and_yaml_files_are_found_with_their_arguments() {
        let text = r#"<robot xmlns:xacro="x"><xacro:arg name="kin" default="k.yaml"/>
            <xacro:include filename="$(find p)/a.xacro"/>
            <xacro:include  filename='b.xacro' />
            <xacro:property name="y" value="${xacro.load_yaml('$(arg kin)')}"/>
            <xacro:include filename="${prefix}/c.xacro"/></robot>"#;
        assert_eq!(
            referenced_files(text),
            [
                "$(find p)/a.xacro",
                "b.xacro",
                "${prefix}/c.xacro",
                "$(arg kin)"
            ]
        );
        let args: HashMap<_, _> = arg_defaults(text).into_iter().collect();
        let dir = Path::new("/r");
        let pk = PackagePaths::default();
        assert_eq!(
            resolve("$(arg kin)", dir, &args, &pk),
            Some("/r/k.yaml".into())
        );
        assert_eq!(resolve("${prefix}/c.xacro", dir, &args, &pk), None);
    }

    #[test]
    fn a_device_include_is_refused_before_anything_reads_it() {
        let text = r#"<robot xmlns:xacro="x"><xacro:include filename="/dev/zero"/></robot>"#;
        let err = check(
            Path::new("/tmp/r.xacro"),
            text,
            &[],
            &PackagePaths::default(),
        )
        .unwrap_err();
        assert!(
            err.contains("/dev/zero") && err.contains("not a regular file"),
            "{err}"
        );
    }
}
