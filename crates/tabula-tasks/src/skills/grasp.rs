//! Grasp planners: where a parallel gripper can hold an object seen from above. One
//! trait ([`GraspPlanner`]) with a planner per kind of grasp, so a task chooses and
//! orders them and a new planner needs no change to the tasks.
//!
//! * [`TopGrasps`]: the whole object from above, closing across its footprint's
//!   principal axis, then the other one (SPEC §3.2), full depth then shallow.
//! * [`NarrowPartGrasps`]: an object too wide to take whole, by its narrow parts.
//! * [`Fallback`]: one planner's grasps, or another's when it has none.

use super::hand::{Hand, extent_along};
use tabula_geom::polygon::Rectangle;
use tabula_geom::{Pose, Vec2, Vec3};

/// What a grasp planner sees of an object (world frame): its points, its footprint's
/// minimal rectangle on what it stands on, the height of that and of its top.
#[derive(Debug, Clone, Copy)]
pub struct GraspTarget<'a> {
    pub points: &'a [Vec3],
    pub rect: Rectangle,
    pub bottom: f64,
    pub top: f64,
}

/// A grasp: where the tool goes and how far the fingers open before it approaches.
#[derive(Debug, Clone)]
pub struct GraspCandidate {
    /// `world_from_tool` at the grasp, and the same grasp with the fingers the other way
    /// round (a parallel gripper holds either way; the arm may reach only one).
    pub poses: [Pose; 2],
    /// The finger gap (m) the gripper opens to before it approaches.
    pub width: f64,
}

/// A source of grasps.
pub trait GraspPlanner {
    /// Grasps of `target`, best first, the approach pointing against `up` (the support's
    /// normal, world); empty when none fits the hand.
    fn candidates(&self, target: &GraspTarget<'_>, hand: &Hand, up: Vec3) -> Vec<GraspCandidate>;
}

/// How deep a top grasp holds and how it meets its neighbours (SPEC §3.2 and §6; the
/// clearing parameters of the same names fill it).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TopGrasps {
    /// The closing point lies this far below the object's top (m): SPEC §3.2's
    /// "lowered by half the finger height" with SPEC §6's 6 cm fingers.
    pub depth: f64,
    /// Fingertips stay at least this far above what the object stands on (m).
    pub fingertip_clearance: f64,
    /// The opening must exceed the object's width by this much on each side (m).
    pub margin: f64,
    /// The fingers open to the object's width plus this on each side (m).
    pub pregrasp_gap: f64,
    /// The same grasps held only this deep below the top come after the full-depth
    /// ones (m): their fingertips pass over lower neighbours.
    pub shallow_grip: f64,
}

impl Default for TopGrasps {
    fn default() -> Self {
        Self {
            depth: 0.03,
            fingertip_clearance: 0.01,
            margin: 0.0,
            pregrasp_gap: 0.01,
            shallow_grip: 0.02,
        }
    }
}

impl TopGrasps {
    /// Fingertip height for a grasp of something whose top is at `top`.
    fn tip_z(&self, target: &GraspTarget<'_>, hand: &Hand, top: f64) -> f64 {
        (top - self.depth - hand.finger_length / 2.0).max(target.bottom + self.fingertip_clearance)
    }

    /// A top grasp with the fingertips at `tips`, closing along `closing` across
    /// something `across` wide.
    fn at(&self, hand: &Hand, up: Vec3, tips: Vec3, closing: Vec2, across: f64) -> GraspCandidate {
        let closing = Vec3::new(closing.x, closing.y, 0.0);
        GraspCandidate {
            poses: [hand.pose(tips, closing, up), hand.pose(tips, -closing, up)],
            width: hand.open_for(across + 2.0 * self.pregrasp_gap).0,
        }
    }
}

