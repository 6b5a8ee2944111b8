//! The yes/no question of a configuration: within the joint limits, and no checked
//! pair within its padding — balls first, the hull of a decomposed link next, exact
//! GJK last.

use super::gjk::{self, Hull};
use super::placed::{Placed, balls_apart, balls_clear_of};
use super::{CollisionWorld, Scratch, WorldError, WorldObject};
use tabula_geom::Pose;
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;

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
        self.with_bodies_at(q, |Scratch { poses, balls, .. }, outside| {
            if let Some(i) = outside {
                return Some(("joint limits".into(), self.chain.joint_names[i].clone()));
            }
            // Shapes in the world frame with their boxes, grown by their link's padding.
            let placed = self.placed_shapes(poses, true, balls);
            self.robot_hits_world(&placed, balls)
                .or_else(|| self.robot_hits_itself(q, &placed, balls))
                .or_else(|| self.attached_hit(poses, &placed))
        })
    }

    /// Robot against the world (only what moves can newly collide): the exact query
    /// only where the shape's cover is within the padding of the object; a decomposed
    /// link's pieces only against what its outer hull touches.
    fn robot_hits_world(
        &self,
        placed: &[Placed],
        balls: &[(tabula_geom::Vec3, f64)],
    ) -> Option<Pair> {
        let mut suspects: (usize, Vec<usize>) = (usize::MAX, Vec::new());
        for p in placed {
            let (b, pad) = (p.body, self.bodies[p.body].padding);
            if !self.bodies[b].moving {
                continue;
            }
            let touches = |o: &WorldObject| {
                !o.allowed_bodies.contains(&b)
                    && o.aabb.intersects(&p.aabb)
                    && !balls_clear_of(&balls[p.balls.clone()], o, pad)
                    && Solid::of(p).touches(&p.aabb, o, pad)
            };
            if p.outer {
                let near = self.object_indices_near(&p.aabb);
                suspects = (b, near.filter(|&i| touches(&self.objects[i])).collect());
                continue;
            }
            let hit = if suspects.0 == b {
                suspects
                    .1
                    .iter()
                    .map(|&i| &self.objects[i])
                    .find(|o| touches(o))
            } else {
                self.objects_near(&p.aabb).find(|o| touches(o))
            };
            if let Some(o) = hit {
                return Some((self.bodies[b].name.clone(), o.name.clone()));
            }
        }
        None
    }

    /// Robot against itself: body pairs first (a decomposed link has dozens of pieces),
    /// then the pieces of the pairs whose boxes meet.
    fn robot_hits_itself(
        &self,
        q: &[f64],
        placed: &[Placed],
        balls: &[(tabula_geom::Vec3, f64)],
    ) -> Option<Pair> {
        let meet = |pi: &Placed, pk: &Placed| {
            let pad = self.bodies[pi.body]
                .padding
                .max(self.bodies[pk.body].padding);
            pi.aabb.intersects(&pk.aabb)
                && !balls_apart(&balls[pi.balls.clone()], &balls[pk.balls.clone()], pad)
                && Solid::of(pi).within(Solid::of(pk), pad)
        };
        let apart = |a: usize, b: usize| {
            let pad = self.bodies[a].padding.max(self.bodies[b].padding);
            self.pair_tables
                .floor(self, a, b, q)
                .is_some_and(|d| d > pad)
        };
        for (i, k) in self.self_piece_pairs(placed, 0.0, apart, meet) {
            let (pi, pk) = (&placed[i], &placed[k]);
            let (a, b) = (pi.body, pk.body);
            if self.self_pair_checked(a, b) && meet(pi, pk) {
                return Some((self.bodies[a].name.clone(), self.bodies[b].name.clone()));
            }
        }
        None
    }

    /// Attached objects against the world and the robot.
    fn attached_hit(&self, poses: &[Pose], placed: &[Placed]) -> Option<Pair> {
        let n = self.bodies.len();
        for a in &self.attached {
            let w = poses[a.body] * a.link_from_object;
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
