//! Objects tracked across frames: which object of this frame is which of the last,
//! what was done to it, and where a push should have put it.

use super::push::Push;
use super::{ClearParams, SeenObject};
use crate::scene::tabletop::seen_standing;
use tabula_geom::Vec2;
use tabula_geom::polygon::inside_convex;

/// A tracked object: where it is expected next and what was done to it.
#[derive(Debug, Clone)]
pub(super) struct Track {
    pub(super) id: usize,
    pub(super) expected: Vec2,
    pub(super) seen: Vec2,
    pub(super) pushes: Vec<Vec2>,
    /// Split pushes of it so far ([`super::split`]).
    pub(super) splits: usize,
    /// Directions of pushes that could not be executed, or were jammed.
    pub(super) failed_pushes: Vec<Vec2>,
    /// The last push, until the next frame sees how far it went: direction, length and
    /// where the object was.
    pub(super) pending: Option<(Vec2, f64, Vec2)>,
    pub(super) grasp_attempts: usize,
    /// Its last grasp lifted another object along and was put back: not grasped
    /// again until something else is taken away (what lies on it may be).
    pub(super) carried_along: bool,
    /// Seen in the last frame and not taken away since (a grasp ends it until the
    /// object is seen again).
    pub(super) live: bool,
    /// Moved by a push together with others (pushed, shoved along, or split from a
    /// segment they merged into): where it is expected splits what is seen there.
    pub(super) pushed_together: bool,
}

impl Track {
    /// Whether its grasp is not to be tried now: tried enough, or it carried another
    /// object along and nothing was taken away since.
    pub(super) fn grasp_ruled_out(&self, params: &ClearParams) -> bool {
        self.grasp_attempts >= params.max_grasp_attempts || self.carried_along
    }

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
    for t in tracks.iter_mut() {
        t.live = false;
    }
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
        tracks[t].live = true;
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
                splits: 0,
                failed_pushes: Vec::new(),
                pending: None,
                grasp_attempts: 0,
                carried_along: false,
                live: true,
                pushed_together: false,
            });
            next += 1;
        }
    }
}

/// Where what a push of `objects[i]` shoves along should end: each moves the push's
/// length less the gap in front of it.
pub(super) fn shoved_along(tracks: &mut [Track], objects: &[SeenObject], i: usize, p: &Push) {
    let reach = |o: &SeenObject| {
        let along = o.footprint.iter().map(|q| q.dot(p.direction));
        along.clone().fold(f64::INFINITY, f64::min)..along.fold(f64::NEG_INFINITY, f64::max)
    };
    let front = reach(&objects[i]).end;
    for &j in &p.chain {
        let gap = (reach(&objects[j]).start - front).max(0.0);
        if let Some(t) = tracks.iter_mut().find(|t| t.id == objects[j].id) {
            t.expected = objects[j].rect.center + p.direction * (p.length - gap).max(0.0);
            t.pushed_together = true;
        }
    }
}

/// Splits a segment that holds where two or more live objects a push moved together
/// are expected, side by side: pushed against each other, two boxes with a seam the camera cannot
/// see become one segment, and a grasp across its middle pinches both at the seam (one
/// falls on the way to the bin). Its points go to the nearest of those positions,
/// refined as k-means; a part with too few points keeps the segment whole.
pub(super) fn split_merged(objects: &mut Vec<SeenObject>, tracks: &[Track]) {
    let moved: Vec<Vec2> = tracks
        .iter()
        .filter(|t| t.live && t.pushed_together)
        .map(|t| t.expected)
        .collect();
    if moved.len() < 2 {
        return;
    }
    let mut out = Vec::with_capacity(objects.len());
    for o in objects.drain(..) {
        let inside: Vec<Vec2> = moved
            .iter()
            .copied()
            .filter(|&c| inside_convex(&o.footprint, c))
            .collect();
        // Side by side, not one on the other (a stack's centres coincide).
        let apart = inside.iter().enumerate().all(|(a, p)| {
            inside[a + 1..]
                .iter()
                .all(|q| (*p - *q).length() >= MIN_APART)
        });
        match (inside.len() >= 2 && apart)
            .then(|| split(&o, inside))
            .flatten()
        {
            Some(parts) => out.extend(parts),
            None => out.push(o),
        }
    }
    *objects = out;
}

/// How far apart (m) the expected centres of objects in one segment must be to split it.
const MIN_APART: f64 = 0.03;

/// `o`'s points parted among `centres` (xy k-means from them); `None` when a part has
/// fewer than a fifth of the points its share would be.
fn split(o: &SeenObject, mut centres: Vec<Vec2>) -> Option<Vec<SeenObject>> {
    let k = centres.len();
    let mut label = vec![0usize; o.points.len()];
    for _ in 0..8 {
        for (l, q) in label.iter_mut().zip(&o.points) {
            let q = q.truncate();
            *l = (0..k)
                .min_by(|&a, &b| {
                    (q - centres[a])
                        .length()
                        .total_cmp(&(q - centres[b]).length())
                })
                .unwrap_or(0);
        }
        for (c, centre) in centres.iter_mut().enumerate() {
            let mine: Vec<Vec2> = o
                .points
                .iter()
                .zip(&label)
                .filter(|(_, l)| **l == c)
                .map(|(q, _)| q.truncate())
                .collect();
            if !mine.is_empty() {
                *centre = mine.iter().copied().sum::<Vec2>() / mine.len() as f64;
            }
        }
    }
    let least = o.points.len() / (5 * k);
    (0..k)
        .map(|c| {
            let points: Vec<_> = o
                .points
                .iter()
                .zip(&label)
                .filter(|(_, l)| **l == c)
                .map(|(q, _)| *q)
                .collect();
            if points.len() < least.max(3) {
                return None;
            }
            seen_standing(points, o.bottom)
        })
        .collect()
}
