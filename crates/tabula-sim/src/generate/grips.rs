//! How the placing suite's PR2 holds the object it must put down: the grip (object
//! from tool) of a generated task.

use crate::objects::ObjectMesh;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use tabula_geom::{Mat3, Pose, Quat, Vec3};

/// Which grips the placing suite's robot holds its object in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GripRule {
    /// Seed 000's suite: the fingers close along an object axis narrow enough, through
    /// the object's middle where there is material, seated deep on the pads, the hand
    /// above the object's base (it was picked up from a table).
    #[default]
    Centred,
    /// Anywhere a parallel gripper can really hold the object (issue 32): the object
    /// turned at random in the hand, the fingers on any part of it — a handle, a rim,
    /// an end — whose width between the pads fits the opening, centred as closing
    /// fingers push it, nothing inside the palm. Whether one of its stable poses leaves
    /// the hand clear of a table needs the stable poses: the caller's test.
    Anywhere,
}

/// Room left between each open finger and the held part (m): fingers that must touch
/// the object to open around it were not really holding it.
const FINGER_ROOM: f64 = 0.005;
/// The narrowest part the PR2's pads hold (m): thinner slips between their rubber.
const MIN_HELD_WIDTH: f64 = 0.008;
/// Clearance kept between the object and the palm or the fingers' knuckles (m).
const PALM_CLEARANCE: f64 = 0.002;
/// Where the object's surface is sampled for the palm test (m between samples).
const PALM_SAMPLING: f64 = 0.004;

/// The grip under `rule` (object from tool; tool x the approach, y the closing axis).
pub(super) fn grip(rng: &mut ChaCha8Rng, mesh: &ObjectMesh, rule: GripRule) -> Pose {
    let hand = Hand::pr2();
    match rule {
        GripRule::Centred => centred_grip(rng, mesh, &hand),
        GripRule::Anywhere => anywhere_grip(rng, mesh, &hand).unwrap_or_else(|| {
            // Never seen on the catalogue: the centred rule's grip.
            centred_grip(rng, mesh, &hand)
        }),
    }
}

/// The PR2 gripper as boxes in its tool frame (x the approach, y the closing axis).
struct Hand {
    /// The fingers' span along the approach (back, tip) and half height (m).
    fingers: Option<(f64, f64, f64)>,
    /// Every other box of the hand (palm, knuckles): (centre, half size).
    palm: Vec<(Vec3, Vec3)>,
    /// Corners of every box of the hand.
    corners: Vec<Vec3>,
    open_width: f64,
}

impl Hand {
    fn pr2() -> Self {
        let gripper = tabula_robot::robots::load("pr2")
            .ok()
            .and_then(|r| r.description.grippers.first().cloned());
        let boxes: Vec<(Vec3, Vec3)> = gripper
            .as_ref()
            .map(|g| {
                g.self_filter_boxes
                    .iter()
                    .map(|b| (Vec3::from_array(b.center), Vec3::from_array(b.size) / 2.0))
                    .collect()
            })
            .unwrap_or_default();
        // The fingers are the box reaching furthest forward.
        let front = (0..boxes.len()).max_by(|&a, &b| {
            (boxes[a].0.x + boxes[a].1.x).total_cmp(&(boxes[b].0.x + boxes[b].1.x))
        });
        let fingers = front.map(|i| {
            let (c, h) = boxes[i];
            (c.x - h.x, c.x + h.x, h.z)
        });
        let corners = boxes
            .iter()
            .flat_map(|(c, h)| {
                (0..8).map(move |i| {
                    *c + *h
                        * Vec3::new(
                            if i & 1 == 0 { -1.0 } else { 1.0 },
                            if i & 2 == 0 { -1.0 } else { 1.0 },
                            if i & 4 == 0 { -1.0 } else { 1.0 },
                        )
                })
            })
            .collect();
        let palm = (0..boxes.len())
            .filter(|i| Some(*i) != front)
            .map(|i| boxes[i])
            .collect();
        Hand {
            fingers,
            palm,
            corners,
            open_width: gripper.map_or(0.09, |g| g.open_width),
        }
    }

