//! The yes/no question of a configuration: within the joint limits, and no checked
//! pair within its padding — balls first, the hull of a decomposed link next, exact
//! GJK last.

use super::gjk::{self, Hull};
use super::placed::{OnDemand, Placed, balls_apart, balls_clear_of, body_piece_pairs};
use super::{CollisionWorld, WorldError, WorldObject};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};

/// A shape where it is, with the hull standing for it when it is a decomposed body's.
#[derive(Clone, Copy)]
struct Solid<'a> {
    pose: &'a Pose,
    shape: &'a SharedShape,
    hull: Option<&'a Hull>,
}

impl<'a> Solid<'a> {
    fn of(p: &'a Placed<'_>) -> Self {
        Self {
            pose: &p.pose,
            shape: p.shape,
            hull: p.hull,
        }
    }

    /// Whether `other` is within `pad`: a yes/no question, so GJK distance, not the
    /// penetration depth (EPA) `contact` computes.
    fn within(self, other: Solid, pad: f64) -> bool {
        match (
            gjk::support(self.shape, self.hull),
            gjk::support(other.shape, other.hull),
        ) {
            (Some(g1), Some(g2)) => gjk::within(self.pose, g1, other.pose, g2, pad),
            _ => query::distance(
                self.pose,
                self.shape.as_ref(),
                other.pose,
                other.shape.as_ref(),
            )
            .is_ok_and(|d| d.distance <= pad),
        }
    }

    /// Whether world object `o` is within `pad` (`aabb`: this solid's box). Against a
    /// compound (an occupancy map) only the parts near the shape count: the compound's
    /// own distance would look for the nearest of all of them.
    fn touches(self, aabb: &Aabb, o: &WorldObject, pad: f64) -> bool {
        match o.shape.as_compound() {
            Some(c) => {
                let local = aabb.transform_by(&o.world_from_object.inverse());
                c.bvh().intersect_aabb(&local).any(|i| {
                    let (part_pose, part) = &c.shapes()[i as usize];
                    let pose = o.world_from_object * *part_pose;
                    self.within(
                        Solid {
                            pose: &pose,
                            shape: part,
                            hull: None,
                        },
                        pad,
                    )
                })
            }
            None => self.within(
                Solid {
                    pose: &o.world_from_object,
                    shape: &o.shape,
                    hull: None,
                },
                pad,
            ),
        }
    }
}

/// The names of a colliding pair.
type Pair = (String, String);

impl CollisionWorld {
    /// The first colliding pair at `q` (names), or `None` when `q` is valid. Joint limits
    /// count: a configuration outside them is reported as `("joint limits", name)`.
    pub fn first_collision(&self, q: &[f64]) -> Result<Option<Pair>, WorldError> {
        self.with_bodies_at(q, |scratch, outside| {
            if let Some(i) = outside {
                return Some(("joint limits".into(), self.chain.joint_names[i].clone()));
            }
            // Shapes in the world frame with their boxes, grown by their link's padding,
            // placed only where a body's bounding ball comes near something.
            let mut bodies = OnDemand::new(self, scratch, true);
            self.robot_hits_world(&mut bodies)
                .or_else(|| self.robot_hits_itself(q, &mut bodies))
                .or_else(|| {
                    (!self.attached.is_empty())
                        .then(|| self.attached_hit(&mut bodies))
                        .flatten()
                })
        })
    }

    /// Robot against the world (only what moves can newly collide): a body's pieces only
    /// against the objects its bounding ball reaches; there, the exact query only where
    /// a piece's cover is within the padding of the object.
    fn robot_hits_world(&self, bodies: &mut OnDemand) -> Option<Pair> {
        for b in 0..self.bodies.len() {
            if !self.bodies[b].moving {
                continue;
            }
            let Some((centre, reach)) = bodies.bound(b) else {
                continue;
            };
            let around = Aabb::new(centre - Vec3::splat(reach), centre + Vec3::splat(reach));
            for i in self.object_indices_near(&around) {
                let o = &self.objects[i];
                if o.allowed_bodies.contains(&b)
                    || o.shape
                        .distance_to_point(&o.world_from_object, centre, true)
                        > reach
                {
                    continue;
                }
                let range = bodies.body(b);
                if self.pieces_touch(&bodies.placed[range], bodies.balls, o) {
                    return Some((self.bodies[b].name.clone(), o.name.clone()));
                }
            }
        }
        None
    }

