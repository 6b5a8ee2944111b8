//! Which of a plan's grasps goes first.
//!
//! A grasp's effects only delete facts other actions need absent (`on`, `block_*`), so
//! every grasp of a plan that can go now can go first and the rest of the plan stays
//! valid, no longer. Objects held up off the table or leaning on a neighbour go first:
//! whatever next disturbs their island — fingers going down beside it, a neighbour
//! lifted away, a pile waking up — drops them, and a dropped can rolls (pile seeds 2,
//! 26 and 48 lost cans over the table's edge that way while their neighbours were
//! taken). People unstacking a pile take from the top for the same reason, and leave
//! what a leaning or perched neighbour rests on for later.

use super::SeenObject;
use super::predicates::Geometry;
use crate::scene::hulls_touch;
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
    /// An object whose top stands this much higher above the table than its
    /// footprint's narrow side is long may lie on others (m): a can lying across two
    /// neighbours (a standing can or box is flagged too, which only delays lifting
    /// its neighbours).
    pub perched: f64,
    /// A neighbour at risk or perched, within this of an object's hull (m) and with its
    /// top higher than the object's by `lean_rise`, may rest on it.
    pub touch: f64,
}

impl Default for AtRisk {
    fn default() -> Self {
        Self {
            held_up: 0.01,
            lean_rise: 0.015,
            lean_slope: 0.18,
            perched: 0.03,
            touch: 0.01,
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

    /// Whether lifting `below` may take away what holds `above` up: `above` is at risk
    /// or perched, touches `below` and stands higher. Pile seeds 26, 35, 41, 47 and 158
    /// lost such a neighbour over the table's edge when the object under it was lifted.
    pub(super) fn props_up(&self, below: &SeenObject, above: &SeenObject, table_z: f64) -> bool {
        let narrow = above.rect.size.x.min(above.rect.size.y);
        above.top > below.top + self.lean_rise
            && (self.of(above, table_z) > 0.0 || above.top - table_z - narrow > self.perched)
            && hulls_touch(below, above, self.touch)
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

/// How urgent lifting an object now is: whether lifting it takes away the support
/// of a neighbour at risk (see [`AtRisk::props_up`]), and its own risk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Urgency {
    pub props_up: bool,
    pub risk: f64,
}

/// The index into `steps` of the step to take first: of the grasps that can go now,
/// one that props up no neighbour at risk before one that does, then the object most
/// at risk (`urgency_of` an object's index); else the plan's own first step.
pub(super) fn first_step(
    steps: &[PlanStep],
    g: &Geometry,
    urgency_of: impl Fn(usize) -> Urgency,
    index_of: impl Fn(&PlanStep) -> Option<usize>,
) -> usize {
    let free = |i: usize| {
        !g.on.iter().any(|&(_, under)| under == i)
            && !g.block_grasp.iter().any(|&(_, blocked)| blocked == i)
    };
    let grasp_of = |step: &PlanStep| {
        (step.action == "grasp")
            .then(|| index_of(step))
            .flatten()
            .filter(|&i| free(i))
    };
    // The plan's first step stands unless a grasp can go now that is safer to lift
    // (props nothing up where it does) or as safe and more at risk itself. A push
    // moves what it pushes: it is as unsafe as lifting it, and frees nothing at risk.
    let calm = Urgency {
        props_up: false,
        risk: 0.0,
    };
    let own = steps.first().map_or(calm, |step| match grasp_of(step) {
        Some(i) => urgency_of(i),
        None if step.action.starts_with("push") => Urgency {
            props_up: index_of(step).is_some_and(|i| urgency_of(i).props_up),
            risk: 0.0,
        },
        None => calm,
    });
    let better = |u: &Urgency, than: &Urgency| {
        (!u.props_up && than.props_up) || (u.props_up == than.props_up && u.risk > than.risk)
    };
    let mut best = (0, own);
    for (k, step) in steps.iter().enumerate().skip(1) {
        if let Some(u) = grasp_of(step).map(&urgency_of)
            && better(&u, &best.1)
        {
            best = (k, u);
        }
    }
    best.0
}
