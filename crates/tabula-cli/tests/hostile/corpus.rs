//! The hostile cases, by format. Each case names the class of failure it guards
//! against (the classes of issue 12), the command, and the answer that is right.

mod commands;
mod descriptions;
mod flags;
mod heavy;
mod labels;
mod meshes;
mod moveit;
mod numbers;
mod params;
mod pcd;
mod pddl;
mod ply;
mod robot_packages;
mod scenes;
mod special_files;
mod urdf;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// The right kind of answer.
#[derive(Debug, Clone, Copy)]
pub enum Expect {
    Ok,
    Error,
    NoSolution,
    Usage,
}

/// Classes of failure, each covered by several cases.
pub const CLASSES: [&str; 7] = [
    "overflow",     // sizes from headers and flags that wrap or exhaust memory
    "unbounded",    // inputs that make work grow without limit
    "recursion",    // nesting that would overflow the stack
    "odd-legal",    // legal but unusual values that once panicked
    "garbage",      // inputs that once gave a wrong answer instead of an error
    "malformed",    // plain syntax errors, truncations, wrong types
    "special-file", // devices, folders, missing files, huge files
];

pub struct Case {
    pub name: String,
    pub class: &'static str,
    args: Vec<String>,
    pub expect: Expect,
    pub needle: Option<String>,
}

impl Case {
    /// The command line, with `@relative` paths resolved under the corpus folder.
    pub fn args(&self, root: &Path) -> Vec<String> {
        self.args
            .iter()
            .map(|a| match a.strip_prefix('@') {
                Some(rel) => root.join(rel).display().to_string(),
                None => a.clone(),
            })
            .collect()
    }
}

pub fn count_by_class(cases: &[Case]) -> BTreeMap<&'static str, usize> {
    let mut m = BTreeMap::new();
    for c in cases {
        *m.entry(c.class).or_insert(0) += 1;
    }
    m
}

struct Corpus<'a> {
    root: &'a Path,
    cases: Vec<Case>,
}

impl Corpus<'_> {
    /// Writes `bytes` as `rel` under the corpus folder; returns the `@rel` argument.
    fn file(&self, rel: &str, bytes: impl AsRef<[u8]>) -> String {
        let path = self.root.join(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, bytes).unwrap();
        format!("@{rel}")
    }

    fn case(&mut self, name: &str, class: &'static str, expect: Expect, args: &[&str]) {
        assert!(CLASSES.contains(&class), "{class}");
        self.cases.push(Case {
            name: name.to_string(),
            class,
            args: args.iter().map(|s| s.to_string()).collect(),
            expect,
            needle: None,
        });
    }

    /// The last case must also print `needle` (case-insensitive).
    fn needs(&mut self, needle: &str) {
        self.cases.last_mut().unwrap().needle = Some(needle.to_string());
    }
}

fn repo(rel: &str) -> String {
    format!("{}/../../{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn read_repo(rel: &str) -> String {
    std::fs::read_to_string(repo(rel)).unwrap()
}

pub fn all(root: &Path) -> Vec<Case> {
    let mut c = Corpus {
        root,
        cases: Vec::new(),
    };
    special_files::special_files(&mut c);
    pcd::pcd(&mut c);
    labels::labels(&mut c);
    ply::ply(&mut c);
    meshes::meshes(&mut c);
    urdf::urdf(&mut c);
    robot_packages::robot_packages(&mut c);
    moveit::moveit(&mut c);
    scenes::scenes(&mut c);
    params::params(&mut c);
    pddl::pddl(&mut c);
    flags::flags(&mut c);
    numbers::numbers(&mut c);
    descriptions::descriptions(&mut c);
    commands::commands(&mut c);
    heavy::heavy(&mut c);
    c.cases
}

use Expect::{Error, NoSolution, Ok, Usage};
// Shared by the PLY and mesh cases.
use pcd::{ascii_body, binary_body, hdr, table_points};
use ply::ply_text;
