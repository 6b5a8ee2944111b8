//! COLLADA (`.dae`) triangle meshes for collision and display: the geometry a file's
//! scene places (`<mesh>` and the physics `<convex_mesh>`; `triangles`, `polylist`,
//! `polygons`), each under the product of its nodes' transforms (`matrix`,
//! `translate`, `rotate`, `scale`, `instance_node`). The asset's `<unit>` and
//! `<up_axis>` are ignored, as MoveIt (geometric_shapes resets assimp's root transform,
//! where assimp puts them) and RViz do: published descriptions are drawn to look right
//! there — the PR2's `kinect.dae` declares centimetres but is written in metres.
//!
//! Written here rather than taken from the `mesh-loader` crate, which this project
//! tried first: it composes nested node transforms in the wrong order (UR20's
//! `wrist2.dae` came out 6.6 mm off against trimesh/pycollada) and rejects the
//! `<convex_mesh>` files the PR2's description uses for collision — a misplaced or
//! missing collision mesh is a safety hole, so the reader is ours, bounded, and checked
//! against trimesh on real descriptions (BENCHMARKS.md).

use crate::{Mat4, Vec3};
use std::collections::HashMap;

/// Most XML nodes a COLLADA file may have (a 256 MB file has fewer).
const MAX_NODES: u32 = 50_000_000;
/// Deepest nesting of scene nodes (and `instance_node` references) followed.
const MAX_NODE_DEPTH: usize = 64;

/// Vertices (m) and triangles of everything the file's scene shows.
pub fn read(bytes: &[u8]) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "COLLADA text is not UTF-8".to_string())?;
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_NODES,
    };
    let doc = roxmltree::Document::parse_with_options(text, options)
        .map_err(|e| format!("COLLADA: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "COLLADA" {
        return Err(format!(
            "the root element is <{}>, not <COLLADA>",
            root.tag_name().name()
        ));
    }
    let by_id: HashMap<&str, roxmltree::Node> = root
        .descendants()
        .filter_map(|n| n.attribute("id").map(|id| (id, n)))
        .collect();
    let mut out = Collected::default();
    let scene = child(root, "scene")
        .and_then(|s| child(s, "instance_visual_scene"))
        .and_then(|i| i.attribute("url"))
        .and_then(|u| by_id.get(u.trim_start_matches('#')).copied());
    if let Some(scene) = scene {
        for node in scene.children().filter(|n| n.has_tag_name("node")) {
            walk(node, Mat4::IDENTITY, &by_id, 0, &mut out)?;
        }
    }
    // Nothing placed by a scene (no scene, or geometry only a physics model uses, as
    // the PR2's convex hulls): every geometry where it is defined — collision geometry
    // is never silently empty.
    if out.triangles.is_empty() {
        for g in root.descendants().filter(|n| n.has_tag_name("geometry")) {
            add_geometry(g, &Mat4::IDENTITY, &mut out)?;
        }
    }
    if out.triangles.is_empty() {
        return Err("the COLLADA file places no triangles in its scene".into());
    }
    Ok((out.points, out.triangles))
}

