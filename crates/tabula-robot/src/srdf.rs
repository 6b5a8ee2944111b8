//! MoveIt's Semantic Robot Description Format (srdfdom's schema): planning groups,
//! named group states, end effectors, virtual and passive joints, and the allowed
//! collision matrix (`disable_collisions`, `disable_default_collisions`,
//! `enable_collisions`). Checked against the URDF as MoveIt does: a group naming a
//! link or joint the URDF lacks is an error; a collision entry that does so is skipped
//! with a warning, because published SRDFs drift from their URDFs.

use crate::description::{ArmGroup, IkKind};
use crate::{RobotError, RobotModel};
use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::path::Path;

/// Most elements an SRDF may have (the PR2's has ~1,500).
const MAX_ELEMENTS: usize = 200_000;

/// One planning group: what srdfdom's `Group` holds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Group {
    pub name: String,
    /// `(base_link, tip_link)` pairs.
    pub chains: Vec<(String, String)>,
    pub joints: Vec<String>,
    pub links: Vec<String>,
    pub subgroups: Vec<String>,
}

/// A named configuration of a group (`<group_state>`).
#[derive(Debug, Clone, PartialEq)]
pub struct GroupState {
    pub name: String,
    pub group: String,
    pub values: BTreeMap<String, f64>,
}

/// An end effector: a group attached to a parent link (of a parent group).
#[derive(Debug, Clone, PartialEq)]
pub struct EndEffector {
    pub name: String,
    pub group: String,
    pub parent_link: String,
    pub parent_group: Option<String>,
}

/// A virtual joint between the robot's root and a fixed frame.
#[derive(Debug, Clone, PartialEq)]
pub struct VirtualJoint {
    pub name: String,
    pub kind: String,
    pub parent_frame: String,
    pub child_link: String,
}

/// A parsed SRDF.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Srdf {
    pub name: String,
    pub groups: Vec<Group>,
    pub group_states: Vec<GroupState>,
    pub end_effectors: Vec<EndEffector>,
    pub virtual_joints: Vec<VirtualJoint>,
    pub passive_joints: Vec<String>,
    /// Pairs never checked (`disable_collisions`).
    pub disabled: Vec<(String, String)>,
    /// Links checked against nothing unless enabled (`disable_default_collisions`).
    pub disabled_default: Vec<String>,
    /// Pairs checked despite a default (`enable_collisions`).
    pub enabled: Vec<(String, String)>,
    /// What was skipped while checking against the URDF, one sentence each.
    pub warnings: Vec<String>,
}

impl Srdf {
    /// Reads and checks the SRDF at `path` against `model`.
    pub fn from_file(path: &Path, model: &RobotModel) -> Result<Self, RobotError> {
        Self::from_file_with(path, model, &[], &Default::default())
    }

    /// [`Self::from_file`] for an SRDF that may be xacro (`panda_arm.srdf.xacro`,
    /// `ur.srdf.xacro`), expanded with `xacro_args` as MoveIt's launch files do.
    pub fn from_file_with(
        path: &Path,
        model: &RobotModel,
        xacro_args: &[(String, String)],
        packages: &crate::packages::PackagePaths,
    ) -> Result<Self, RobotError> {
        let text = if crate::xacro::is_xacro(path) {
            crate::xacro::expand(path, xacro_args, packages)?
        } else {
            tabula_geom::input::read_text(path, tabula_geom::input::Format::Robot)?
        };
        Self::parse(&text, model).map_err(|e| match e {
            RobotError::Description(m) => {
                RobotError::Description(format!("{}: {m}", path.display()))
            }
            other => other,
        })
    }

