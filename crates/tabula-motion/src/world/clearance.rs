//! Clearance: the smallest distance between anything [`CollisionWorld::first_collision`]
//! would test, capped — what conservative advancement steps by. Sphere covers bound a
//! pair's distance from below for a few multiplications, so the exact (GJK) distance is
//! computed only for pairs whose cover comes closer than the best found so far.

use super::gjk::{self, Hull};
use super::{CollisionWorld, WorldError, WorldObject};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};

/// One convex thing placed for a distance query.
struct Solid<'a> {
    pose: Pose,
    shape: &'a SharedShape,
    hull: Option<&'a Hull>,
}

impl<'a> Solid<'a> {
    fn of(p: &super::Placed<'a>) -> Self {
        Self {
            pose: p.pose,
            shape: p.shape,
            hull: p.hull,
        }
    }

    /// The distance to `other`, or `limit` when it is at least that.
    fn distance(&self, other: &Solid, limit: f64) -> f64 {
        match (
            gjk::support(self.shape, self.hull),
            gjk::support(other.shape, other.hull),
        ) {
            (Some(a), Some(b)) => {
                gjk::distance_within(&self.pose, a, &other.pose, b, limit).unwrap_or(limit)
            }
            _ => query::distance(
                &self.pose,
                self.shape.as_ref(),
                &other.pose,
                other.shape.as_ref(),
            )
            .map_or(0.0, |d| d.distance),
        }
    }
}

/// A lower bound on the distance from balls to an object (0 when a ball reaches it).
fn balls_to_object(balls: &[(Vec3, f64)], o: &WorldObject, best: f64) -> f64 {
    let mut lb = f64::INFINITY;
    for (c, r) in balls {
        let reach = r + best;
        let near = Aabb::new(*c - Vec3::splat(reach), *c + Vec3::splat(reach));
        if !near.intersects(&o.aabb) {
            continue;
        }
        lb = lb.min(o.shape.distance_to_point(&o.world_from_object, *c, true) - r);
    }
    lb.max(0.0)
}

/// A lower bound on the distance between two sets of balls.
fn balls_to_balls(a: &[(Vec3, f64)], b: &[(Vec3, f64)]) -> f64 {
    let mut lb = f64::INFINITY;
    for (ca, ra) in a {
        for (cb, rb) in b {
            lb = lb.min((*ca - *cb).length() - ra - rb);
        }
    }
    lb.max(0.0)
}

impl CollisionWorld {
    /// Clearance at `q`, capped at `cap`: the smallest distance between any pair that
    /// [`Self::first_collision`] would test (moving links and held objects against the
    /// world and the robot), or a negative number when `q` is out of limits.
    pub fn clearance(&self, q: &[f64], cap: f64) -> Result<f64, WorldError> {
        self.checks.set(self.checks.get() + 1);
        let poses = self.body_poses(q)?;
        for (i, v) in q.iter().enumerate() {
            if *v < self.chain.lower[i] - 1e-9 || *v > self.chain.upper[i] + 1e-9 {
                return Ok(-1.0);
            }
        }
        let mut best = cap;
        let mut balls = Vec::new();
        let placed = self.placed_shapes(&poses, false, &mut balls);
        // A decomposed link's pieces only where its outer hull comes closer than the
        // best so far (the hull contains them: its distance bounds theirs from below).
        let mut far: (usize, Vec<usize>) = (usize::MAX, Vec::new());
        for p in placed.iter().filter(|p| self.bodies[p.body].moving) {
            let reach = p.aabb.loosened(best);
            let near: Vec<usize> = if far.0 == p.body {
                far.1.clone()
            } else {
                self.objects_bvh
                    .intersect_aabb(&reach)
                    .map(|i| i as usize)
                    .collect()
            };
            let mut closer = Vec::new();
            for i in near {
                let o = &self.objects[i];
                if o.allowed_bodies.contains(&p.body)
                    || !reach.intersects(&o.aabb)
                    || balls_to_object(&balls[p.balls.clone()], o, best) >= best
                {
                    continue;
                }
                let d = self.object_distance(&Solid::of(p), &p.aabb.loosened(best), o, best);
                if p.outer {
                    if d < best {
                        closer.push(i);
                    }
                } else {
                    best = best.min(d);
                }
            }
            if p.outer {
                far = (p.body, closer);
            }
        }
        let pairs = self.self_piece_pairs(&placed, best, |pi, pk| {
            balls_to_balls(&balls[pi.balls.clone()], &balls[pk.balls.clone()]) < best
                && Solid::of(pi).distance(&Solid::of(pk), best) < best
        });
        for (i, k) in pairs {
            let (pi, pk) = (&placed[i], &placed[k]);
            if !pi.aabb.loosened(best).intersects(&pk.aabb)
                || balls_to_balls(&balls[pi.balls.clone()], &balls[pk.balls.clone()]) >= best
            {
                continue;
            }
            best = best.min(Solid::of(pi).distance(&Solid::of(pk), best));
        }
        for att in &self.attached {
            let held = Solid {
                pose: poses[att.body] * att.link_from_object,
                shape: &att.shape,
                hull: None,
            };
            let aabb = att.shape.compute_aabb(&held.pose);
            for o in self.objects_near(&aabb.loosened(best)) {
                best = best.min(self.object_distance(&held, &aabb.loosened(best), o, best));
            }
            for p in placed.iter().filter(|p| !p.outer) {
                if !att.touch.contains(&p.body) && aabb.loosened(best).intersects(&p.aabb) {
                    best = best.min(held.distance(&Solid::of(p), best));
                }
            }
        }
        Ok(best)
    }

    /// Distance from a solid to an object (or `limit` when at least that); of a
    /// compound (an occupancy map) only the parts within `near` count.
    fn object_distance(&self, s: &Solid, near: &Aabb, o: &WorldObject, limit: f64) -> f64 {
        let Some(c) = o.shape.as_compound() else {
            return s.distance(
                &Solid {
                    pose: o.world_from_object,
                    shape: &o.shape,
                    hull: None,
                },
                limit,
            );
        };
        let local = near.transform_by(&o.world_from_object.inverse());
        c.bvh()
            .intersect_aabb(&local)
            .map(|i| {
                let (part_pose, part) = &c.shapes()[i as usize];
                s.distance(
                    &Solid {
                        pose: o.world_from_object * *part_pose,
                        shape: part,
                        hull: None,
                    },
                    limit,
                )
            })
            .fold(f64::INFINITY, f64::min)
    }
}
