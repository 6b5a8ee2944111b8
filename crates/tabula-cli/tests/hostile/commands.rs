//! What a user types and copies: numbers in exponent form, misspelt flags, the printed
//! parameters of every command, the built-in scenes from any folder, zenoh
//! configurations that are devices or garbage, a worker pointed at nothing.

use super::*;

pub(super) fn commands(c: &mut Corpus) {
    let joints = ["0.3", "-5e-1", "0", "2.0", "-0E+0", "4e-1", "0"];
    let mut fk = vec!["ik", "fk", "--robot", "wam", "--joints"];
    fk.extend(joints);
    c.case("cli-negative-exponents", "odd-legal", Ok, &fk);
    c.needs("base_link → wam_tool");
    // The pose the joints above reach, typed in exponent form.
    c.case(
        "cli-negative-exponent-pose",
        "odd-legal",
        Ok,
        &[
            "ik",
            "solve",
            "--robot",
            "wam",
            "--pose",
            "1.92967e-1",
            "5.9692e-2",
            "8.71901e-1",
            "-3.141593e0",
            "1.241593",
            "-2.841593E+0",
        ],
    );
    c.case(
        "cli-negative-exponent-tiny",
        "odd-legal",
        Ok,
        &[
            "ik", "fk", "--robot", "wam", "--joints", "-1e-300", "0", "0", "0", "0", "0", "0",
        ],
    );
    c.case(
        "cli-negative-exponent-huge",
        "garbage",
        Error,
        &[
            "ik", "fk", "--robot", "wam", "--joints", "-1e300", "0", "0", "0", "0", "0", "0",
        ],
    );
    c.needs("outside its limits");
    for (name, args, hint) in [
        ("sceen", vec!["clear", "--sceen", "clutter"], "--scene"),
        ("josn", vec!["perceive", "--josn"], "--json"),
        ("seeds", vec!["plan", "generate", "--seeds", "3"], "--seed"),
        (
            "params-plural",
            vec!["place", "--scene", "pr2_holding", "--param", "x"],
            "--params",
        ),
    ] {
        c.case(&format!("cli-misspelt-{name}"), "malformed", Usage, &args);
        c.needs(&format!("similar argument exists: '{hint}'"));
    }
    for (name, command, needle) in [
        ("place", vec!["place"], "scan_distance"),
        ("clear", vec!["clear"], "decimate"),
        ("tidy", vec!["tidy"], "[grasp]"),
        ("pick-place", vec!["pick-place"], "pregrasp_distance"),
        ("perceive", vec!["perceive"], "cluster_tolerance"),
        ("arm", vec!["arm"], "max_acceleration"),
        ("teleop", vec!["teleop"], "[planner]"),
        ("stable-poses", vec!["stable-poses"], "relaxation_angle"),
        ("motion-plan", vec!["motion", "plan"], "padding = 0.001"),
        ("motion-bench", vec!["motion", "bench"], "padding = 0.001"),
        ("bench-clear", vec!["bench", "clear"], "decimate"),
        ("bench-place", vec!["bench", "place"], "scan_distance"),
    ] {
        let mut args = command.clone();
        args.push("--print-params");
        c.case(&format!("cli-print-params-{name}"), "odd-legal", Ok, &args);
        c.needs(needle);
        // With anything else it is refused: it never runs the job.
        let mut with = command;
        with.extend(["--print-params", "--params", "p.toml"]);
        c.case(
            &format!("cli-print-params-{name}-and-more"),
            "malformed",
            Usage,
            &with,
        );
        c.needs("--print-params");
    }
    c.case("cli-scenes", "odd-legal", Ok, &["scenes"]);
    c.needs("golem_shelves");
    c.case("cli-scenes-print", "odd-legal", Ok, &["scenes", "tidy"]);
    c.needs("[[robot]]");
    c.case(
        "cli-scenes-unknown",
        "garbage",
        Error,
        &["scenes", "kitchen"],
    );
    c.needs("built-in: clutter");
    c.case(
        "cli-builtin-scene",
        "odd-legal",
        Ok,
        &["sim", "settle", "--scene", "clutter"],
    );
    c.needs("cube_top");
    c.case(
        "cli-builtin-scene-toml",
        "odd-legal",
        Ok,
        &["sim", "settle", "--scene", "surfaces.toml"],
    );
    c.case(
        "cli-scene-missing",
        "special-file",
        Error,
        &["sim", "settle", "--scene", "kitchen"],
    );
    c.needs("built-in scenes:");
    c.case(
        "cli-arm-no-subcommand",
        "malformed",
        Usage,
        &["arm", "--scene", "clutter"],
    );
    c.needs("requires a subcommand");
    // zenoh configurations go through the same reader as every other file.
    let garbage = c.file("zenoh/garbage.json5", "{ mode: \"peer\", connect: ");
    let words = c.file("zenoh/words.json5", "this is not json5 at all");
    for (name, config, needle) in [
        ("dev-zero", "/dev/zero", "not a regular file"),
        ("dev-urandom", "/dev/urandom", "not a regular file"),
        ("folder", "/tmp", "not a regular file"),
        ("missing", "/nonexistent/zenoh.json5", "cannot read"),
        ("garbage", garbage.as_str(), "garbage.json5"),
        ("words", words.as_str(), "words.json5"),
    ] {
        c.case(
            &format!("zenoh-config-{name}"),
            "special-file",
            Error,
            &[
                "serve",
                "--scene",
                "clutter",
                "--zenoh-config",
                config,
                "--listen",
                "tcp/127.0.0.1:0",
                "--duration",
                "1",
            ],
        );
        c.needs(needle);
    }
    c.case(
        "worker-closed-port",
        "garbage",
        Error,
        &[
            "worker",
            "--connect",
            "tcp/127.0.0.1:1",
            "--wait",
            "1",
            "--duration",
            "5",
        ],
    );
    c.needs("nothing answered");
    // Scenes that put an object inside the robot, or name one after the robot or a
    // link: refused when the world is built, before anything moves.
    let clutter = read_repo("scenes/clutter.toml");
    let red = "pose = { xyz = [0.52, -0.20, 0.771], rpy = [0.0, 0.0, 0.3] }";
    for (name, from, to, needle) in [
        (
            "object-in-robot",
            red,
            "pose = { xyz = [0.0, 0.0, 1.0] }",
            "would overlap `wam/",
        ),
        (
            "object-named-link",
            "name = \"box_red\"",
            "name = \"wam_link3\"",
            "link",
        ),
        (
            "object-named-robot",
            "name = \"box_red\"",
            "name = \"wam\"",
            "is used twice",
        ),
        (
            "furniture-named-link",
            "name = \"bin\"",
            "name = \"base_link\"",
            "link",
        ),
    ] {
        assert!(clutter.contains(from), "{from}");
        let scene = c.file(&format!("scene/{name}.toml"), clutter.replacen(from, to, 1));
        c.case(
            &format!("scene-{name}"),
            "garbage",
            Error,
            &["sim", "settle", "--scene", &scene],
        );
        c.needs(needle);
    }
}
