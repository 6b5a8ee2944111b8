//! What a run leaves on the table, and why: the loop's last word when it stops with
//! objects still there (issue 32: a table is finished only when the loop says which
//! objects remain and why).

use super::predicates::Geometry;
use super::track::Track;
use super::{ClearParams, SeenObject};
use serde::Serialize;

/// An object the run left on the table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeftObject {
    /// Tracked id.
    pub id: usize,
    /// Where it was last seen (world: footprint centre, mid-height).
    pub position: [f64; 3],
    /// Its footprint's sides and its height (m).
    pub size: [f64; 3],
    pub why: String,
}

/// Every object of the last frame with the reason it stays: from what the last
/// decision knew (`geometry`: the grasps that fit, the pushes left) and the tracks;
/// `stop` when no decision was made (an action limit).
pub(super) fn left_objects(
    objects: &[SeenObject],
    geometry: Option<&Geometry>,
    tracks: &[Track],
    params: &ClearParams,
    stop: &str,
) -> Vec<LeftObject> {
    objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let track = tracks.iter().find(|t| t.id == o.id);
            let why = match geometry {
                Some(g) => why_left(i, g, track, params),
                None => stop.to_string(),
            };
            let c = o.rect.center;
            LeftObject {
                id: o.id,
                position: [c.x, c.y, (o.bottom + o.top) / 2.0],
                size: [o.rect.size.x, o.rect.size.y, o.top - o.bottom],
                why,
            }
        })
        .collect()
}

fn why_left(i: usize, g: &Geometry, track: Option<&Track>, params: &ClearParams) -> String {
    let attempts = track.map_or(0, |t| t.grasp_attempts);
    let grasp = if g.grasps[i].is_none() {
        "no grasp of the gripper fits it"
    } else if track.is_some_and(|t| t.carried_along) {
        "its grasp lifted another object along with it"
    } else if attempts >= params.max_grasp_attempts {
        "its grasp failed every time it was tried"
    } else {
        "no grasp reaches it without collision"
    };
    let pushes = &g.pushes[i];
    let pushable = pushes
        .iter()
        .any(|p| p.feasible && track.is_none_or(|t| !t.rules_out(p.direction, params)));
    let push = if pushable {
        "and no plan clears its way with a push"
    } else if pushes.iter().any(|p| p.feasible) {
        "and every push left was tried, jammed or would push it back"
    } else {
        "and every push would take it off the table or is blocked"
    };
    let split = if track.is_some_and(|t| t.splits > 0) {
        "; one half was pushed aside and it stayed one object"
    } else {
        ""
    };
    format!("{grasp}, {push}{split}")
}
