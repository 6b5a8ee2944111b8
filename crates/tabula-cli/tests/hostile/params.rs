//! Parameter files of every task.

use super::*;

pub(super) fn params(c: &mut Corpus) {
    // Motion parameters through `tabula arm --dry-run`: the defaults written out load,
    // a misspelt key is named with the valid ones, and goals say what is wrong with them.
    let scene = repo("scenes/clutter.toml");
    let joints = ["0.3", "-0.5", "0", "2.0", "0", "0.4", "0"];
    for (name, toml, class, expect, needle) in [
        (
            "motion-defaults",
            "cartesian_tolerance = 0.0\n[world]\npadding = 0.01\n",
            "odd-legal",
            Ok,
            "move-joints",
        ),
        (
            "motion-unknown-key",
            "[world]\npaddin = 0.01\n",
            "garbage",
            Error,
            "expected one of",
        ),
        (
            "motion-tolerance-negative",
            "cartesian_tolerance = -0.1\n",
            "garbage",
            Error,
            "cartesian_tolerance",
        ),
    ] {
        let f = c.file(&format!("params/{name}.toml"), toml);
        let mut args = vec![
            "arm",
            "--scene",
            &scene,
            "--dry-run",
            "--params",
            &f,
            "--json",
            "move-joints",
        ];
        args.extend(joints);
        c.case(&format!("params-{name}"), class, expect, &args);
        c.needs(needle);
    }
    let mut beyond = vec!["arm", "--scene", &scene, "--dry-run", "move-joints", "9"];
    beyond.extend(&joints[1..]);
    c.case("arm-joint-beyond-limit", "garbage", NoSolution, &beyond);
    c.needs("outside its limits");
    c.case(
        "ik-solve-no-pose",
        "malformed",
        Usage,
        &["ik", "solve", "--robot", "wam"],
    );
    c.needs("--pose");
    for seed in ["18446744073709551615", "9007199254740992"] {
        c.case(
            &format!("seed-{seed}"),
            "overflow",
            Usage,
            &["plan", "generate", "--objects", "3", "--seed", seed],
        );
        c.needs("not a seed");
    }
    let cloud = "@cloud/valid-binary.pcd";
    for (name, toml, class) in [
        ("nan", "min_height = nan", "garbage"),
        ("inf", "cluster_tolerance = inf", "garbage"),
        ("neg-inf", "[surfaces]\nmax_tilt = -inf", "garbage"),
        ("huge", "cluster_tolerance = 1e300", "garbage"),
        (
            "integer-huge",
            "min_object_points = 9223372036854775807",
            "overflow",
        ),
        (
            "count-1e7",
            "[surfaces.ransac]\nmax_iterations = 10000001",
            "unbounded",
        ),
        ("negative-count", "min_object_points = -5", "malformed"),
        ("unknown-key", "min_heigth = 0.01", "garbage"),
        ("unknown-table", "[surfacez]\nmax_tilt = 0.1", "garbage"),
        ("wrong-type", "min_height = \"low\"", "malformed"),
        ("not-toml", "min_height: 0.01", "malformed"),
        ("cluster-zero", "cluster_tolerance = 0.0", "odd-legal"),
        ("cluster-negative", "cluster_tolerance = -0.01", "garbage"),
        ("cell-zero", "[surfaces]\ncell = 0.0", "odd-legal"),
        ("cell-negative", "[surfaces]\ncell = -0.04", "garbage"),
        ("window-zero", "[normals]\nwindow = 0", "odd-legal"),
        ("k-zero", "[normals]\nk = 0", "odd-legal"),
        ("mean-k-zero", "[outliers]\nmean_k = 0", "odd-legal"),
        ("std-mul-negative", "[outliers]\nstd_mul = -1.0", "garbage"),
        (
            "ransac-threshold-zero",
            "[surfaces.ransac]\nthreshold = 0.0",
            "odd-legal",
        ),
        (
            "ransac-confidence-2",
            "[surfaces.ransac]\nconfidence = 2.0",
            "garbage",
        ),
        (
            "height-range-reversed",
            "[surfaces]\nheight_range = [2.0, 0.1]",
            "garbage",
        ),
        (
            "height-range-short",
            "[surfaces]\nheight_range = [2.0]",
            "malformed",
        ),
        ("stride-zero", "[surfaces]\nstride = 0", "odd-legal"),
        ("concavity-step-zero", "concavity_step = 0", "odd-legal"),
        ("max-planes-zero", "[surfaces]\nmax_planes = 0", "odd-legal"),
    ] {
        let p = c.file(&format!("params/tabletop-{name}.toml"), toml);
        // Zero or negative sizes and windows are refused with the key named.
        c.case(
            &format!("params-tabletop-{name}"),
            class,
            Error,
            &["perceive", "--cloud", cloud, "--params", &p],
        );
    }
    let p = c.file(
        "params/tabletop-valid.toml",
        "min_height = 0.01\n[surfaces]\nmax_tilt = 0.2\n",
    );
    c.case(
        "params-tabletop-valid",
        "garbage",
        Ok,
        &["perceive", "--cloud", cloud, "--params", &p],
    );
    c.needs("table:");
    let p = c.file("params/empty.toml", "");
    c.case(
        "params-empty",
        "odd-legal",
        Ok,
        &["perceive", "--cloud", cloud, "--params", &p],
    );
    c.needs("table:");
    // IK configuration files.
    for (name, toml, class) in [
        ("timeout-inf", "[numeric_ik]\ntimeout_s = inf", "odd-legal"),
        (
            "timeout-1e300",
            "[numeric_ik]\ntimeout_s = 1e300",
            "odd-legal",
        ),
        (
            "timeout-negative",
            "[numeric_ik]\ntimeout_s = -1.0",
            "garbage",
        ),
        (
            "tolerance-nan",
            "[numeric_ik]\nposition_tolerance = nan",
            "garbage",
        ),
        (
            "tolerance-zero",
            "[numeric_ik]\nposition_tolerance = 0.0",
            "garbage",
        ),
        (
            "damping-negative",
            "[numeric_ik]\ndamping = -1.0",
            "garbage",
        ),
        ("unknown-table", "[numerik]\ndamping = 1.0", "garbage"),
    ] {
        let p = c.file(&format!("params/ik-{name}.toml"), toml);
        c.case(
            &format!("params-ik-{name}"),
            class,
            Error,
            &[
                "ik", "solve", "--robot", "wam", "--solver", "numeric", "--config", &p, "--pose",
                "0.5", "0", "0.8", "0", "0", "0",
            ],
        );
    }
    let p = c.file(
        "params/ik-attempts-huge.toml",
        "[numeric_ik]\nmax_attempts = 10000000",
    );
    c.case(
        "params-ik-attempts-huge",
        "unbounded",
        Ok,
        &[
            "ik", "solve", "--robot", "wam", "--solver", "numeric", "--config", &p, "--pose",
            "0.5", "0", "0.8", "0", "0", "0",
        ],
    );
    // Task parameter files: refused before any simulation starts.
    for (cmd, scene) in [
        ("clear", "scenes/clutter.toml"),
        ("place", "scenes/pr2_holding.toml"),
    ] {
        for (name, toml, class) in [
            ("nan", "[motion]\nmax_acceleration = nan", "garbage"),
            (
                "timeout-inf",
                "[motion.planner]\ntimeout_s = inf",
                "odd-legal",
            ),
            (
                "timeout-zero",
                "[motion.planner]\ntimeout_s = 0.0",
                "garbage",
            ),
            ("unknown", "lift_heigth = 0.2", "garbage"),
            (
                "velocity-zero",
                "[motion]\nvelocity_scaling = 0.0",
                "garbage",
            ),
            ("dt-zero", "[motion]\nsample_dt = 0.0", "unbounded"),
        ] {
            let p = c.file(&format!("params/{cmd}-{name}.toml"), toml);
            c.case(
                &format!("params-{cmd}-{name}"),
                class,
                Error,
                &[cmd, "--scene", &repo(scene), "--params", &p],
            );
        }
    }
}