    /// Where the samples between the pads (the fingers' slab through `o`) lie along
    /// the closing axis, relative to `o`: (lowest, highest).
    fn pad_span(&self, surface: &[Vec3], o: Vec3, frame: &Mat3) -> Option<(f64, f64)> {
        let (back, tip, half) = self.fingers?;
        let (approach, closing, third) = (frame.col(0), frame.col(1), frame.col(2));
        let (lo, hi) = surface
            .iter()
            .filter(|p| {
                let d = **p - o;
                (back..=tip).contains(&d.dot(approach)) && d.dot(third).abs() <= half
            })
            .map(|p| (*p - o).dot(closing))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                (a.min(c), b.max(c))
            });
        (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
    }

    /// `o` moved along the closing axis to the middle of what lies between the pads, as
    /// closing parallel fingers push an object (else one finger would close into it
    /// until the other touched).
    fn centred(&self, surface: &[Vec3], o: Vec3, frame: &Mat3) -> Vec3 {
        self.pad_span(surface, o, frame)
            .map_or(o, |(lo, hi)| o + frame.col(1) * (lo + hi) / 2.0)
    }

    /// No sample inside the palm or the knuckles (with the clearance).
    fn palm_clear(&self, surface: &[Vec3], o: Vec3, frame: &Mat3) -> bool {
        let tool_from_object = frame.transpose();
        surface.iter().all(|p| {
            let q = tool_from_object * (*p - o);
            self.palm.iter().all(|(c, h)| {
                ((q - *c).abs() - *h - Vec3::splat(PALM_CLEARANCE)).max_element() > 0.0
            })
        })
    }
}

/// Seed 000's grip: fingers closing along an object axis narrow enough, the approach at
/// any angle about it, the palm against the object's back.
fn centred_grip(rng: &mut ChaCha8Rng, mesh: &ObjectMesh, hand: &Hand) -> Pose {
    let (lo, hi) = tabula_geom::bounds(&mesh.vertices);
    let extent = hi - lo;
    let axes: Vec<Vec3> = [Vec3::X, Vec3::Y, Vec3::Z]
        .into_iter()
        .zip(extent.to_array())
        .filter(|(_, e)| *e <= 0.078)
        .map(|(a, _)| a)
        .collect();
    let axes = if axes.is_empty() { vec![Vec3::Z] } else { axes };
    // Candidates until the fingers, closing through the tool point, meet material on
    // both sides (an L's or a mug's bounding-box centre may be empty air), with the hand
    // above the object's base: it was picked up from a table, so the hand came from
    // above or the side, never from under it.
    let surface = surface_samples(mesh, f64::INFINITY);
    let mut grip = None;
    for attempt in 0..400 {
        let closing = axes[rng.random_range(0..axes.len())];
        let (u, v) = (
            closing.any_orthonormal_vector(),
            closing.cross(closing.any_orthonormal_vector()),
        );
        let theta = rng.random_range(0.0..std::f64::consts::TAU);
        let approach = u * theta.cos() + v * theta.sin();
        let mut origin = if attempt == 0 {
            (lo + hi) / 2.0
        } else {
            lo + extent
                * Vec3::new(
                    rng.random_range(0.2..0.8),
                    rng.random_range(0.2..0.8),
                    rng.random_range(0.2..0.8),
                )
        };
        let reach = |origin: Vec3, d: Vec3| {
            mesh.vertices
                .iter()
                .map(|p| (*p - origin).dot(d))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let behind = reach(origin, -approach);
        if behind > 0.035 {
            origin -= approach * (behind - 0.035);
        }
        // Seated on the finger pads: the object reaches past the fingertips (2.25 cm
        // beyond the tool frame on a PR2) where it can, as a closed grasp holds it.
        let front = reach(origin, approach);
        let rotation = Mat3::from_cols(approach, closing, approach.cross(closing));
        let (origin, seated) = (
            hand.centred(&surface, origin, &rotation),
            hand.centred(
                &surface,
                origin + approach * (front - 0.03).min(0.0),
                &rotation,
            ),
        );
        // The hand clear of the table the object stood on (a flat box taken from above
        // cannot also be seated deep on the pads: then it is held nearer the tips).
        let clear = |o: Vec3| {
            hand.corners
                .iter()
                .all(|h| (o + rotation * *h).z >= lo.z + 0.004)
        };
        let chosen = [seated, origin]
            .into_iter()
            .find(|o| clear(*o) && ray_hits(mesh, *o, closing) && ray_hits(mesh, *o, -closing));
        if let Some(o) = chosen {
            grip = Some((o, rotation));
            break;
        }
    }
    // Never seen in the suite; a plain grip from the side if nothing else was found.
    let (origin, rotation) = grip.unwrap_or_else(|| {
        let approach = Vec3::Z.cross(axes[0]).normalize_or(Vec3::X);
        (
            (lo + hi) / 2.0,
            Mat3::from_cols(approach, axes[0], approach.cross(axes[0])),
        )
    });
    Pose::from_parts(origin, Quat::from_mat3(&rotation))
}

/// A grip anywhere on the object ([`GripRule::Anywhere`]): the closing axis uniform on
/// the sphere, the approach uniform about it, the tool point uniform in the object's
/// box, kept when the pads' part fits the opening, the fingers meet material on both
/// sides of the tool point and the palm is clear. `None` after 4,000 draws.
fn anywhere_grip(rng: &mut ChaCha8Rng, mesh: &ObjectMesh, hand: &Hand) -> Option<Pose> {
    let (lo, hi) = tabula_geom::bounds(&mesh.vertices);
    let extent = hi - lo;
    let surface = surface_samples(mesh, PALM_SAMPLING);
    for _ in 0..4000 {
        let closing = loop {
            let v = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let n = v.length();
            if (0.1..=1.0).contains(&n) {
                break v / n;
            }
        };
        let (u, v) = (
            closing.any_orthonormal_vector(),
            closing.cross(closing.any_orthonormal_vector()),
        );
        let theta = rng.random_range(0.0..std::f64::consts::TAU);
        let approach = u * theta.cos() + v * theta.sin();
        let rotation = Mat3::from_cols(approach, closing, approach.cross(closing));
        let origin = lo
            + extent
                * Vec3::new(
                    rng.random_range(0.0..1.0),
                    rng.random_range(0.0..1.0),
                    rng.random_range(0.0..1.0),
                );
        let Some((a, b)) = hand.pad_span(&surface, origin, &rotation) else {
            continue;
        };
        let width = b - a;
        if !(MIN_HELD_WIDTH..=hand.open_width - 2.0 * FINGER_ROOM).contains(&width) {
            continue;
        }
        let o = origin + closing * (a + b) / 2.0;
        if ray_hits(mesh, o, closing)
            && ray_hits(mesh, o, -closing)
            && hand.palm_clear(&surface, o, &rotation)
        {
            return Some(Pose::from_parts(o, Quat::from_mat3(&rotation)));
        }
    }
    None
}

/// Whether the ray from `o` along `d` crosses a triangle of the mesh (Möller–Trumbore).
fn ray_hits(mesh: &ObjectMesh, o: Vec3, d: Vec3) -> bool {
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            return false;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
    })
}