    /// Whether one body's placed entries touch object `o`: a decomposed body's pieces
    /// only when its outer hull does.
    fn pieces_touch(&self, entries: &[Placed], balls: &[(Vec3, f64)], o: &WorldObject) -> bool {
        let Some(first) = entries.first() else {
            return false;
        };
        let pad = self.bodies[first.body].padding;
        let touches = |p: &Placed| {
            o.aabb.intersects(&p.aabb)
                && !balls_clear_of(&balls[p.balls.clone()], o, pad)
                && Solid::of(p).touches(&p.aabb, o, pad)
        };
        if first.outer {
            touches(first) && entries[1..].iter().any(touches)
        } else {
            entries.iter().any(touches)
        }
    }

    /// Robot against itself: the pairs the matrix checks, by their bounding balls and
    /// remembered distances first; a decomposed body's pieces only when its outer hull
    /// meets the other body.
    fn robot_hits_itself(&self, q: &[f64], bodies: &mut OnDemand) -> Option<Pair> {
        let meet = |pi: &Placed, pk: &Placed, balls: &[(Vec3, f64)]| {
            let pad = self.bodies[pi.body]
                .padding
                .max(self.bodies[pk.body].padding);
            pi.aabb.intersects(&pk.aabb)
                && !balls_apart(&balls[pi.balls.clone()], &balls[pk.balls.clone()], pad)
                && Solid::of(pi).within(Solid::of(pk), pad)
        };
        let mut pairs = Vec::new();
        for &(a, b) in &self.checked_pairs {
            let (Some((ca, ra)), Some((cb, rb))) = (bodies.bound(a), bodies.bound(b)) else {
                continue;
            };
            // Each ball is grown by its own padding: together at least the pair's.
            if (ca - cb).length_squared() > (ra + rb) * (ra + rb) {
                continue;
            }
            let pad = self.bodies[a].padding.max(self.bodies[b].padding);
            if self
                .pair_tables
                .floor(self, a, b, q)
                .is_some_and(|d| d > pad)
            {
                continue;
            }
            let (sa, sb) = (bodies.body(a), bodies.body(b));
            pairs.clear();
            let balls = &*bodies.balls;
            body_piece_pairs(
                &bodies.placed,
                sa,
                sb,
                0.0,
                |pi, pk| meet(pi, pk, balls),
                &mut pairs,
            );
            for &(i, k) in &pairs {
                if meet(&bodies.placed[i], &bodies.placed[k], balls) {
                    return Some((self.bodies[a].name.clone(), self.bodies[b].name.clone()));
                }
            }
        }
        None
    }

    /// Attached objects against the world and the robot.
    fn attached_hit(&self, bodies: &mut OnDemand) -> Option<Pair> {
        let n = self.bodies.len();
        bodies.place_all();
        let placed = &bodies.placed;
        for a in &self.attached {
            let w = bodies.pose(a.body) * a.link_from_object;
            let pad = self.bodies[a.body].padding;
            let aabb = a.shape.compute_aabb(&w).loosened(pad);
            let solid = Solid {
                pose: &w,
                shape: &a.shape,
                hull: None,
            };
            for o in self.objects_near(&aabb) {
                if solid.touches(&aabb, o, pad) {
                    return Some((a.name.clone(), o.name.clone()));
                }
            }
            for p in placed {
                if p.outer || a.touch.contains(&p.body) || p.body >= n {
                    continue;
                }
                let other = Solid {
                    pose: &p.pose,
                    shape: p.shape,
                    hull: None,
                };
                if aabb.intersects(&p.aabb) && solid.within(other, pad) {
                    return Some((a.name.clone(), self.bodies[p.body].name.clone()));
                }
            }
        }
        None
    }
}
