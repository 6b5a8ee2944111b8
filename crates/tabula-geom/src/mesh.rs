//! Triangle meshes from COLLADA, OBJ, STL (ASCII and binary) and PLY files, for
//! collision shapes.

use crate::Vec3;
use std::path::Path;

/// A mesh file that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("mesh `{path}`: {message}")]
pub struct MeshError {
    pub path: String,
    pub message: String,
}

/// Vertices and triangles of an OBJ or STL file, scaled.
pub fn load_mesh(path: &Path, scale: [f64; 3]) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), MeshError> {
    let fail = |m: String| MeshError {
        path: path.display().to_string(),
        message: m,
    };
    let bytes = crate::input::read_bytes(path, crate::input::Format::Mesh)
        .map_err(|e| fail(e.to_string()))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    parse_mesh(&bytes, &ext, scale).map_err(|m| fail(m.message))
}

/// [`load_mesh`] on bytes already read; `ext` is `obj` or `stl`.
pub fn parse_mesh(
    bytes: &[u8],
    ext: &str,
    scale: [f64; 3],
) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), MeshError> {
    let fail = |m: String| MeshError {
        path: String::new(),
        message: m,
    };
    let mut points = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let parse3 = |w: &mut std::str::SplitWhitespace| -> Option<Vec3> {
        let v: Vec<f64> = w.take(3).filter_map(|x| x.parse().ok()).collect();
        (v.len() == 3).then(|| Vec3::new(v[0], v[1], v[2]))
    };
    let quote = |line: &str| crate::input::clip(line, 60);
    // A polygon as a triangle fan, its corners checked against the vertex count.
    let fan = |triangles: &mut Vec<[u32; 3]>, idx: &[u32], n: usize| -> Result<(), MeshError> {
        if let Some(bad) = idx.iter().find(|&&i| i as usize >= n) {
            return Err(fail(format!(
                "face refers to vertex {bad}, which does not exist ({n} vertices)"
            )));
        }
        for k in 1..idx.len().saturating_sub(1) {
            triangles.push([idx[0], idx[k], idx[k + 1]]);
        }
        Ok(())
    };
    match ext {
        "obj" => {
            let text = String::from_utf8_lossy(bytes);
            for line in text.lines() {
                let mut w = line.split_whitespace();
                match w.next() {
                    Some("v") => points.push(
                        parse3(&mut w)
                            .ok_or_else(|| fail(format!("bad vertex line `{}`", quote(line))))?,
                    ),
                    Some("f") => {
                        // `f a b c …`, each `a` possibly `a/t/n`, negative = from the end.
                        let mut idx = Vec::new();
                        for item in w {
                            let first = item.split('/').next().unwrap_or("");
                            let i: i64 = first
                                .parse()
                                .map_err(|_| fail(format!("bad face line `{}`", quote(line))))?;
                            let n = points.len() as i64;
                            let i = if i < 0 {
                                n.saturating_add(i)
                            } else {
                                i.saturating_sub(1)
                            };
                            if i < 0 || i >= n {
                                return Err(fail(format!(
                                    "face refers to vertex {}, which does not exist",
                                    quote(first)
                                )));
                            }
                            idx.push(i as u32);
                        }
                        fan(&mut triangles, &idx, points.len())?;
                    }
                    _ => {}
                }
            }
        }
        "stl" => {
            // Binary when the size matches the triangle count exactly: exporters write
            // "solid …" into binary headers too, so the first word proves nothing.
            let binary_size = bytes
                .get(80..84)
                .map(|c| 84 + 50 * u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as u64);
            if binary_size == Some(bytes.len() as u64) {
                let n = (bytes.len() - 84) / 50;
                points.reserve(3 * n);
                for t in 0..n {
                    let base = 84 + t * 50 + 12;
                    for k in 0..3 {
                        let f = |i: usize| {
                            let o = base + k * 12 + i * 4;
                            f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]])
                                as f64
                        };
                        points.push(Vec3::new(f(0), f(1), f(2)));
                    }
                }
            } else if bytes.starts_with(b"solid") {
                let text = String::from_utf8_lossy(bytes);
                let mut in_loop: Option<usize> = None;
                for line in text.lines() {
                    let mut w = line.split_whitespace();
                    match w.next() {
                        Some("outer") => in_loop = Some(points.len()),
                        Some("vertex") => {
                            points.push(parse3(&mut w).ok_or_else(|| {
                                fail(format!("bad vertex line `{}`", quote(line)))
                            })?)
                        }
                        Some("endloop") => {
                            let corners = points.len() - in_loop.take().unwrap_or(0);
                            if corners != 3 {
                                return Err(fail(format!(
                                    "a facet has {corners} vertices; STL facets have 3"
                                )));
                            }
                        }
                        _ => {}
                    }
                }
                if points.len() % 3 != 0 {
                    return Err(fail("ASCII STL ends inside a facet".into()));
                }
            } else if bytes.len() < 84 {
                return Err(fail("binary STL shorter than its 84-byte header".into()));
            } else {
                return Err(fail(format!(
                    "binary STL declares {} triangles ({} bytes) but is {} bytes",
                    (binary_size.unwrap_or(84) - 84) / 50,
                    binary_size.unwrap_or(84),
                    bytes.len()
                )));
            }
            triangles = (0..points.len() as u32 / 3)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect();
        }
        "ply" => {
            let (vertices, faces) =
                crate::ply::read_ply_mesh(bytes).map_err(|e| fail(e.to_string()))?;
            points = vertices;
            for face in &faces {
                fan(&mut triangles, face, points.len())?;
            }
        }
        "dae" => (points, triangles) = crate::collada::read(bytes).map_err(fail)?,
        other => {
            return Err(fail(format!(
                "unsupported mesh format `{}` (use .dae, .obj, .stl or .ply)",
                crate::input::clip(other, 20)
            )));
        }
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(fail("non-finite vertex".into()));
    }
    if let Some(p) = points
        .iter()
        .find(|p| p.abs().max_element() > crate::input::MAX_MAGNITUDE)
    {
        return Err(fail(format!(
            "vertex ({}, {}, {}) is beyond ±{:e} m",
            p.x,
            p.y,
            p.z,
            crate::input::MAX_MAGNITUDE
        )));
    }
    if points.len() < 4 {
        return Err(fail("fewer than 4 vertices".into()));
    }
    let s = Vec3::from_array(scale);
    Ok((points.into_iter().map(|p| p * s).collect(), triangles))
}

