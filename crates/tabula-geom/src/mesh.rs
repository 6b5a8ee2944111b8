//! Triangle meshes from OBJ and STL files (ASCII and binary), for collision shapes.

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
    let bytes = std::fs::read(path).map_err(|e| fail(e.to_string()))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mut points = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let parse3 = |w: &mut std::str::SplitWhitespace| -> Option<Vec3> {
        let v: Vec<f64> = w.take(3).filter_map(|x| x.parse().ok()).collect();
        (v.len() == 3).then(|| Vec3::new(v[0], v[1], v[2]))
    };
    match ext.as_str() {
        "obj" => {
            let text = String::from_utf8_lossy(&bytes);
            for line in text.lines() {
                let mut w = line.split_whitespace();
                match w.next() {
                    Some("v") => points.push(
                        parse3(&mut w).ok_or_else(|| fail(format!("bad vertex line `{line}`")))?,
                    ),
                    Some("f") => {
                        // `f a b c …`, each `a` possibly `a/t/n`, negative = from the end.
                        let mut idx = Vec::new();
                        for item in w {
                            let first = item.split('/').next().unwrap_or("");
                            let i: i64 = first
                                .parse()
                                .map_err(|_| fail(format!("bad face line `{line}`")))?;
                            let n = points.len() as i64;
                            let i = if i < 0 { n + i } else { i - 1 };
                            if i < 0 || i >= n {
                                return Err(fail(format!(
                                    "face refers to vertex {first}, which does not exist"
                                )));
                            }
                            idx.push(i as u32);
                        }
                        for k in 1..idx.len().saturating_sub(1) {
                            triangles.push([idx[0], idx[k], idx[k + 1]]);
                        }
                    }
                    _ => {}
                }
            }
        }
        "stl" => {
            let text = String::from_utf8_lossy(&bytes);
            if bytes.starts_with(b"solid") && text.contains("facet") {
                for line in text.lines() {
                    let mut w = line.split_whitespace();
                    if w.next() == Some("vertex") {
                        points.push(
                            parse3(&mut w)
                                .ok_or_else(|| fail(format!("bad vertex line `{line}`")))?,
                        );
                    }
                }
            } else {
                if bytes.len() < 84 {
                    return Err(fail("binary STL shorter than its header".into()));
                }
                let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
                if bytes.len() < 84 + n.saturating_mul(50) {
                    return Err(fail(format!(
                        "binary STL declares {n} triangles but is too short"
                    )));
                }
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
            }
            triangles = (0..points.len() as u32 / 3)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect();
        }
        other => {
            return Err(fail(format!(
                "unsupported mesh format `{other}` (use .obj or .stl)"
            )));
        }
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(fail("non-finite vertex".into()));
    }
    if points.len() < 4 {
        return Err(fail("fewer than 4 vertices".into()));
    }
    let s = Vec3::from_array(scale);
    Ok((points.into_iter().map(|p| p * s).collect(), triangles))
}