    /// Parses SRDF text and checks it against `model`.
    pub fn parse(text: &str, model: &RobotModel) -> Result<Self, RobotError> {
        let bad = |m: String| RobotError::Description(format!("SRDF: {m}"));
        let depth = tabula_geom::input::xml_depth(text, 64);
        if depth > 64 {
            return Err(RobotError::TooDeep(depth));
        }
        let options = roxmltree::ParsingOptions {
            allow_dtd: false,
            nodes_limit: MAX_ELEMENTS as u32,
        };
        let doc = roxmltree::Document::parse_with_options(text, options)
            .map_err(|e| bad(e.to_string()))?;
        let root = doc.root_element();
        if root.tag_name().name() != "robot" {
            return Err(bad(format!(
                "the root element is <{}>, not <robot>",
                root.tag_name().name()
            )));
        }
        let mut srdf = Srdf {
            name: root.attribute("name").unwrap_or_default().to_string(),
            ..Self::default()
        };
        for e in root.children().filter(|n| n.is_element()) {
            srdf.read_element(e).map_err(bad)?;
        }
        srdf.check(model)?;
        Ok(srdf)
    }

    fn read_element(&mut self, e: roxmltree::Node) -> Result<(), String> {
        let attr = |name: &str| -> Result<String, String> {
            e.attribute(name)
                .map(str::to_string)
                .ok_or_else(|| format!("<{}> without `{name}`", e.tag_name().name()))
        };
        match e.tag_name().name() {
            "group" => self.groups.push(read_group(e)?),
            "group_state" => {
                let mut values = BTreeMap::new();
                for j in e.children().filter(|n| n.has_tag_name("joint")) {
                    let name = j
                        .attribute("name")
                        .ok_or("<joint> in a group_state without `name`")?;
                    let raw = j
                        .attribute("value")
                        .ok_or("<joint> in a group_state without `value`")?;
                    // Multi-DOF joints list several values; the first is the one a
                    // single-axis joint has.
                    let first = raw.split_whitespace().next().unwrap_or("");
                    let v: f64 = first.parse().map_err(|_| {
                        format!(
                            "group state `{}`: joint `{name}` has value `{raw}`",
                            attr("name").unwrap_or_default()
                        )
                    })?;
                    if !v.is_finite() || v.abs() > tabula_geom::input::MAX_MAGNITUDE {
                        return Err(format!(
                            "group state `{}`: joint `{name}` = {v}",
                            attr("name")?
                        ));
                    }
                    values.insert(name.to_string(), v);
                }
                self.group_states.push(GroupState {
                    name: attr("name")?,
                    group: attr("group")?,
                    values,
                });
            }
            "end_effector" => self.end_effectors.push(EndEffector {
                name: attr("name")?,
                group: attr("group")?,
                parent_link: attr("parent_link")?,
                parent_group: e.attribute("parent_group").map(str::to_string),
            }),
            "virtual_joint" => self.virtual_joints.push(VirtualJoint {
                name: attr("name")?,
                kind: attr("type")?,
                parent_frame: attr("parent_frame")?,
                child_link: attr("child_link")?,
            }),
            "passive_joint" => self.passive_joints.push(attr("name")?),
            "disable_collisions" => self.disabled.push((attr("link1")?, attr("link2")?)),
            "enable_collisions" => self.enabled.push((attr("link1")?, attr("link2")?)),
            "disable_default_collisions" => self.disabled_default.push(attr("link")?),
            _ => {} // link_sphere_approximation and extensions: not used here
        }
        Ok(())
    }

