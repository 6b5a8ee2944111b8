//! The scene model of a tabletop as one frame shows it: the table (its plane and
//! outline) and the objects on it (points, footprint, what each stands on, hull), built
//! by [`tabletop`] from a camera frame — and the geometric tests tasks decide with
//! (hull against hull, hand against hull).

pub mod attempts;
pub mod body;
pub mod observer;
pub mod tabletop;
pub mod target;

pub use attempts::Attempts;
pub use body::robot_solids;
pub use observer::{Observation, Observer};
pub use target::GraspTarget;

/// Why a frame gave no scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The perception pipeline found no table (or no usable points).
    #[error("{0}")]
    Perception(String),
    /// The robot gave no frame.
    #[error("driver: {0}")]
    Driver(String),
}

use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::polygon::{Rectangle, distance_to_boundary, inside_convex};
use tabula_geom::{Pose, Vec2, Vec3};

/// A tabletop object as the predicates see it.
#[derive(Debug, Clone)]
pub struct SeenObject {
    /// Tracked id (stable across frames).
    pub id: usize,
    /// Points seen (world).
    pub points: Vec<Vec3>,
    /// Footprint in the table plane (world xy) and its minimal-area rectangle.
    pub footprint: Vec<Vec2>,
    pub rect: Rectangle,
    /// What it stands on (z of the table, or of the object under it) and its top (m).
    pub bottom: f64,
    pub top: f64,
    /// Convex hull of its points and their projection onto what it stands on (SPEC
    /// §3.1: the camera sees tops, the hull fills in the sides).
    pub hull: SharedShape,
    pub aabb: Aabb,
}

impl SeenObject {
    /// Centre of the footprint at mid-height.
    pub fn center(&self) -> Vec3 {
        Vec3::new(
            self.rect.center.x,
            self.rect.center.y,
            (self.bottom + self.top) / 2.0,
        )
    }

    /// A seen object standing at `bottom`: its hull is its points and their projection
    /// (its outline `footprint`) onto what it stands on (SPEC §3.1: the camera sees
    /// tops, the hull fills in the sides). `None` when the points span no volume.
    pub fn standing(
        points: Vec<Vec3>,
        (footprint, rect): (Vec<Vec2>, Rectangle),
        (bottom, top): (f64, f64),
    ) -> Option<Self> {
        let mut hull_points = points.clone();
        hull_points.extend(footprint.iter().map(|p| Vec3::new(p.x, p.y, bottom)));
        let hull = SharedShape::convex_hull(&hull_points)?;
        let aabb = hull.compute_aabb(&Pose::IDENTITY);
        Some(Self {
            id: usize::MAX,
            points,
            footprint,
            rect,
            bottom,
            top,
            hull,
            aabb,
        })
    }

    /// What a grasp planner sees of it.
    pub fn grasp_target(&self) -> GraspTarget<'_> {
        self.grasp_target_from(None)
    }

    /// What a grasp planner sees of it, reached by an arm whose base is at `arm_base`
    /// (world).
    pub fn grasp_target_from(&self, arm_base: Option<Vec3>) -> GraspTarget<'_> {
        GraspTarget {
            points: &self.points,
            outline: &self.footprint,
            rect: self.rect,
            bottom: self.bottom,
            top: self.top,
            arm_base,
        }
    }

    pub fn height(&self) -> f64 {
        self.top - self.bottom
    }

    /// The object's frame: footprint centre at the bottom, x along the footprint
    /// rectangle's first side, z up.
    pub fn world_from_object(&self) -> Pose {
        let a = self.rect.axis;
        Pose::from_parts(
            Vec3::new(self.rect.center.x, self.rect.center.y, self.bottom),
            tabula_geom::Quat::from_rotation_z(a.y.atan2(a.x)),
        )
    }

    /// A box of the footprint rectangle and height in the object's frame (origin at the
    /// bottom centre): what a collision world carries for it when its hull is too fine.
    pub fn collision_shape(&self) -> (SharedShape, Pose) {
        self.shrunk_shape(0.0)
    }

    /// The collision box shrunk by `by` on every side (at least 2 mm thick): what a
    /// hand that may touch the object must still not sweep through.
    pub fn shrunk_shape(&self, by: f64) -> (SharedShape, Pose) {
        let s = self.rect.size;
        let h = self.height().max(0.005);
        let half = |v: f64| (v / 2.0 - by).max(0.001);
        (
            SharedShape::cuboid(half(s.x), half(s.y), half(h)),
            Pose::from_translation(Vec3::new(0.0, 0.0, h / 2.0)),
        )
    }

    /// Push direction `k` (world, unit).
    pub(crate) fn direction(&self, k: usize) -> Vec2 {
        let (major, minor) = self.rect.principal_axes();
        match k {
            0 => major,
            1 => -major,
            2 => minor,
            _ => -minor,
        }
    }
}

/// The table as one frame sees it.
pub struct Table {
    pub z: f64,
    pub up: Vec3,
    /// Convex outline (world xy).
    pub outline: Vec<Vec2>,
}

