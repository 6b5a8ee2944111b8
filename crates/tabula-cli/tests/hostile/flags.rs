//! Command-line flags: numbers tiny and huge, words, ranges.

use super::*;

pub(super) fn flags(c: &mut Corpus) {
    let huge = "18446744073709551615";
    // Counts: u64::MAX, zero, negative, words.
    let counted: [(&str, &[&str], &str); 10] = [
        (
            "ik-bench-poses",
            &["ik", "bench", "--robot", "wam"],
            "--poses",
        ),
        ("plan-generate-objects", &["plan", "generate"], "--objects"),
        ("plan-bench-objects", &["plan", "bench"], "--objects"),
        ("plan-bench-problems", &["plan", "bench"], "--problems"),
        ("motion-bench-problems", &["motion", "bench"], "--problems"),
        ("bench-clear-scenes", &["bench", "clear"], "--scenes"),
        ("bench-place-trials", &["bench", "place"], "--trials"),
        (
            "bench-perception-scenes",
            &["bench", "perception"],
            "--scenes",
        ),
        ("bench-perception-reps", &["bench", "perception"], "--reps"),
        (
            "bench-pick-place-variants",
            &["bench", "pick-place"],
            "--variants",
        ),
    ];
    for (name, cmd, flag) in counted {
        for (label, value, class) in [
            ("max", huge, "overflow"),
            ("2pow63", "9223372036854775808", "overflow"),
            ("zero", "0", "odd-legal"),
            ("negative", "-1", "malformed"),
        ] {
            let mut args = cmd.to_vec();
            args.extend([flag, value]);
            c.case(&format!("flag-{name}-{label}"), class, Usage, &args);
        }
    }
    c.case(
        "flag-plan-generate-10001",
        "overflow",
        Usage,
        &["plan", "generate", "--objects", "10001"],
    );
    c.case(
        "flag-clear-max-actions-max",
        "overflow",
        Usage,
        &[
            "clear",
            "--scene",
            &repo("scenes/clutter.toml"),
            "--max-actions",
            huge,
        ],
    );
    // Time limits.
    let d = repo("pddl/tablewclear-domain.pddl");
    let p = repo("pddl/thesis6-a.pddl");
    for (label, value, class) in [
        ("1e300", "1e300", "overflow"),
        ("inf", "inf", "garbage"),
        ("nan", "nan", "garbage"),
        ("zero", "0", "garbage"),
        ("negative", "-1", "garbage"),
    ] {
        c.case(
            &format!("flag-plan-timeout-{label}"),
            class,
            Usage,
            &["plan", &d, &p, "--timeout", value],
        );
        c.case(
            &format!("flag-motion-timeout-{label}"),
            class,
            Usage,
            &["motion", "bench", "--problems", "1", "--timeout", value],
        );
    }
    c.case(
        "flag-plan-timeout-1e6",
        "odd-legal",
        Ok,
        &["plan", &d, &p, "--timeout", "1e6"],
    );
    c.needs("cost = 9");
    // Coordinates: NaN and infinities are usage errors naming the value.
    let cloud = "@cloud/valid-binary.pcd";
    let coordinate_flags: [(&str, Vec<&str>); 9] = [
        (
            "perceive-up",
            vec!["perceive", "--cloud", cloud, "--up", "X", "0", "1"],
        ),
        (
            "perceive-near",
            vec![
                "perceive", "--cloud", cloud, "--place", "0.1", "0.1", "--near", "X", "0", "1",
            ],
        ),
        (
            "perceive-margin",
            vec![
                "perceive", "--cloud", cloud, "--place", "0.1", "0.1", "--margin", "X",
            ],
        ),
        (
            "perceive-place",
            vec!["perceive", "--cloud", cloud, "--place", "X", "0.1"],
        ),
        (
            "perceive-world-from-camera",
            vec![
                "perceive",
                "--cloud",
                cloud,
                "--world-from-camera",
                "X",
                "0",
                "0",
                "0",
                "0",
                "0",
                "1",
            ],
        ),
        (
            "perceive-robot-base",
            vec![
                "perceive",
                "--cloud",
                cloud,
                "--robot",
                "wam",
                "--robot-base",
                "X",
                "0",
                "0",
                "0",
                "0",
                "0",
                "1",
            ],
        ),
        (
            "ik-pose",
            vec![
                "ik", "solve", "--robot", "wam", "--pose", "X", "0", "0.8", "0", "0", "0",
            ],
        ),
        (
            "ik-seed-joints",
            vec![
                "ik",
                "solve",
                "--robot",
                "wam",
                "--pose",
                "0.5",
                "0",
                "0.8",
                "0",
                "0",
                "0",
                "--seed-joints",
                "X",
                "0",
                "0",
                "0",
                "0",
                "0",
                "0",
            ],
        ),
        (
            "pick-place-pick",
            vec![
                "pick-place",
                "--scene",
                "SCENE",
                "--pick",
                "X",
                "0",
                "1",
                "--place",
                "0",
                "0",
                "1",
            ],
        ),
    ];
    let shelves = repo("scenes/golem_shelves.toml");
    for (name, template) in coordinate_flags {
        for (label, value) in [
            ("nan", "nan"),
            ("inf", "inf"),
            ("neg-inf", "-inf"),
            ("word", "north"),
        ] {
            let args: Vec<&str> = template
                .iter()
                .map(|a| match *a {
                    "X" => value,
                    "SCENE" => shelves.as_str(),
                    other => other,
                })
                .collect();
            c.case(&format!("flag-{name}-{label}"), "garbage", Usage, &args);
        }
    }
    // Odd but legal coordinate values that need a clear answer.
    for (name, args, class, expect) in [
        (
            "perceive-up-zero",
            vec!["perceive", "--cloud", cloud, "--up", "0", "0", "0"],
            "garbage",
            Error,
        ),
        (
            "perceive-up-tiny",
            vec!["perceive", "--cloud", cloud, "--up", "0", "0", "1e-300"],
            "odd-legal",
            Error,
        ),
        (
            "perceive-world-from-camera-zero-quat",
            vec![
                "perceive",
                "--cloud",
                cloud,
                "--world-from-camera",
                "0",
                "0",
                "0",
                "0",
                "0",
                "0",
                "0",
            ],
            "garbage",
            Error,
        ),
        (
            "perceive-place-negative",
            vec!["perceive", "--cloud", cloud, "--place", "-0.1", "0.1"],
            "garbage",
            Error,
        ),
        (
            "perceive-place-huge",
            vec!["perceive", "--cloud", cloud, "--place", "1e300", "1e300"],
            "odd-legal",
            NoSolution,
        ),
        (
            "perceive-place-too-big",
            vec!["perceive", "--cloud", cloud, "--place", "3", "3"],
            "garbage",
            NoSolution,
        ),
        (
            "perceive-margin-negative",
            vec![
                "perceive", "--cloud", cloud, "--place", "0.1", "0.1", "--margin", "-1",
            ],
            "garbage",
            Error,
        ),
        (
            "perceive-joint-nan",
            vec![
                "perceive",
                "--cloud",
                cloud,
                "--robot",
                "wam",
                "--joint",
                "wam_joint1=nan",
            ],
            "garbage",
            Error,
        ),
        (
            "perceive-joint-unknown",
            vec![
                "perceive", "--cloud", cloud, "--robot", "wam", "--joint", "nope=1",
            ],
            "garbage",
            Error,
        ),
        (
            "perceive-joint-no-equals",
            vec![
                "perceive",
                "--cloud",
                cloud,
                "--robot",
                "wam",
                "--joint",
                "wam_joint1",
            ],
            "malformed",
            Error,
        ),
        (
            "ik-pose-1e300",
            vec![
                "ik", "solve", "--robot", "wam", "--pose", "1e300", "0", "0.8", "0", "0", "0",
            ],
            "odd-legal",
            NoSolution,
        ),
        (
            "ik-pose-unreachable",
            vec![
                "ik", "solve", "--robot", "wam", "--pose", "5", "0", "0.8", "0", "0", "0",
            ],
            "garbage",
            NoSolution,
        ),
        (
            "ik-seed-joints-count",
            vec![
                "ik",
                "solve",
                "--robot",
                "wam",
                "--pose",
                "0.5",
                "0",
                "0.8",
                "0",
                "0",
                "0",
                "--seed-joints",
                "0",
            ],
            "malformed",
            Error,
        ),
        (
            "ik-tip-unknown",
            vec![
                "ik", "solve", "--robot", "wam", "--tip", "nowhere", "--pose", "0.5", "0", "0.8",
                "0", "0", "0",
            ],
            "malformed",
            Error,
        ),
        (
            "pick-place-unreachable",
            vec![
                "pick-place",
                "--scene",
                shelves.as_str(),
                "--pick",
                "50",
                "0",
                "1",
                "--place",
                "0",
                "0",
                "1",
            ],
            "garbage",
            NoSolution,
        ),
        (
            "pick-place-1e300",
            vec![
                "pick-place",
                "--scene",
                shelves.as_str(),
                "--pick",
                "1e300",
                "0",
                "1",
                "--place",
                "0",
                "0",
                "1",
            ],
            "odd-legal",
            NoSolution,
        ),
        (
            "place-arm-unknown",
            vec![
                "place",
                "--scene",
                &repo("scenes/pr2_holding.toml"),
                "--arm",
                "tentacle",
            ],
            "malformed",
            Error,
        ),
        (
            "clear-robot-unknown",
            vec![
                "clear",
                "--scene",
                &repo("scenes/clutter.toml"),
                "--robot",
                "nobody",
            ],
            "malformed",
            Error,
        ),
        (
            "clear-no-robot",
            vec!["clear", "--scene", "@scene/interpenetrating.toml"],
            "garbage",
            Error,
        ),
        (
            "bench-clear-suite-unknown",
            vec!["bench", "clear", "--suite", "tornado", "--scenes", "1"],
            "malformed",
            Error,
        ),
        (
            "bench-frames-layout-unknown",
            vec!["bench", "frames", "--cloud", cloud, "--layout", "diagonal"],
            "malformed",
            Error,
        ),
        (
            "unknown-flag",
            vec!["perceive", "--colud", cloud],
            "malformed",
            Usage,
        ),
        ("unknown-command", vec!["teleport"], "malformed", Usage),
    ] {
        c.case(&format!("flag-{name}"), class, expect, &args);
    }
}
