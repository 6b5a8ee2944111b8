//! PCD point clouds: headers that lie, sizes that overflow, compressed bombs.

use super::*;

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

pub(super) fn hdr(h: &[String]) -> Vec<&str> {
    h.iter().map(String::as_str).collect()
}

/// A small table with a box on it, seen from above, as world-frame points with the
/// sensor in `VIEWPOINT`: valid input the mutations start from.
pub(super) fn table_points() -> Vec<[f32; 3]> {
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

pub(super) fn ascii_body(pts: &[[f32; 3]]) -> String {
    let mut s = String::new();
    for p in pts {
        let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
    }
    s
}

pub(super) fn binary_body(pts: &[[f32; 3]]) -> Vec<u8> {
    pts.iter().flatten().flat_map(|v| v.to_le_bytes()).collect()
}

pub(super) fn pcd(c: &mut Corpus) {
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
