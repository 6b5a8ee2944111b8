//! Devices, folders, missing files and huge files given where a file is read.

use super::*;

pub(super) fn special_files(c: &mut Corpus) {
    let dir = c.file("special/folder/.keep", "");
    let folder = dir.trim_end_matches("/.keep").to_string();
    let big = c.root.join("special/big.pcd");
    std::fs::create_dir_all(big.parent().unwrap()).unwrap();
    // A sparse 600 MiB file: over the cloud limit, refused without being read.
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(600 << 20).unwrap();
    let big = "@special/big.pcd".to_string();
    let commands: [(&str, &[&str]); 7] = [
        ("perceive", &["perceive", "--cloud"]),
        ("stable-cloud", &["stable-poses", "--cloud"]),
        ("stable-mesh", &["stable-poses", "--mesh"]),
        ("urdf", &["ik", "info", "--robot"]),
        ("scene", &["sim", "settle", "--scene"]),
        (
            "params",
            &["stable-poses", "--mesh", "@mesh/cube.obj", "--params"],
        ),
        (
            "bench-frames",
            &["bench", "frames", "--reps", "1", "--cloud"],
        ),
    ];
    for (what, cmd) in commands {
        for (label, path) in [
            ("dev-zero", "/dev/zero"),
            ("dev-urandom", "/dev/urandom"),
            ("folder", folder.as_str()),
            ("missing", "/no/such/file.pcd"),
            ("sparse-600mib", big.as_str()),
        ] {
            let mut args = cmd.to_vec();
            args.push(path);
            c.case(&format!("{what}-{label}"), "special-file", Error, &args);
        }
    }
    // A URDF name that is not a file and not a built-in robot.
    c.case(
        "urdf-unknown-robot",
        "special-file",
        Error,
        &["ik", "info", "--robot", "r2d2"],
    );
    c.case(
        "plan-dev-zero",
        "special-file",
        Error,
        &["plan", "/dev/zero", "/dev/zero"],
    );
}
