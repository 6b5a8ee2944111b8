//! Scene files: shapes, sizes, masses, poses, names, robots, cameras.

use super::*;

pub(super) fn scenes(c: &mut Corpus) {
    let clutter = read_repo("scenes/clutter.toml");
    let settle = |c: &mut Corpus, name: &str, class, expect, text: String| {
        let f = c.file(&format!("scene/{name}.toml"), text);
        c.case(
            &format!("scene-{name}"),
            class,
            expect,
            &["sim", "settle", "--scene", &f],
        );
    };
    settle(c, "clutter", "garbage", Ok, clutter.clone());
    c.needs("all asleep: true");
    let with = |from: &str, to: &str| {
        assert!(clutter.contains(from), "{from}");
        clutter.replacen(from, to, 1)
    };
    let start = clutter.find("[floor]").unwrap();
    for cut in [0, 3, 40, 300, 700] {
        let mut t = clutter[..start + cut].to_string();
        t.push_str("[[object");
        settle(c, &format!("cut-{cut}"), "malformed", Error, t);
    }
    let red_box = "shape = { box = [0.05, 0.08, 0.10] }";
    for (name, text, class) in [
        (
            "box-negative",
            with(red_box, "shape = { box = [-0.05, 0.08, 0.10] }"),
            "garbage",
        ),
        (
            "box-zero",
            with(red_box, "shape = { box = [0.0, 0.08, 0.10] }"),
            "garbage",
        ),
        (
            "box-1e300",
            with(red_box, "shape = { box = [1e300, 0.08, 0.10] }"),
            "odd-legal",
        ),
        (
            "box-1e-300",
            with(red_box, "shape = { box = [1e-300, 0.08, 0.10] }"),
            "garbage",
        ),
        (
            "box-nan",
            with(red_box, "shape = { box = [nan, 0.08, 0.10] }"),
            "garbage",
        ),
        (
            "box-inf",
            with(red_box, "shape = { box = [inf, 0.08, 0.10] }"),
            "garbage",
        ),
        (
            "box-short",
            with(red_box, "shape = { box = [0.05, 0.08] }"),
            "malformed",
        ),
        (
            "shape-unknown",
            with(red_box, "shape = { torus = [0.05, 0.08] }"),
            "malformed",
        ),
        (
            "prism-bowtie",
            with(
                red_box,
                r#"shape = { prism = { outline = [[0.0, 0.0], [0.04, 0.04], [0.04, 0.0], [0.0, 0.02]], length = 0.1 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-two-vertices",
            with(
                red_box,
                r#"shape = { prism = { outline = [[0.0, 0.0], [0.04, 0.0]], length = 0.1 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-collinear",
            with(
                red_box,
                r#"shape = { prism = { outline = [[0.0, 0.0], [0.02, 0.0], [0.04, 0.0]], length = 0.1 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-nan",
            with(
                red_box,
                r#"shape = { prism = { outline = [[0.0, 0.0], [nan, 0.0], [0.0, 0.04]], length = 0.1 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-1e300",
            with(
                red_box,
                r#"shape = { prism = { outline = [[0.0, 0.0], [1e300, 0.0], [0.0, 0.04]], length = 0.1 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-1e-300",
            with(
                red_box,
                r#"shape = { prism = { outline = [[0.0, 0.0], [1e-300, 0.0], [0.0, 1e-300]], length = 0.1 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-length-zero",
            with(
                red_box,
                r#"shape = { prism = { outline = [[-0.025, -0.04], [0.025, -0.04], [0.0, 0.04]], length = 0.0 } }"#,
            ),
            "garbage",
        ),
        (
            "prism-outline-word",
            with(
                red_box,
                r#"shape = { prism = { outline = "triangle", length = 0.1 } }"#,
            ),
            "malformed",
        ),
        (
            "mass-1e300",
            with("mass = 0.2\ncolor = [0.85", "mass = 1e300\ncolor = [0.85"),
            "garbage",
        ),
        (
            "mass-1e-300",
            with("mass = 0.2\ncolor = [0.85", "mass = 1e-300\ncolor = [0.85"),
            "garbage",
        ),
        (
            "mass-zero",
            with("mass = 0.2\ncolor = [0.85", "mass = 0.0\ncolor = [0.85"),
            "garbage",
        ),
        (
            "mass-negative",
            with("mass = 0.2\ncolor = [0.85", "mass = -1.0\ncolor = [0.85"),
            "garbage",
        ),
        (
            "mass-word",
            with(
                "mass = 0.2\ncolor = [0.85",
                "mass = \"heavy\"\ncolor = [0.85",
            ),
            "malformed",
        ),
        (
            "pose-nan",
            with("xyz = [0.52, -0.20, 0.771]", "xyz = [nan, -0.20, 0.771]"),
            "garbage",
        ),
        (
            "pose-1e300",
            with("xyz = [0.52, -0.20, 0.771]", "xyz = [1e300, -0.20, 0.771]"),
            "garbage",
        ),
        (
            "pose-short",
            with("xyz = [0.52, -0.20, 0.771]", "xyz = [0.52]"),
            "malformed",
        ),
        (
            "rpy-inf",
            with("rpy = [0.0, 0.0, 0.3]", "rpy = [0.0, 0.0, inf]"),
            "garbage",
        ),
        (
            "duplicate-name",
            with("name = \"box_green\"", "name = \"box_red\""),
            "garbage",
        ),
        (
            "empty-name",
            with("name = \"box_green\"", "name = \"\""),
            "garbage",
        ),
        (
            "furniture-size-negative",
            with("size = [0.7, 1.0, 0.72]", "size = [0.7, -1.0, 0.72]"),
            "garbage",
        ),
        (
            "furniture-size-1e300",
            with("size = [0.7, 1.0, 0.72]", "size = [0.7, 1e300, 0.72]"),
            "garbage",
        ),
        (
            "furniture-kind-unknown",
            with("kind = \"table\"", "kind = \"sofa\""),
            "malformed",
        ),
        (
            "floor-size-zero",
            with("size = [8.0, 8.0]", "size = [0.0, 8.0]"),
            "garbage",
        ),
        (
            "floor-size-nan",
            with("size = [8.0, 8.0]", "size = [nan, 8.0]"),
            "garbage",
        ),
        (
            "unknown-key",
            with(
                "mass = 0.2\ncolor = [0.85",
                "mass = 0.2\nmas = 3\ncolor = [0.85",
            ),
            "garbage",
        ),
        (
            "friction-negative",
            with(
                "mass = 0.2\ncolor = [0.85",
                "mass = 0.2\nfriction = -1.0\ncolor = [0.85",
            ),
            "garbage",
        ),
        (
            "color-nan",
            with("color = [0.85, 0.2, 0.2]", "color = [nan, 0.2, 0.2]"),
            "garbage",
        ),
        (
            "color-huge",
            with("color = [0.85, 0.2, 0.2]", "color = [1e300, 0.2, 0.2]"),
            "garbage",
        ),
        (
            "robot-unknown",
            clutter.replacen("urdf = \"wam\"", "urdf = \"hal9000\"", 1),
            "garbage",
        ),
        (
            "robot-joint-unknown",
            clutter.replacen("wam_joint2 = -1.9", "wam_joint99 = -1.9", 1),
            "garbage",
        ),
        (
            "robot-joint-nan",
            clutter.replacen("wam_joint2 = -1.9", "wam_joint2 = nan", 1),
            "garbage",
        ),
        (
            "robot-joint-1e300",
            clutter.replacen("wam_joint2 = -1.9", "wam_joint2 = 1e300", 1),
            "garbage",
        ),
        (
            "integer-huge",
            with(
                "mass = 0.2\ncolor = [0.85",
                "mass = 9223372036854775807\ncolor = [0.85",
            ),
            "overflow",
        ),
        (
            "not-utf8",
            String::from_utf8_lossy(b"[floor]\nsize = [8.0, \xff8.0]\n").into_owned(),
            "malformed",
        ),
        ("toml-not-table", "= 3".to_string(), "malformed"),
    ] {
        settle(c, name, class, Error, text);
    }
    let circle: Vec<String> = (0..300)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 300.0;
            format!("[{:.6}, {:.6}]", 0.03 * t.cos(), 0.03 * t.sin())
        })
        .collect();
    let many = format!(
        "shape = {{ prism = {{ outline = [{}], length = 0.1 }} }}",
        circle.join(", ")
    );
    settle(
        c,
        "prism-300-vertices",
        "unbounded",
        Error,
        with(red_box, &many),
    );
    settle(
        c,
        "prism-wedge",
        "odd-legal",
        Ok,
        with(
            red_box,
            r#"shape = { prism = { outline = [[-0.025, -0.04], [0.025, -0.04], [0.0, 0.04]], length = 0.1 } }"#,
        ),
    );
    c.needs("all asleep: true");
    settle(
        c,
        "prism-notched",
        "odd-legal",
        Ok,
        with(
            red_box,
            r#"shape = { prism = { outline = [[0.025, -0.04], [0.025, 0.04], [-0.025, 0.04], [-0.025, -0.04], [-0.012, -0.04], [0.0, -0.028], [0.012, -0.04]], length = 0.1 } }"#,
        ),
    );
    c.needs("all asleep: true");
    // Cameras: sizes that wrap, fields of view, degenerate look-at.
    let camera = |w: &str, h: &str, extra: &str| {
        format!(
            "[floor]\nsize = [4.0, 4.0]\n\n[[camera]]\nname = \"cam\"\nlook_at = {{ eye = [1.0, 0.0, 1.0], target = [0.0, 0.0, 0.0] }}\nwidth = {w}\nheight = {h}\n{extra}"
        )
    };
    for (name, text, class) in [
        (
            "camera-wraps",
            camera("4294967296", "4294967296", ""),
            "overflow",
        ),
        ("camera-huge", camera("100000", "100000", ""), "overflow"),
        ("camera-zero", camera("0", "480", ""), "garbage"),
        ("camera-negative", camera("-640", "480", ""), "malformed"),
        (
            "camera-fov-zero",
            camera("64", "48", "hfov_deg = 0.0\n"),
            "garbage",
        ),
        (
            "camera-fov-180",
            camera("64", "48", "hfov_deg = 180.0\n"),
            "garbage",
        ),
        (
            "camera-range-reversed",
            camera("64", "48", "min_range = 5.0\nmax_range = 1.0\n"),
            "garbage",
        ),
        (
            "camera-noise-nan",
            camera("64", "48", "noise_coefficient = nan\n"),
            "garbage",
        ),
        (
            "camera-outliers-2",
            camera("64", "48", "outlier_fraction = 2.0\n"),
            "garbage",
        ),
    ] {
        let f = c.file(&format!("scene/{name}.toml"), text);
        c.case(
            &format!("scene-{name}"),
            class,
            Error,
            &["sim", "capture", "--scene", &f, "--out", "out.pcd"],
        );
    }
    let degenerate = "[floor]\nsize = [4.0, 4.0]\n\n[[camera]]\nname = \"cam\"\nlook_at = { eye = [1.0, 0.0, 1.0], target = [1.0, 0.0, 1.0] }\nwidth = 64\nheight = 48\n";
    let f = c.file("scene/camera-eye-is-target.toml", degenerate);
    c.case(
        "scene-camera-eye-is-target",
        "garbage",
        Error,
        &["sim", "capture", "--scene", &f, "--out", "out.pcd"],
    );
    let vertical = "[floor]\nsize = [4.0, 4.0]\n\n[[camera]]\nname = \"cam\"\nlook_at = { eye = [0.0, 0.0, 2.0], target = [0.0, 0.0, 0.0] }\nwidth = 64\nheight = 48\n";
    let f = c.file("scene/camera-straight-down.toml", vertical);
    c.case(
        "scene-camera-straight-down",
        "odd-legal",
        Ok,
        &["sim", "capture", "--scene", &f, "--out", "out.pcd"],
    );
    // Meshes referenced by scenes.
    let mesh_object = |file: &str| {
        format!(
            "[floor]\nsize = [4.0, 4.0]\n\n[[object]]\nname = \"m\"\nshape = {{ mesh = {{ path = \"{file}\" }} }}\npose = {{ xyz = [0.0, 0.0, 0.5] }}\nmass = 0.2\n"
        )
    };
    for (name, file, class) in [
        ("mesh-missing", "no-such.obj", "special-file"),
        ("mesh-dev-zero", "/dev/zero", "special-file"),
        ("mesh-coplanar", "../mesh/coplanar.obj", "garbage"),
        ("mesh-nan", "../mesh/vertex-nan.obj", "garbage"),
        ("mesh-escapes", "../../../../../../etc/passwd", "garbage"),
    ] {
        settle(c, name, class, Error, mesh_object(file));
    }
    settle(
        c,
        "mesh-cube",
        "odd-legal",
        Ok,
        mesh_object("../mesh/cube.obj").replace(
            "path = \"../mesh/cube.obj\" }",
            "path = \"../mesh/cube.obj\", scale = [0.1, 0.1, 0.1] }",
        ),
    );
    // 3,000 boxes: a legal scene, bounded work (or refused as too large).
    let mut many = String::from("[floor]\nsize = [40.0, 40.0]\n");
    for i in 0..3000 {
        let _ = write!(
            many,
            "\n[[object]]\nname = \"b{i}\"\nshape = {{ box = [0.05, 0.05, 0.05] }}\npose = {{ xyz = [{}, {}, 0.025] }}\nmass = 0.1\n",
            (i % 60) as f64 * 0.3 - 9.0,
            (i / 60) as f64 * 0.3 - 7.5
        );
    }
    settle(c, "boxes-3000", "unbounded", Ok, many);
    // Two boxes in the same place: settles apart or is refused, never NaN.
    let overlap = "[floor]\nsize = [4.0, 4.0]\n\n[[object]]\nname = \"a\"\nshape = { box = [0.1, 0.1, 0.1] }\npose = { xyz = [0.0, 0.0, 0.05] }\nmass = 0.2\n\n[[object]]\nname = \"b\"\nshape = { box = [0.1, 0.1, 0.1] }\npose = { xyz = [0.0, 0.0, 0.05] }\nmass = 0.2\n";
    settle(c, "interpenetrating", "odd-legal", Error, overlap.into());
    c.needs("overlap");
    // sim do / spawn with hostile values.
    let f = "@scene/clutter.toml";
    for (name, args, class, expect) in [
        (
            "do-move-nan",
            vec!["sim", "do", "--scene", f, "--cmd", "move box_red nan 0 1"],
            "garbage",
            Error,
        ),
        (
            "do-move-1e300",
            vec!["sim", "do", "--scene", f, "--cmd", "move box_red 1e300 0 1"],
            "garbage",
            Error,
        ),
        (
            "do-move-unknown",
            vec!["sim", "do", "--scene", f, "--cmd", "move ghost 0 0 1"],
            "malformed",
            Error,
        ),
        (
            "do-spawn-short",
            vec!["sim", "do", "--scene", f, "--cmd", "spawn can"],
            "malformed",
            Error,
        ),
        (
            "do-spawn-dup",
            vec![
                "sim",
                "do",
                "--scene",
                f,
                "--cmd",
                "spawn can box_red 0 0 1",
            ],
            "garbage",
            Error,
        ),
        (
            "do-unknown",
            vec!["sim", "do", "--scene", f, "--cmd", "explode"],
            "malformed",
            Error,
        ),
        (
            "do-long",
            vec!["sim", "do", "--scene", f, "--cmd", &"x".repeat(100_000)],
            "garbage",
            Error,
        ),
        (
            "spawn-at-nan",
            vec![
                "sim", "spawn", "--scene", f, "--model", "can", "--name", "c2", "--at", "nan", "0",
                "1",
            ],
            "garbage",
            Usage,
        ),
        (
            "spawn-at-1e300",
            vec![
                "sim", "spawn", "--scene", f, "--model", "can", "--name", "c2", "--at", "1e300",
                "0", "1",
            ],
            "garbage",
            Error,
        ),
        (
            "spawn-model-unknown",
            vec![
                "sim", "spawn", "--scene", f, "--model", "ufo", "--name", "c2", "--at", "0", "0",
                "1",
            ],
            "malformed",
            Error,
        ),
        (
            "snapshot-eye-nan",
            vec![
                "sim", "snapshot", "--scene", f, "--png", "s.png", "--eye", "nan", "0", "1",
            ],
            "garbage",
            Usage,
        ),
        (
            "snapshot-eye-target",
            vec![
                "sim", "snapshot", "--scene", f, "--png", "s.png", "--eye", "1", "1", "1",
                "--target", "1", "1", "1",
            ],
            "garbage",
            Error,
        ),
        (
            "snapshot-wraps",
            vec![
                "sim",
                "snapshot",
                "--scene",
                f,
                "--png",
                "s.png",
                "--width",
                "4294967296",
                "--height",
                "4294967296",
            ],
            "overflow",
            Usage,
        ),
        (
            "snapshot-huge",
            vec![
                "sim", "snapshot", "--scene", f, "--png", "s.png", "--width", "16384", "--height",
                "16384",
            ],
            "overflow",
            Error,
        ),
        (
            "snapshot-zero",
            vec![
                "sim", "snapshot", "--scene", f, "--png", "s.png", "--width", "0",
            ],
            "odd-legal",
            Usage,
        ),
        (
            "snapshot-tiny",
            vec![
                "sim", "snapshot", "--scene", f, "--png", "s.png", "--width", "1", "--height", "1",
            ],
            "odd-legal",
            Ok,
        ),
        (
            "capture-camera-unknown",
            vec![
                "sim", "capture", "--scene", f, "--camera", "nope", "--out", "o.pcd",
            ],
            "malformed",
            Error,
        ),
        (
            "capture-out-folder",
            vec!["sim", "capture", "--scene", f, "--out", "/"],
            "special-file",
            Error,
        ),
        (
            "capture-out-unwritable",
            vec!["sim", "capture", "--scene", f, "--out", "/proc/nope/x.pcd"],
            "special-file",
            Error,
        ),
        (
            "capture-out-disk-full",
            vec!["sim", "capture", "--scene", f, "--out", "/dev/full"],
            "special-file",
            Error,
        ),
        (
            "stable-poses-nothing",
            vec!["stable-poses"],
            "malformed",
            Usage,
        ),
        (
            "bench-frames-huge",
            vec![
                "sim",
                "bench",
                "--scene",
                f,
                "--frames",
                "18446744073709551615",
            ],
            "overflow",
            Usage,
        ),
    ] {
        c.case(&format!("scene-{name}"), class, expect, &args);
    }
}
