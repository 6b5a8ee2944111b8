//! The prism above the table and what carries a normal in it: the points above the
//! table's plane inside its outline, and on an unorganized cloud one point per voxel
//! standing for the others in it.

use super::TabletopParams;
use crate::plane::Plane;
use crate::surfaces::plane_basis;
use tabula_geom::polygon::{distance_to_boundary, inside_convex, polygon_area};
use tabula_geom::{Vec2, Vec3, voxel_key};

/// The points above `plane` (facing the camera) by more than the floor height, inside
/// the table's `outline` (convex) — or, for a support found without a world pose (`reach` > 0),
/// within `reach` of it: such a support is seen only where what stands on it does not
/// hide it, so its objects stand at the edge of its visible part as often as inside.
pub(super) fn above(
    pts: &[Vec3],
    (plane, outline): (&Plane, &[Vec3]),
    (floor, reach): (f64, f64),
) -> Vec<bool> {
    let (u, v) = plane_basis(plane.normal);
    let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
    let mut poly: Vec<Vec2> = outline.iter().map(|&q| to2(q)).collect();
    if polygon_area(&poly) < 0.0 {
        poly.reverse();
    }
    // Outlier removal decides what may seed an object, not what may belong to one:
    // points it dropped join an object if they touch it (a real stray point touches
    // nothing), so objects keep their edges.
    let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
    for q in &poly {
        lo = lo.min(*q - Vec2::splat(reach));
        hi = hi.max(*q + Vec2::splat(reach));
    }
    (0..pts.len())
        .map(|i| {
            if !pts[i].is_finite() || plane.distance(pts[i]) <= floor {
                return false;
            }
            let q = to2(pts[i]);
            q.cmpge(lo).all()
                && q.cmple(hi).all()
                && (inside_convex(&poly, q)
                    || reach > 0.0 && distance_to_boundary(&poly, q) <= reach)
        })
        .collect()
}

/// On an unorganized cloud with `unorganized_leaf` > 0, one prism point per voxel (the
/// first in index order) carries a normal and is segmented for the others in it: the
/// carriers, and each point's carrier.
pub(super) fn voxel_carriers(
    pts: &[Vec3],
    prism: &[usize],
    organized: bool,
    p: &TabletopParams,
) -> Option<(Vec<usize>, Vec<usize>)> {
    if organized || p.unorganized_leaf <= 0.0 {
        return None;
    }
    let mut first: rustc_hash::FxHashMap<[i64; 3], usize> = Default::default();
    let mut carrier_of = vec![usize::MAX; pts.len()];
    let mut carriers = Vec::new();
    for &i in prism {
        let c = *first
            .entry(voxel_key(pts[i], p.unorganized_leaf))
            .or_insert_with(|| {
                carriers.push(i);
                i
            });
        carrier_of[i] = c;
    }
    Some((carriers, carrier_of))
}

/// Each point's slot in the carriers' local planes: a carrier's own, or its carrier's.
pub(super) fn slots(
    n: usize,
    prism: &[usize],
    (carriers, carrier_of): (&[usize], Option<&Vec<usize>>),
) -> Vec<u32> {
    let mut slot = vec![u32::MAX; n];
    for (k, &i) in carriers.iter().enumerate() {
        slot[i] = k as u32;
    }
    if let Some(carrier_of) = carrier_of {
        for &i in prism {
            slot[i] = slot[carrier_of[i]];
        }
    }
    slot
}
