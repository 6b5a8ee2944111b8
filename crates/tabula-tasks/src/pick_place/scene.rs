//! What the views show: the object near the pick position, the free surface at the
//! target, and the occupancy the planner avoids — with the supports under the object
//! and under the target as exact slabs.

use super::look::Views;
use super::{ObjectReport, PickPlaceError, PickPlaceParams, PickPlaceReport, PickPlaceRequest};
use crate::observe::{ObserveError, Support, object_near, support_under, voxel_keys};
use crate::scene::SeenObject;
use crate::skills::phase::{Clock, timed};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec2, Vec3};
use tabula_motion::{CollisionWorld, MoveError};

/// The object, the target surface and the occupancy around them.
pub(super) struct Scene {
    pub(super) object: SeenObject,
    pub(super) support: Support,
    pub(super) occupancy: Occupancy,
}

/// The collision world's view of the surroundings: occupancy of everything seen,
/// except the supports under the object and under the target, which are exact slabs at
/// their measured height (seed 000 added the found surface to the planning scene) —
/// so the fingers may pass a centimetre above a board, and the slab can be taken away
/// while the object leaves it or arrives on it.
pub(super) struct Occupancy {
    scene: Vec<Vec3>,
    pick_support: Option<(SharedShape, Pose)>,
    place_support: Option<(SharedShape, Pose)>,
}

/// A slab whose top is at `z`, under the seen surface points of a column, kept off
/// the footprint `avoid` (lo, hi): a place spot near the object on the same table
/// gives a slab whose box reaches under the object, which then "touches" the place
/// support as it is lifted.
fn support_slab(
    points: &[Vec3],
    z: f64,
    avoid: Option<(Vec2, Vec2)>,
) -> Option<(SharedShape, Pose)> {
    let near: Vec<Vec2> = points
        .iter()
        .filter(|q| (q.z - z).abs() <= 0.015)
        .map(|q| q.truncate())
        .collect();
    if near.len() < 10 {
        return None;
    }
    let mut lo = near
        .iter()
        .fold(Vec2::splat(f64::INFINITY), |a, b| a.min(*b));
    let mut hi = near
        .iter()
        .fold(Vec2::splat(f64::NEG_INFINITY), |a, b| a.max(*b));
    if let Some(avoid) = avoid {
        clip_off(&mut lo, &mut hi, avoid);
    }
    let half = ((hi - lo) / 2.0).max(Vec2::splat(0.005));
    let thickness = 0.02;
    Some((
        SharedShape::cuboid(half.x, half.y, thickness / 2.0),
        Pose::from_translation(((lo + hi) / 2.0).extend(z - thickness / 2.0)),
    ))
}

/// Shrinks the box `lo..hi` on the side facing the box `avoid` until they no longer
/// overlap (nothing when they do not).
fn clip_off(lo: &mut Vec2, hi: &mut Vec2, (avoid_lo, avoid_hi): (Vec2, Vec2)) {
    let overlaps = lo.x < avoid_hi.x && avoid_lo.x < hi.x && lo.y < avoid_hi.y && avoid_lo.y < hi.y;
    if !overlaps {
        return;
    }
    let toward = (avoid_lo + avoid_hi) / 2.0 - (*lo + *hi) / 2.0;
    match (
        toward.x.abs() >= toward.y.abs(),
        toward.x > 0.0,
        toward.y > 0.0,
    ) {
        (true, true, _) => hi.x = hi.x.min(avoid_lo.x),
        (true, false, _) => lo.x = lo.x.max(avoid_hi.x),
        (false, _, true) => hi.y = hi.y.min(avoid_lo.y),
        (false, _, false) => lo.y = lo.y.max(avoid_hi.y),
    }
    *hi = hi.max(*lo);
}

fn in_column(q: Vec3, center: Vec2, radius: f64, z: f64) -> bool {
    (q.truncate() - center).length() <= radius && q.z >= z - 0.06 && q.z <= z + 0.03
}

pub(super) fn add_occupancy(
    world: &mut CollisionWorld,
    o: &Occupancy,
    voxel: f64,
) -> Result<(), MoveError> {
    world.add_occupancy("scene", &o.scene, voxel)?;
    // Absent slabs are empty placeholders, so stages can always remove them by name.
    let nothing = || {
        (
            SharedShape::ball(1e-6),
            Pose::from_translation(Vec3::splat(1e6)),
        )
    };
    for (name, slab) in [
        ("pick_support", &o.pick_support),
        ("place_support", &o.place_support),
    ] {
        let (shape, pose) = slab.clone().unwrap_or_else(nothing);
        world.add_object(name, shape, pose)?;
    }
    Ok(())
}

