//! Robot descriptions (the TOML beside a URDF) that are wrong in number or in sense —
//! NaN or huge joint values, gripper widths of ±1e300, zero or parallel axes, the same
//! arm twice, a chain from a link to itself — each refused naming what is wrong; and
//! URDF limits so small that a trajectory would last for ages.

use super::*;

/// A WAM whose description has `from` replaced by `to`, in a scene of its own.
fn wam_with(c: &mut Corpus, name: &str, urdf: &str, from: &str, to: &str) -> String {
    let toml = read_repo("robots/wam.toml");
    assert!(toml.contains(from), "{from}");
    let dir = format!("description/{name}");
    c.file(&format!("{dir}/wam.urdf"), urdf);
    c.file(&format!("{dir}/wam.toml"), toml.replacen(from, to, 1));
    c.file(
        &format!("{dir}/scene.toml"),
        "[[robot]]\nname = \"wam\"\nurdf = \"wam.urdf\"\npose = { xyz = [0.0, 0.0, 0.6] }\n",
    )
}

pub(super) fn descriptions(c: &mut Corpus) {
    let urdf = read_repo("robots/wam.urdf");
    let tucked = "wam_joint2 = -1.9";
    let closed = "closed_width = 0.03";
    let open = "open_width = 0.07";
    let approach = "approach_axis = [0.0, 0.0, 1.0]";
    let arm = "[[gripper]]";
    let second_arm = "[[arm]]\nname = \"arm\"\nbase = \"base_link\"\ntip = \"wam_tool\"\nik = \"numeric\"\n\n[[gripper]]";
    let fingers = "fingers = [\"wam_gripper_left_finger\", \"wam_gripper_right_finger\"]";
    for (name, from, to, class, needle) in [
        (
            "tucked-nan",
            tucked,
            "wam_joint2 = nan",
            "garbage",
            "arm[0].tucked.wam_joint2",
        ),
        (
            "tucked-inf",
            tucked,
            "wam_joint2 = -inf",
            "garbage",
            "arm[0].tucked.wam_joint2",
        ),
        (
            "tucked-1e300",
            tucked,
            "wam_joint2 = 1e300",
            "overflow",
            "wam_joint2",
        ),
        (
            "tucked-beyond-limit",
            tucked,
            "wam_joint2 = 5.0",
            "garbage",
            "outside its limits",
        ),
        (
            "tucked-unknown-joint",
            tucked,
            "wam_joint99 = 0.0",
            "garbage",
            "wam_joint99",
        ),
        (
            "closed-negative-huge",
            closed,
            "closed_width = -1e300",
            "overflow",
            "closed_width",
        ),
        (
            "closed-negative",
            closed,
            "closed_width = -0.01",
            "garbage",
            "closed_width",
        ),
        (
            "open-huge",
            open,
            "open_width = 1e300",
            "overflow",
            "open_width",
        ),
        (
            "open-10m",
            open,
            "open_width = 10.0",
            "garbage",
            "open_width",
        ),
        (
            "open-tiny-stroke",
            open,
            "open_width = 0.0300001",
            "odd-legal",
            "open width must exceed",
        ),
        (
            "open-below-closed",
            open,
            "open_width = 0.01",
            "garbage",
            "open width must exceed",
        ),
        (
            "approach-zero",
            approach,
            "approach_axis = [0.0, 0.0, 0.0]",
            "garbage",
            "approach_axis",
        ),
        (
            "approach-tiny",
            approach,
            "approach_axis = [1e-300, 0.0, 0.0]",
            "odd-legal",
            "approach_axis",
        ),
        (
            "approach-parallel",
            approach,
            "approach_axis = [1.0, 0.0, 0.0]",
            "garbage",
            "perpendicular",
        ),
        (
            "approach-short",
            approach,
            "approach_axis = [0.0, 1.0]",
            "malformed",
            "approach_axis",
        ),
        ("arm-twice", arm, second_arm, "garbage", "two arms"),
        (
            "base-is-tip",
            "tip = \"wam_tool\"",
            "tip = \"base_link\"",
            "garbage",
            "same link",
        ),
        (
            "tip-above-base",
            "tip = \"wam_tool\"",
            "tip = \"base_link\"\nbase = \"wam_link3\"",
            "malformed",
            "duplicate key",
        ),
        (
            "fingers-same",
            fingers,
            "fingers = [\"wam_gripper_left_finger\", \"wam_gripper_left_finger\"]",
            "garbage",
            "both `fingers`",
        ),
        (
            "finger-joint-unknown",
            "finger_joint = \"wam_gripper_left_finger_joint\"",
            "finger_joint = \"nope\"",
            "garbage",
            "nope",
        ),
        (
            "unknown-key",
            "ik = \"numeric\"",
            "ik = \"numeric\"\nspeed = 3",
            "garbage",
            "unknown field `speed`",
        ),
        (
            "ik-unknown",
            "ik = \"numeric\"",
            "ik = \"magic\"",
            "garbage",
            "magic",
        ),
        (
            "gripper-unknown",
            "gripper = \"gripper\"",
            "gripper = \"claw\"",
            "garbage",
            "claw",
        ),
        (
            "width-word",
            closed,
            "closed_width = \"three\"",
            "malformed",
            "closed_width",
        ),
    ] {
        let scene = wam_with(c, name, &urdf, from, to);
        c.case(
            &format!("description-{name}"),
            class,
            Error,
            &["arm", "--scene", &scene, "--dry-run", "named", "tuck"],
        );
        c.needs(needle);
    }
    // URDF limits that pass as numbers but make a move last for days: refused with the
    // joint and the limit named (the sampler would fill the memory).
    for (name, from, to, needle) in [
        (
            "velocity-1e-300",
            "velocity=\"2.0\"",
            "velocity=\"1e-300\"",
            "velocity limit",
        ),
        (
            "velocity-1e-9",
            "velocity=\"2.0\"",
            "velocity=\"1e-9\"",
            "velocity limit",
        ),
    ] {
        let slow = urdf.replace(from, to);
        let scene = wam_with(c, name, &slow, tucked, tucked);
        let mut args = vec!["arm", "--scene", &scene, "--dry-run", "move-joints"];
        args.extend(["0.3", "-0.5", "0", "2.0", "0", "0.4", "0"]);
        c.case(&format!("urdf-{name}"), "unbounded", NoSolution, &args);
        c.needs(needle);
    }
}