/// Enclosed volume of a triangle mesh (divergence theorem; orientation-consistent).
pub fn mesh_volume(points: &[Vec3], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .filter(|t| t.iter().all(|&i| (i as usize) < points.len()))
        .map(|t| {
            points[t[0] as usize].dot(points[t[1] as usize].cross(points[t[2] as usize])) / 6.0
        })
        .sum::<f64>()
        .abs()
}

/// Most vertices a collision hull is computed over exactly: real robot and object
/// meshes have tens of thousands at most; a scan-sized mesh of millions made parry's
/// quickhull run for minutes.
pub const MAX_EXACT_HULL: usize = 100_000;

/// The one way a mesh becomes a solid collision shape, everywhere in tabula: its convex
/// hull when the mesh is (nearly) convex or `decompose` is off, a convex decomposition
/// (V-HACD) when it is notably concave, so a cup's hollow stays hollow and a concave
/// body cannot tunnel as a dynamic trimesh would. (A trimesh is a surface: a point
/// inside it does not "intersect" it.)
pub fn mesh_shape(
    points: &[Vec3],
    triangles: &[[u32; 3]],
    decompose: bool,
) -> Result<crate::parry::shape::SharedShape, String> {
    use crate::parry::shape::SharedShape;
    if points.iter().any(|p| !p.is_finite()) {
        return Err("non-finite vertex".into());
    }
    // Collision hulls stay exact up to MAX_EXACT_HULL points (any real robot or object
    // mesh); beyond, a scan-sized mesh is thinned, with a warning saying by how much.
    let thinned =
        crate::hull_input::thinned_with_cell(points, MAX_EXACT_HULL).map(|(kept, cell)| {
            tracing::warn!(
                "a mesh of {} vertices: its collision hull is taken over the outermost {} \
                 (shrunk by under {:.1} mm)",
                points.len(),
                kept.len(),
                1e3 * cell * 3f64.sqrt()
            );
            kept
        });
    let (hull_points, hull_triangles) =
        crate::parry::transformation::try_convex_hull(thinned.as_deref().unwrap_or(points))
            .map_err(|_| "degenerate (flat or collinear) vertices: no convex hull".to_string())?;
    let hull = SharedShape::convex_mesh(hull_points, &hull_triangles)
        .ok_or_else(|| "degenerate (flat or collinear) vertices: no convex hull".to_string())?;
    // A flat mesh gives a "hull" of no volume, which the physics would keep floating
    // where it was put: a body needs a thickness of at least a millionth of its size.
    let (lo, hi) = crate::bounds(points);
    let size = (hi - lo).max_element();
    if hull.mass_properties(1.0).mass() <= 1e-6 * size.powi(3) {
        return Err("flat (coplanar) vertices: the mesh encloses no volume".into());
    }
    if !decompose || triangles.is_empty() {
        return Ok(hull);
    }
    let hull_volume = hull.mass_properties(1.0).mass();
    if mesh_volume(points, triangles) >= 0.95 * hull_volume {
        return Ok(hull);
    }
    let key = crate::shape_cache::key(points, triangles);
    if let Some(shape) = crate::shape_cache::load(key).and_then(|parts| compound_of(&parts)) {
        return Ok(shape);
    }
    // V-HACD is third-party code on arbitrary input: a panic there is a mesh error.
    let (pts, tris) = (points.to_vec(), triangles.to_vec());
    let shape = crate::guard::catch_quietly(move || SharedShape::convex_decomposition(&pts, &tris))
        .map_err(|_| "convex decomposition failed".to_string())?;
    if let Some(compound) = shape.as_compound() {
        let parts: Vec<Vec<Vec3>> = compound
            .shapes()
            .iter()
            .filter_map(|(pose, part)| {
                let points = part.as_convex_polyhedron()?.points();
                Some(points.iter().map(|p| *pose * *p).collect())
            })
            .collect();
        if parts.len() == compound.shapes().len() {
            crate::shape_cache::store(key, &parts);
        }
    }
    Ok(shape)
}

