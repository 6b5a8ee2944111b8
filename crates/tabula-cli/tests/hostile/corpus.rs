//! The hostile cases, by format. Each case names the class of failure it guards
//! against (the classes of issue 12), the command, and the answer that is right.

mod moveit;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// The right kind of answer.
#[derive(Debug, Clone, Copy)]
pub enum Expect {
    Ok,
    Error,
    NoSolution,
    Usage,
}

/// Classes of failure, each covered by several cases.
pub const CLASSES: [&str; 7] = [
    "overflow",     // sizes from headers and flags that wrap or exhaust memory
    "unbounded",    // inputs that make work grow without limit
    "recursion",    // nesting that would overflow the stack
    "odd-legal",    // legal but unusual values that once panicked
    "garbage",      // inputs that once gave a wrong answer instead of an error
    "malformed",    // plain syntax errors, truncations, wrong types
    "special-file", // devices, folders, missing files, huge files
];

pub struct Case {
    pub name: String,
    pub class: &'static str,
    args: Vec<String>,
    pub expect: Expect,
    pub needle: Option<String>,
}

impl Case {
    /// The command line, with `@relative` paths resolved under the corpus folder.
    pub fn args(&self, root: &Path) -> Vec<String> {
        self.args
            .iter()
            .map(|a| match a.strip_prefix('@') {
                Some(rel) => root.join(rel).display().to_string(),
                None => a.clone(),
            })
            .collect()
    }
}

pub fn count_by_class(cases: &[Case]) -> BTreeMap<&'static str, usize> {
    let mut m = BTreeMap::new();
    for c in cases {
        *m.entry(c.class).or_insert(0) += 1;
    }
    m
}

struct Corpus<'a> {
    root: &'a Path,
    cases: Vec<Case>,
}

impl Corpus<'_> {
    /// Writes `bytes` as `rel` under the corpus folder; returns the `@rel` argument.
    fn file(&self, rel: &str, bytes: impl AsRef<[u8]>) -> String {
        let path = self.root.join(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, bytes).unwrap();
        format!("@{rel}")
    }

    fn case(&mut self, name: &str, class: &'static str, expect: Expect, args: &[&str]) {
        assert!(CLASSES.contains(&class), "{class}");
        self.cases.push(Case {
            name: name.to_string(),
            class,
            args: args.iter().map(|s| s.to_string()).collect(),
            expect,
            needle: None,
        });
    }

    /// The last case must also print `needle` (case-insensitive).
    fn needs(&mut self, needle: &str) {
        self.cases.last_mut().unwrap().needle = Some(needle.to_string());
    }
}

