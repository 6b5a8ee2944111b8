//! The yes/no question of a configuration: within the joint limits, and no checked
//! pair within its padding — balls first, the hull of a decomposed link next, exact
//! GJK last.

use super::gjk::{self, Hull};
use super::placed::{Placed, balls_apart, balls_clear_of};
use super::{Attached, CollisionWorld, WorldError, WorldObject};
use tabula_geom::Pose;
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;

impl CollisionWorld {
    /// The first colliding pair at `q` (names), or `None` when `q` is valid. Joint limits
    /// count: a configuration outside them is reported as `("joint limits", name)`.
    pub fn first_collision(&self, q: &[f64]) -> Result<Option<(String, String)>, WorldError> {
        self.checks.set(self.checks.get() + 1);
        let poses = self.body_poses(q)?;
        for (i, v) in q.iter().enumerate() {
            if *v < self.chain.lower[i] - 1e-9 || *v > self.chain.upper[i] + 1e-9 {
                return Ok(Some((
                    "joint limits".into(),
                    self.chain.joint_names[i].clone(),
                )));
            }
        }
        let n = self.bodies.len();
        // Shapes in the world frame with their boxes, grown by their link's padding.
        let mut balls = Vec::new();
        let placed = self.placed_shapes(&poses, true, &mut balls);
        let attached: Vec<(usize, Pose, &Attached, Aabb)> = self
            .attached
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let w = poses[a.body] * a.link_from_object;
                (
                    i,
                    w,
                    a,
                    a.shape
                        .compute_aabb(&w)
                        .loosened(self.bodies[a.body].padding),
                )
            })
            .collect();
        // A yes/no question: GJK distance, not the penetration depth (EPA) `contact` computes.
        let hits_hull = |p1: &Pose,
                         s1: &SharedShape,
                         h1: Option<&Hull>,
                         p2: &Pose,
                         s2: &SharedShape,
                         h2: Option<&Hull>,
                         pad: f64| {
            match (gjk::support(s1, h1), gjk::support(s2, h2)) {
                (Some(g1), Some(g2)) => gjk::within(p1, g1, p2, g2, pad),
                _ => query::distance(p1, s1.as_ref(), p2, s2.as_ref())
                    .is_ok_and(|d| d.distance <= pad),
            }
        };
        let hits = |p1: &Pose, s1: &SharedShape, p2: &Pose, s2: &SharedShape, pad: f64| {
            hits_hull(p1, s1, None, p2, s2, None, pad)
        };
        // Against a compound (an occupancy map) only the parts near the shape count:
        // the compound's own distance would look for the nearest of all of them.
        let hits_object = |p1: &Pose,
                           s1: &SharedShape,
                           h1: Option<&Hull>,
                           aabb: &Aabb,
                           o: &WorldObject,
                           pad: f64| match o.shape.as_compound() {
            Some(c) => {
                let local = aabb.transform_by(&o.world_from_object.inverse());
                c.bvh().intersect_aabb(&local).any(|i| {
                    let (part_pose, part) = &c.shapes()[i as usize];
                    hits_hull(
                        p1,
                        s1,
                        h1,
                        &(o.world_from_object * *part_pose),
                        part,
                        None,
                        pad,
                    )
                })
            }
            None => hits_hull(p1, s1, h1, &o.world_from_object, &o.shape, None, pad),
        };
        // Robot against the world (only what moves can newly collide): the exact query
        // only where the shape's cover is within the padding of the object; a
        // decomposed link's pieces only against what its outer hull touches.
        let mut suspects: (usize, Vec<usize>) = (usize::MAX, Vec::new());
        for p in &placed {
            let (b, pad) = (p.body, self.bodies[p.body].padding);
            if !self.bodies[b].moving {
                continue;
            }
            let touches = |o: &WorldObject| {
                !o.allowed_bodies.contains(&b)
                    && o.aabb.intersects(&p.aabb)
                    && !balls_clear_of(&balls[p.balls.clone()], o, pad)
                    && hits_object(&p.pose, p.shape, p.hull, &p.aabb, o, pad)
            };
            if p.outer {
                let near = self.objects_bvh.intersect_aabb(&p.aabb).map(|i| i as usize);
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
                return Ok(Some((self.bodies[b].name.clone(), o.name.clone())));
            }
        }
        // Robot against itself: body pairs first (a decomposed link has dozens of
        // pieces), then the pieces of the pairs whose boxes meet.
        let outer_touches = |pi: &Placed, pk: &Placed| {
            let pad = self.bodies[pi.body]
                .padding
                .max(self.bodies[pk.body].padding);
            pi.aabb.intersects(&pk.aabb)
                && !balls_apart(&balls[pi.balls.clone()], &balls[pk.balls.clone()], pad)
                && hits_hull(
                    &pi.pose, pi.shape, pi.hull, &pk.pose, pk.shape, pk.hull, pad,
                )
        };
        for (i, k) in self.self_piece_pairs(&placed, 0.0, outer_touches) {
            {
                let (pi, pk) = (&placed[i], &placed[k]);
                let (a, b) = (pi.body, pk.body);
                if !self.self_pair_checked(a, b) {
                    continue;
                }
                let pad = self.bodies[a].padding.max(self.bodies[b].padding);
                if pi.aabb.intersects(&pk.aabb)
                    && !balls_apart(&balls[pi.balls.clone()], &balls[pk.balls.clone()], pad)
                    && hits_hull(
                        &pi.pose, pi.shape, pi.hull, &pk.pose, pk.shape, pk.hull, pad,
                    )
                {
                    return Ok(Some((
                        self.bodies[a].name.clone(),
                        self.bodies[b].name.clone(),
                    )));
                }
            }
        }
        // Attached objects against the world and the robot.
        for (_, w, a, aabb) in &attached {
            let pad = self.bodies[a.body].padding;
            for o in self.objects_near(aabb) {
                if hits_object(w, &a.shape, None, aabb, o, pad) {
                    return Ok(Some((a.name.clone(), o.name.clone())));
                }
            }
            for p in &placed {
                if p.outer || a.touch.contains(&p.body) || p.body >= n {
                    continue;
                }
                if aabb.intersects(&p.aabb) && hits(w, &a.shape, &p.pose, p.shape, pad) {
                    return Ok(Some((a.name.clone(), self.bodies[p.body].name.clone())));
                }
            }
        }
        Ok(None)
    }
}
