//! Prism objects: an outline extruded, as exact convex pieces.

use super::SimError;
use rapier3d_f64::prelude::SharedShape;
use tabula_geom::{Pose, Vec3};

/// A prism as exact convex pieces of its outline, each extruded (one convex
/// polyhedron when the outline is convex, a compound otherwise).
pub(super) fn prism_shape(outline: &[[f64; 2]], length: f64) -> Result<SharedShape, SimError> {
    let points: Vec<tabula_geom::Vec2> = outline
        .iter()
        .map(|&[x, y]| tabula_geom::Vec2::new(x, y))
        .collect();
    let bad = |message: String| SimError::Mesh {
        path: "a prism's outline".into(),
        message,
    };
    let pieces =
        tabula_geom::convex_pieces::convex_pieces(&points).map_err(|e| bad(e.to_string()))?;
    let mut parts = Vec::with_capacity(pieces.len());
    for piece in &pieces {
        let corners: Vec<Vec3> = [-0.5, 0.5]
            .iter()
            .flat_map(|s| piece.iter().map(move |p| Vec3::new(p.x, p.y, s * length)))
            .collect();
        let part = SharedShape::convex_hull(&corners)
            .ok_or_else(|| bad("a piece of the outline has no volume".into()))?;
        parts.push((Pose::IDENTITY, part));
    }
    Ok(match parts.len() {
        1 => parts.remove(0).1,
        _ => SharedShape::compound(parts),
    })
}
