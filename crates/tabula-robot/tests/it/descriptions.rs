//! The built-in robot descriptions agree with their URDFs: grippers open and close to
//! the widths they claim along the axes they claim, tucked poses are within limits,
//! every arm's own IK solver inverts its chain.

use tabula_geom::Vec3;
use tabula_robot::description::RobotDescription;
use tabula_robot::ik::{IkMode, NumericIkParams};
use tabula_robot::robots;

#[test]
fn grippers_open_and_close_to_their_widths_along_their_axes() {
    for name in ["golem3", "wam", "pr2"] {
        let r = robots::load(name).unwrap();
        assert!(!r.description.grippers.is_empty(), "{name} has no gripper");
        for g in &r.description.grippers {
            let j = r.model.joint(&g.finger_joint).unwrap();
            let lim = r.model.joints[j].limits;
            let tool = r.model.link(&g.tool_link).unwrap();
            let f0 = r.model.link(&g.fingers[0]).unwrap();
            let f1 = r.model.link(&g.fingers[1]).unwrap();
            for (value, width) in [(lim.lower, g.closed_width), (lim.upper, g.open_width)] {
                let mut q = r.model.mid_configuration();
                q[j] = value;
                let poses = r.model.forward_kinematics(&q).unwrap();
                let tool_from_world = poses[tool].inverse();
                let a = tool_from_world.transform_point(poses[f0].translation);
                let b = tool_from_world.transform_point(poses[f1].translation);
                let gap = (a - b).dot(g.closing()).abs();
                assert!(
                    (gap - width).abs() < 1e-9,
                    "{name}/{}: gap {gap} at {value}, described {width}",
                    g.name
                );
                assert!((g.width_at(&r.model, value) - width).abs() < 1e-12);
                // The palm is behind the tool point along the approach.
                let palm = r.model.link(&g.palm).unwrap();
                let p = tool_from_world.transform_point(poses[palm].translation);
                assert!(
                    p.dot(g.approach()) <= 1e-9,
                    "{name}: palm ahead of the tool"
                );
            }
        }
    }
}

#[test]
fn tucked_poses_are_within_limits_and_arms_solve_their_own_chains() {
    for name in ["golem3", "wam", "pr2"] {
        let r = robots::load(name).unwrap();
        for arm in &r.description.arms {
            for (joint, v) in &arm.tucked {
                let l = r.model.joints[r.model.joint(joint).unwrap()].limits;
                assert!(*v >= l.lower && *v <= l.upper, "{name}: {joint}={v}");
            }
            let chain = arm.chain(&r.model).unwrap();
            let solver = arm.ik_solver(&r.model, NumericIkParams::default()).unwrap();
            let q: Vec<f64> = (0..chain.dof())
                .map(|i| {
                    let (lo, hi) = chain.sample_range(i);
                    lo + (hi - lo) * (0.3 + 0.05 * i as f64)
                })
                .collect();
            let target = chain.fk(&q).unwrap();
            let sols = solver
                .solve(&target, IkMode::Full, &chain.mid_configuration())
                .unwrap();
            let reached = chain.fk(&sols[0].joints).unwrap();
            assert!((reached.translation - target.translation).length() < 1e-5);
        }
    }
}

#[test]
fn golem3_tool_frame_approaches_along_x() {
    let r = robots::load("golem3").unwrap();
    let chain = r.description.arm("right").unwrap().chain(&r.model).unwrap();
    // All joints zero: the tool points forward, level (SPEC §2.1's 6′ row).
    let tool = chain.fk(&[0.0; 6]).unwrap();
    let approach = tool.rotation * Vec3::X;
    assert!(approach.dot(Vec3::X) > 0.999, "approach {approach}");
}

#[test]
fn descriptions_with_unknown_names_are_refused() {
    let r = robots::load("wam").unwrap();
    let bad = r#"
name = "wam"
[[arm]]
name = "arm"
base = "base_link"
tip = "no_such_link"
ik = "numeric"
"#;
    assert!(RobotDescription::from_toml(bad, &r.model).is_err());
    let bad_gripper = r#"
name = "wam"
[[arm]]
name = "arm"
base = "base_link"
tip = "wam_tool"
ik = "numeric"
gripper = "missing"
"#;
    assert!(RobotDescription::from_toml(bad_gripper, &r.model).is_err());
    assert!(RobotDescription::from_toml("name = 3", &r.model).is_err());
}
