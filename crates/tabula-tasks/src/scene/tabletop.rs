//! One frame in, the table and its objects out: the robot's own body filtered from the
//! cloud, the tabletop pipeline, and for each object what it stands on and its hull.

use super::robot_solids;
use super::{SceneError, SeenObject, Table};
use tabula_geom::polygon::{
    Rectangle, convex_hull_2d, distance_to_boundary, inside_convex, min_area_rectangle,
};
use tabula_geom::{PointCloud, Pose, Vec2, Vec3};
use tabula_perception::selffilter::{SelfFilterParams, self_filter};
use tabula_perception::tabletop::{TabletopParams, extract};
use tabula_robot::driver::{CameraFrame, JointState};
use tabula_robot::robots::NamedRobot;

/// An object segment's points (world), its footprint, the footprint's rectangle and
/// its top.
struct Segment {
    points: Vec<Vec3>,
    footprint: Vec<Vec2>,
    rect: Rectangle,
    top: f64,
}

/// Perceives the table and its objects in a frame (world-frame cloud, organized or not).
pub(crate) fn perceive(
    cloud: &PointCloud,
    viewpoint: Vec3,
    tabletop: &TabletopParams,
) -> Result<(Table, Vec<SeenObject>), SceneError> {
    let top =
        extract(cloud, viewpoint, tabletop).map_err(|e| SceneError::Perception(e.to_string()))?;
    if tracing::enabled!(tracing::Level::DEBUG) {
        tracing::debug!("tabletop stages (ms): {:?}", top.times);
    }
    let up = top.plane.normal;
    let height_at = |p: Vec2| -> f64 {
        // Table plane: n·x + d = 0, solved for z.
        let n = top.plane.normal;
        if n.z.abs() < 1e-6 {
            return f64::NAN;
        }
        -(top.plane.d + n.x * p.x + n.y * p.y) / n.z
    };
    let mut idx: Vec<usize> = convex_hull_2d(
        &top.table
            .hull
            .iter()
            .map(|q| q.truncate())
            .collect::<Vec<_>>(),
    );
    if idx.is_empty() {
        idx = (0..top.table.hull.len()).collect();
    }
    let outline: Vec<Vec2> = idx.iter().map(|&i| top.table.hull[i].truncate()).collect();
    let table_z = height_at(top.table.centroid.truncate());
    let segments: Vec<Segment> = top
        .objects
        .iter()
        .filter_map(|o| segment(cloud, &o.indices))
        .collect();
    let mut objects = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        let table_here = height_at(s.rect.center);
        let on_table = if table_here.is_finite() {
            table_here
        } else {
            table_z
        };
        let bottom = standing_on(&segments, i, on_table, tabletop.min_stacked_height);
        if let Some(o) = seen_object(s, bottom) {
            objects.push(o);
        }
    }
    Ok((
        Table {
            z: table_z,
            up: if up.z < 0.0 { -up } else { up },
            outline,
        },
        objects,
    ))
}

/// The finite points of `indices`, their footprint and its rectangle; `None` for a
/// footprint without area.
fn segment(cloud: &PointCloud, indices: &[usize]) -> Option<Segment> {
    let points: Vec<Vec3> = indices
        .iter()
        .map(|&i| cloud.points[i])
        .filter(|q| q.is_finite())
        .collect();
    Segment::of(points)
}

impl Segment {
    /// `points` with their footprint, its rectangle and their top; `None` for a
    /// footprint without area.
    fn of(points: Vec<Vec3>) -> Option<Segment> {
        let flat: Vec<Vec2> = points.iter().map(|q| q.truncate()).collect();
        let hull = convex_hull_2d(&flat);
        let footprint: Vec<Vec2> = hull.iter().map(|&i| flat[i]).collect();
        let rect = min_area_rectangle(&footprint)?;
        let top = points.iter().map(|q| q.z).fold(f64::NEG_INFINITY, f64::max);
        Some(Segment {
            points,
            footprint,
            rect,
            top,
        })
    }
}

/// The object `points` make standing at `bottom` (a part of a segment split apart).
pub(crate) fn seen_standing(points: Vec<Vec3>, bottom: f64) -> Option<SeenObject> {
    seen_object(&Segment::of(points)?, bottom)
}

/// The height segment `i` stands on: the table (`table_z` under it), or an object whose
/// footprint holds most of its points and whose top is near its lowest point (seed eq.
/// 4.2's overlap test, with shares instead of its 100-point counts so it holds at any
/// resolution).
fn standing_on(segments: &[Segment], i: usize, table_z: f64, min_stacked_height: f64) -> f64 {
    let s = &segments[i];
    let lowest = s.points.iter().map(|q| q.z).fold(f64::INFINITY, f64::min);
    if lowest <= table_z + 0.015 {
        return table_z;
    }
    let candidates: Vec<&Segment> = segments
        .iter()
        .enumerate()
        .filter(|(j, r)| *j != i && r.top < lowest + 0.02 && r.top > table_z + 0.01)
        .map(|(_, r)| r)
        .collect();
    let highest = |rs: &mut dyn Iterator<Item = f64>| rs.fold(f64::NEG_INFINITY, f64::max);
    let mut under = highest(&mut candidates.iter().filter_map(|r| {
        let inside = s
            .points
            .iter()
            .filter(|q| inside_convex(&r.footprint, q.truncate()))
            .count();
        (inside as f64 / s.points.len().max(1) as f64 > 0.5).then_some(r.top)
    }));
    if !under.is_finite() {
        // Held up by something whose top it hides: the seen part of that footprint
        // only reaches to its edge. It stands a whole object's height above that top (a
        // segment seen only by its top face is no higher than its neighbours and
        // stands on the table).
        under = highest(&mut candidates.iter().filter_map(|r| {
            (r.top <= s.top - min_stacked_height
                && s.footprint.iter().any(|&p| {
                    inside_convex(&r.footprint, p) || distance_to_boundary(&r.footprint, p) < 0.01
                }))
            .then_some(r.top)
        }));
    }
    if under.is_finite() { under } else { table_z }
}

/// The object a segment standing at `bottom` is (see [`SeenObject::standing`]).
fn seen_object(s: &Segment, bottom: f64) -> Option<SeenObject> {
    SeenObject::standing(
        s.points.clone(),
        (s.footprint.clone(), s.rect),
        (bottom, s.top),
    )
}

/// The frame's cloud in the world frame, decimated to every `decimate`-th pixel of
/// every `decimate`-th row, with the robot's own body (padded by `padding`, SPEC §1.1)
/// set to NaN so the cloud stays organized.
pub(crate) fn filtered_cloud(
    frame: &CameraFrame,
    robot: &NamedRobot,
    state: &JointState,
    world_from_root: Pose,
    decimate: usize,
    padding: f64,
) -> PointCloud {
    let solids = robot_solids(
        &robot.model,
        &state.model_values(&robot.model),
        world_from_root,
    );
    let mut cloud = frame
        .cloud
        .decimated(decimate)
        .transformed(&frame.world_from_camera);
    let keep = self_filter(&cloud.points, &solids, &SelfFilterParams { padding });
    for (q, k) in cloud.points.iter_mut().zip(keep) {
        if !k {
            *q = Vec3::NAN;
        }
    }
    cloud
}
