//! What one query places: every body piece at its pose with its box and its cover's
//! balls, the hull of a decomposed link's pieces in front of them, and the cheap tests
//! on balls that spare the exact ones.

use super::cover::{Cover, box_corners};
use super::gjk::Hull;
use super::{CollisionWorld, WorldObject};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};

impl CollisionWorld {
    /// Index pairs of placed pieces of two bodies that may collide (checked pair, not
    /// allowed) and whose boxes, grown by `margin`, meet; bodies are paired first —
    /// `apart` (body indices) drops pairs known to be far enough, and where either is
    /// decomposed, `outers_meet` on the two outer shapes (a piece is its body's own outer
    /// shape) decides whether their pieces are paired at all.
    pub(super) fn self_piece_pairs(
        &self,
        placed: &[Placed<'_>],
        margin: f64,
        apart: impl Fn(usize, usize) -> bool,
        outers_meet: impl Fn(&Placed<'_>, &Placed<'_>) -> bool,
    ) -> Vec<(usize, usize)> {
        // Per body: its outer entry (or its only piece), its pieces, its box.
        let mut groups: Vec<(usize, usize, std::ops::Range<usize>, Aabb, bool)> =
            Vec::with_capacity(self.bodies.len());
        for (i, p) in placed.iter().enumerate() {
            match groups.last_mut() {
                Some((b, _, range, aabb, _)) if *b == p.body => {
                    if range.start == range.end {
                        *range = i..i + 1;
                    } else {
                        range.end = i + 1;
                    }
                    *aabb = aabb.merged(&p.aabb);
                }
                _ if p.outer => groups.push((p.body, i, i + 1..i + 1, p.aabb, true)),
                _ => groups.push((p.body, i, i..i + 1, p.aabb, false)),
            }
        }
        let mut pairs = Vec::new();
        for (g, (a, rep_a, ra, box_a, outer_a)) in groups.iter().enumerate() {
            let grown = box_a.loosened(margin);
            for (b, rep_b, rb, box_b, outer_b) in &groups[g + 1..] {
                if !self.self_pair_checked(*a, *b) || !grown.intersects(box_b) || apart(*a, *b) {
                    continue;
                }
                if (*outer_a || *outer_b) && !outers_meet(&placed[*rep_a], &placed[*rep_b]) {
                    continue;
                }
                for i in ra.clone() {
                    let piece = placed[i].aabb.loosened(margin);
                    for k in rb.clone() {
                        if piece.intersects(&placed[k].aabb) {
                            pairs.push((i, k));
                        }
                    }
                }
            }
        }
        pairs
    }

    /// Every body shape placed at `poses`, with its box (grown by the link's padding if
    /// `padded`) and its cover's balls in the world (in `balls`).
    pub(super) fn placed_shapes<'a>(
        &'a self,
        poses: &[Pose],
        padded: bool,
        balls: &mut Vec<(Vec3, f64)>,
    ) -> Vec<Placed<'a>> {
        // Sized up front: growing these is a good part of a check's cost.
        let (mut pieces, mut spheres) = (0, 0);
        for lb in &self.bodies {
            if let Some(o) = &lb.outer {
                pieces += 1;
                spheres += o.cover.spheres.len();
            }
            pieces += lb.shapes.len();
            spheres += lb.covers.iter().map(|c| c.spheres.len()).sum::<usize>();
        }
        balls.reserve(spheres);
        let mut placed = Vec::with_capacity(pieces);
        for (b, lb) in self.bodies.iter().enumerate() {
            if let Some(o) = &lb.outer {
                let first = balls.len();
                balls.extend(o.cover.spheres.iter().map(|(c, r)| (poses[b] * *c, *r)));
                let aabb = o.cover.aabb_at(&poses[b]);
                placed.push(Placed {
                    body: b,
                    outer: true,
                    pose: poses[b],
                    shape: &o.shape,
                    hull: o.hull.as_ref(),
                    aabb: if padded {
                        aabb.loosened(lb.padding)
                    } else {
                        aabb
                    },
                    balls: first..balls.len(),
                });
            }
            for (((s, p), cover), hull) in lb.shapes.iter().zip(&lb.covers).zip(&lb.hulls) {
                let w = poses[b] * *p;
                let aabb = cover.aabb_at(&poses[b]);
                let first = balls.len();
                balls.extend(cover.spheres.iter().map(|(c, r)| (poses[b] * *c, *r)));
                placed.push(Placed {
                    body: b,
                    outer: false,
                    pose: w,
                    shape: s,
                    hull: hull.as_ref(),
                    aabb: if padded {
                        aabb.loosened(lb.padding)
                    } else {
                        aabb
                    },
                    balls: first..balls.len(),
                });
            }
        }
        placed
    }
}

/// The convex hull of a link's pieces, in the link frame.
#[derive(Clone)]
pub(super) struct Outer {
    pub shape: SharedShape,
    pub cover: Cover,
    pub hull: Option<Hull>,
}

impl Outer {
    /// `None` for a link of one piece (its piece is its own outer shape).
    pub(super) fn of(shapes: &[(SharedShape, Pose)]) -> Option<Self> {
        if shapes.len() < 2 {
            return None;
        }
        let mut points = Vec::new();
        for (s, p) in shapes {
            // A mesh hull's vertices; any other shape through its box's corners.
            let local: Vec<Vec3> = match s.as_convex_polyhedron() {
                Some(c) => c.points().to_vec(),
                None => box_corners(&s.compute_local_aabb()).to_vec(),
            };
            points.extend(local.into_iter().map(|v| *p * v));
        }
        let shape = SharedShape::convex_hull(&points)?;
        Some(Self {
            cover: Cover::of(&shape),
            hull: shape.as_convex_polyhedron().and_then(Hull::of),
            shape,
        })
    }
}

/// A body shape placed for one query.
pub(super) struct Placed<'a> {
    pub body: usize,
    /// The hull of a decomposed body's pieces (placed just before them), not a piece.
    pub outer: bool,
    pub pose: Pose,
    pub shape: &'a SharedShape,
    pub hull: Option<&'a Hull>,
    pub aabb: Aabb,
    /// Its cover's balls in the query's ball list.
    pub balls: std::ops::Range<usize>,
}

/// Whether every ball is farther than `pad` from the object (so the shape they cover is).
pub(super) fn balls_clear_of(balls: &[(Vec3, f64)], o: &WorldObject, pad: f64) -> bool {
    balls.iter().all(|(c, r)| {
        let reach = r + pad;
        let near = Aabb::new(*c - Vec3::splat(reach), *c + Vec3::splat(reach));
        !near.intersects(&o.aabb)
            || o.shape.distance_to_point(&o.world_from_object, *c, true) > reach
    })
}

/// Whether every ball of one cover is farther than `pad` from every ball of the other.
pub(super) fn balls_apart(a: &[(Vec3, f64)], b: &[(Vec3, f64)], pad: f64) -> bool {
    a.iter().all(|(ca, ra)| {
        b.iter().all(|(cb, rb)| {
            let reach = ra + rb + pad;
            (*ca - *cb).length_squared() > reach * reach
        })
    })
}
