//! Every number of every parameter file, tiny, negative and huge (issue 34's first
//! kind: values that pass a check and blow up later). The keys come from the commands'
//! own `--print-params`, so a key added later is covered without touching this file.
//! A value is refused with its key named, or — where the table below says the value is
//! legal — the command answers normally within the corpus's time and memory.

use super::*;
use std::process::Command;

/// A command's printed parameters: (dotted key, is an integer), arrays and strings left
/// out (their own cases are elsewhere).
fn numeric_keys(command: &[&str]) -> Vec<(String, bool)> {
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(command)
        .arg("--print-params")
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "{command:?} --print-params failed");
    let table: toml::Table = String::from_utf8(out.stdout).unwrap().parse().unwrap();
    let mut keys = Vec::new();
    fn walk(prefix: &str, t: &toml::Table, keys: &mut Vec<(String, bool)>) {
        for (k, v) in t {
            let key = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                toml::Value::Float(_) => keys.push((key, false)),
                toml::Value::Integer(_) => keys.push((key, true)),
                toml::Value::Table(inner) => walk(&key, inner, keys),
                _ => {}
            }
        }
    }
    walk("", &table, &mut keys);
    assert!(keys.len() >= 5, "{command:?}: only {} keys", keys.len());
    keys
}

/// `key = value` inside its table.
fn one_key(key: &str, value: &str) -> String {
    match key.rsplit_once('.') {
        Some((table, k)) => format!("[{table}]\n{k} = {value}\n"),
        None => format!("{key} = {value}\n"),
    }
}

/// A family: the command (before `--params`), what follows it, and for each value the
/// keys at which it is legal with the answer it then gets (success; "no solution"; an
/// error that is the answer for that input, as "no horizontal surface"). Every other
/// key must refuse the value naming itself.
struct Family<'a> {
    name: &'a str,
    command: Vec<String>,
    after: Vec<String>,
    values: &'a [Value<'a>],
}

/// A value tried at every key: its label, its text, and the keys where it is legal
/// with the answer they get.
type Value<'a> = (&'a str, &'a str, &'a [(&'a str, Expect)]);

/// Each key legal with success.
fn succeed<'a>(keys: &[&'a str]) -> Vec<(&'a str, Expect)> {
    keys.iter().map(|&k| (k, Ok)).collect()
}

fn family(c: &mut Corpus, f: &Family<'_>) {
    let printed: Vec<&str> = f.command.iter().map(String::as_str).collect();
    for (key, integer) in numeric_keys(&printed[..1]) {
        for &(label, value, legal) in f.values {
            // An integer key given a float is a type error naming the key, as wanted.
            let legal = legal
                .iter()
                .find(|(k, _)| *k == key)
                .map(|&(_, e)| e)
                .filter(|_| !(integer && value.contains(['e', '.'])));
            let name = format!("numbers/{}-{}-{label}", f.name, key.replace('.', "-"));
            let file = c.file(&format!("{name}.toml"), one_key(&key, value));
            let mut args: Vec<&str> = f.command.iter().map(String::as_str).collect();
            args.extend(["--params", &file]);
            args.extend(f.after.iter().map(String::as_str));
            let class = if label == "tiny" {
                "odd-legal"
            } else {
                "garbage"
            };
            c.case(&name, class, legal.unwrap_or(Error), &args);
            if legal.is_none() {
                c.needs(key.rsplit('.').next().unwrap());
            }
        }
    }
}

pub(super) fn numbers(c: &mut Corpus) {
    let strings = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let cloud = c.root.join("cloud/valid-binary.pcd").display().to_string();
    let mesh = c.root.join("mesh/cube.obj").display().to_string();
    // Motion: through a dry run of the WAM (a third of a second each).
    family(
        c,
        &Family {
            name: "motion",
            command: strings(&["arm", "--scene", "clutter", "--dry-run"]),
            after: strings(&["move-joints", "0.3", "-0.5", "0", "2.0", "0", "0.4", "0"]),
            values: &[
                (
                    "tiny",
                    "1e-300",
                    &succeed(&[
                        "cartesian_tolerance",
                        "world.padding",
                        "world.always_fraction",
                    ]),
                ),
                ("negative", "-1", &[]),
                (
                    "huge",
                    "1e6",
                    &[
                        ("cartesian_tolerance", Ok),
                        ("planner.timeout_s", Ok),
                        // A kilometre of padding touches the stand: no start.
                        ("world.padding", NoSolution),
                    ],
                ),
            ],
        },
    );
    // Perception on a small frame: most thresholds are legal anywhere (the answer is
    // "no objects" or one big one); sizes that divide or key a grid are bounded.
    let tabletop_any = [
        "min_height",
        "cluster_tolerance",
        "cluster_range_gain",
        "step_tolerance",
        "min_object_height",
        "min_stacked_height",
        "top_band",
        "support_reach",
        "rest_tolerance",
        "max_object_extent",
        "partial_gap",
        "outliers.std_mul",
        "surfaces.max_slice_ratio",
        "surfaces.refine_threshold",
        "surfaces.ransac.threshold",
        "normals.depth_edge_factor",
    ];
    // A surface this strict or this big is not in the frame: that is the answer.
    let no_surface = |k| (k, Error);
    let mut tiny = succeed(&tabletop_any);
    tiny.extend(succeed(&[
        "concavity_tolerance",
        "surfaces.max_tilt",
        "surfaces.min_plane_fraction",
        "surfaces.stop_fraction",
        "surfaces.min_area",
        "surfaces.min_inscribed_radius",
        "surfaces.min_flat_fraction",
        "surfaces.ransac.max_normal_angle",
    ]));
    tiny.push(no_surface("surfaces.flat_normal_angle"));
    let mut huge = succeed(&tabletop_any);
    huge.extend([
        no_surface("surfaces.min_area"),
        no_surface("surfaces.min_inscribed_radius"),
    ]);
    family(
        c,
        &Family {
            name: "perceive",
            command: strings(&["perceive", "--cloud", &cloud]),
            after: Vec::new(),
            values: &[
                ("tiny", "1e-300", &tiny),
                ("negative", "-1", &[]),
                ("huge", "1e6", &huge),
            ],
        },
    );
    family(
        c,
        &Family {
            name: "stable",
            command: strings(&["stable-poses", "--mesh", &mesh]),
            after: Vec::new(),
            values: &[
                (
                    "tiny",
                    "1e-300",
                    &succeed(&[
                        "relaxation_angle",
                        "coplanar_angle",
                        "contact_tolerance",
                        "cloud_contact_tolerance",
                        "min_topple_deg",
                    ]),
                ),
                ("negative", "-1", &[]),
                (
                    "huge",
                    "1e6",
                    &succeed(&["contact_tolerance", "cloud_contact_tolerance"]),
                ),
            ],
        },
    );
    // The jobs: a negative length, angle or count is refused before the scene loads.
    for (name, command) in [
        ("clear", vec!["clear", "--scene", "clutter"]),
        ("place", vec!["place", "--scene", "pr2_holding"]),
        ("tidy", vec!["tidy", "--scene", "tidy"]),
        (
            "pick-place",
            vec![
                "pick-place",
                "--scene",
                "golem_shelves",
                "--pick",
                "0.556",
                "-0.663",
                "1.07",
                "--place",
                "0.82",
                "-0.2",
                "1.01",
            ],
        ),
    ] {
        family(
            c,
            &Family {
                name,
                command: strings(&command),
                after: Vec::new(),
                values: &[("negative", "-1", &[])],
            },
        );
    }
}
