//! Grasp planners: where a parallel gripper can hold an object seen from above. One
//! trait ([`GraspPlanner`]) with a planner per kind of grasp, so a task chooses and
//! orders them and a new planner needs no change to the tasks.
//!
//! * [`TopGrasps`]: the whole object from above, closing across its footprint's
//!   principal axis, then the other one (SPEC §3.2), full depth then shallow.
//! * [`NarrowPartGrasps`]: an object too wide to take whole, by its narrow parts.
//! * [`SideGrasps`]: from the side, level or tilted down, turned toward the arm (and
//!   from above after them) — what a shelf leaves.
//! * [`Fallback`]: one planner's grasps, or another's when it has none.

use super::hand::{Hand, extent_along, tool_rotation};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec2, Vec3};

pub use crate::scene::GraspTarget;

/// How a grasp approaches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GraspKind {
    /// Approach horizontal (or tilted down a little), fingers closing horizontally.
    Side,
    /// Approach from above.
    Top,
}

/// A grasp: where the tool goes and how far the fingers open before it approaches.
#[derive(Debug, Clone)]
pub struct GraspCandidate {
    pub kind: GraspKind,
    /// `world_from_tool` at the grasp, and the same grasp with the fingers the other way
    /// round (a parallel gripper holds either way; the arm may reach only one).
    pub poses: [Pose; 2],
    /// Approach direction (world, unit).
    pub approach: Vec3,
    /// The finger gap (m) the gripper opens to before it approaches.
    pub width: f64,
}

impl GraspCandidate {
    /// `world_from_tool` at the grasp (the first way round).
    pub fn world_from_tool(&self) -> Pose {
        self.poses[0]
    }
}

/// A source of grasps.
pub trait GraspPlanner {
    /// Grasps of `target`, best first, the approach pointing against `up` (the support's
    /// normal, world); empty when none fits the hand.
    fn candidates(&self, target: &GraspTarget<'_>, hand: &Hand, up: Vec3) -> Vec<GraspCandidate>;
}

/// How deep a top grasp holds and how it meets its neighbours (SPEC §3.2 and §6; the
/// clearing parameters of the same names fill it).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct TopGrasps {
    /// The closing point lies this far below the object's top (m): SPEC §3.2's
    /// "lowered by half the finger height" with SPEC §6's 6 cm fingers.
    pub depth: f64,
    /// Fingertips stay at least this far above what the object stands on (m).
    pub fingertip_clearance: f64,
    /// The opening must exceed the object's width by this much on each side (m).
    pub margin: f64,
    /// A closing direction whose full opening leaves less than this on each side of the
    /// seen width (m) is offered only for an object no roomier direction holds: the
    /// camera sees an object a few millimetres narrower than it is (its edges fall
    /// between pixels), so a prism seen 6.9 cm long in a 7 cm hand is 7.07 cm and the
    /// fingers land on its ends. Not in the seed.
    pub snug_room: f64,
    /// The fingers open to the object's width plus this on each side (m).
    pub pregrasp_gap: f64,
    /// The same grasps held only this deep below the top come after the full-depth
    /// ones (m): their fingertips pass over lower neighbours.
    pub shallow_grip: f64,
}

impl tabula_geom::input::Validate for TopGrasps {
    fn check(&self, at: &str) -> Result<(), String> {
        for (name, v) in [
            ("depth", self.depth),
            ("fingertip_clearance", self.fingertip_clearance),
            ("margin", self.margin),
            ("snug_room", self.snug_room),
            ("pregrasp_gap", self.pregrasp_gap),
            ("shallow_grip", self.shallow_grip),
        ] {
            // Lengths of a hand: a metre is already no gripper's.
            tabula_geom::input::check_in(at, name, v, 0.0, 1.0)?;
        }
        Ok(())
    }
}

