//! One URDF element at a time into the model: a link with its shapes, a joint with its
//! kind, axis and limits, the mimic relations, and the tree they must form — each
//! checked, each failure one typed [`RobotError`].

use super::geometry::{MeshContext, convert_geometry};
use super::{Joint, JointKind, JointLimits, Link, Mimic, Shape};
use crate::RobotError;
use std::collections::HashMap;
use tabula_geom::{Pose, Vec3, pose_from_xyz_rpy};

/// A URDF link: its collision and visual shapes, its mass; not yet in the tree.
pub(super) fn link_of(l: &urdf_rs::Link, meshes: &MeshContext) -> Result<Link, RobotError> {
    let shapes = |role: &'static str,
                  items: Vec<(&urdf_rs::Pose, &urdf_rs::Geometry)>|
     -> Result<Vec<Shape>, RobotError> {
        items
            .into_iter()
            .map(|(o, g)| {
                Ok(Shape {
                    link_from_shape: checked_pose(&l.name, o)?,
                    geometry: convert_geometry(&l.name, role, g, meshes)?,
                })
            })
            .collect()
    };
    let collision = l.collision.iter().map(|c| (&c.origin, &c.geometry));
    let collision = shapes("collision", collision.collect())?;
    let visual = l.visual.iter().map(|v| (&v.origin, &v.geometry));
    let visual = shapes("visual", visual.collect())?;
    checked_pose(&l.name, &l.inertial.origin)?;
    Ok(Link {
        name: l.name.clone(),
        parent_joint: None,
        child_joints: Vec::new(),
        collision,
        visual,
        mass: checked_value(&l.name, "inertial mass", l.inertial.mass.value)?.max(0.0),
    })
}

/// A URDF joint between two of `link_index`'s links, its mimic not yet resolved.
pub(super) fn joint_of(
    j: &urdf_rs::Joint,
    link_index: &HashMap<String, usize>,
) -> Result<Joint, RobotError> {
    let find = |link: &str| {
        link_index
            .get(link)
            .copied()
            .ok_or_else(|| RobotError::JointMissingLink {
                joint: j.name.clone(),
                link: link.to_string(),
            })
    };
    let parent = find(&j.parent.link)?;
    let child = find(&j.child.link)?;
    if parent == child {
        return Err(RobotError::SelfLoop(j.name.clone()));
    }
    let kind = joint_kind(&j.joint_type);
    let axis = joint_axis(j, kind)?;
    let limits = joint_limits(j, kind)?;
    Ok(Joint {
        name: j.name.clone(),
        kind,
        parent,
        child,
        parent_from_joint: checked_pose(&j.name, &j.origin)?,
        axis,
        limits,
        mimic: None,
    })
}

fn joint_kind(t: &urdf_rs::JointType) -> JointKind {
    match t {
        urdf_rs::JointType::Revolute => JointKind::Revolute,
        urdf_rs::JointType::Continuous => JointKind::Continuous,
        urdf_rs::JointType::Prismatic => JointKind::Prismatic,
        urdf_rs::JointType::Fixed => JointKind::Fixed,
        urdf_rs::JointType::Floating => JointKind::MultiAxis("floating"),
        urdf_rs::JointType::Planar => JointKind::MultiAxis("planar"),
        urdf_rs::JointType::Spherical => JointKind::MultiAxis("spherical"),
    }
}

/// The unit axis of a single-axis joint (a zero axis is an error); any axis of others.
fn joint_axis(j: &urdf_rs::Joint, kind: JointKind) -> Result<Vec3, RobotError> {
    if let Some(bad) = j.axis.xyz.0.iter().find(|v| !v.is_finite()) {
        return Err(RobotError::NonFinite {
            joint: j.name.clone(),
            field: "axis",
            value: *bad,
        });
    }
    let axis = Vec3::from_array(j.axis.xyz.0);
    if !kind.is_single_axis() {
        return Ok(axis.try_normalize().unwrap_or(Vec3::X));
    }
    if axis.length() < 1e-12 {
        return Err(RobotError::ZeroAxis {
            joint: j.name.clone(),
        });
    }
    Ok(axis.normalize())
}

/// Position limits (none for continuous joints, none for a revolute joint whose limits
/// were left out), velocity and effort (unbounded when not given).
fn joint_limits(j: &urdf_rs::Joint, kind: JointKind) -> Result<JointLimits, RobotError> {
    let (lower, upper) = match kind {
        JointKind::Continuous => (f64::NEG_INFINITY, f64::INFINITY),
        JointKind::Revolute | JointKind::Prismatic => {
            let lo = checked_value(&j.name, "lower limit", j.limit.lower)?;
            let hi = checked_value(&j.name, "upper limit", j.limit.upper)?;
            if lo > hi {
                return Err(RobotError::InvertedLimits {
                    joint: j.name.clone(),
                    lower: lo,
                    upper: hi,
                });
            }
            if kind == JointKind::Revolute && lo == 0.0 && hi == 0.0 {
                // Limits left out (urdf-rs reads them as 0, 0): URDF 1.2 says
                // "no limit", and a revolute joint locked at 0 would be a fixed one.
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                (lo, hi)
            }
        }
        _ => (0.0, 0.0),
    };
    let velocity = if j.limit.velocity.is_finite() && j.limit.velocity > 0.0 {
        j.limit.velocity
    } else {
        f64::INFINITY
    };
    let effort = if j.limit.effort.is_finite() {
        j.limit.effort.abs()
    } else {
        f64::INFINITY
    };
    Ok(JointLimits {
        lower,
        upper,
        velocity,
        effort,
    })
}