    /// Groups must name what the URDF has (an error otherwise); collision entries that
    /// do not are dropped with a warning.
    fn check(&mut self, model: &RobotModel) -> Result<(), RobotError> {
        let bad = |m: String| Err(RobotError::Description(format!("SRDF: {m}")));
        let names: HashSet<&str> = self.groups.iter().map(|g| g.name.as_str()).collect();
        for g in &self.groups {
            for (base, tip) in &g.chains {
                crate::Chain::new(model, base, tip).map_err(|e| {
                    RobotError::Description(format!(
                        "SRDF: group `{}`: chain {base} → {tip}: {e}",
                        g.name
                    ))
                })?;
            }
            for j in &g.joints {
                if model.joint(j).is_none() && !self.virtual_joints.iter().any(|v| &v.name == j) {
                    return bad(format!(
                        "group `{}` names joint `{j}`, which the URDF lacks",
                        g.name
                    ));
                }
            }
            for l in &g.links {
                if model.link(l).is_err() {
                    return bad(format!(
                        "group `{}` names link `{l}`, which the URDF lacks",
                        g.name
                    ));
                }
            }
            if let Some(s) = g.subgroups.iter().find(|s| !names.contains(s.as_str())) {
                return bad(format!(
                    "group `{}` names subgroup `{s}`, which is not defined",
                    g.name
                ));
            }
        }
        for s in &self.group_states {
            let known = |j: &str| {
                model.joint(j).is_some() || self.virtual_joints.iter().any(|v| v.name == j)
            };
            if let Some(j) = s.values.keys().find(|j| !known(j)) {
                return bad(format!(
                    "group state `{}` sets joint `{j}`, which the URDF lacks",
                    s.name
                ));
            }
            if !names.contains(s.group.as_str()) {
                return bad(format!(
                    "group state `{}` is for unknown group `{}`",
                    s.name, s.group
                ));
            }
        }
        // Entries naming links the URDF lacks are dropped; one warning names them all.
        let known = |l: &str| model.link(l).is_ok();
        let mut missing = BTreeSet::new();
        let before = self.disabled.len() + self.enabled.len() + self.disabled_default.len();
        let mut keep = |l: &String| {
            if !known(l) {
                missing.insert(l.clone());
            }
            known(l)
        };
        self.disabled.retain(|(a, b)| keep(a) & keep(b));
        self.enabled.retain(|(a, b)| keep(a) & keep(b));
        self.disabled_default.retain(|l| keep(l));
        let skipped =
            before - self.disabled.len() - self.enabled.len() - self.disabled_default.len();
        let mut warnings = Vec::new();
        if skipped > 0 {
            let names: Vec<&str> = missing.iter().map(String::as_str).collect();
            warnings.push(format!(
                "{skipped} collision entries skipped: the URDF lacks link(s) {}",
                tabula_geom::input::clip(&names.join(", "), 400)
            ));
        }
        self.warnings.extend(warnings);
        Ok(())
    }

    /// Whether the SRDF says anything about collisions (else the matrix is sampled).
    pub fn has_collision_matrix(&self) -> bool {
        !(self.disabled.is_empty() && self.disabled_default.is_empty())
    }

    /// The links of a group as srdfdom counts them: its links, each joint's child, every
    /// link along its chains, and its subgroups' links (each group visited once, so a
    /// subgroup cycle ends).
    pub fn group_links(&self, group: &str, model: &RobotModel) -> BTreeSet<usize> {
        let mut links = BTreeSet::new();
        let mut seen = HashSet::new();
        let mut todo = vec![group];
        while let Some(name) = todo.pop() {
            let Some(g) = self.groups.iter().find(|g| g.name == name) else {
                continue;
            };
            if !seen.insert(name) {
                continue;
            }
            links.extend(g.links.iter().filter_map(|l| model.link(l).ok()));
            links.extend(
                g.joints
                    .iter()
                    .filter_map(|j| model.joint(j))
                    .map(|j| model.joints[j].child),
            );
            for (base, tip) in &g.chains {
                let (Ok(base), Ok(mut link)) = (model.link(base), model.link(tip)) else {
                    continue;
                };
                links.insert(link);
                while let Some(j) = model.links[link].parent_joint.filter(|_| link != base) {
                    link = model.joints[j].parent;
                    links.insert(link);
                }
            }
            todo.extend(g.subgroups.iter().map(String::as_str));
        }
        links
    }

    /// Whether the pair of links is allowed to touch by this SRDF.
    pub fn allows(&self, a: &str, b: &str) -> bool {
        let same = |(x, y): &(String, String)| (x == a && y == b) || (x == b && y == a);
        if self.enabled.iter().any(same) {
            return false;
        }
        self.disabled.iter().any(same) || self.disabled_default.iter().any(|l| l == a || l == b)
    }