impl Table {
    /// The table as a solid for planning: its outline from just below the top down to
    /// the floor (an arm swinging low must not pass under it).
    pub fn prism(&self) -> Option<SharedShape> {
        let body: Vec<Vec3> = self
            .outline
            .iter()
            .flat_map(|p| [p.extend(self.z - 0.005), p.extend(0.0)])
            .collect();
        SharedShape::convex_hull(&body)
    }
}

/// `(on a b)` for every pair: `a`'s bottom is `b`'s top and most of `a`'s points are over
/// `b`'s footprint. An object held up with most of it over neither (a can lying
/// against a box, its low end in the air over the table) is on every object of that
/// height its footprint touches, when it can be taken off first (`takeable`: a grasp
/// fits it): taking one of them first would drop it, and a dropped can rolls. One that
/// cannot be taken stays on nothing, so taking what holds it up is still allowed (a
/// 9 cm box over three others would leave them all on the table, pile seed 129).
pub(crate) fn on_pairs(
    objects: &[SeenObject],
    table_z: f64,
    takeable: &dyn Fn(&SeenObject) -> bool,
) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (i, a) in objects.iter().enumerate() {
        if a.bottom < table_z + 0.01 {
            continue;
        }
        let level: Vec<(usize, &SeenObject)> = objects
            .iter()
            .enumerate()
            .filter(|&(j, b)| i != j && (b.top - a.bottom).abs() <= 0.02)
            .collect();
        let over = |b: &SeenObject| {
            a.points
                .iter()
                .filter(|q| inside_convex(&b.footprint, q.truncate()))
                .count()
        };
        let mostly: Vec<usize> = level
            .iter()
            .filter(|(_, b)| over(b) * 2 > a.points.len())
            .map(|&(j, _)| j)
            .collect();
        let under = if mostly.is_empty() && takeable(a) {
            level
                .iter()
                .filter(|(_, b)| footprints_touch(&a.footprint, &b.footprint, 0.01))
                .map(|&(j, _)| j)
                .collect()
        } else {
            mostly
        };
        out.extend(under.into_iter().map(|j| (i, j)));
    }
    out
}

/// Whether two convex outlines overlap or come within `gap` of each other.
fn footprints_touch(a: &[Vec2], b: &[Vec2], gap: f64) -> bool {
    let near = |p: &[Vec2], q: &[Vec2]| {
        p.iter()
            .any(|&v| inside_convex(q, v) || distance_to_boundary(q, v) < gap)
    };
    near(a, b) || near(b, a)
}

/// A moving shape's clearance test against object hulls: AABB first, then exact.
pub(crate) fn hits(
    shapes: &[(SharedShape, Pose)],
    world_from: &Pose,
    other: &SeenObject,
    pad: f64,
) -> bool {
    shapes.iter().any(|(s, p)| {
        let w = *world_from * *p;
        let aabb = s.compute_aabb(&w).loosened(pad);
        aabb.intersects(&other.aabb)
            && query::distance(&w, s.as_ref(), &Pose::IDENTITY, other.hull.as_ref())
                .is_ok_and(|d| d.distance <= pad)
    })
}

/// Whether two objects' hulls come within `pad` of each other.
pub(crate) fn hulls_touch(a: &SeenObject, b: &SeenObject, pad: f64) -> bool {
    a.aabb.loosened(pad).intersects(&b.aabb)
        && query::distance(
            &Pose::IDENTITY,
            a.hull.as_ref(),
            &Pose::IDENTITY,
            b.hull.as_ref(),
        )
        .is_ok_and(|d| d.distance <= pad)
}

/// Whether a hull moved by `by` runs into another by more than `tolerance`: a neighbour it
/// only grazes (touching objects seen with noise overlap by millimetres already) lets
/// it slide past; one ahead is entered by a whole sweep step.
pub(crate) fn hulls_collide(
    moved: &SeenObject,
    by: Vec3,
    other: &SeenObject,
    tolerance: f64,
) -> bool {
    Aabb::new(moved.aabb.mins + by, moved.aabb.maxs + by).intersects(&other.aabb)
        && query::contact(
            &Pose::from_translation(by),
            moved.hull.as_ref(),
            &Pose::IDENTITY,
            other.hull.as_ref(),
            0.0,
        )
        .ok()
        .flatten()
        .is_some_and(|c| c.dist < -tolerance)
}

/// `o` moved by `by`; its hull too when `with_hull` (a new convex hull: costly).
pub(crate) fn translated(o: &SeenObject, by: Vec3, with_hull: bool) -> SeenObject {
    let mut t = o.clone();
    t.rect.center += by.truncate();
    for p in &mut t.points {
        *p += by;
    }
    for p in &mut t.footprint {
        *p += by.truncate();
    }
    if with_hull {
        // Hulls are kept in world coordinates: a moved copy is rebuilt around its
        // vertices.
        let moved: Vec<Vec3> = hull_vertices(&o.hull).into_iter().map(|p| p + by).collect();
        if let Some(h) = SharedShape::convex_hull(&moved) {
            t.hull = h;
        }
        t.aabb = t.hull.compute_aabb(&Pose::IDENTITY);
    }
    t
}

pub(crate) fn hull_vertices(s: &SharedShape) -> Vec<Vec3> {
    s.as_convex_polyhedron()
        .map(|c| c.points().to_vec())
        .unwrap_or_default()
}