#[derive(Default)]
struct Collected {
    points: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

fn child<'a, 'i>(n: roxmltree::Node<'a, 'i>, name: &str) -> Option<roxmltree::Node<'a, 'i>> {
    n.children().find(|c| c.has_tag_name(name))
}

fn walk(
    node: roxmltree::Node,
    parent: Mat4,
    by_id: &HashMap<&str, roxmltree::Node>,
    depth: usize,
    out: &mut Collected,
) -> Result<(), String> {
    if depth > MAX_NODE_DEPTH {
        return Err(format!(
            "COLLADA nodes nested deeper than {MAX_NODE_DEPTH} (a reference loop?)"
        ));
    }
    let mut world = parent;
    for t in node.children().filter(|c| c.is_element()) {
        if let Some(local) = transform(t)? {
            world *= local;
        }
    }
    for c in node.children().filter(|c| c.is_element()) {
        let target = |c: roxmltree::Node| {
            let url = c.attribute("url").unwrap_or("").trim_start_matches('#');
            by_id.get(url).copied().ok_or_else(|| {
                format!(
                    "COLLADA <{}> names `#{url}`, which is not in the file",
                    c.tag_name().name()
                )
            })
        };
        match c.tag_name().name() {
            "node" => walk(c, world, by_id, depth + 1, out)?,
            "instance_node" => walk(target(c)?, world, by_id, depth + 1, out)?,
            "instance_geometry" => add_geometry(target(c)?, &world, out)?,
            _ => {}
        }
    }
    Ok(())
}

/// A node's transform element as a matrix (`None` for other elements).
fn transform(t: roxmltree::Node) -> Result<Option<Mat4>, String> {
    let name = t.tag_name().name();
    if !matches!(name, "matrix" | "translate" | "rotate" | "scale") {
        return Ok(None);
    }
    let v = numbers(t.text().unwrap_or(""))
        .map_err(|_| format!("COLLADA <{name}> holds something that is not a number"))?;
    let need = match name {
        "matrix" => 16,
        "rotate" => 4,
        _ => 3,
    };
    if v.len() != need {
        return Err(format!(
            "COLLADA <{name}> has {} numbers, not {need}",
            v.len()
        ));
    }
    let m = match name {
        // COLLADA writes matrices row by row.
        "matrix" => Mat4::from_cols_slice(&v).transpose(),
        "translate" => Mat4::from_translation(Vec3::new(v[0], v[1], v[2])),
        "scale" => Mat4::from_scale(Vec3::new(v[0], v[1], v[2])),
        _ => {
            let axis = Vec3::new(v[0], v[1], v[2])
                .try_normalize()
                .unwrap_or(Vec3::Z);
            Mat4::from_axis_angle(axis, v[3].to_radians())
        }
    };
    Ok(Some(m))
}

/// The triangles of one `<geometry>` (its `<mesh>` or `<convex_mesh>`), transformed.
fn add_geometry(g: roxmltree::Node, world: &Mat4, out: &mut Collected) -> Result<(), String> {
    let Some(mesh) = g
        .children()
        .find(|c| c.has_tag_name("mesh") || c.has_tag_name("convex_mesh"))
    else {
        return Ok(()); // splines and other geometry hold no triangles
    };
    let sources: HashMap<&str, roxmltree::Node> = mesh
        .children()
        .filter(|c| c.has_tag_name("source"))
        .filter_map(|s| s.attribute("id").map(|id| (id, s)))
        .collect();
    let positions = positions(mesh, &sources)?;
    let offset = out.points.len();
    let limit = u32::MAX as usize;
    if offset + positions.len() > limit {
        return Err("COLLADA file has more vertices than a mesh may".into());
    }
    out.points
        .extend(positions.iter().map(|p| world.transform_point3(*p)));
    for prim in mesh.children().filter(|c| c.is_element()) {
        let kind = prim.tag_name().name();
        if !matches!(kind, "triangles" | "polylist" | "polygons") {
            continue;
        }
        let inputs: Vec<roxmltree::Node> = prim
            .children()
            .filter(|c| c.has_tag_name("input"))
            .collect();
        let stride = inputs
            .iter()
            .filter_map(|i| i.attribute("offset")?.parse::<usize>().ok())
            .max()
            .map_or(1, |m| m + 1);
        let vertex_offset = inputs
            .iter()
            .find(|i| i.attribute("semantic") == Some("VERTEX"))
            .and_then(|i| i.attribute("offset")?.parse::<usize>().ok())
            .ok_or_else(|| format!("COLLADA <{kind}> without a VERTEX input"))?;
        let vcounts: Option<Vec<usize>> = match kind {
            "polylist" => Some(
                indices(child(prim, "vcount").and_then(|v| v.text()).unwrap_or(""))?
                    .into_iter()
                    .map(|c| c as usize)
                    .collect(),
            ),
            _ => None,
        };
        for p in prim.children().filter(|c| c.has_tag_name("p")) {
            let raw = indices(p.text().unwrap_or(""))?;
            let corners: Vec<u32> = raw
                .iter()
                .skip(vertex_offset)
                .step_by(stride)
                .copied()
                .collect();
            if let Some(bad) = corners.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(format!(
                    "COLLADA face refers to vertex {bad}, beyond the mesh's {}",
                    positions.len()
                ));
            }
            let polygon_sizes: Vec<usize> = match (&vcounts, kind) {
                (Some(v), _) => v.clone(),
                (None, "polygons") => vec![corners.len()],
                _ => vec![3; corners.len() / 3],
            };
            let mut at = 0;
            for n in polygon_sizes {
                let Some(poly) = corners.get(at..at + n) else {
                    return Err(format!(
                        "COLLADA <{kind}> lists fewer indices than its polygons need"
                    ));
                };
                for k in 1..n.saturating_sub(1) {
                    out.triangles
                        .push([poly[0], poly[k], poly[k + 1]].map(|i| i + offset as u32));
                }
                at += n;
            }
        }
    }
    Ok(())
}

/// The POSITION source of a mesh (through its `<vertices>`), as points.
fn positions(
    mesh: roxmltree::Node,
    sources: &HashMap<&str, roxmltree::Node>,
) -> Result<Vec<Vec3>, String> {
    let source_id = child(mesh, "vertices")
        .and_then(|v| {
            v.children()
                .find(|i| i.has_tag_name("input") && i.attribute("semantic") == Some("POSITION"))
        })
        .and_then(|i| i.attribute("source"))
        .map(|s| s.trim_start_matches('#'))
        .ok_or("COLLADA mesh without <vertices> POSITION")?;
    let source = sources
        .get(source_id)
        .ok_or_else(|| format!("COLLADA positions `#{source_id}` are not in the mesh"))?;
    let floats = numbers(
        child(*source, "float_array")
            .and_then(|f| f.text())
            .unwrap_or(""),
    )
    .map_err(|_| "COLLADA <float_array> holds something that is not a number".to_string())?;
    let stride = child(*source, "technique_common")
        .and_then(|t| child(t, "accessor"))
        .and_then(|a| a.attribute("stride")?.parse::<usize>().ok())
        .unwrap_or(3);
    if stride < 3 {
        return Err(format!("COLLADA positions with stride {stride}"));
    }
    Ok(floats
        .chunks_exact(stride)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect())
}

fn numbers(text: &str) -> Result<Vec<f64>, std::num::ParseFloatError> {
    text.split_whitespace().map(str::parse).collect()
}

fn indices(text: &str) -> Result<Vec<u32>, String> {
    text.split_whitespace()
        .map(|s| {
            s.parse::<u32>().map_err(|_| {
                format!(
                    "COLLADA index `{}` is not a whole number",
                    crate::input::clip(s, 20)
                )
            })
        })
        .collect()
}
