//! What a grasp planner sees of an object.

use tabula_geom::polygon::Rectangle;
use tabula_geom::{Vec2, Vec3};

/// What a grasp planner sees of an object (world frame): its points, its footprint's
/// convex outline and minimal rectangle on what it stands on, the height of that and of
/// its top — and where the arm reaches from.
#[derive(Debug, Clone, Copy)]
pub struct GraspTarget<'a> {
    pub points: &'a [Vec3],
    pub outline: &'a [Vec2],
    pub rect: Rectangle,
    pub bottom: f64,
    pub top: f64,
    /// The arm's base (world), for planners that turn grasps toward it.
    pub arm_base: Option<Vec3>,
}

impl GraspTarget<'_> {
    /// The object as a solid: its outline (the rectangle without one) from bottom to
    /// top, convex; `None` when that has no volume.
    pub fn solid(&self) -> Option<tabula_geom::parry::shape::SharedShape> {
        let corners;
        let outline = if self.outline.len() >= 3 {
            self.outline
        } else {
            corners = self.rect.corners();
            &corners[..]
        };
        let points: Vec<Vec3> = [self.bottom, self.top]
            .iter()
            .flat_map(|&z| outline.iter().map(move |p| p.extend(z)))
            .collect();
        tabula_geom::parry::shape::SharedShape::convex_hull(&points)
    }

    /// Width of the outline across unit direction `d` (what the fingers must span);
    /// the rectangle's without an outline.
    pub fn width_along(&self, d: Vec2) -> f64 {
        let (lo, hi) = self
            .outline
            .iter()
            .map(|p| p.dot(d))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        if hi >= lo {
            hi - lo
        } else {
            self.rect.extent_along(d)
        }
    }
}