    /// The serial chain `(base, tip)` a group moves, when it is one: its `<chain>`, or
    /// its joints when they line up parent to child.
    pub fn group_chain(&self, group: &str, model: &RobotModel) -> Option<(String, String)> {
        let g = self.groups.iter().find(|g| g.name == group)?;
        if let [chain] = g.chains.as_slice() {
            return Some(chain.clone());
        }
        if !g.chains.is_empty() || g.joints.is_empty() {
            return None;
        }
        let idx: Vec<usize> = g.joints.iter().filter_map(|j| model.joint(j)).collect();
        let children: BTreeSet<usize> = idx.iter().map(|&j| model.joints[j].child).collect();
        // The top joint is the one whose parent link no other listed joint makes.
        let top = idx
            .iter()
            .find(|&&j| !children.contains(&model.joints[j].parent))?;
        let bottom = idx
            .iter()
            .max_by_key(|&&j| depth(model, model.joints[j].child))?;
        let base = model.links[model.joints[*top].parent].name.clone();
        let tip = model.links[model.joints[*bottom].child].name.clone();
        let chain = crate::Chain::new(model, &base, &tip).ok()?;
        (chain.dof() > 0).then_some((base, tip))
    }

    /// Arm groups: every group that is one serial chain with moving joints and is not
    /// an end effector's own group; the tip is the end effector's parent link when the
    /// group has one (Panda's `panda_link8`, UR's `tool0`). Named states go with them.
    pub fn arms(&self, model: &RobotModel) -> Vec<ArmGroup> {
        let ee_groups: HashSet<&str> = self
            .end_effectors
            .iter()
            .map(|e| e.group.as_str())
            .collect();
        self.groups
            .iter()
            .filter(|g| !ee_groups.contains(g.name.as_str()))
            .filter_map(|g| {
                let (base, mut tip) = self.group_chain(&g.name, model)?;
                if let Some(ee) = self.end_effectors.iter().find(|e| {
                    e.parent_group.as_deref() == Some(g.name.as_str())
                        && crate::Chain::new(model, &base, &e.parent_link).is_ok()
                }) {
                    tip = ee.parent_link.clone();
                }
                let named: BTreeMap<String, BTreeMap<String, f64>> = self
                    .group_states
                    .iter()
                    .filter(|s| s.group == g.name)
                    .map(|s| (s.name.clone(), s.values.clone()))
                    .collect();
                let tucked = named
                    .iter()
                    .find(|(n, _)| n.contains("tuck"))
                    .map(|(_, v)| v.clone())
                    .unwrap_or_default();
                Some(ArmGroup {
                    name: g.name.clone(),
                    base,
                    tip,
                    ik: IkKind::Numeric,
                    gripper: None,
                    tucked,
                    named,
                })
            })
            .collect()
    }
}

fn depth(model: &RobotModel, mut link: usize) -> usize {
    let mut d = 0;
    while let Some(j) = model.links[link].parent_joint {
        link = model.joints[j].parent;
        d += 1;
    }
    d
}

fn read_group(e: roxmltree::Node) -> Result<Group, String> {
    let name = e
        .attribute("name")
        .ok_or("<group> without `name`")?
        .to_string();
    let mut g = Group {
        name,
        ..Group::default()
    };
    for c in e.children().filter(|n| n.is_element()) {
        let need = |a: &str| {
            c.attribute(a).map(str::to_string).ok_or_else(|| {
                format!(
                    "group `{}`: <{}> without `{a}`",
                    g.name,
                    c.tag_name().name()
                )
            })
        };
        match c.tag_name().name() {
            "chain" => g.chains.push((need("base_link")?, need("tip_link")?)),
            "joint" => g.joints.push(need("name")?),
            "link" => g.links.push(need("name")?),
            "group" => g.subgroups.push(need("name")?),
            _ => {}
        }
    }
    Ok(g)
}
