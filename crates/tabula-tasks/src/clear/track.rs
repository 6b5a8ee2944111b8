//! Objects tracked across frames: which object of this frame is which of the last,
//! what was done to it, and where a push should have put it.

use super::{ClearParams, SeenObject};
use tabula_geom::Vec2;

/// A tracked object: where it is expected next and what was done to it.
#[derive(Debug, Clone)]
pub(super) struct Track {
    pub(super) id: usize,
    pub(super) expected: Vec2,
    pub(super) seen: Vec2,
    pub(super) pushes: Vec<Vec2>,
    /// Directions of pushes that could not be executed, or were jammed.
    pub(super) failed_pushes: Vec<Vec2>,
    /// The last push, until the next frame sees how far it went: direction, length and
    /// where the object was.
    pub(super) pending: Option<(Vec2, f64, Vec2)>,
    pub(super) grasp_attempts: usize,
}

impl Track {
    /// Whether a push along `direction` is ruled out: too many pushes already, back
    /// against an earlier push (no pushing to and fro), or the way one failed.
    pub(super) fn rules_out(&self, direction: Vec2, params: &ClearParams) -> bool {
        self.pushes.len() >= params.max_pushes_per_object
            || self.pushes.iter().any(|d| d.dot(direction) < -0.5)
            || self.failed_pushes.iter().any(|d| d.dot(direction) > 0.85)
    }
}

/// Gives every object the id of the track it continues (nearest expected position
/// within `radius`, greedily by distance) or a new one. A pushed object that moved
/// less than `jam_share` of the push's length along it was jammed (by neighbours the
/// predicates let it slide past): that way is not tried again.
pub(super) fn track(
    objects: &mut [SeenObject],
    tracks: &mut Vec<Track>,
    radius: f64,
    jam_share: f64,
) {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        for (t, tr) in tracks.iter().enumerate() {
            // Where a push should have put it, or where it was (a push may fail).
            let d = (o.rect.center - tr.expected)
                .length()
                .min((o.rect.center - tr.seen).length());
            if d <= radius {
                pairs.push((d, i, t));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut used_o = vec![false; objects.len()];
    let mut used_t = vec![false; tracks.len()];
    for (_, i, t) in pairs {
        if used_o[i] || used_t[t] {
            continue;
        }
        used_o[i] = true;
        used_t[t] = true;
        objects[i].id = tracks[t].id;
        if let Some((d, length, from)) = tracks[t].pending.take()
            && (objects[i].rect.center - from).dot(d) < jam_share * length
        {
            tracks[t].failed_pushes.push(d);
        }
        tracks[t].expected = objects[i].rect.center;
        tracks[t].seen = objects[i].rect.center;
    }
    let mut next = tracks.iter().map(|t| t.id + 1).max().unwrap_or(0);
    for (i, o) in objects.iter_mut().enumerate() {
        if !used_o[i] {
            o.id = next;
            tracks.push(Track {
                id: next,
                expected: o.rect.center,
                seen: o.rect.center,
                pushes: Vec::new(),
                failed_pushes: Vec::new(),
                pending: None,
                grasp_attempts: 0,
            });
            next += 1;
        }
    }
}