/// A compound of the convex hulls of `parts` (`None` if any part is degenerate).
fn compound_of(parts: &[Vec<Vec3>]) -> Option<crate::parry::shape::SharedShape> {
    use crate::parry::shape::SharedShape;
    let shapes = parts
        .iter()
        .map(|p| SharedShape::convex_hull(p).map(|s| (crate::Pose::IDENTITY, s)))
        .collect::<Option<Vec<_>>>()?;
    Some(SharedShape::compound(shapes))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron 10 units tall (the declared centimetres are ignored, as MoveIt and
    /// RViz ignore them), placed 100 units up by a node inside a node turned a quarter
    /// about x then translated: the order of nested transforms matters.
    pub(crate) const TETRA_DAE: &str = r##"<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="0.01" name="centimeter"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="g" name="g"><mesh>
<source id="p"><float_array id="pa" count="12">0 0 0 10 0 0 0 10 0 0 0 10</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="4"><input semantic="VERTEX" source="#v" offset="0"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="outer"><translate>5 0 0</translate><rotate>1 0 0 90</rotate><node id="n"><translate>0 -100 0</translate><instance_geometry url="#g"/></node></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>"##;

    #[test]
    fn collada_meshes_are_read_in_metres_with_their_node_transforms() {
        let (points, triangles) = parse_mesh(TETRA_DAE.as_bytes(), "dae", [1.0; 3]).unwrap();
        assert_eq!(triangles.len(), 4);
        // Inner node: y from -100 to -90 and z 0..10; turned +90° about x, y → z and
        // z → -y; then 5 along x.
        let lo = points.iter().fold(Vec3::MAX, |a, p| a.min(*p));
        let hi = points.iter().fold(Vec3::MIN, |a, p| a.max(*p));
        assert!(lo.abs_diff_eq(Vec3::new(5.0, -10.0, -100.0), 1e-9), "{lo}");
        assert!(hi.abs_diff_eq(Vec3::new(15.0, 0.0, -90.0), 1e-9), "{hi}");
        assert!((mesh_volume(&points, &triangles).abs() - 1000.0 / 6.0).abs() < 1e-6);
        for bad in [
            "",
            "<COLLADA/>",
            "<COLLADA><asset></COLLADA>",
            &TETRA_DAE.replace("0 2 1 0 1 3", "0 2 9 0 1 3"),
        ] {
            assert!(
                parse_mesh(bad.as_bytes(), "dae", [1.0; 3]).is_err(),
                "{bad:.40}"
            );
        }
    }

    fn binary_stl(header: &[u8], count: u32, triangles: usize) -> Vec<u8> {
        let mut b = header.to_vec();
        b.resize(80, b' ');
        b.extend_from_slice(&count.to_le_bytes());
        for t in 0..triangles {
            b.extend_from_slice(&[0; 12]);
            for k in 0..9 {
                let v = [
                    [0.0f32, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, (t % 2) as f32],
                ][k / 3][k % 3]
                    + (t / 2) as f32;
                b.extend_from_slice(&v.to_le_bytes());
            }
            b.extend_from_slice(&[0, 0]);
        }
        b
    }

    #[test]
    fn a_binary_stl_whose_header_says_solid_facet_is_binary() {
        let stl = binary_stl(b"solid facet vertex endloop", 2, 2);
        let (v, t) = parse_mesh(&stl, "stl", [1.0; 3]).unwrap();
        assert_eq!((v.len(), t.len()), (6, 2));
        assert!(parse_mesh(&binary_stl(b"x", 3, 2), "stl", [1.0; 3]).is_err());
    }

    #[test]
    fn an_ascii_facet_needs_three_vertices_and_coordinates_are_bounded() {
        let four = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
                    vertex 0 0 1\nendloop\nendfacet\nendsolid t\n";
        assert!(
            parse_mesh(four.as_bytes(), "stl", [1.0; 3])
                .unwrap_err()
                .message
                .contains("4 vertices")
        );
        let far = "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";
        assert!(parse_mesh(far.as_bytes(), "obj", [1.0; 3]).is_err());
    }

    #[test]
    fn a_flat_mesh_has_no_collision_shape() {
        let flat = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        assert!(mesh_shape(&flat, &[[0, 1, 2], [1, 3, 2]], false).is_err());
    }

    #[test]
    fn obj_and_stl_read_and_bad_files_are_errors() {
        let (v, t) = parse_mesh(
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf -1 -2 -3\n",
            "obj",
            [2.0; 3],
        )
        .unwrap();
        assert_eq!((v.len(), t.len()), (4, 3));
        assert_eq!(v[1], Vec3::new(2.0, 0.0, 0.0));
        assert!(parse_mesh(b"v 0 0 0\nf 1 2 3\n", "obj", [1.0; 3]).is_err());
        assert!(parse_mesh(b"v 0 0\n", "obj", [1.0; 3]).is_err());
        assert!(parse_mesh(&[0u8; 10], "stl", [1.0; 3]).is_err());
        let mut stl = vec![0u8; 80];
        stl.extend_from_slice(&u32::MAX.to_le_bytes());
        assert!(
            parse_mesh(&stl, "stl", [1.0; 3]).is_err(),
            "a lying triangle count"
        );
        assert!(parse_mesh(b"", "ply", [1.0; 3]).is_err());
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        // A small deterministic fuzz: mutations of valid files and random bytes.
        let mut seed = 0x2545F4914F6CDD1Du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let base_obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1/1/1 3 4\n".to_vec();
        let mut base_stl = vec![0u8; 80];
        base_stl.extend_from_slice(&2u32.to_le_bytes());
        base_stl.extend(std::iter::repeat_n(0u8, 100));
        for round in 0..4000 {
            let (mut bytes, ext) = if round % 2 == 0 {
                (base_obj.clone(), "obj")
            } else {
                (base_stl.clone(), "stl")
            };
            for _ in 0..(next() % 6) {
                let i = (next() as usize) % bytes.len().max(1);
                match next() % 3 {
                    0 if !bytes.is_empty() => {
                        bytes.remove(i);
                    }
                    1 => bytes.insert(i.min(bytes.len()), (next() % 256) as u8),
                    _ if !bytes.is_empty() => bytes[i] = (next() % 256) as u8,
                    _ => {}
                }
            }
            let _ = parse_mesh(&bytes, ext, [1.0; 3]);
        }
    }
}