impl GraspPlanner for TopGrasps {
    /// Closing across the principal axis, then across the other one when the object
    /// fits that way too (a square box can be taken either way: one may be free of a
    /// neighbour); the same held `shallow_grip` deep after them.
    fn candidates(&self, target: &GraspTarget<'_>, hand: &Hand, up: Vec3) -> Vec<GraspCandidate> {
        let (major, minor) = target.rect.principal_axes();
        let rect = &target.rect;
        let fits: Vec<Vec2> = [minor, major]
            .into_iter()
            .filter(|&c| rect.extent_along(c) + 2.0 * self.margin <= hand.open_width)
            .collect();
        let deep = self.tip_z(target, hand, target.top);
        let at_height = |z: f64| {
            fits.iter().map(move |&c| {
                let tips = Vec3::new(rect.center.x, rect.center.y, z);
                self.at(hand, up, tips, c, rect.extent_along(c))
            })
        };
        let mut out: Vec<GraspCandidate> = at_height(deep).collect();
        let shallow = target.top - self.shallow_grip;
        if shallow > deep + 0.01 {
            out.extend(at_height(shallow));
        }
        out
    }
}

/// Grasps of the narrow parts of an object too wide to take whole: slices across its
/// principal axis, a finger's width and a few millimetres, whose points fit the
/// gripper — narrowest first, at most three. A blob wider than the gripper is often
/// two objects the camera cannot tell apart (touching, tops level); taking one part
/// first lets the next frame see the other alone.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NarrowPartGrasps {
    /// Depth, clearance, margin and opening as for whole objects.
    pub top: TopGrasps,
}

/// A slice of an object that fits the hand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// Where the fingers close (world xy) and the slice's top (m).
    pub at: Vec2,
    pub top: f64,
    /// Its width across the principal axis (m).
    pub width: f64,
}

impl NarrowPartGrasps {
    /// The parts that fit, narrowest first, at most three.
    pub fn parts(&self, target: &GraspTarget<'_>, hand: &Hand) -> Vec<Part> {
        let (major, minor) = target.rect.principal_axes();
        let c = target.rect.center;
        let local: Vec<(f64, f64, f64)> = target
            .points
            .iter()
            .map(|p| {
                let d = p.truncate() - c;
                (d.dot(major), d.dot(minor), p.z)
            })
            .collect();
        let half = target.rect.extent_along(major) / 2.0;
        let (finger_lo, finger_hi) =
            extent_along(&hand.open_fingers, hand.closing.cross(hand.approach));
        let window = (finger_hi - finger_lo) / 2.0 + 0.003;
        let mut found: Vec<Part> = Vec::new();
        // Slice centres every centimetre from one end to the other, both ends included.
        let span = (2.0 * (half - window)).max(0.0);
        let steps = (span / 0.01).ceil() as usize;
        for k in 0..=steps {
            let t = -half + window + span * k as f64 / steps.max(1) as f64;
            let (lo, hi, top, count) = local.iter().filter(|q| (q.0 - t).abs() <= window).fold(
                (f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY, 0usize),
                |(lo, hi, top, n), q| (lo.min(q.1), hi.max(q.1), top.max(q.2), n + 1),
            );
            let width = hi - lo;
            if count >= 20 && width + 2.0 * self.top.margin <= hand.open_width {
                let at = c + major * t + minor * ((lo + hi) / 2.0);
                found.push(Part { at, top, width });
            }
        }
        found.sort_by(|a, b| a.width.total_cmp(&b.width));
        found.truncate(3);
        found
    }
}

impl GraspPlanner for NarrowPartGrasps {
    fn candidates(&self, target: &GraspTarget<'_>, hand: &Hand, up: Vec3) -> Vec<GraspCandidate> {
        let (_, minor) = target.rect.principal_axes();
        self.parts(target, hand)
            .into_iter()
            .map(|p| {
                let tips = p.at.extend(self.top.tip_z(target, hand, p.top));
                self.top.at(hand, up, tips, minor, p.width)
            })
            .collect()
    }
}

/// The first planner's grasps, or the second's when the first has none.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Fallback<A, B>(pub A, pub B);

impl<A: GraspPlanner, B: GraspPlanner> GraspPlanner for Fallback<A, B> {
    fn candidates(&self, target: &GraspTarget<'_>, hand: &Hand, up: Vec3) -> Vec<GraspCandidate> {
        let first = self.0.candidates(target, hand, up);
        if first.is_empty() {
            self.1.candidates(target, hand, up)
        } else {
            first
        }
    }
}