/// The mesh's surface, sampled: where the fingers and the palm meet it. Each triangle
/// is cut into at least 8 steps a side, more where its longest edge is longer than
/// `spacing` steps.
fn surface_samples(mesh: &ObjectMesh, spacing: f64) -> Vec<Vec3> {
    mesh.triangles
        .iter()
        .flat_map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            let longest = (b - a).length().max((c - a).length()).max((c - b).length());
            let steps = ((longest / spacing).ceil() as usize).clamp(8, 64);
            (0..=steps).flat_map(move |i| {
                (0..=steps - i).map(move |j| {
                    let (s, t) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    a + (b - a) * s + (c - a) * t
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Every catalogue object gets grips anywhere on it: each one fits the opening,
    /// keeps the palm clear and has material on both sides of the tool point; over 40
    /// draws they reach the object's ends and turn it every way.
    #[test]
    fn anywhere_grips_hold_and_spread_over_the_object() {
        let hand = Hand::pr2();
        for mesh in crate::objects::catalogue() {
            let (lo, hi) = tabula_geom::bounds(&mesh.vertices);
            let middle = (lo + hi) / 2.0;
            let surface = surface_samples(&mesh, PALM_SAMPLING);
            let mut rng = ChaCha8Rng::seed_from_u64(7);
            let (mut farthest, mut closings) = (0.0f64, Vec::<Vec3>::new());
            for _ in 0..40 {
                let Some(g) = anywhere_grip(&mut rng, &mesh, &hand) else {
                    panic!("{}: no grip", mesh.name);
                };
                let frame = Mat3::from_quat(g.rotation);
                let (a, b) = hand.pad_span(&surface, g.translation, &frame).unwrap();
                assert!(
                    b - a <= hand.open_width - 2.0 * FINGER_ROOM + 1e-9,
                    "{}",
                    mesh.name
                );
                assert!((a + b).abs() < 1e-6, "{}: not centred", mesh.name);
                assert!(hand.palm_clear(&surface, g.translation, &frame));
                farthest = farthest.max((g.translation - middle).length());
                closings.push(frame.col(1));
            }
            let size = (hi - lo).max_element();
            eprintln!("{}: farthest {:.3} of {:.3}", mesh.name, farthest, size);
            assert!(
                farthest > 0.25 * size,
                "{}: grips stay in the middle",
                mesh.name
            );
            let spread = closings
                .iter()
                .map(|c| closings[0].dot(*c).abs())
                .fold(1.0f64, f64::min);
            assert!(spread < 0.5, "{}: one closing axis only", mesh.name);
        }
    }
}
