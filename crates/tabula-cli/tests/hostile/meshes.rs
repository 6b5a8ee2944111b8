//! Meshes as scene objects and for stable poses.

use super::*;

pub(super) fn meshes(c: &mut Corpus) {
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