/// Resolves every `<mimic>` of the URDF's joints into `joints`; what was ignored (a
/// fixed joint or master says nothing), one line each.
pub(super) fn resolve_mimics(
    urdf_joints: &[urdf_rs::Joint],
    joints: &mut [Joint],
    joint_index: &HashMap<String, usize>,
) -> Result<Vec<String>, RobotError> {
    let mut ignored = Vec::new();
    for (ji, j) in urdf_joints.iter().enumerate() {
        let Some(m) = &j.mimic else { continue };
        // A fixed joint cannot move, so its mimic says nothing (MotionBenchMaker's
        // Panda fixes its fingers this way); a fixed master leaves the mimic still.
        let fixed = |k: usize| joints[k].kind == JointKind::Fixed;
        if fixed(ji) || joint_index.get(&m.joint).is_some_and(|&mi| fixed(mi)) {
            ignored.push(format!(
                "joint `{}`: <mimic joint=\"{}\"> ignored: {} is fixed",
                j.name,
                tabula_geom::input::clip(&m.joint, 80),
                if fixed(ji) { "the joint" } else { "its master" }
            ));
            continue;
        }
        let master = mimic_master((ji, j), &m.joint, joints, joint_index)?;
        let multiplier = m.multiplier.unwrap_or(1.0);
        let offset = m.offset.unwrap_or(0.0);
        if !multiplier.is_finite() || !offset.is_finite() {
            return Err(RobotError::NonFinite {
                joint: j.name.clone(),
                field: "mimic multiplier or offset",
                value: if multiplier.is_finite() {
                    offset
                } else {
                    multiplier
                },
            });
        }
        joints[ji].mimic = Some(Mimic {
            master,
            multiplier,
            offset,
        });
    }
    Ok(ignored)
}

/// The joint `master` a mimic follows: in the URDF, not the mimic itself, single-axis
/// and not a mimic in turn.
fn mimic_master(
    (ji, j): (usize, &urdf_rs::Joint),
    master: &str,
    joints: &[Joint],
    joint_index: &HashMap<String, usize>,
) -> Result<usize, RobotError> {
    let problem = match joint_index.get(master) {
        None => "not in the URDF",
        Some(&mi) if mi == ji => "itself",
        Some(&mi) if !joints[mi].kind.is_single_axis() => "not a single-axis joint",
        Some(&mi) if joints[mi].mimic.is_some() => "itself a mimic joint",
        Some(&mi) => return Ok(mi),
    };
    Err(RobotError::BadMimic {
        joint: j.name.clone(),
        master: master.to_string(),
        problem,
    })
}

/// Links the joints into the links' tree; its roots. Two parents or a cycle is an error.
pub(super) fn connect(links: &mut [Link], joints: &[Joint]) -> Result<Vec<usize>, RobotError> {
    for (ji, j) in joints.iter().enumerate() {
        if let Some(first) = links[j.child].parent_joint {
            return Err(RobotError::MultipleParents {
                link: links[j.child].name.clone(),
                first: joints[first].name.clone(),
                second: j.name.clone(),
            });
        }
        links[j.child].parent_joint = Some(ji);
        links[j.parent].child_joints.push(ji);
    }
    let roots: Vec<usize> = (0..links.len())
        .filter(|&l| links[l].parent_joint.is_none())
        .collect();
    // Every link must be reachable from a root; what is not sits on a cycle.
    let mut seen = vec![false; links.len()];
    let mut stack = roots.clone();
    while let Some(l) = stack.pop() {
        seen[l] = true;
        stack.extend(links[l].child_joints.iter().map(|&j| joints[j].child));
    }
    if let Some(l) = seen.iter().position(|s| !s) {
        return Err(RobotError::Cycle(links[l].name.clone()));
    }
    Ok(roots)
}

/// `value` when finite and within the policy's ±1e6 (INPUT_POLICY.md).
pub(super) fn checked_value(
    owner: &str,
    field: &'static str,
    value: f64,
) -> Result<f64, RobotError> {
    if !value.is_finite() {
        return Err(RobotError::NonFinite {
            joint: owner.to_string(),
            field,
            value,
        });
    }
    if value.abs() > tabula_geom::input::MAX_MAGNITUDE {
        return Err(RobotError::OutOfRange {
            joint: owner.to_string(),
            field,
            value,
        });
    }
    Ok(value)
}

fn checked_pose(owner: &str, p: &urdf_rs::Pose) -> Result<Pose, RobotError> {
    for (field, v) in [("origin xyz", &p.xyz.0), ("origin rpy", &p.rpy.0)] {
        for x in v {
            checked_value(owner, field, *x)?;
        }
    }
    Ok(pose_from_xyz_rpy(p.xyz.0, p.rpy.0))
}