/// Finds the object and the target surface in `views` (each a phase of `report`) and
/// builds the occupancy around them.
pub(super) fn perceive(
    views: &Views,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
    report: &mut PickPlaceReport,
) -> Result<Scene, PickPlaceError> {
    let obs = &params.observe;
    let object = timed(
        &mut report.phases,
        "pick-place",
        "perceive object",
        Clock::Cpu,
        || {
            object_near(&views.points, request.pick, obs).map_err(|e| match e {
                ObserveError::NoSurface(..) | ObserveError::NoObject(..) => {
                    PickPlaceError::ObjectNotFound(e.to_string())
                }
            })
        },
    )?;
    report.object = Some(ObjectReport {
        position: object.world_from_object().translation.to_array(),
        size: [object.rect.size.x, object.rect.size.y, object.height()],
        points: object.points.len(),
    });
    let near_object = near(&object, obs.cluster_gap);
    let others: Vec<Vec3> = views
        .points
        .iter()
        .copied()
        .filter(|q| !near_object(q))
        .collect();
    let solid = solid_points(views, &near_object, params);
    let support = timed(
        &mut report.phases,
        "pick-place",
        "perceive target",
        Clock::Cpu,
        || free_support(&others, &object, request, params),
    )?;
    report.target_surface = Some(support.z);
    let occupancy = occupancy(&object, &support, &others, &solid, request);
    Ok(Scene {
        object,
        support,
        occupancy,
    })
}

/// Whether a point is within a cluster gap of the object's points.
fn near(object: &SeenObject, gap: f64) -> impl Fn(&Vec3) -> bool + use<> {
    let object_keys = voxel_keys(&object.points, gap);
    // A box around the object first: most points are nowhere near it.
    let (lo, hi) = tabula_geom::bounds(&object.points);
    let (lo, hi) = (lo - Vec3::splat(2.0 * gap), hi + Vec3::splat(2.0 * gap));
    move |q: &Vec3| {
        if q.cmplt(lo).any() || q.cmpgt(hi).any() {
            return false;
        }
        let k = tabula_geom::voxel_key(*q, gap);
        (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                (-1..=1).any(|dz| object_keys.contains(&[k[0] + dx, k[1] + dy, k[2] + dz]))
            })
        })
    }
}

/// Everything seen but the object, made solid for a few centimetres behind each seen
/// surface (a shelf's side panel seen only by its front edge, a board seen from above,
/// are thick). Occupancy needs no more than a few points per voxel: they are thinned
/// first (the views overlap, and the perception leaf is finer than the collision
/// voxel).
fn solid_points(
    views: &Views,
    near_object: &dyn Fn(&Vec3) -> bool,
    params: &PickPlaceParams,
) -> Vec<Vec3> {
    let obs = &params.observe;
    let mut keep = rustc_hash::FxHashSet::default();
    let cell = obs.voxel / 2.0;
    views
        .points
        .iter()
        .zip(&views.origins)
        .filter(|(q, _)| keep.insert(tabula_geom::voxel_key(**q, cell)) && !near_object(q))
        .flat_map(|(q, o)| {
            let ray = (*q - *o).normalize_or(Vec3::ZERO);
            obs.thickness_steps(*q, ray)
        })
        .collect()
}

/// The surface under the target, free: nothing stands within the object's footprint
/// (and margin) there.
fn free_support(
    others: &[Vec3],
    object: &SeenObject,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
) -> Result<Support, PickPlaceError> {
    let obs = &params.observe;
    let s = support_under(others, request.place, request.place.z + 0.03, obs).ok_or_else(|| {
        PickPlaceError::NoSurface(format!(
            "nothing horizontal under ({:.3}, {:.3}, {:.3})",
            request.place.x, request.place.y, request.place.z
        ))
    })?;
    let radius = object.rect.size.length() / 2.0 + params.place_margin;
    let blocking: Vec<Vec3> = others
        .iter()
        .copied()
        .filter(|q| {
            (q.truncate() - request.place.truncate()).length() <= radius
                && q.z > s.z + obs.object_clearance + 0.01
                && q.z < s.z + object.height()
        })
        .collect();
    if blocking.len() >= obs.min_object_points / 2 {
        let c = blocking.iter().sum::<Vec3>() / blocking.len() as f64;
        return Err(PickPlaceError::TargetOccupied {
            points: blocking.len(),
            at: c.to_array(),
        });
    }
    Ok(s)
}

/// The solid scene but the columns over the object and the target, whose supports
/// become slabs.
fn occupancy(
    object: &SeenObject,
    support: &Support,
    others: &[Vec3],
    solid: &[Vec3],
    request: &PickPlaceRequest,
) -> Occupancy {
    let column_radius = object.rect.size.length() / 2.0 + 0.04;
    let pick_xy = object.rect.center;
    // Beyond the planner's padding (1 cm) around the held object.
    let margin = Vec2::splat(0.025);
    let footprint = (
        object.aabb.mins.truncate() - margin,
        object.aabb.maxs.truncate() + margin,
    );
    let place_xy = request.place.truncate();
    let in_pick = |q: &Vec3| in_column(*q, pick_xy, column_radius, object.bottom);
    let in_place = |q: &Vec3| in_column(*q, place_xy, column_radius, support.z);
    let pick_column: Vec<Vec3> = others.iter().copied().filter(|q| in_pick(q)).collect();
    let place_column: Vec<Vec3> = others
        .iter()
        .copied()
        .filter(|q| in_place(q) && !in_pick(q))
        .collect();
    Occupancy {
        scene: solid
            .iter()
            .copied()
            .filter(|q| !in_pick(q) && !in_place(q))
            .collect(),
        pick_support: support_slab(&pick_column, object.bottom, None),
        place_support: support_slab(&place_column, support.z, Some(footprint)),
    }
}
