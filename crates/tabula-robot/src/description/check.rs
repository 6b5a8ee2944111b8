//! A description checked against its URDF before anything uses it (INPUT_POLICY.md):
//! every name exists, no name is given twice, every chain runs from its base to a
//! different tip, named joint values lie within the joints' limits, a gripper's widths
//! are a gripper's (a gap that opens, at most [`MAX_GRIPPER_WIDTH`]) and its approach
//! and closing axes are real, perpendicular directions. Each error names the key.

use super::{ArmGroup, Gripper, RobotDescription};
use crate::model::JointKind;
use crate::{Chain, RobotError, RobotModel};
use std::collections::{BTreeMap, BTreeSet};
use tabula_geom::Vec3;

/// The widest gap a parallel gripper of a manipulator has (m): the largest commercial
/// ones open about 0.3 m; beyond a metre a width is a unit mistake.
pub const MAX_GRIPPER_WIDTH: f64 = 1.0;

/// The smallest stroke (m) between closed and open: less cannot hold anything the
/// closed gripper does not already.
pub const MIN_GRIPPER_STROKE: f64 = 1e-3;

/// How far from perpendicular the approach and closing axes may be (cosine ≈ 3°).
const MAX_AXIS_COSINE: f64 = 0.05;

/// The shortest axis accepted before normalising (an axis of 1e-300 normalises to
/// garbage or to nothing).
const MIN_AXIS_LENGTH: f64 = 1e-3;

fn bad(what: String) -> Result<(), RobotError> {
    Err(RobotError::Description(what))
}

pub(super) fn check(d: &RobotDescription, model: &RobotModel) -> Result<(), RobotError> {
    unique("arm", d.arms.iter().map(|a| a.name.as_str()))?;
    unique("gripper", d.grippers.iter().map(|g| g.name.as_str()))?;
    for a in &d.arms {
        arm(a, d, model)?;
    }
    for g in &d.grippers {
        gripper(g, model)?;
    }
    if let Some(h) = &d.head {
        joints(model, "head", [&h.pan_joint, &h.tilt_joint])?;
        model.link(&h.camera_link)?;
    }
    if let Some(b) = &d.base {
        joints(model, "base", [&b.x_joint, &b.y_joint, &b.theta_joint])?;
    }
    joints(model, "torso_joints", &d.torso_joints)
}

/// Names given once each.
fn unique<'a>(what: &str, names: impl Iterator<Item = &'a str>) -> Result<(), RobotError> {
    let mut seen = BTreeSet::new();
    for n in names {
        if n.trim().is_empty() {
            return bad(format!("an {what} has an empty `name`"));
        }
        if !seen.insert(n) {
            return bad(format!("two {what}s are called `{n}`"));
        }
    }
    Ok(())
}

/// Joints that exist and are not listed twice.
fn joints<'a>(
    model: &RobotModel,
    at: &str,
    names: impl IntoIterator<Item = &'a String>,
) -> Result<(), RobotError> {
    let mut seen = BTreeSet::new();
    for n in names {
        joint(model, at, n)?;
        if !seen.insert(n) {
            return bad(format!("`{at}` lists joint `{n}` twice"));
        }
    }
    Ok(())
}

fn joint(model: &RobotModel, at: &str, name: &str) -> Result<usize, RobotError> {
    model
        .joint(name)
        .ok_or_else(|| RobotError::Description(format!("`{at}`: no joint `{name}` in the URDF")))
}

fn arm(a: &ArmGroup, d: &RobotDescription, model: &RobotModel) -> Result<(), RobotError> {
    let at = format!("arm `{}`", a.name);
    model.link(&a.base)?;
    model.link(&a.tip)?;
    if a.base == a.tip {
        return bad(format!(
            "{at}: `base` and `tip` are the same link `{}` (a chain needs two)",
            a.base
        ));
    }
    Chain::new(model, &a.base, &a.tip)
        .map_err(|e| RobotError::Description(format!("{at}: {e}")))?;
    if let Some(g) = &a.gripper
        && !d.grippers.iter().any(|x| &x.name == g)
    {
        return bad(format!("{at} names an unknown gripper `{g}`"));
    }
    values(model, &format!("{at} `tucked`"), &a.tucked)?;
    for (pose, v) in &a.named {
        values(model, &format!("{at} `named.{pose}`"), v)?;
    }
    Ok(())
}

