//! A frame's PDDL problem, built from the predicates as atoms and handed to the planner
//! (no text written and parsed back), and the plan's first step read as an action.

use super::predicates::Geometry;
use super::{ActionKind, DIRECTIONS, SeenObject};
use tabula_pddl::{
    Domain, GroundAtom, GroundOptions, PddlError, PlanStep, Planner, Problem, TypedName,
};

/// The planner's name for a tracked object.
fn object_name(id: usize) -> String {
    format!("o{id}")
}

fn atom(predicate: &str, objects: &[usize]) -> GroundAtom {
    GroundAtom {
        predicate: predicate.into(),
        args: objects.iter().map(|&id| object_name(id)).collect(),
    }
}

/// The fact that `kind` on tracked object `object` has no IK (SPEC §3.5's backtracking).
pub(super) fn infeasible_atom(kind: ActionKind, object: usize) -> GroundAtom {
    match kind {
        ActionKind::Grasp => atom("ik_unfeasible_grasp", &[object]),
        ActionKind::Push(k) => atom(&format!("ik_unfeasible_{}", DIRECTIONS[k]), &[object]),
    }
}

/// The problem of a frame: its objects, what stands on what and blocks what, and the
/// goal that the objects `goal` (indices) are removed.
pub(super) fn problem(
    domain: &Domain,
    objects: &[SeenObject],
    g: &Geometry,
    goal: &[usize],
) -> Result<Problem, PddlError> {
    let id = |i: usize| objects[i].id;
    let pair = |p: &str, &(a, b): &(usize, usize)| atom(p, &[id(a), id(b)]);
    let mut init: Vec<GroundAtom> = g.on.iter().map(|ab| pair("on", ab)).collect();
    init.extend(g.block_grasp.iter().map(|ab| pair("block_grasp", ab)));
    for (k, pairs) in g.block_push.iter().enumerate() {
        let predicate = format!("block_{}", DIRECTIONS[k]);
        init.extend(pairs.iter().map(|ab| pair(&predicate, ab)));
    }
    let names = objects
        .iter()
        .map(|o| TypedName {
            name: object_name(o.id),
            type_name: "obj".into(),
        })
        .collect();
    let goal: Vec<GroundAtom> = goal.iter().map(|&i| atom("removed", &[id(i)])).collect();
    Problem::from_atoms(domain, "clear", names, init, &goal)
}

/// A planner for a frame's problem whose `ik_unfeasible_*` facts switch without
/// grounding again.
pub(super) fn planner(domain: &Domain, problem: Problem) -> Option<Planner> {
    let options = GroundOptions::switchable(domain, "ik_unfeasible");
    Planner::new(domain.clone(), problem, options).ok()
}

/// The object (index into `objects`) and action of a plan step.
pub(super) fn action_of(step: &PlanStep, objects: &[SeenObject]) -> Option<(usize, ActionKind)> {
    let i = step
        .args
        .first()
        .and_then(|a| a.strip_prefix('o'))
        .and_then(|id| id.parse::<usize>().ok())
        .and_then(|id| objects.iter().position(|o| o.id == id))?;
    let kind = if step.action == "grasp" {
        ActionKind::Grasp
    } else {
        let k = DIRECTIONS
            .iter()
            .position(|d| step.action == format!("push_{d}"))?;
        ActionKind::Push(k)
    };
    Some((i, kind))
}
