//! PLY clouds and meshes: headers that lie, sizes that overflow.

use super::*;

pub(super) fn ply_text(header: &[&str], body: &[u8]) -> Vec<u8> {
    let mut v = b"ply\n".to_vec();
    for h in header {
        v.extend_from_slice(h.as_bytes());
        v.push(b'\n');
    }
    v.extend_from_slice(b"end_header\n");
    v.extend_from_slice(body);
    v
}

pub(super) fn ply(c: &mut Corpus) {
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