/// Joint values that exist and lie within their joints' limits.
fn values(model: &RobotModel, at: &str, v: &BTreeMap<String, f64>) -> Result<(), RobotError> {
    for (name, &value) in v {
        let j = &model.joints[joint(model, at, name)?];
        let l = j.limits;
        let bounded = matches!(j.kind, JointKind::Revolute | JointKind::Prismatic);
        if !value.is_finite() || (bounded && !(l.lower - 1e-9..=l.upper + 1e-9).contains(&value)) {
            return bad(format!(
                "{at}: `{name}` = {} is outside its limits [{}, {}]",
                tabula_geom::input::shown(value),
                tabula_geom::input::shown(l.lower),
                tabula_geom::input::shown(l.upper)
            ));
        }
    }
    Ok(())
}

fn gripper(g: &Gripper, model: &RobotModel) -> Result<(), RobotError> {
    let at = format!("gripper `{}`", g.name);
    model.link(&g.tool_link)?;
    model.link(&g.palm)?;
    model.link(&g.fingers[0])?;
    model.link(&g.fingers[1])?;
    if g.fingers[0] == g.fingers[1] {
        return bad(format!("{at}: both `fingers` are `{}`", g.fingers[0]));
    }
    let j = joint(model, &at, &g.finger_joint)?;
    if !model.joints[j].kind.is_single_axis() {
        return bad(format!(
            "{at}: `finger_joint` `{}` does not move",
            g.finger_joint
        ));
    }
    widths(g, &at)?;
    axes(g, &at)?;
    for (i, b) in g.self_filter_boxes.iter().enumerate() {
        if b.size.iter().any(|&s| !(s > 0.0 && s <= 10.0)) {
            return bad(format!(
                "{at}: `self_filter_boxes[{i}].size` = {:?}: each side must be in (0, 10] m",
                b.size
            ));
        }
    }
    Ok(())
}

fn widths(g: &Gripper, at: &str) -> Result<(), RobotError> {
    let (closed, open) = (g.closed_width, g.open_width);
    let show = tabula_geom::input::shown;
    if !(0.0..=MAX_GRIPPER_WIDTH).contains(&closed) || !(0.0..=MAX_GRIPPER_WIDTH).contains(&open) {
        return bad(format!(
            "{at}: `closed_width` = {} and `open_width` = {} must be in [0, {MAX_GRIPPER_WIDTH}] m",
            show(closed),
            show(open)
        ));
    }
    if open - closed < MIN_GRIPPER_STROKE {
        return bad(format!(
            "{at}: open width must exceed closed by at least {} m (`open_width` = {}, `closed_width` = {})",
            MIN_GRIPPER_STROKE,
            show(open),
            show(closed)
        ));
    }
    Ok(())
}

fn axes(g: &Gripper, at: &str) -> Result<(), RobotError> {
    let axis = |name: &str, v: [f64; 3]| {
        let v = Vec3::from_array(v);
        if v.length() >= MIN_AXIS_LENGTH {
            Ok(v.normalize())
        } else {
            Err(RobotError::Description(format!(
                "{at}: `{name}` = {:?} is not a direction (length under {MIN_AXIS_LENGTH})",
                v.to_array()
            )))
        }
    };
    let approach = axis("approach_axis", g.approach_axis)?;
    let closing = axis("closing_axis", g.closing_axis)?;
    if approach.dot(closing).abs() > MAX_AXIS_COSINE {
        return bad(format!(
            "{at}: `approach_axis` {:?} and `closing_axis` {:?} must be perpendicular \
             (fingers close across the approach)",
            g.approach_axis, g.closing_axis
        ));
    }
    Ok(())
}
