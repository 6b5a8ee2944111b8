//! Heavy but legal inputs (issue 34's third kind): a scan-sized mesh as a scene object,
//! ten thousand objects to settle, a PDDL problem of 100,000 objects — each answered
//! within the corpus's 20 s and 1 GiB — and `--time-limit`, the deadline every command
//! honours, ending a run that would take longer.

use super::*;
use std::fmt::Write as _;

/// A closed sphere of `2 · n²` triangles (radius 5 cm, resting on z = 0) as binary STL.
fn sphere_stl(n: usize) -> Vec<u8> {
    let point = |i: usize, j: usize| {
        let (th, ph) = (
            std::f32::consts::PI * i as f32 / n as f32,
            std::f32::consts::TAU * j as f32 / n as f32,
        );
        [
            0.05 * th.sin() * ph.cos(),
            0.05 * th.sin() * ph.sin(),
            0.05 * th.cos() + 0.05,
        ]
    };
    let mut out = vec![0u8; 80];
    out.extend(((2 * n * n) as u32).to_le_bytes());
    for i in 0..n {
        for j in 0..n {
            let [a, b, c, d] = [
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            ];
            for t in [[a, b, c], [a, c, d]] {
                out.extend([0f32; 3].iter().flat_map(|v| v.to_le_bytes()));
                out.extend(t.iter().flatten().flat_map(|v| v.to_le_bytes()));
                out.extend([0u8; 2]);
            }
        }
    }
    out
}

pub(super) fn heavy(c: &mut Corpus) {
    c.file("heavy/sphere.stl", sphere_stl(500));
    let scene = c.file(
        "heavy/sphere-scene.toml",
        "[floor]\nsize = [4.0, 4.0]\n\n[[object]]\nname = \"ball\"\nshape = { mesh = { path = \"sphere.stl\" } }\npose = { xyz = [0.0, 0.0, 0.01] }\n",
    );
    c.case(
        "heavy-mesh-500k-triangles",
        "unbounded",
        Ok,
        &["sim", "settle", "--scene", &scene],
    );
    c.needs("outermost");
    let sphere = c.root.join("heavy/sphere.stl").display().to_string();
    c.case(
        "heavy-mesh-500k-stable",
        "unbounded",
        Ok,
        &["stable-poses", "--mesh", &sphere],
    );
    c.needs("stable poses");
    let mut many = String::from("[floor]\nsize = [40.0, 40.0]\n");
    for i in 0..10_000 {
        let (x, y) = ((i % 100) as f64 * 0.3 - 15.0, (i / 100) as f64 * 0.3 - 15.0);
        write!(
            many,
            "\n[[object]]\nname = \"o{i}\"\nshape = {{ box = [0.1, 0.1, 0.1] }}\npose = {{ xyz = [{x:.2}, {y:.2}, 0.2] }}\n"
        )
        .unwrap();
    }
    let many = c.file("heavy/objects-10000.toml", many);
    c.case(
        "heavy-settle-10000-objects",
        "unbounded",
        Ok,
        &["sim", "settle", "--scene", &many],
    );
    c.needs("all asleep: true");
    c.case(
        "heavy-settle-10000-time-limit",
        "unbounded",
        Error,
        &["sim", "settle", "--scene", &many, "--time-limit", "0.5"],
    );
    c.needs("time limit of 0.5 s");
    let objects: String = (0..100_000).map(|i| format!(" o{i}")).collect();
    let problem = c.file(
        "heavy/objects-100000.pddl",
        format!(
            "(define (problem big) (:domain tablewclear) (:objects{objects} - obj) (:init)\n\
             (:goal (and (removed o1) (removed o99999))))\n"
        ),
    );
    let domain = repo("pddl/tablewclear-domain.pddl");
    c.case(
        "heavy-pddl-100000-objects",
        "unbounded",
        Ok,
        &["plan", &domain, &problem, "--timeout", "10"],
    );
    c.needs("optimal plan");
    for (name, args, needle) in [
        (
            "plan-generate",
            vec![
                "plan",
                "generate",
                "--objects",
                "10000",
                "--time-limit",
                "0.3",
            ],
            "time limit of 0.3 s",
        ),
        (
            "clear",
            vec!["clear", "--scene", "clutter", "--time-limit", "0.3"],
            "time limit of 0.3 s",
        ),
        (
            "bench-clear",
            vec!["bench", "clear", "--scenes", "50", "--time-limit", "1"],
            "time limit of 1 s",
        ),
        (
            "motion-bench",
            vec![
                "motion",
                "bench",
                "--problems",
                "100000",
                "--time-limit",
                "1",
            ],
            "time limit of 1 s",
        ),
    ] {
        c.case(&format!("time-limit-{name}"), "unbounded", Error, &args);
        c.needs(needle);
    }
    for (name, value) in [
        ("zero", "0"),
        ("negative", "-1"),
        ("nan", "nan"),
        ("huge", "1e300"),
    ] {
        c.case(
            &format!("time-limit-{name}"),
            "garbage",
            Usage,
            &["sim", "settle", "--scene", "clutter", "--time-limit", value],
        );
        c.needs("--time-limit");
    }
}