impl Default for TopGrasps {
    fn default() -> Self {
        Self {
            depth: 0.03,
            fingertip_clearance: 0.01,
            margin: 0.0,
            snug_room: 0.0015,
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
            kind: GraspKind::Top,
            poses: [hand.pose(tips, closing, up), hand.pose(tips, -closing, up)],
            approach: -up,
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
        let mut fits: Vec<Vec2> = [minor, major]
            .into_iter()
            .filter(|&c| hand.holds(rect.extent_along(c), self.margin))
            .collect();
        let roomy = |c: &Vec2| hand.holds(rect.extent_along(*c), self.margin.max(self.snug_room));
        if fits.iter().any(roomy) {
            fits.retain(roomy);
        }
        let deep = self.tip_z(target, hand, target.top);
        let at_height = |z: f64| {
            // The fingers stop on the widest of what is between them anywhere from
            // their tips up; they hold where the pads overlap it.
            let [from_tips, between] = Between::above(target, [z, z + PAD_OVERLAP]);
            fits.iter().flat_map(move |&c| {
                let (Some(t), Some(b)) = (&from_tips, &between) else {
                    return vec![self.at(hand, up, rect.center.extend(z), c, rect.extent_along(c))];
                };
                // What is between the fingers is too narrow to hold: they would close
                // past it.
                if hand.passes(t.extent_along(c)) {
                    return Vec::new();
                }
                // Along the pads the fingers must be where the points are (they are a
                // finger wide). Across, fingers centred on the points meet them at once
                // (a leaning object is not shoved over), but must open wider to pass the
                // whole footprint; closing over the footprint's middle centres the object
                // between them with a narrower hand — the one to take beside close
                // neighbours.
                let along_pads = c.perp();
                let pads_middle =
                    rect.center + along_pads * (b.centre - rect.center).dot(along_pads);
                let off_centre = (b.centre - rect.center).dot(c).abs();
                let mut out = Vec::with_capacity(2);
                let across = rect.extent_along(c) + 2.0 * off_centre;
                if hand.holds(across, self.margin) {
                    out.push(self.at(hand, up, b.centre.extend(z), c, across));
                }
                if off_centre > SELF_CENTRING || out.is_empty() {
                    out.push(self.at(hand, up, pads_middle.extend(z), c, rect.extent_along(c)));
                }
                out
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

/// The pads hold what lies at least this far (m) above their tips.
const PAD_OVERLAP: f64 = 0.005;
/// Points this far (m) off the footprint's middle across the fingers are held where
/// they are, and also where closing centres them: below it the two grasps are one.
const SELF_CENTRING: f64 = 0.002;
/// Fewer points than this between the pads say nothing of where the object is there.
const MIN_POINTS_BETWEEN: usize = 10;

/// The seen points of an object above a top grasp's fingertips, in its footprint
/// rectangle's axes: where the pads will meet it. For an upright object that is the
/// footprint's middle; for one that leans it is off it — a box tilted 50° has only its
/// upper corner above a shallow grasp's tips, 3 cm from the footprint's centre, and
/// fingers closed over the centre met nothing (pile seed 65).
struct Between {
    centre: Vec2,
    axes: [Vec2; 2],
    size: [f64; 2],
}

impl Between {
    /// The points above each of `heights`, in one pass over them (the decision asks
    /// for every grasp of every pushed copy of an object); `None` where too few lie
    /// above to tell.
    fn above<const N: usize>(target: &GraspTarget<'_>, heights: [f64; N]) -> [Option<Self>; N] {
        let rect = &target.rect;
        let axes = [
            rect.axis.normalize_or(Vec2::X),
            rect.axis.normalize_or(Vec2::X).perp(),
        ];
        let mut lo = [[f64::INFINITY; 2]; N];
        let mut hi = [[f64::NEG_INFINITY; 2]; N];
        let mut n = [0usize; N];
        for p in target.points.iter().filter(|p| p.z.is_finite()) {
            let t = [axes[0].dot(p.truncate()), axes[1].dot(p.truncate())];
            for h in (0..N).filter(|&h| p.z >= heights[h]) {
                n[h] += 1;
                for k in 0..2 {
                    lo[h][k] = lo[h][k].min(t[k]);
                    hi[h][k] = hi[h][k].max(t[k]);
                }
            }
        }
        std::array::from_fn(|h| {
            let (lo, hi) = (lo[h], hi[h]);
            (n[h] >= MIN_POINTS_BETWEEN).then(|| Self {
                centre: axes[0] * (lo[0] + hi[0]) / 2.0 + axes[1] * (lo[1] + hi[1]) / 2.0,
                axes,
                size: [hi[0] - lo[0], hi[1] - lo[1]],
            })
        })
    }

    /// Width along `d` (unit) of the rectangle the points span.
    fn extent_along(&self, d: Vec2) -> f64 {
        self.size[0] * self.axes[0].dot(d).abs() + self.size[1] * self.axes[1].dot(d).abs()
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
            if count >= 20 && hand.holds(width, self.top.margin) {
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

/// Side grasps around the direction from the arm to the object — the approach level or
/// tilted down a little, the grasp point a little deeper or shallower, higher or lower
/// (an arm with few joints reaches some of these and not others) — then top grasps,
/// ordered by how far each turns and tilts from the straight level one (seed 001's pick
/// and place, SPEC §2.5).
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SideGrasps {
    /// Room left between each open finger and the object (m).
    pub finger_clearance: f64,
    /// … or less, down to this, for an object that leaves the open hand less room
    /// (a 6 cm box in the Panda's 8 cm hand); such grasps rank after roomier ones (m).
    pub min_finger_clearance: f64,
    /// The tool point stays at least this far above the support (m).
    pub min_grasp_height: f64,
    /// Approach yaws within ± this of the direction from the arm (rad) …
    pub yaw_range: f64,
    /// … this far apart (rad).
    pub yaw_step: f64,
    /// Downward tilts of the approach (rad).
    pub tilts: Vec<f64>,
    /// The grasp point may also sit this far deeper (+) or shallower (−) along the
    /// approach than the object's centre (m).
    pub depth_offsets: Vec<f64>,
    /// Top grasps follow the side grasps.
    pub top: bool,
}

/// A side grasp's fingertips reach at least this far past the object's near face (m).
const MIN_PAD_OVERLAP: f64 = 0.01;

impl Default for SideGrasps {
    fn default() -> Self {
        Self {
            finger_clearance: 0.01,
            min_finger_clearance: 0.005,
            min_grasp_height: 0.035,
            yaw_range: 1.5,
            yaw_step: 0.05,
            tilts: vec![0.0, 0.2, 0.4],
            depth_offsets: vec![0.015, -0.01],
            top: true,
        }
    }
}

impl SideGrasps {
    /// The yaw steps tried on either side of the facing direction.
    fn steps(&self) -> i64 {
        (self.yaw_range / self.yaw_step.max(1e-3)).ceil() as i64
    }

    /// The direction (rad) from the arm's base to the object.
    fn facing(target: &GraspTarget<'_>) -> f64 {
        let toward = target.rect.center - target.arm_base.unwrap_or(Vec3::ZERO).truncate();
        toward.y.atan2(toward.x)
    }

    /// The room left between each open finger and an object `across` wide: the
    /// nominal clearance, else what the hand leaves if that is at least the minimum.
    fn clearance(&self, hand: &Hand, across: f64) -> Option<f64> {
        if hand.holds(across, self.finger_clearance) {
            return Some(self.finger_clearance);
        }
        let room = (hand.open_width - across) / 2.0;
        (room < self.finger_clearance && hand.holds(across, self.min_finger_clearance))
            .then_some(room)
    }

    /// The narrowest width of the object across any closing direction tried (m): when
    /// even that does not fit, the object is too wide for the hand.
    pub fn narrowest(&self, target: &GraspTarget<'_>) -> f64 {
        let facing = Self::facing(target);
        (-self.steps()..=self.steps())
            .map(|k| {
                let yaw = facing + k as f64 * self.yaw_step;
                target.width_along(Vec2::new(-yaw.sin(), yaw.cos()))
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Offsets (along the approach, up) of the grasp point from the object's centre
    /// line.
    fn offsets(&self, kind: GraspKind, height: f64) -> Vec<(f64, f64)> {
        let mut out = vec![(0.0, 0.0)];
        out.extend(self.depth_offsets.iter().map(|&d| (d, 0.0)));
        if kind == GraspKind::Side && height > 2.0 * self.min_grasp_height + 0.03 {
            for d in [0.0, self.depth_offsets.first().copied().unwrap_or(0.0)] {
                out.push((d, 0.015));
                out.push((d, -0.015));
            }
        }
        out
    }
}

impl GraspPlanner for SideGrasps {
    fn candidates(&self, target: &GraspTarget<'_>, hand: &Hand, up: Vec3) -> Vec<GraspCandidate> {
        let c = target.rect.center;
        let facing = Self::facing(target);
        let h = target.top - target.bottom;
        let side_z = target.bottom + (h / 2.0).max(self.min_grasp_height);
        // From above the palm stays above the top as it does beside the object below.
        let palm_behind = hand.beyond_palm - hand.tip;
        let top_z = (target.bottom + (h - 0.03).max(self.min_grasp_height))
            .max(target.top - palm_behind + self.finger_clearance);
        let tops = self
            .top
            .then_some((GraspKind::Top, std::f64::consts::FRAC_PI_2, top_z));
        let solid = target.solid().filter(|_| !hand.palm.is_empty());
        let mut scored: Vec<(f64, GraspCandidate)> = Vec::new();
        for k in -self.steps()..=self.steps() {
            let yaw = facing + k as f64 * self.yaw_step;
            let closing = Vec2::new(-yaw.sin(), yaw.cos());
            let across = target.width_along(closing);
            let Some(clearance) = self.clearance(hand, across) else {
                continue;
            };
            let c3 = closing.extend(0.0);
            let kinds = self
                .tilts
                .iter()
                .map(|&t| (GraspKind::Side, t, side_z))
                .chain(tops);
            // Not so shallow that the pads miss the object.
            let near_side = target.width_along(Vec2::new(yaw.cos(), yaw.sin())) / 2.0;
            let shallowest = MIN_PAD_OVERLAP - near_side - hand.tip;
            for (kind, tilt, z) in kinds {
                let a = Vec3::new(yaw.cos() * tilt.cos(), yaw.sin() * tilt.cos(), -tilt.sin());
                let r = tool_rotation(hand.approach, hand.closing, a, c3);
                let turned = tool_rotation(hand.approach, hand.closing, a, -c3);
                let mut offsets = self.offsets(kind, h);
                if kind == GraspKind::Side {
                    // The palm stays outside the object: a side grasp goes no deeper
                    // than the palm meets it (tilted down, the palm's lower edge leads).
                    limit_depths(&mut offsets, shallowest, |rise| {
                        let at = c.extend(z) + up * rise;
                        let palm_meets = match &solid {
                            Some(solid) => palm_limit(hand, solid, Pose::from_parts(at, r), a),
                            None => palm_behind - near_side,
                        };
                        palm_meets - clearance
                    });
                    offsets.dedup();
                }
                for (depth, rise) in offsets {
                    let at = c.extend(z) + a * depth + up * rise;
                    let score = k.unsigned_abs() as f64 * self.yaw_step
                        + tilt
                        + 2.0 * (depth.abs() + rise.abs())
                        + 20.0 * (self.finger_clearance - clearance)
                        + if kind == GraspKind::Top { 0.5 } else { 0.0 };
                    let grasp = GraspCandidate {
                        kind,
                        poses: [Pose::from_parts(at, r), Pose::from_parts(at, turned)],
                        approach: a,
                        width: hand.open_width,
                    };
                    scored.push((score, grasp));
                }
            }
        }
        // Stable: equal scores keep the order they were made in.
        scored.sort_by(|a, b| a.0.total_cmp(&b.0));
        scored.into_iter().map(|(_, g)| g).collect()
    }
}

/// Caps each `(depth, rise)` offset at the deepest its rise allows (`deepest_at`, asked
/// once per rise: offsets share them) and drops those that end shallower than
/// `shallowest`.
fn limit_depths(
    offsets: &mut Vec<(f64, f64)>,
    shallowest: f64,
    mut deepest_at: impl FnMut(f64) -> f64,
) {
    let mut limits: Vec<(f64, f64)> = Vec::new();
    offsets.retain_mut(|(depth, rise)| {
        let deepest = match limits.iter().find(|l| l.0 == *rise) {
            Some(&(_, limit)) => limit,
            None => {
                let limit = deepest_at(*rise);
                limits.push((*rise, limit));
                limit
            }
        };
        *depth = depth.min(deepest);
        *depth >= shallowest
    });
}

/// How far (m) the tool at `world_from_tool` can move along unit `a` before its palm
/// meets `solid` (negative: it already has; infinite: it passes by).
fn palm_limit(hand: &Hand, solid: &SharedShape, world_from_tool: Pose, a: Vec3) -> f64 {
    /// Where the cast starts, behind the grasp (m): farther than any palm reaches.
    const BACK: f64 = 0.5;
    let start = Pose::from_parts(
        world_from_tool.translation - a * BACK,
        world_from_tool.rotation,
    );
    hand.palm
        .iter()
        .filter_map(|(shape, tool_from_shape)| {
            query::cast_shapes(
                &(start * *tool_from_shape),
                a,
                shape.as_ref(),
                &Pose::IDENTITY,
                Vec3::ZERO,
                solid.as_ref(),
                query::ShapeCastOptions::with_max_time_of_impact(2.0 * BACK),
            )
            .ok()
            .flatten()
            .map(|hit| hit.time_of_impact - BACK)
        })
        .fold(f64::INFINITY, f64::min)
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

#[cfg(test)]
mod tests {
    use super::*;
    use tabula_geom::polygon::min_area_rectangle;

    fn hand() -> Hand {
        let robot = tabula_robot::robots::load("wam").unwrap();
        Hand::new(&robot, &robot.description.grippers[0]).unwrap()
    }

    /// An object of `outline` standing from z 0.7 to 0.7 + `height`.
    fn target(outline: &[Vec2], height: f64, arm_base: Option<Vec3>) -> GraspTarget<'_> {
        GraspTarget {
            points: &[],
            outline,
            rect: min_area_rectangle(outline).unwrap(),
            bottom: 0.7,
            top: 0.7 + height,
            arm_base,
        }
    }

    fn box_outline(centre: Vec2, size: Vec2) -> Vec<Vec2> {
        let h = size / 2.0;
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(x, y)| centre + Vec2::new(x * h.x, y * h.y))
            .collect()
    }

    /// A grasp holds the fingers' closing axis across a width that fits, the tool's
    /// approach along the candidate's approach, and its twin the fingers swapped.
    fn check_candidate(g: &GraspCandidate, h: &Hand, t: &GraspTarget<'_>, clearance: f64) {
        let closing = g.poses[0].rotation * h.closing;
        let approach = g.poses[0].rotation * h.approach;
        assert!((approach - g.approach).length() < 1e-9);
        assert!(closing.z.abs() < 1e-9, "closing horizontal: {closing}");
        let across = t.width_along(closing.truncate().normalize());
        assert!(across + 2.0 * clearance <= h.open_width + 1e-9);
        let twin = g.poses[1].rotation * h.closing;
        assert!((twin + closing).length() < 1e-9);
        assert!((g.poses[0].translation - g.poses[1].translation).length() < 1e-9);
    }

    #[test]
    fn top_grasps_close_across_the_narrow_side_first_then_shallow() {
        let h = hand();
        let outline = box_outline(Vec2::new(0.6, 0.1), Vec2::new(0.05, 0.04));
        let t = target(&outline, 0.1, None);
        let grasps = TopGrasps::default().candidates(&t, &h, Vec3::Z);
        // Both ways fit a 5 × 4 cm box: two deep, two shallow.
        assert_eq!(grasps.len(), 4);
        let depth = |g: &GraspCandidate| 0.8 - g.poses[0].translation.z;
        assert!(depth(&grasps[0]) > depth(&grasps[2]));
        for g in &grasps {
            assert_eq!(g.kind, GraspKind::Top);
            check_candidate(g, &h, &t, 0.0);
        }
        let first = (grasps[0].poses[0].rotation * h.closing).truncate();
        assert!(first.y.abs() > 0.99, "across the 4 cm side: {first}");
    }

    /// Points of a 10 × 5 cm footprint centred at (0.6, 0.1) from z 0.7 to 0.8: a slab
    /// 5 cm across leaning from x 0.55 at the bottom to 0.65 at the top, `width(z)`
    /// across y at height z.
    fn leaning(width: impl Fn(f64) -> f64) -> Vec<Vec3> {
        let mut points = Vec::new();
        for i in 0..=40 {
            let t = i as f64 / 40.0;
            let z = 0.7 + 0.1 * t;
            for j in 0..=10 {
                let y = 0.1 + width(z) * (j as f64 / 10.0 - 0.5);
                points.push(Vec3::new(0.55 + 0.1 * t, y, z));
            }
        }
        points
    }

    /// Pile seed 65: fingers closed over the middle of a leaning box's footprint met
    /// nothing; they close where its points are above the fingertips.
    #[test]
    fn a_leaning_object_is_held_where_it_is_between_the_pads() {
        let h = hand();
        let outline = box_outline(Vec2::new(0.6, 0.1), Vec2::new(0.1, 0.05));
        let points = leaning(|_| 0.05);
        let t = GraspTarget {
            points: &points,
            ..target(&outline, 0.1, None)
        };
        let params = TopGrasps::default();
        let grasps = params.candidates(&t, &h, Vec3::Z);
        assert_eq!(grasps.len(), 2, "across y, deep then shallow");
        for g in &grasps {
            check_candidate(g, &h, &t, 0.0);
            let tool = g.poses[0].translation;
            // The tool is straight above the fingertips; the points above them span x
            // from the slab's height there up to 0.65.
            let tips_z = tool.z - h.tip;
            let from = 0.55 + (tips_z + PAD_OVERLAP - 0.7).max(0.0);
            assert!(
                (tool.x - (from + 0.65) / 2.0).abs() < 3e-3 && (tool.y - 0.1).abs() < 1e-6,
                "tips at {tool} for points above {tips_z:.3}"
            );
        }
        // The upright object of the same footprint is held at its middle.
        let grasps = params.candidates(&target(&outline, 0.1, None), &h, Vec3::Z);
        assert!((grasps[0].poses[0].translation.x - 0.6).abs() < 1e-9);
    }

    /// What is between the pads at a shallow grasp's height is 1 cm wide, under the
    /// closed gap: only the deep grasp is offered.
    #[test]
    fn no_grasp_closes_where_too_little_is_between_the_pads() {
        let h = hand();
        let outline = box_outline(Vec2::new(0.6, 0.1), Vec2::new(0.1, 0.05));
        let points = leaning(|z| if z >= 0.78 { 0.01 } else { 0.05 });
        let t = GraspTarget {
            points: &points,
            ..target(&outline, 0.1, None)
        };
        let grasps = TopGrasps::default().candidates(&t, &h, Vec3::Z);
        assert_eq!(grasps.len(), 1);
        assert!(
            grasps[0].poses[0].translation.z - h.tip < 0.76,
            "the deep one"
        );
    }

    /// Blocks 17: a triangular prism lying on a face, apex up (4.6 cm base, 4.4 cm
    /// tall, 7.5 cm long), is under 3.2 cm wide 5 mm above a deep grasp's tips but
    /// wider at the tips, where the fingers closing to 3 cm stop on it: it is held
    /// across. At the shallow grasp's height only its 1.5 cm ridge is there: not.
    #[test]
    fn a_wedge_is_held_where_it_is_wide_at_the_fingertips() {
        let h = hand();
        let (half_base, height) = (0.023, 0.044);
        let mut points = Vec::new();
        for i in 0..=40 {
            let z = 0.7 + height * i as f64 / 40.0;
            let half = half_base * (1.0 - (z - 0.7) / height);
            for j in 0..=20 {
                let x = 0.6 - 0.0375 + 0.075 * j as f64 / 20.0;
                points.push(Vec3::new(x, 0.1 - half, z));
                points.push(Vec3::new(x, 0.1 + half, z));
            }
        }
        let outline = box_outline(Vec2::new(0.6, 0.1), Vec2::new(0.075, 2.0 * half_base));
        let t = GraspTarget {
            points: &points,
            ..target(&outline, height, None)
        };
        let grasps = TopGrasps::default().candidates(&t, &h, Vec3::Z);
        assert!(!grasps.is_empty(), "a grasp across the wedge");
        for g in &grasps {
            check_candidate(g, &h, &t, 0.0);
            let tips_z = g.poses[0].translation.z - h.tip;
            assert!(tips_z < 0.72, "only the deep grasp: tips at {tips_z:.3}");
            let closing = g.poses[0].rotation * h.closing;
            assert!(closing.y.abs() > 0.99, "across the wedge: {closing}");
        }
    }

    /// Blocks 105: a lying prism seen 6.9 × 3.7 cm, 7.07 cm long, held along its length
    /// by the 7 cm hand's full opening — the fingers landed on its ends, and it left the
    /// open hand only outside the bin.
    #[test]
    fn a_snug_grasp_is_offered_only_where_no_roomier_one_holds() {
        let h = hand();
        let closings = |size: Vec2| {
            let outline = box_outline(Vec2::new(0.6, 0.0), size);
            let t = target(&outline, 0.1, None);
            let grasps = TopGrasps::default().candidates(&t, &h, Vec3::Z);
            for g in &grasps {
                check_candidate(g, &h, &t, 0.0);
            }
            grasps
                .iter()
                .map(|g| (g.poses[0].rotation * h.closing).truncate().x.abs() > 0.99)
                .collect::<Vec<bool>>()
        };
        let snug = h.open_width - 0.001;
        // Across its 3.7 cm only (closing along y), deep then shallow.
        assert_eq!(closings(Vec2::new(snug, 0.037)), vec![false, false]);
        // Both ways when both leave room …
        assert_eq!(closings(Vec2::new(0.05, 0.037)).len(), 4);
        // … and the snug way when it is the only one.
        assert_eq!(closings(Vec2::new(snug, 0.09)), vec![true, true]);
    }

    #[test]
    fn side_grasps_face_the_arm_and_fit_the_hand() {
        let h = hand();
        let planner = SideGrasps::default();
        for (centre, base) in [
            (Vec2::new(0.6, 0.0), Vec3::ZERO),
            (Vec2::new(-0.3, 0.5), Vec3::new(0.2, -0.1, 0.3)),
            (Vec2::new(0.0, -0.7), Vec3::ZERO),
        ] {
            // A can 4 cm across fits the hand every way: the first grasp faces the arm.
            let outline: Vec<Vec2> = (0..16)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 16.0;
                    centre + Vec2::new(a.cos(), a.sin()) * 0.02
                })
                .collect();
            let t = target(&outline, 0.15, Some(base));
            let grasps = planner.candidates(&t, &h, Vec3::Z);
            assert!(!grasps.is_empty());
            let facing = (centre - base.truncate()).normalize();
            let first = grasps[0].approach;
            assert!(first.truncate().normalize().dot(facing) > 0.99, "{first}");
            for g in &grasps {
                check_candidate(g, &h, &t, planner.finger_clearance);
                let level = g.approach.truncate().normalize();
                assert!(level.dot(facing) >= (planner.yaw_range + 1e-6).cos() - 1e-9);
            }
            assert!(grasps.iter().any(|g| g.kind == GraspKind::Top));
            assert_eq!(grasps.last().map(|g| g.kind), Some(GraspKind::Top));
        }
    }

    /// Level or tilted down, however the box is turned, the palm stops short of the
    /// object by the clearance (tilted, its lower edge leads: a level estimate let it
    /// press 6 mm into a box and tip it into the table).
    #[test]
    fn side_grasps_keep_the_palm_off_the_object_at_every_tilt() {
        let h = hand();
        assert!(!h.palm.is_empty());
        let planner = SideGrasps::default();
        let mut tilted = 0;
        for turn in [0.0f64, 0.2, 0.6, 1.0] {
            let (u, v) = (
                Vec2::new(turn.cos(), turn.sin()),
                Vec2::new(-turn.sin(), turn.cos()),
            );
            let outline: Vec<Vec2> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .iter()
                .map(|&(x, y)| Vec2::new(0.6, 0.0) + u * (x * 0.03) + v * (y * 0.02))
                .collect();
            let t = target(&outline, 0.09, Some(Vec3::ZERO));
            let solid = t.solid().unwrap();
            for g in planner.candidates(&t, &h, Vec3::Z) {
                if g.kind != GraspKind::Side {
                    continue;
                }
                tilted += usize::from(g.approach.z < -0.1);
                for (shape, tool_from_shape) in &h.palm {
                    let gap = query::distance(
                        &(g.poses[0] * *tool_from_shape),
                        shape.as_ref(),
                        &Pose::IDENTITY,
                        solid.as_ref(),
                    )
                    .unwrap()
                    .distance;
                    assert!(
                        gap >= planner.min_finger_clearance - 1e-6,
                        "{gap} at {turn}"
                    );
                }
            }
        }
        assert!(tilted > 0);
    }

    #[test]
    fn an_object_near_the_opening_is_held_with_less_room_but_not_less_than_the_minimum() {
        let h = hand();
        let planner = SideGrasps::default();
        let grasps_of = |narrow: f64| {
            // Narrow across the direction from the arm: closed across it facing the arm.
            let size = Vec2::new(h.open_width + 0.05, narrow);
            let outline = box_outline(Vec2::new(0.6, 0.0), size);
            let t = target(&outline, 0.1, Some(Vec3::ZERO));
            let found = planner.candidates(&t, &h, Vec3::Z);
            for g in &found {
                check_candidate(g, &h, &t, planner.min_finger_clearance);
            }
            found.len()
        };
        // 7 mm of room each side: held (the nominal 1 cm does not fit); 4 mm: not.
        assert!(grasps_of(h.open_width - 0.014) > 0);
        assert_eq!(grasps_of(h.open_width - 0.008), 0);
        // With room to spare, held as before.
        assert!(grasps_of(h.open_width - 0.03) > 0);
    }

    #[test]
    fn nothing_fits_an_object_wider_than_the_hand_every_way() {
        let h = hand();
        let outline = box_outline(Vec2::new(0.6, 0.0), Vec2::new(0.2, 0.2));
        let t = target(&outline, 0.1, Some(Vec3::ZERO));
        let side = SideGrasps::default();
        assert!(side.candidates(&t, &h, Vec3::Z).is_empty());
        assert!(side.narrowest(&t) > h.open_width);
        assert!(TopGrasps::default().candidates(&t, &h, Vec3::Z).is_empty());
        let fallback = Fallback(TopGrasps::default(), NarrowPartGrasps::default());
        assert!(fallback.candidates(&t, &h, Vec3::Z).is_empty());
    }
}
