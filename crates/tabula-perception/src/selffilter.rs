//! Robot self-filter (SPEC §1.1): points inside the robot's own link shapes, inflated
//! by a padding, are the robot, not the world. The caller poses the shapes (forward
//! kinematics lives in tabula-robot); this module only does the geometry, so it also
//! filters a held object or a gripper's protective sphere.

use rayon::prelude::*;
use tabula_geom::input::{Validate, check_non_negative};
use tabula_geom::{Pose, Vec3};

/// Parameters.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SelfFilterParams {
    /// Inflation of every shape (m), SPEC §1.1: 0.9 cm.
    pub padding: f64,
}

impl Default for SelfFilterParams {
    fn default() -> Self {
        Self { padding: 0.009 }
    }
}

/// A solid in its own frame (cylinders and capsules along z, centred).
#[derive(Debug, Clone, PartialEq)]
pub enum Solid {
    Box {
        half_extents: Vec3,
    },
    Sphere {
        radius: f64,
    },
    Cylinder {
        radius: f64,
        half_length: f64,
    },
    Capsule {
        radius: f64,
        half_length: f64,
    },
    /// Intersection of half-spaces `n · p ≤ d` (a convex hull) whose vertices are
    /// within `radius` of the origin.
    Convex {
        planes: Vec<(Vec3, f64)>,
        radius: f64,
    },
}

impl Solid {
    /// The convex hull of `points` as half-spaces; `None` for degenerate input.
    pub fn convex_hull(points: &[Vec3]) -> Option<Self> {
        let (vertices, triangles) =
            tabula_geom::parry::transformation::try_convex_hull(points).ok()?;
        let centre = vertices.iter().copied().sum::<Vec3>() / vertices.len().max(1) as f64;
        let planes: Vec<(Vec3, f64)> = triangles
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|i| vertices[i as usize]);
                let mut n = (b - a).cross(c - a).try_normalize()?;
                if n.dot(centre - a) > 0.0 {
                    n = -n;
                }
                Some((n, n.dot(a)))
            })
            .collect();
        let radius = vertices.iter().map(|v| v.length()).fold(0.0, f64::max);
        (planes.len() >= 4).then_some(Solid::Convex { planes, radius })
    }

    /// Signed distance-like test: is `p` (shape frame) within `pad` of the solid?
    fn contains(&self, p: Vec3, pad: f64) -> bool {
        match self {
            Solid::Box { half_extents } => {
                (p.abs() - *half_extents).max(Vec3::ZERO).length() <= pad
            }
            Solid::Sphere { radius } => p.length() <= radius + pad,
            Solid::Cylinder {
                radius,
                half_length,
            } => {
                let radial = (p.x * p.x + p.y * p.y).sqrt() - radius;
                let axial = p.z.abs() - half_length;
                radial.max(0.0).hypot(axial.max(0.0)) <= pad
            }
            Solid::Capsule {
                radius,
                half_length,
            } => {
                let z = p.z.clamp(-half_length, *half_length);
                (p - Vec3::new(0.0, 0.0, z)).length() <= radius + pad
            }
            Solid::Convex { planes, .. } => planes.iter().all(|(n, d)| n.dot(p) - d <= pad),
        }
    }

    /// Radius of a sphere about the shape origin that holds the solid.
    fn bound(&self) -> f64 {
        match self {
            Solid::Box { half_extents } => half_extents.length(),
            Solid::Sphere { radius } => *radius,
            Solid::Cylinder {
                radius,
                half_length,
            } => radius.hypot(*half_length),
            Solid::Capsule {
                radius,
                half_length,
            } => radius + half_length,
            Solid::Convex { radius, .. } => *radius,
        }
    }
}

/// A solid placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedSolid {
    pub world_from_solid: Pose,
    pub solid: Solid,
}

/// Keep mask: `false` for points within `padding` of any solid (and for non-finite
/// points).
pub fn self_filter(points: &[Vec3], solids: &[PlacedSolid], p: &SelfFilterParams) -> Vec<bool> {
    let pad = p.padding.max(0.0);
    let prepared: Vec<(Pose, Vec3, f64, &Solid)> = solids
        .iter()
        .filter(|s| s.world_from_solid.is_finite())
        .map(|s| {
            let r = s.solid.bound() + pad;
            (
                s.world_from_solid.inverse(),
                s.world_from_solid.translation,
                r * r,
                &s.solid,
            )
        })
        .collect();
    points
        .par_iter()
        .map(|q| {
            q.is_finite()
                && !prepared
                    .iter()
                    .any(|(solid_from_world, centre, r2, solid)| {
                        q.distance_squared(*centre) <= *r2
                            && solid.contains(*solid_from_world * *q, pad)
                    })
        })
        .collect()
}

impl Validate for SelfFilterParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_non_negative(at, "padding", self.padding)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_in_padded_shapes_go() {
        let at = |x: f64| Pose::from_translation(Vec3::new(x, 0.0, 0.0));
        let solids = vec![
            PlacedSolid {
                world_from_solid: at(0.0),
                solid: Solid::Box {
                    half_extents: Vec3::splat(0.05),
                },
            },
            PlacedSolid {
                world_from_solid: at(1.0),
                solid: Solid::Sphere { radius: 0.05 },
            },
            PlacedSolid {
                world_from_solid: at(2.0),
                solid: Solid::Cylinder {
                    radius: 0.05,
                    half_length: 0.1,
                },
            },
            PlacedSolid {
                world_from_solid: at(3.0),
                solid: Solid::Capsule {
                    radius: 0.05,
                    half_length: 0.1,
                },
            },
            PlacedSolid {
                world_from_solid: at(4.0),
                solid: Solid::convex_hull(&[
                    Vec3::new(-0.05, -0.05, -0.05),
                    Vec3::new(0.05, -0.05, -0.05),
                    Vec3::new(-0.05, 0.05, -0.05),
                    Vec3::new(0.05, 0.05, -0.05),
                    Vec3::new(-0.05, -0.05, 0.05),
                    Vec3::new(0.05, -0.05, 0.05),
                    Vec3::new(-0.05, 0.05, 0.05),
                    Vec3::new(0.05, 0.05, 0.05),
                ])
                .unwrap(),
            },
        ];
        let p = SelfFilterParams::default();
        for x in [0.0, 1.0, 2.0, 3.0, 4.0] {
            let pts = [
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x + 0.058, 0.0, 0.0),
                Vec3::new(x + 0.062, 0.0, 0.0),
                Vec3::new(x, 0.0, 0.3),
            ];
            assert_eq!(
                self_filter(&pts, &solids, &p),
                [false, false, true, true],
                "shape at {x}"
            );
        }
        assert_eq!(self_filter(&[Vec3::NAN], &solids, &p), [false]);
        assert!(Solid::convex_hull(&[Vec3::ZERO, Vec3::X]).is_none());
    }
}