fn repo(rel: &str) -> String {
    format!("{}/../../{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn read_repo(rel: &str) -> String {
    std::fs::read_to_string(repo(rel)).unwrap()
}

pub fn all(root: &Path) -> Vec<Case> {
    let mut c = Corpus {
        root,
        cases: Vec::new(),
    };
    special_files(&mut c);
    pcd(&mut c);
    ply(&mut c);
    meshes(&mut c);
    urdf(&mut c);
    robot_packages(&mut c);
    moveit::moveit(&mut c);
    scenes(&mut c);
    params(&mut c);
    pddl(&mut c);
    flags(&mut c);
    c.cases
}

use Expect::{Error, NoSolution, Ok, Usage};

fn special_files(c: &mut Corpus) {
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

/// A PCD file from header lines and a body.
fn pcd_text(header: &[&str], body: &[u8]) -> Vec<u8> {
    let mut v = Vec::new();
    for h in header {
        v.extend_from_slice(h.as_bytes());
        v.push(b'\n');
    }
    v.extend_from_slice(body);
    v
}

fn header([fields, size, ty, count, w, h, pts, data]: [&str; 8]) -> Vec<String> {
    vec![
        "# .PCD v0.7".into(),
        "VERSION 0.7".into(),
        format!("FIELDS {fields}"),
        format!("SIZE {size}"),
        format!("TYPE {ty}"),
        format!("COUNT {count}"),
        format!("WIDTH {w}"),
        format!("HEIGHT {h}"),
        "VIEWPOINT 0 0 0 1 0 0 0".into(),
        format!("POINTS {pts}"),
        format!("DATA {data}"),
    ]
}

fn hdr(h: &[String]) -> Vec<&str> {
    h.iter().map(String::as_str).collect()
}

/// A small table with a box on it, seen from above, as world-frame points with the
/// sensor in `VIEWPOINT`: valid input the mutations start from.
fn table_points() -> Vec<[f32; 3]> {
    let mut pts = Vec::new();
    for i in 0..120 {
        for j in 0..80 {
            let (x, y) = (0.3 + i as f32 * 0.005, -0.2 + j as f32 * 0.005);
            let on_box = (0.45..0.53).contains(&x) && (-0.04..0.04).contains(&y);
            pts.push([x, y, if on_box { 0.82 } else { 0.72 }]);
        }
    }
    pts
}

fn ascii_body(pts: &[[f32; 3]]) -> String {
    let mut s = String::new();
    for p in pts {
        let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
    }
    s
}

fn binary_body(pts: &[[f32; 3]]) -> Vec<u8> {
    pts.iter().flatten().flat_map(|v| v.to_le_bytes()).collect()
}

fn pcd(c: &mut Corpus) {
    let pts = table_points();
    let n = pts.len().to_string();
    let viewpoint = "VIEWPOINT 0.5 0 1.6 1 0 0 0";
    let good_header = |data: &str| {
        let mut h = header(["x y z", "4 4 4", "F F F", "1 1 1", &n, "1", &n, data]);
        h[8] = viewpoint.into();
        h
    };
    let ascii = pcd_text(&hdr(&good_header("ascii")), ascii_body(&pts).as_bytes());
    let binary = pcd_text(&hdr(&good_header("binary")), &binary_body(&pts));
    let perceive = |c: &mut Corpus, name: &str, class, expect, bytes: Vec<u8>| {
        let f = c.file(&format!("cloud/{name}.pcd"), bytes);
        c.case(
            &format!("pcd-{name}"),
            class,
            expect,
            &["perceive", "--cloud", &f],
        );
    };
    perceive(c, "valid-ascii", "garbage", Ok, ascii.clone());
    c.needs("table:");
    perceive(c, "valid-binary", "garbage", Ok, binary.clone());
    c.needs("table:");
    // Truncations at many points of the header and body.
    for cut in [0, 1, 10, 40, 80, 120, 160, 200] {
        perceive(
            c,
            &format!("ascii-cut-{cut}"),
            "malformed",
            Error,
            ascii[..cut].to_vec(),
        );
    }
    let header_len = binary.len() - pts.len() * 12;
    for cut in [header_len, header_len + 1, header_len + 7, binary.len() - 1] {
        perceive(
            c,
            &format!("binary-cut-{cut}"),
            "malformed",
            Error,
            binary[..cut].to_vec(),
        );
    }
    let mutate = |field: &str, value: &str| {
        let mut h = good_header("binary");
        let i = h.iter().position(|l| l.starts_with(field)).unwrap();
        h[i] = format!("{field} {value}");
        pcd_text(&hdr(&h), &binary_body(&pts))
    };
    for (name, field, value, class) in [
        ("points-huge", "POINTS", "18446744073709551615", "overflow"),
        ("points-2pow62", "POINTS", "4611686018427387904", "overflow"),
        ("points-negative", "POINTS", "-5", "malformed"),
        ("points-word", "POINTS", "many", "malformed"),
        ("width-huge", "WIDTH", "4294967296", "overflow"),
        ("width-zero", "WIDTH", "0", "odd-legal"),
        ("height-huge", "HEIGHT", "4294967296", "overflow"),
        ("count-huge", "COUNT", "4611686018427387904 1 1", "overflow"),
        ("count-zero", "COUNT", "0 1 1", "odd-legal"),
        ("count-short", "COUNT", "1 1", "malformed"),
        ("size-huge", "SIZE", "9223372036854775807 4 4", "overflow"),
        ("size-3", "SIZE", "3 4 4", "malformed"),
        ("size-0", "SIZE", "0 4 4", "malformed"),
        ("type-q", "TYPE", "Q F F", "malformed"),
        ("type-short", "TYPE", "F F", "malformed"),
        ("fields-no-z", "FIELDS", "x y w", "garbage"),
        ("fields-dup", "FIELDS", "x x z", "garbage"),
        ("fields-none", "FIELDS", "", "malformed"),
        ("data-unknown", "DATA", "zip", "malformed"),
        ("viewpoint-nan", "VIEWPOINT", "nan 0 0 1 0 0 0", "garbage"),
        ("viewpoint-short", "VIEWPOINT", "0 0 0", "malformed"),
        (
            "viewpoint-zero-quat",
            "VIEWPOINT",
            "0 0 1 0 0 0 0",
            "garbage",
        ),
        ("viewpoint-inf", "VIEWPOINT", "0 0 inf 1 0 0 0", "garbage"),
        ("version-odd", "VERSION", "99", "odd-legal"),
    ] {
        let expect = if matches!(name, "version-odd") {
            Ok
        } else {
            Error
        };
        perceive(c, name, class, expect, mutate(field, value));
    }
    // WIDTH × HEIGHT that wraps 64 bits to the real count.
    perceive(
        c,
        "wh-wraps",
        "overflow",
        Error,
        pcd_text(
            &hdr(&header([
                "x y z",
                "4 4 4",
                "F F F",
                "1 1 1",
                "4294967296",
                "4294967296",
                "0",
                "binary",
            ])),
            b"",
        ),
    );
    // fields × count × points wrapping past the length check.
    perceive(
        c,
        "stride-wraps",
        "overflow",
        Error,
        pcd_text(
            &hdr(&header([
                "x y z",
                "4 4 4",
                "F F F",
                "1 1 1",
                "1537228672809129302",
                "1",
                "1537228672809129302",
                "binary",
            ])),
            &[0u8; 64],
        ),
    );
    // binary_compressed: a 100-byte file claiming 4 GiB, sizes that lie, bad LZF.
    let compressed = |sizes: [u32; 2], payload: &[u8]| {
        let mut body = sizes[0].to_le_bytes().to_vec();
        body.extend_from_slice(&sizes[1].to_le_bytes());
        body.extend_from_slice(payload);
        pcd_text(&hdr(&good_header("binary_compressed")), &body)
    };
    for (name, sizes, payload, class) in [
        (
            "lzf-claims-4gib",
            [80u32, u32::MAX],
            vec![0u8; 80],
            "overflow",
        ),
        (
            "lzf-compressed-longer-than-file",
            [1 << 30, (pts.len() * 12) as u32],
            vec![0u8; 10],
            "overflow",
        ),
        (
            "lzf-backref-before-start",
            [4, (pts.len() * 12) as u32],
            vec![0xe0, 0xff, 0x00, 0x00],
            "malformed",
        ),
        (
            "lzf-literal-past-end",
            [2, (pts.len() * 12) as u32],
            vec![0x1f, 0x00],
            "malformed",
        ),
        ("lzf-zero-sizes", [0, 0], vec![], "odd-legal"),
        (
            "lzf-short-output",
            [2, (pts.len() * 12) as u32],
            vec![0x00, 0x41],
            "malformed",
        ),
    ] {
        perceive(c, name, class, Error, compressed(sizes, &payload));
    }
    perceive(
        c,
        "lzf-no-sizes",
        "malformed",
        Error,
        pcd_text(&hdr(&good_header("binary_compressed")), b"\x01"),
    );
    // ASCII bodies.
    let with_body = |body: &str| pcd_text(&hdr(&good_header("ascii")), body.as_bytes());
    let n_lines = |line: &str| line.repeat(pts.len());
    for (name, body, class, expect) in [
        ("ascii-words", n_lines("a b c\n"), "garbage", Error),
        ("ascii-short-rows", n_lines("1 2\n"), "malformed", Error),
        ("ascii-all-nan", n_lines("nan nan nan\n"), "garbage", Error),
        ("ascii-hex", n_lines("0x1 0x2 0x3\n"), "garbage", Error),
        ("ascii-empty-body", String::new(), "malformed", Error),
        ("ascii-1e39", n_lines("1e39 1e39 1e39\n"), "garbage", Error),
    ] {
        perceive(c, name, class, expect, with_body(&body));
    }
    // Half the points NaN (an organized frame's padding): still a table.
    let mut padded = String::new();
    for p in &pts {
        let _ = writeln!(padded, "{} {} {}\nnan nan nan", p[0], p[1], p[2]);
    }
    let mut h = header([
        "x y z",
        "4 4 4",
        "F F F",
        "1 1 1",
        &(2 * pts.len()).to_string(),
        "1",
        &(2 * pts.len()).to_string(),
        "ascii",
    ]);
    h[8] = viewpoint.into();
    perceive(
        c,
        "nan-padded",
        "odd-legal",
        Ok,
        pcd_text(&hdr(&h), padded.as_bytes()),
    );
    c.needs("table:");
    // Organized frames narrower than the normal-estimation window.
    for w in [1usize, 2, 3] {
        let rows = pts.len() / w;
        let mut h = header([
            "x y z",
            "4 4 4",
            "F F F",
            "1 1 1",
            &w.to_string(),
            &rows.to_string(),
            &(w * rows).to_string(),
            "binary",
        ]);
        h[8] = viewpoint.into();
        perceive(
            c,
            &format!("organized-width-{w}"),
            "odd-legal",
            Error,
            pcd_text(&hdr(&h), &binary_body(&pts[..w * rows])),
        );
    }
    // 200,000 identical points: outlier removal and clustering must not go quadratic.
    let same = vec![[0.5f32, 0.0, 0.72]; 200_000];
    let mut h = header([
        "x y z", "4 4 4", "F F F", "1 1 1", "200000", "1", "200000", "binary",
    ]);
    h[8] = viewpoint.into();
    perceive(
        c,
        "identical-200k",
        "unbounded",
        Error,
        pcd_text(&hdr(&h), &binary_body(&same)),
    );
    // One point, two points, a line of points, all coplanar tiny.
    for (name, k) in [("one-point", 1usize), ("two-points", 2), ("ten-points", 10)] {
        let mut h = header([
            "x y z",
            "4 4 4",
            "F F F",
            "1 1 1",
            &k.to_string(),
            "1",
            &k.to_string(),
            "binary",
        ]);
        h[8] = viewpoint.into();
        perceive(
            c,
            name,
            "odd-legal",
            Error,
            pcd_text(&hdr(&h), &binary_body(&pts[..k])),
        );
    }
    // Coordinates of 1e30: finite, but no table anywhere near.
    let far: Vec<[f32; 3]> = pts
        .iter()
        .map(|p| [p[0] * 1e30, p[1] * 1e30, p[2]])
        .collect();
    perceive(
        c,
        "coordinates-1e30",
        "garbage",
        Error,
        pcd_text(&hdr(&good_header("binary")), &binary_body(&far)),
    );
    // A 200 KB header line: the error quotes a clipped part of it.
    let mut long = good_header("binary");
    long[2] = format!("FIELDS {}", "x".repeat(200_000));
    perceive(
        c,
        "header-200kb",
        "garbage",
        Error,
        pcd_text(&hdr(&long), b""),
    );
    // Doubles, unsigned bytes, rgb packed, comments and CRLF line ends: legal.
    let doubles: Vec<u8> = pts
        .iter()
        .flatten()
        .flat_map(|v| (*v as f64).to_le_bytes())
        .collect();
    let mut h = header(["x y z", "8 8 8", "F F F", "1 1 1", &n, "1", &n, "binary"]);
    h[8] = viewpoint.into();
    perceive(c, "doubles", "odd-legal", Ok, pcd_text(&hdr(&h), &doubles));
    c.needs("table:");
    let crlf = String::from_utf8(ascii.clone())
        .unwrap()
        .replace('\n', "\r\n");
    perceive(c, "crlf", "odd-legal", Ok, crlf.into_bytes());
    c.needs("table:");
    let mut h = good_header("ascii");
    h[3] = "SIZE 4 4 4 4".into();
    h[2] = "FIELDS x y z rgb".into();
    h[4] = "TYPE F F F U".into();
    h[5] = "COUNT 1 1 1 1".into();
    let rgb: String = pts
        .iter()
        .map(|p| format!("{} {} {} 16711680\n", p[0], p[1], p[2]))
        .collect();
    perceive(
        c,
        "rgb-uint",
        "odd-legal",
        Ok,
        pcd_text(&hdr(&h), rgb.as_bytes()),
    );
    c.needs("table:");
    let rgb_bad: String = pts
        .iter()
        .map(|p| format!("{} {} {} red\n", p[0], p[1], p[2]))
        .collect();
    perceive(
        c,
        "rgb-word",
        "garbage",
        Error,
        pcd_text(&hdr(&h), rgb_bad.as_bytes()),
    );
    perceive(
        c,
        "not-utf8-header",
        "malformed",
        Error,
        b"\xff\xfe\xfd VERSION\n\x80\x81".to_vec(),
    );
    perceive(c, "empty", "malformed", Error, Vec::new());
    // The same hostile PCDs as scanned objects for stable poses.
    for name in [
        "points-huge",
        "lzf-claims-4gib",
        "ascii-all-nan",
        "one-point",
        "stride-wraps",
    ] {
        let f = format!("@cloud/{name}.pcd");
        c.case(
            &format!("stable-cloud-{name}"),
            "garbage",
            Error,
            &["stable-poses", "--cloud", &f],
        );
    }
    // A flat scan (all points coplanar): no volume, no stable poses.
    let flat: Vec<[f32; 3]> = (0..400)
        .map(|i| [(i % 20) as f32 * 0.01, (i / 20) as f32 * 0.01, 0.0])
        .collect();
    let h = header([
        "x y z", "4 4 4", "F F F", "1 1 1", "400", "1", "400", "binary",
    ]);
    let f = c.file(
        "cloud/flat-scan.pcd",
        pcd_text(&hdr(&h), &binary_body(&flat)),
    );
    c.case(
        "stable-cloud-flat",
        "garbage",
        Error,
        &["stable-poses", "--cloud", &f],
    );
    // bench frames on a hostile frame: an error, not a panic in the timing loop.
    c.case(
        "bench-frames-one-point",
        "odd-legal",
        Error,
        &[
            "bench",
            "frames",
            "--reps",
            "1",
            "--cloud",
            "@cloud/one-point.pcd",
        ],
    );
}

fn ply_text(header: &[&str], body: &[u8]) -> Vec<u8> {
    let mut v = b"ply\n".to_vec();
    for h in header {
        v.extend_from_slice(h.as_bytes());
        v.push(b'\n');
    }
    v.extend_from_slice(b"end_header\n");
    v.extend_from_slice(body);
    v
}

fn ply(c: &mut Corpus) {
    let pts = table_points();
    let n = pts.len();
    let vertex = |fmt: &str, count: &str| {
        vec![
            format!("format {fmt} 1.0"),
            format!("element vertex {count}"),
            "property float x".into(),
            "property float y".into(),
            "property float z".into(),
        ]
    };
    let run = |c: &mut Corpus, name: &str, class, expect, bytes: Vec<u8>| {
        let f = c.file(&format!("cloud/{name}.ply"), bytes);
        c.case(
            &format!("ply-{name}"),
            class,
            expect,
            &["perceive", "--cloud", &f, "--up", "0", "0", "1"],
        );
    };
    // PLY has no sensor pose: the points are in the sensor's frame (sensor at the
    // origin), here with z up and the table 0.88 m below the sensor.
    let pts: Vec<[f32; 3]> = pts.iter().map(|p| [p[0] - 0.5, p[1], p[2] - 1.6]).collect();
    let ascii = ply_text(
        &hdr(&vertex("ascii", &n.to_string())),
        ascii_body(&pts).as_bytes(),
    );
    run(c, "valid-ascii", "garbage", Ok, ascii.clone());
    c.needs("table:");
    let binary = ply_text(
        &hdr(&vertex("binary_little_endian", &n.to_string())),
        &binary_body(&pts),
    );
    run(c, "valid-binary", "garbage", Ok, binary.clone());
    c.needs("table:");
    let be: Vec<u8> = pts.iter().flatten().flat_map(|v| v.to_be_bytes()).collect();
    run(
        c,
        "valid-big-endian",
        "odd-legal",
        Ok,
        ply_text(&hdr(&vertex("binary_big_endian", &n.to_string())), &be),
    );
    c.needs("table:");
    for cut in [3, 10, 30, 60, 90] {
        run(
            c,
            &format!("header-cut-{cut}"),
            "malformed",
            Error,
            ascii[..cut].to_vec(),
        );
    }
    run(
        c,
        "binary-cut",
        "malformed",
        Error,
        binary[..binary.len() - 5].to_vec(),
    );
    for (name, count, class) in [
        ("count-huge", "18446744073709551615", "overflow"),
        ("count-2pow60", "1152921504606846976", "overflow"),
        ("count-negative", "-1", "malformed"),
        ("count-word", "lots", "malformed"),
        ("count-zero", "0", "odd-legal"),
    ] {
        run(
            c,
            name,
            class,
            Error,
            ply_text(
                &hdr(&vertex("binary_little_endian", count)),
                &binary_body(&pts),
            ),
        );
    }
    // An element with a huge count and no properties: zero bytes each, once a spin.
    run(
        c,
        "propertyless-element",
        "unbounded",
        Error,
        ply_text(
            &[
                "format binary_little_endian 1.0",
                "element junk 18446744073709551615",
                "element vertex 1",
                "property float x",
                "property float y",
                "property float z",
            ],
            &[0u8; 12],
        ),
    );
    run(
        c,
        "propertyless-ascii",
        "unbounded",
        Error,
        ply_text(
            &[
                "format ascii 1.0",
                "element junk 9999999999999",
                "element vertex 1",
                "property float x",
                "property float y",
                "property float z",
            ],
            b"0 0 0\n",
        ),
    );
    // A list property with a huge length prefix.
    let mut faces = vertex("binary_little_endian", "3");
    faces.extend([
        "element face 1".to_string(),
        "property list uchar int vertex_indices".to_string(),
    ]);
    let mut body = binary_body(&pts[..3]);
    body.push(255);
    run(
        c,
        "list-past-end",
        "malformed",
        Error,
        ply_text(&hdr(&faces), &body),
    );
    let mut faces_u32 = vertex("binary_little_endian", "3");
    faces_u32.extend([
        "element face 1".to_string(),
        "property list uint int vertex_indices".to_string(),
    ]);
    let mut body = binary_body(&pts[..3]);
    body.extend_from_slice(&u32::MAX.to_le_bytes());
    run(
        c,
        "list-u32-max",
        "overflow",
        Error,
        ply_text(&hdr(&faces_u32), &body),
    );
    // A comment that contains `end_header`.
    let mut commented = vertex("ascii", &n.to_string());
    commented.insert(0, "comment written by end_header tool".into());
    run(
        c,
        "comment-end-header",
        "garbage",
        Ok,
        ply_text(&hdr(&commented), ascii_body(&pts).as_bytes()),
    );
    c.needs("table:");
    for (name, fmt, class) in [
        (
            "format-unknown",
            "format binary_middle_endian 1.0",
            "malformed",
        ),
        ("format-missing", "", "malformed"),
        ("version-2", "format ascii 2.0", "malformed"),
    ] {
        let mut h = vertex("ascii", &n.to_string());
        h[0] = fmt.into();
        run(
            c,
            name,
            class,
            Error,
            ply_text(&hdr(&h), ascii_body(&pts).as_bytes()),
        );
    }
    let mut h = vertex("ascii", &n.to_string());
    h[2] = "property quaternion x".into();
    run(
        c,
        "property-type-unknown",
        "malformed",
        Error,
        ply_text(&hdr(&h), ascii_body(&pts).as_bytes()),
    );
    let mut h = vertex("ascii", &n.to_string());
    h.truncate(3);
    run(
        c,
        "no-z",
        "garbage",
        Error,
        ply_text(&hdr(&h), ascii_body(&pts).as_bytes()),
    );
    let words: String = "x y z\n".repeat(n);
    run(
        c,
        "ascii-words",
        "garbage",
        Error,
        ply_text(&hdr(&vertex("ascii", &n.to_string())), words.as_bytes()),
    );
    let nans: String = "nan nan nan\n".repeat(n);
    run(
        c,
        "ascii-all-nan",
        "garbage",
        Error,
        ply_text(&hdr(&vertex("ascii", &n.to_string())), nans.as_bytes()),
    );
    run(
        c,
        "no-end-header",
        "malformed",
        Error,
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n0\n".to_vec(),
    );
    run(c, "only-magic", "malformed", Error, b"ply".to_vec());
    let long = format!("comment {}", "z".repeat(300_000));
    let mut h = vertex("ascii", &n.to_string());
    h.insert(0, long);
    run(
        c,
        "comment-300kb",
        "odd-legal",
        Ok,
        ply_text(&hdr(&h), ascii_body(&pts).as_bytes()),
    );
    c.needs("table:");
}

fn meshes(c: &mut Corpus) {
    let stable = |c: &mut Corpus, name: &str, ext: &str, class, expect, bytes: Vec<u8>| {
        let f = c.file(&format!("mesh/{name}.{ext}"), bytes);
        c.case(
            &format!("mesh-{name}"),
            class,
            expect,
            &["stable-poses", "--mesh", &f],
        );
    };
    let cube_v = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
    let cube_f = "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let cube = format!("{cube_v}{cube_f}");
    stable(c, "cube", "obj", "garbage", Ok, cube.clone().into_bytes());
    c.needs("most likely");
    for (name, text, class, expect) in [
        ("empty", String::new(), "malformed", Error),
        ("index-zero", format!("{cube_v}f 0 1 2\n"), "malformed", Error),
        ("index-past-end", format!("{cube_v}f 1 2 99\n"), "malformed", Error),
        ("index-negative-past", format!("{cube_v}f -1 -2 -99\n"), "malformed", Error),
        ("index-huge", format!("{cube_v}f 1 2 99999999999999999999\n"), "overflow", Error),
        ("vertex-nan", format!("v nan 0 0\n{cube}"), "garbage", Error),
        ("vertex-inf", format!("v inf 0 0\n{cube}"), "garbage", Error),
        ("vertex-1e300", format!("v 1e300 0 0\n{cube}"), "garbage", Error),
        ("vertex-short", "v 1 2\n".to_string(), "malformed", Error),
        ("vertex-word", "v a b c\n".to_string(), "malformed", Error),
        ("coplanar", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n".to_string(), "garbage", Error),
        ("collinear", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n".to_string(), "garbage", Error),
        ("one-point", "v 0 0 0\n".to_string(), "garbage", Error),
        ("same-point", "v 1 1 1\nv 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\nf 2 3 4\n".to_string(), "garbage", Error),
        ("tiny-1e-300", "v 0 0 0\nv 1e-300 0 0\nv 0 1e-300 0\nv 0 0 1e-300\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n".to_string(), "garbage", Error),
        ("degenerate-faces", format!("{cube_v}f 1 1 1\nf 2 2 3\n{cube_f}"), "odd-legal", Ok),
        ("inside-out", format!("{cube_v}f 2 3 4 1\nf 8 7 6 5\nf 5 6 2 1\nf 6 7 3 2\nf 7 8 4 3\nf 8 5 1 4\n"), "odd-legal", Ok),
        ("open-box", format!("{cube_v}f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"), "odd-legal", Ok),
        ("points-only", cube_v.to_string(), "odd-legal", Ok),
        ("texture-normals", format!("{cube_v}vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n{cube_f}"), "odd-legal", Ok),
        ("line-200kb", format!("{cube}# {}\n", "c".repeat(200_000)), "odd-legal", Ok),
        ("face-line-200kb", format!("{cube}f {}\n", "q".repeat(200_000)), "garbage", Error),
    ] {
        stable(c, name, "obj", class, expect, text.into_bytes());
    }
    // A face with 100,000 corners (a fan): many triangles, bounded work.
    let mut fan = String::new();
    for i in 0..100_000 {
        let a = i as f64 * 2.0 * std::f64::consts::PI / 100_000.0;
        let _ = writeln!(fan, "v {} {} 0", a.cos(), a.sin());
    }
    fan.push_str("v 0 0 1\nf");
    for i in 1..=100_000 {
        let _ = write!(fan, " {i}");
    }
    fan.push('\n');
    stable(c, "fan-100k", "obj", "unbounded", Ok, fan.into_bytes());
    let mut noise = Vec::new();
    let mut x: u32 = 12345;
    for _ in 0..5000 {
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
        noise.push((x >> 16) as u8);
    }
    stable(c, "random-bytes", "obj", "malformed", Error, noise.clone());
    stable(c, "random-bytes", "stl", "malformed", Error, noise);
    // STL.
    let tri = |v: [[f32; 3]; 3]| {
        let mut b = vec![0u8; 12];
        for p in v {
            for k in p {
                b.extend_from_slice(&k.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
        b
    };
    let tetra = [
        [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    ];
    let binary_stl = |header: &[u8], count: u32, tris: &[[[f32; 3]; 3]]| {
        let mut b = header.to_vec();
        b.resize(80, b' ');
        b.extend_from_slice(&count.to_le_bytes());
        for t in tris {
            b.extend(tri(*t));
        }
        b
    };
    stable(
        c,
        "stl-binary",
        "stl",
        "garbage",
        Ok,
        binary_stl(b"tetra", 4, &tetra),
    );
    c.needs("most likely");
    // A binary STL whose header starts with "solid" (many exporters write that).
    stable(
        c,
        "stl-binary-solid-header",
        "stl",
        "garbage",
        Ok,
        binary_stl(b"solid tetra exported", 4, &tetra),
    );
    c.needs("most likely");
    stable(
        c,
        "stl-binary-solid-facet-header",
        "stl",
        "garbage",
        Ok,
        binary_stl(b"solid facet vertex", 4, &tetra),
    );
    c.needs("most likely");
    stable(
        c,
        "stl-count-huge",
        "stl",
        "overflow",
        Error,
        binary_stl(b"x", u32::MAX, &tetra),
    );
    stable(
        c,
        "stl-count-short",
        "stl",
        "malformed",
        Error,
        binary_stl(b"x", 5, &tetra),
    );
    stable(
        c,
        "stl-count-zero",
        "stl",
        "odd-legal",
        Error,
        binary_stl(b"x", 0, &[]),
    );
    stable(c, "stl-83-bytes", "stl", "malformed", Error, vec![b'x'; 83]);
    let nan_tetra: Vec<_> = tetra
        .iter()
        .map(|t| [[f32::NAN, 0.0, 0.0], t[1], t[2]])
        .collect();
    stable(
        c,
        "stl-nan",
        "stl",
        "garbage",
        Error,
        binary_stl(b"x", 4, &nan_tetra),
    );
    let ascii_stl = "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";
    stable(
        c,
        "stl-ascii",
        "stl",
        "garbage",
        Ok,
        ascii_stl.as_bytes().to_vec(),
    );
    c.needs("most likely");
    stable(
        c,
        "stl-ascii-nan",
        "stl",
        "garbage",
        Error,
        ascii_stl
            .replacen("vertex 0 1 0", "vertex nan 1 0", 1)
            .into_bytes(),
    );
    stable(
        c,
        "stl-ascii-4-vertices",
        "stl",
        "malformed",
        Error,
        ascii_stl
            .replacen("vertex 0 0 0\n", "vertex 0 0 0\nvertex 0 0 0\n", 1)
            .into_bytes(),
    );
    stable(
        c,
        "stl-ascii-words",
        "stl",
        "malformed",
        Error,
        ascii_stl
            .replacen("vertex 0 1 0", "vertex a b c", 1)
            .into_bytes(),
    );
    stable(
        c,
        "unknown-extension",
        "dae",
        "malformed",
        Error,
        b"<COLLADA/>".to_vec(),
    );
    // PLY meshes.
    let ply_mesh = |count: &str| {
        let mut v = ply_text(
            &[
                "format ascii 1.0",
                "element vertex 4",
                "property float x",
                "property float y",
                "property float z",
                &format!("element face {count}"),
                "property list uchar int vertex_indices",
            ],
            b"0 0 0\n1 0 0\n0 1 0\n0 0 1\n",
        );
        v.extend_from_slice(b"3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
        v
    };
    stable(c, "ply-mesh", "ply", "garbage", Ok, ply_mesh("4"));
    c.needs("most likely");
    stable(
        c,
        "ply-mesh-faces-huge",
        "ply",
        "overflow",
        Error,
        ply_mesh("18446744073709551615"),
    );
    let mut bad_index = ply_mesh("4");
    bad_index.extend_from_slice(b"");
    let text = String::from_utf8(bad_index)
        .unwrap()
        .replace("3 1 2 3", "3 1 2 300");
    stable(
        c,
        "ply-mesh-index-past-end",
        "ply",
        "malformed",
        Error,
        text.into_bytes(),
    );
    // Scales in --params? No: stable-poses parameters that make no sense.
    for (name, toml) in [
        ("relaxation-nan", "relaxation_angle = nan"),
        ("relaxation-negative", "relaxation_angle = -1.0"),
        ("tolerance-inf", "contact_tolerance = inf"),
        ("unknown-key", "relaxaton_angle = 0.1"),
        ("wrong-type", "relaxation_angle = \"big\""),
        ("huge", "coplanar_angle = 1e300"),
    ] {
        let p = c.file(&format!("params/stable-{name}.toml"), toml);
        c.case(
            &format!("stable-params-{name}"),
            "garbage",
            Error,
            &["stable-poses", "--mesh", "@mesh/cube.obj", "--params", &p],
        );
    }
}

fn urdf(c: &mut Corpus) {
    let wam = read_repo("robots/wam.urdf");
    let info = |c: &mut Corpus, name: &str, class, expect, text: String| {
        let f = c.file(&format!("urdf/{name}.urdf"), text);
        c.case(
            &format!("urdf-{name}"),
            class,
            expect,
            &["ik", "info", "--robot", &f],
        );
    };
    info(c, "wam", "garbage", Ok, wam.clone());
    c.needs("wam_joint1");
    for cut in [0, 10, 100, 1000, 5000] {
        info(
            c,
            &format!("cut-{cut}"),
            "malformed",
            Error,
            wam[..cut].to_string(),
        );
    }
    let first_joint_origin = wam.find("<origin").unwrap();
    let with = |from: &str, to: &str| {
        assert!(wam.contains(from), "{from}");
        wam.replacen(from, to, 1)
    };
    let limit = &wam[wam.find("<limit").unwrap()..];
    let limit = &limit[..limit.find("/>").unwrap() + 2];
    for (name, text, class) in [
        ("not-xml", "robot { links }".to_string(), "malformed"),
        ("no-robot", "<?xml version=\"1.0\"?><thing/>".to_string(), "malformed"),
        ("no-links", "<robot name=\"r\"></robot>".to_string(), "garbage"),
        ("origin-nan", format!("{}<origin xyz=\"nan 0 0\" rpy=\"0 0 0\"/>{}", &wam[..first_joint_origin], &wam[wam[first_joint_origin..].find("/>").unwrap() + first_joint_origin + 2..]), "garbage"),
        ("limit-inf", with(limit, "<limit lower=\"-inf\" upper=\"inf\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("limit-nan", with(limit, "<limit lower=\"nan\" upper=\"1\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("limit-reversed", with(limit, "<limit lower=\"2\" upper=\"-2\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("limit-1e300", with(limit, "<limit lower=\"-1e300\" upper=\"1e300\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("axis-zero", with("<axis xyz=\"0.0 0.0 1.0\"/>", "<axis xyz=\"0 0 0\"/>"), "garbage"),
        ("axis-nan", with("<axis xyz=\"0.0 0.0 1.0\"/>", "<axis xyz=\"nan 0 1\"/>"), "garbage"),
        ("duplicate-link", wam.replacen("</robot>", "<link name=\"wam_link1\"/></robot>", 1), "garbage"),
        ("missing-parent", wam.replacen("</robot>", "<link name=\"extra\"/><joint name=\"jx\" type=\"fixed\"><parent link=\"nowhere\"/><child link=\"extra\"/></joint></robot>", 1), "garbage"),
        ("cycle", wam.replacen("</robot>", "<joint name=\"jx\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"base_link\"/></joint></robot>", 1), "garbage"),
        ("self-loop", wam.replacen("</robot>", "<joint name=\"jx\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"wam_tool\"/></joint></robot>", 1), "garbage"),
        ("joint-type-unknown", with("type=\"revolute\"", "type=\"teleport\""), "malformed"),
        ("mesh-escapes", wam.replacen("</robot>", "<link name=\"m\"><collision><geometry><mesh filename=\"package://x/../../../../etc/passwd\"/></geometry></collision></link><joint name=\"jm\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"m\"/></joint></robot>", 1), "garbage"),
        ("mesh-dev-zero-unused", wam.replacen("</robot>", "<link name=\"m\"><collision><geometry><mesh filename=\"/dev/zero\"/></geometry></collision></link><joint name=\"jm\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"m\"/></joint></robot>", 1), "special-file"),
        ("box-negative", wam.replacen("</robot>", "<link name=\"m\"><collision><geometry><box size=\"-1 1 1\"/></geometry></collision></link><joint name=\"jm\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"m\"/></joint></robot>", 1), "garbage"),
        ("entity-expansion", ("<?xml version=\"1.0\"?><!DOCTYPE r [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;\"><!ENTITY c \"&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;\"><!ENTITY d \"&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;\"><!ENTITY e \"&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;\"><!ENTITY f \"&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;\"><!ENTITY g \"&f;&f;&f;&f;&f;&f;&f;&f;&f;&f;\"><!ENTITY h \"&g;&g;&g;&g;&g;&g;&g;&g;&g;&g;\">]><robot name=\"&h;\"><link name=\"a\"/></robot>").to_string(), "unbounded"),
    ] {
        info(c, name, class, Error, text);
    }
    // Deep nesting: 30,000 elements, and a 100,000-deep one inside a link.
    info(
        c,
        "nested-30000",
        "recursion",
        Error,
        format!(
            "<robot name=\"r\">{}{}</robot>",
            "<link name=\"a\">".repeat(30_000),
            "</link>".repeat(30_000)
        ),
    );
    info(
        c,
        "nested-100000-other",
        "recursion",
        Error,
        format!(
            "<robot name=\"r\"><link name=\"a\"/>{}{}</robot>",
            "<x>".repeat(100_000),
            "</x>".repeat(100_000)
        ),
    );
    // A 22 MB URDF: over the size limit, refused before parsing.
    let mut big = String::from("<robot name=\"big\"><link name=\"l0\"/>");
    let mut i = 0;
    while big.len() < 22 << 20 {
        let _ = write!(
            big,
            "<link name=\"l{}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>",
            i + 1,
            i + 1
        );
        i += 1;
    }
    big.push_str("</robot>");
    info(c, "size-22mb", "unbounded", Error, big);
    // A long chain (2,000 joints): legal, loads in bounded time.
    let mut chain = String::from("<robot name=\"chain\"><link name=\"l0\"/>");
    for i in 0..2000 {
        let _ = write!(
            chain,
            "<link name=\"l{}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>",
            i + 1,
            i + 1
        );
    }
    chain.push_str("</robot>");
    info(c, "chain-2000", "unbounded", Ok, chain);
    c.needs("j1999");
    c.case(
        "urdf-chain-2000-fk",
        "unbounded",
        Ok,
        &[
            "ik",
            "fk",
            "--robot",
            "@urdf/chain-2000.urdf",
            "--base",
            "l0",
            "--tip",
            "l2000",
        ],
    );
    // A description TOML beside a URDF that is malformed.
    let f = c.file("urdf/described.urdf", &wam);
    c.file("urdf/described.toml", "[[arm]]\nname = 5\n");
    c.case(
        "urdf-description-malformed",
        "malformed",
        Error,
        &["ik", "info", "--robot", &f],
    );
    // FK at values that are not joint values.
    for (name, joints, class, expect) in [
        (
            "fk-nan",
            vec!["nan", "0", "0", "0", "0", "0", "0"],
            "garbage",
            Usage,
        ),
        (
            "fk-inf",
            vec!["inf", "0", "0", "0", "0", "0", "0"],
            "garbage",
            Usage,
        ),
        (
            "fk-1e300",
            vec!["1e300", "0", "0", "0", "0", "0", "0"],
            "garbage",
            Error,
        ),
        ("fk-too-few", vec!["0"], "malformed", Error),
        (
            "fk-word",
            vec!["zero", "0", "0", "0", "0", "0", "0"],
            "malformed",
            Usage,
        ),
    ] {
        let mut args = vec!["ik", "fk", "--robot", "wam", "--joints"];
        args.extend(joints);
        c.case(&format!("urdf-{name}"), class, expect, &args);
    }
    c.case(
        "urdf-base-unknown",
        "malformed",
        Error,
        &["ik", "info", "--robot", "wam", "--base", "nowhere"],
    );
}

fn scenes(c: &mut Corpus) {
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

fn params(c: &mut Corpus) {
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

fn pddl(c: &mut Corpus) {
    let domain = read_repo("pddl/tablewclear-domain.pddl");
    let problem = read_repo("pddl/thesis6-a.pddl");
    let d = c.file("pddl/domain.pddl", &domain);
    let plan = |c: &mut Corpus, name: &str, class, expect, dom: Option<String>, prob: String| {
        let df = match dom {
            Some(t) => c.file(&format!("pddl/{name}-domain.pddl"), t),
            None => d.clone(),
        };
        let pf = c.file(&format!("pddl/{name}-problem.pddl"), prob);
        c.case(
            &format!("pddl-{name}"),
            class,
            expect,
            &["plan", &df, &pf, "--timeout", "15"],
        );
    };
    plan(c, "valid", "garbage", Ok, None, problem.clone());
    c.needs("cost = 9");
    plan(
        c,
        "unsolvable",
        "garbage",
        NoSolution,
        None,
        read_repo("pddl/thesis6-unsolvable.pddl"),
    );
    c.needs("unsolvable");
    for cut in [0, 1, 30, 200, 500] {
        plan(
            c,
            &format!("problem-cut-{cut}"),
            "malformed",
            Error,
            None,
            problem[..cut].to_string(),
        );
        plan(
            c,
            &format!("domain-cut-{cut}"),
            "malformed",
            Error,
            Some(domain[..cut * 8].to_string()),
            problem.clone(),
        );
    }
    for (name, text, class) in [
        ("unbalanced", problem.replacen(")", "", 3), "malformed"),
        ("extra-close", format!("{problem}))"), "malformed"),
        (
            "undeclared-object",
            problem.replacen("(on o1 o2)", "(on o1 o99)", 1),
            "garbage",
        ),
        (
            "unknown-predicate",
            problem.replacen("(on o1 o2)", "(under o1 o2)", 1),
            "garbage",
        ),
        (
            "wrong-arity",
            problem.replacen("(on o1 o2)", "(on o1)", 1),
            "garbage",
        ),
        (
            "wrong-domain",
            problem.replacen("(:domain tablewclear)", "(:domain other)", 1),
            "garbage",
        ),
        (
            "goal-missing",
            problem.replacen("(:goal", "(:gaol", 1),
            "malformed",
        ),
        (
            "duplicate-object",
            problem.replacen("o6 - obj", "o6 o6 - obj", 1),
            "garbage",
        ),
        ("nul-bytes", problem.replacen("o1", "o\0", 1), "malformed"),
        (
            "string-literal",
            problem.replacen("o1 o2 o3", "\"o1\" o2 o3", 1),
            "malformed",
        ),
    ] {
        plan(c, name, class, Error, None, text);
    }
    // Deep nesting: 100,000 parentheses, in a goal and bare.
    plan(
        c,
        "nested-goal-100k",
        "recursion",
        Error,
        None,
        problem.replacen(
            "(:goal (and",
            &format!("(:goal {}(and", "(and ".repeat(100_000)),
            1,
        ),
    );
    plan(
        c,
        "nested-bare-100k",
        "recursion",
        Error,
        None,
        format!("{}{}", "(".repeat(100_000), ")".repeat(100_000)),
    );
    plan(
        c,
        "nested-domain-100k",
        "recursion",
        Error,
        Some(format!("{}{}", "(".repeat(100_000), ")".repeat(100_000))),
        problem.clone(),
    );
    // A type cycle and an undefined parent type.
    let typed = "(define (domain t) (:requirements :typing) (:types a - b b - a) (:predicates (p ?x - a)) (:action go :parameters (?x - a) :precondition (p ?x) :effect (not (p ?x))))";
    plan(
        c,
        "type-cycle",
        "garbage",
        Error,
        Some(typed.into()),
        "(define (problem q) (:domain t) (:objects x - a) (:init (p x)) (:goal (not (p x))))"
            .into(),
    );
    let self_typed = "(define (domain t) (:requirements :typing) (:types a - a) (:predicates (p ?x - a)) (:action go :parameters (?x - a) :precondition (p ?x) :effect (not (p ?x))))";
    plan(
        c,
        "type-self",
        "garbage",
        Error,
        Some(self_typed.into()),
        "(define (problem q) (:domain t) (:objects x - a) (:init (p x)) (:goal (not (p x))))"
            .into(),
    );
    // Grounding blow-ups: quantifiers over many variables, many-parameter actions.
    let objects: String = (0..66).map(|i| format!(" o{i}")).collect();
    let quant = "(define (domain q) (:requirements :adl) (:predicates (p ?a ?b ?c ?d ?e ?f) (done)) (:action go :parameters () :precondition (forall (?a ?b ?c ?d ?e ?f) (not (p ?a ?b ?c ?d ?e ?f))) :effect (done)))";
    // Quantifiers over 5 and 6 variables (1.25e9 and 8.3e10 bindings): grounding counts
    // them and stops at the deadline (0.3 s here: on a fast machine the 5e7-binding work
    // limit — a clean error too, but another status — was reached within 2 s).
    let exists = "(define (domain q) (:requirements :adl) (:predicates (p ?a ?b ?c ?d ?e) (done)) (:action go :parameters () :precondition (exists (?a ?b ?c ?d ?e) (p ?a ?b ?c ?d ?e)) :effect (done)))";
    for (name, domain, init) in [
        ("forall-6-vars", quant, ""),
        ("exists-5-vars", exists, "(p o1 o2 o3 o4 o5)"),
    ] {
        let df = c.file(&format!("pddl/{name}-domain.pddl"), domain);
        let pf = c.file(
            &format!("pddl/{name}-problem.pddl"),
            format!("(define (problem q1) (:domain q) (:objects{objects}) (:init {init}) (:goal (done)))"),
        );
        c.case(
            &format!("pddl-{name}"),
            "unbounded",
            NoSolution,
            &["plan", &df, &pf, "--timeout", "0.3"],
        );
        c.needs("time limit");
    }
    let four = "(define (domain f) (:predicates (p ?a ?b ?c ?d) (q ?a)) (:action go :parameters (?a ?b ?c ?d) :precondition (q ?a) :effect (p ?a ?b ?c ?d)))";
    plan(
        c,
        "four-params-66-objects",
        "unbounded",
        Ok,
        Some(four.into()),
        format!(
            "(define (problem f1) (:domain f) (:objects{objects}) (:init (q o1)) (:goal (p o1 o1 o1 o2)))"
        ),
    );
    let many: String = (0..60).map(|i| format!(" ?v{i}")).collect();
    let wide = format!(
        "(define (domain w) (:predicates (p{many}) (d)) (:action go :parameters ({many}) :precondition (d) :effect (p{many})))"
    );
    plan(
        c,
        "sixty-params",
        "unbounded",
        Error,
        Some(wide),
        format!("(define (problem w1) (:domain w) (:objects{objects}) (:init (d)) (:goal (d)))"),
    );
    // An unsolvable search space too big to exhaust: ends at --timeout with exit 2.
    let counter = "(define (domain c) (:predicates (at ?x) (next ?x ?y) (goal-reached)) (:action step :parameters (?x ?y) :precondition (and (at ?x) (next ?x ?y)) :effect (and (not (at ?x)) (at ?y))))";
    let n = 60;
    let objs: String = (0..n).map(|i| format!(" c{i}")).collect();
    let mut init = String::new();
    for i in 0..n {
        for j in 0..n {
            if i != j {
                let _ = write!(init, " (next c{i} c{j})");
            }
        }
    }
    let f = c.file("pddl/no-goal-reachable-domain.pddl", counter);
    let p = c.file("pddl/no-goal-reachable-problem.pddl", format!("(define (problem c1) (:domain c) (:objects{objs}) (:init (at c0){init}) (:goal (goal-reached)))"));
    c.case(
        "pddl-goal-unreachable",
        "unbounded",
        NoSolution,
        &["plan", &f, &p, "--timeout", "5"],
    );
    // A plan to validate that is malformed.
    let good_plan = c.file("pddl/plan-ok.txt", "(grasp o6)\n");
    c.case(
        "pddl-validate-wrong-plan",
        "garbage",
        Error,
        &[
            "plan",
            "--validate",
            &d,
            "@pddl/valid-problem.pddl",
            &good_plan,
        ],
    );
    for (name, text) in [
        ("unknown-action", "(fly o1)\n"),
        ("unbalanced", "(grasp o1\n"),
        ("unknown-object", "(grasp o99)\n"),
        ("huge", &"(grasp o1)\n".repeat(100_000)),
    ] {
        let f = c.file(&format!("pddl/plan-{name}.txt"), text);
        c.case(
            &format!("pddl-validate-{name}"),
            "malformed",
            Error,
            &["plan", "--validate", &d, "@pddl/valid-problem.pddl", &f],
        );
    }
}

fn flags(c: &mut Corpus) {
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

/// Robots as description packages bring them: xacro (includes, `load_yaml`, `$(find)`,
/// macro and property bombs), SRDF and COLLADA meshes — each refused with what is wrong,
/// within the time and memory bounds.
fn robot_packages(c: &mut Corpus) {
    let head = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">"#;
    let xacro = |c: &mut Corpus, name: &str, class, expect, text: String, needle: &str| {
        let f = c.file(&format!("xacro/{name}.urdf.xacro"), text);
        c.case(
            &format!("xacro-{name}"),
            class,
            expect,
            &["ik", "info", "--robot", &f],
        );
        c.needs(needle);
    };
    let mut macro_bomb = String::from(head);
    for k in 0..10 {
        let call = format!(r#"<xacro:m{} p="${{p}}x"/>"#, k + 1);
        macro_bomb += &format!(
            r#"<xacro:macro name="m{k}" params="p">{}</xacro:macro>"#,
            call.repeat(10)
        );
    }
    macro_bomb += r#"<xacro:macro name="m10" params="p"><link name="${p}"/></xacro:macro><xacro:m0 p="a"/></robot>"#;
    let mut property_bomb =
        format!(r#"{head}<xacro:property name="p0" value="aaaaaaaaaaaaaaaa"/>"#);
    for k in 1..48 {
        property_bomb += &format!(
            r#"<xacro:property name="p{k}" value="${{p{0}}}${{p{0}}}"/>"#,
            k - 1
        );
    }
    property_bomb += r#"<link name="${p47}"/></robot>"#;
    for (name, text, class, needle) in [
        (
            "include-dev-zero",
            format!(r#"{head}<xacro:include filename="/dev/zero"/></robot>"#),
            "special-file",
            "not a regular file",
        ),
        (
            "include-folder",
            format!(r#"{head}<xacro:include filename="/tmp"/></robot>"#),
            "special-file",
            "not a regular file",
        ),
        (
            "yaml-dev-urandom",
            format!(
                r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('/dev/urandom')}}"/><link name="a"/></robot>"#
            ),
            "special-file",
            "not a regular file",
        ),
        (
            "include-self",
            format!(
                r#"{head}<xacro:include filename="include-self.urdf.xacro"/><link name="a"/></robot>"#
            ),
            "recursion",
            "xacro",
        ),
        (
            "macro-recursion",
            format!(
                r#"{head}<xacro:macro name="m" params=""><xacro:m/></xacro:macro><xacro:m/></robot>"#
            ),
            "recursion",
            "xacro",
        ),
        ("macro-bomb", macro_bomb, "unbounded", "xacro"),
        ("property-bomb", property_bomb, "unbounded", "xacro"),
        (
            "find-missing-package",
            format!(r#"{head}<xacro:include filename="$(find no_such_package)/a.xacro"/></robot>"#),
            "special-file",
            "no_such_package",
        ),
        (
            "arg-undefined",
            format!(r#"{head}<link name="$(arg nothing)"/></robot>"#),
            "malformed",
            "nothing",
        ),
        (
            "extension-unknown",
            format!(r#"{head}<link name="$(launch everything)"/></robot>"#),
            "malformed",
            "xacro",
        ),
        (
            "yaml-missing",
            format!(
                r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('gone.yaml')}}"/><link name="${{y}}"/></robot>"#
            ),
            "special-file",
            "gone.yaml",
        ),
    ] {
        xacro(c, name, class, Error, text, needle);
    }
    // A legal xacro with an argument from the command line, and the argument malformed.
    let f = c.file(
        "xacro/arg.urdf.xacro",
        format!(r#"{head}<xacro:arg name="n" default="a"/><link name="$(arg n)_base"/></robot>"#),
    );
    // XML read as YAML is one string: legal, and unused here.
    let f_yaml = c.file(
        "xacro/yaml-not-yaml.urdf.xacro",
        format!(r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('../urdf/wam.urdf')}}"/><link name="a"/></robot>"#),
    );
    c.case(
        "xacro-yaml-not-yaml",
        "odd-legal",
        Ok,
        &["ik", "info", "--robot", &f_yaml],
    );
    c.case(
        "xacro-arg-given",
        "odd-legal",
        Ok,
        &["ik", "info", "--robot", &f, "--xacro-arg", "n:=left"],
    );
    c.needs("left_base");
    c.case(
        "xacro-arg-malformed",
        "malformed",
        Usage,
        &["ik", "info", "--robot", &f, "--xacro-arg", "no-separator"],
    );

    // SRDF against the WAM.
    let wam = c.file("srdf/wam.urdf", read_repo("robots/wam.urdf"));
    let srdf = |c: &mut Corpus, name: &str, class, expect, text: String, needle: &str| {
        let s = c.file(&format!("srdf/{name}.srdf"), text);
        c.case(
            &format!("srdf-{name}"),
            class,
            expect,
            &["ik", "info", "--robot", &wam, "--srdf", &s],
        );
        c.needs(needle);
    };
    let group = r#"<group name="arm"><chain base_link="base_link" tip_link="wam_tool"/></group>"#;
    srdf(
        c,
        "good",
        "garbage",
        Ok,
        format!(
            r#"<robot name="wam">{group}<group_state name="home" group="arm"><joint name="wam_joint1" value="0.1"/></group_state><disable_collisions link1="wam_link1" link2="gone" reason="Never"/></robot>"#
        ),
        "wam_joint1",
    );
    for (name, text, class, needle) in [
        ("group-link-missing", r#"<robot name="wam"><group name="arm"><link name="no_such_link"/></group></robot>"#.to_string(), "garbage", "no_such_link"),
        ("group-chain-missing", r#"<robot name="wam"><group name="arm"><chain base_link="base_link" tip_link="gone_tip"/></group></robot>"#.to_string(), "garbage", "gone_tip"),
        ("group-joint-missing", r#"<robot name="wam"><group name="arm"><joint name="jx"/></group></robot>"#.to_string(), "garbage", "jx"),
        ("subgroup-undefined", r#"<robot name="wam"><group name="all"><group name="ghost"/></group></robot>"#.to_string(), "garbage", "ghost"),
        ("state-nan", format!(r#"<robot name="wam">{group}<group_state name="s" group="arm"><joint name="wam_joint1" value="nan"/></group_state></robot>"#), "garbage", "wam_joint1"),
        ("state-1e300", format!(r#"<robot name="wam">{group}<group_state name="s" group="arm"><joint name="wam_joint1" value="1e300"/></group_state></robot>"#), "garbage", "wam_joint1"),
        ("state-unknown-group", r#"<robot name="wam"><group_state name="s" group="nope"><joint name="wam_joint1" value="0"/></group_state></robot>"#.to_string(), "garbage", "nope"),
        ("state-joint-missing", format!(r#"<robot name="wam">{group}<group_state name="s" group="arm"><joint name="elbow_x" value="0"/></group_state></robot>"#), "garbage", "elbow_x"),
        ("not-xml", "group arm { }".to_string(), "malformed", "SRDF"),
        ("entity-expansion", r#"<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]><robot name="&b;"/>"#.to_string(), "unbounded", "SRDF"),
        ("nested-10000", format!("<robot>{}{}</robot>", "<group name=\"g\">".repeat(10_000), "</group>".repeat(10_000)), "recursion", "nest"),
        ("attribute-missing", r#"<robot name="wam"><disable_collisions link1="wam_link1"/></robot>"#.to_string(), "malformed", "link2"),
    ] {
        srdf(c, name, class, Error, text, needle);
    }
    c.case(
        "srdf-dev-zero",
        "special-file",
        Usage,
        &["ik", "info", "--robot", &wam, "--srdf", "/dev/zero"],
    );
    c.needs("regular file");

    // COLLADA meshes.
    let stable = |c: &mut Corpus, name: &str, class, expect, text: String| {
        let f = c.file(&format!("mesh/{name}.dae"), text);
        c.case(
            &format!("dae-{name}"),
            class,
            expect,
            &["stable-poses", "--mesh", &f],
        );
    };
    let dae = |geometry: &str, scene: &str| {
        format!(
            r##"<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><library_geometries>{geometry}</library_geometries><library_visual_scenes><visual_scene id="s">{scene}</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>"##
        )
    };
    let cube = |indices: &str| {
        format!(
            r##"<geometry id="g"><mesh><source id="p"><float_array id="pa" count="24">0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1</float_array><technique_common><accessor source="#pa" count="8" stride="3"/></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="12"><input semantic="VERTEX" source="#v" offset="0"/><p>{indices}</p></triangles></mesh></geometry>"##
        )
    };
    let faces = "0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7";
    let placed = r##"<node><instance_geometry url="#g"/></node>"##;
    stable(c, "cube", "garbage", Ok, dae(&cube(faces), placed));
    c.needs("most likely");
    for (name, text, class) in [
        (
            "index-past-end",
            dae(&cube(&faces.replacen("0 2 1", "0 2 99", 1)), placed),
            "malformed",
        ),
        (
            "index-negative",
            dae(&cube(&faces.replacen("0 2 1", "0 2 -1", 1)), placed),
            "malformed",
        ),
        (
            "float-word",
            dae(&cube(faces).replace("1 1 1 0 1 1", "1 1 one 0 1 1"), placed),
            "malformed",
        ),
        (
            "vertex-nan",
            dae(&cube(faces).replace("1 1 1 0 1 1", "1 1 nan 0 1 1"), placed),
            "garbage",
        ),
        (
            "url-dangling",
            dae(
                &cube(faces),
                r##"<node><instance_geometry url="#nowhere"/></node>"##,
            ),
            "malformed",
        ),
        (
            "instance-node-loop",
            dae(
                &cube(faces),
                r##"<node id="n"><instance_node url="#n"/></node>"##,
            ),
            "recursion",
        ),
        (
            "matrix-short",
            dae(
                &cube(faces),
                r##"<node><matrix>1 0 0</matrix><instance_geometry url="#g"/></node>"##,
            ),
            "malformed",
        ),
        ("no-triangles", dae("", ""), "garbage"),
        ("not-collada", "<robot/>".to_string(), "malformed"),
        (
            "dtd",
            format!(
                "<!DOCTYPE c [<!ENTITY a \"b\">]>{}",
                dae(&cube(faces), placed)
            ),
            "unbounded",
        ),
    ] {
        stable(c, name, class, Error, text);
    }
}
