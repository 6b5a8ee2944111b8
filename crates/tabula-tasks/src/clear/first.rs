//! Which of a plan's grasps goes first.
//!
//! A grasp's effects only delete facts other actions need absent (`on`, `block_*`), so
//! every grasp of a plan that can go now can go first and the rest of the plan stays
//! valid, no longer. Objects held up off the table or leaning on a neighbour go first:
//! whatever next disturbs their island — fingers going down beside it, a neighbour
//! lifted away, a pile waking up — drops them, and a dropped can rolls (pile seeds 2,
//! 26 and 48 lost cans over the table's edge that way while their neighbours were
//! taken). People unstacking a pile take from the top for the same reason.

use super::SeenObject;
use super::predicates::Geometry;
use tabula_pddl::PlanStep;

/// When an object counts as at risk of falling (not in the seed: set from pile seeds 2,
/// 26 and 48, where every can lost leaned or stood on others).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct AtRisk {
    /// An object standing this far above the table is held up by others (m).
    pub held_up: f64,
    /// An object whose two ends' tops differ by this much (m) …
    pub lean_rise: f64,
    /// … and by this share of its length leans.
    pub lean_slope: f64,
}

impl Default for AtRisk {
    fn default() -> Self {
        Self {
            held_up: 0.01,
            lean_rise: 0.015,
            lean_slope: 0.18,
        }
    }
}

impl AtRisk {
    /// How high an object is held up or how much it leans (m); 0 when it rests on the
    /// table by itself.
    pub(super) fn of(&self, o: &SeenObject, table_z: f64) -> f64 {
        let held_up = o.bottom - table_z;
        if held_up > self.held_up {
            return held_up;
        }
        let rise = end_rise(o);
        let length = o.rect.size.x.max(o.rect.size.y);
        if rise > self.lean_rise && rise > self.lean_slope * length {
            rise
        } else {
            0.0
        }
    }
}

/// The difference between the highest points over the first and the last third of
/// the footprint's long side: a box or a can lying flat has the same top at both ends,
/// one leaning against a neighbour has its raised end there.
fn end_rise(o: &SeenObject) -> f64 {
    let r = &o.rect;
    let (axis, half) = if r.size.x >= r.size.y {
        (r.axis, r.size.x / 2.0)
    } else {
        (r.axis.perp(), r.size.y / 2.0)
    };
    if half <= 0.0 {
        return 0.0;
    }
    let mut ends = [f64::NEG_INFINITY; 2];
    for p in &o.points {
        let s = (p.truncate() - r.center).dot(axis) / half;
        if s <= -1.0 / 3.0 {
            ends[0] = ends[0].max(p.z);
        } else if s >= 1.0 / 3.0 {
            ends[1] = ends[1].max(p.z);
        }
    }
    if ends.iter().all(|e| e.is_finite()) {
        (ends[0] - ends[1]).abs()
    } else {
        0.0
    }
}

/// The index into `steps` of the step to take first: the grasp that can go now of the
/// object most at risk (`risk_of` an object's index, as [`AtRisk::of`]), else the
/// plan's own first step.
pub(super) fn first_step(
    steps: &[PlanStep],
    g: &Geometry,
    risk_of: impl Fn(usize) -> f64,
    index_of: impl Fn(&PlanStep) -> Option<usize>,
) -> usize {
    let free = |i: usize| {
        !g.on.iter().any(|&(_, under)| under == i)
            && !g.block_grasp.iter().any(|&(_, blocked)| blocked == i)
    };
    let mut best = (0, 0.0);
    for (k, step) in steps.iter().enumerate() {
        if step.action != "grasp" {
            continue;
        }
        let Some(i) = index_of(step).filter(|&i| free(i)) else {
            continue;
        };
        let r = risk_of(i);
        if r > best.1 {
            best = (k, r);
        }
    }
    best.0
}
