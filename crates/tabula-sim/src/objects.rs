//! Test objects as closed triangle meshes: the simple shapes and the complex ones seed
//! 000 tried (a drill, a door handle, a bottle …) and the ones that make stable-pose
//! search hard (a mug's handle, a sphere with a pocket, an overhanging L). Every mesh is
//! closed and outward-facing, made of disjoint closed parts, so its volume centroid is
//! its centre of mass at uniform density. Meshes are in metres, resting on z = 0 when
//! upright, centred on the z axis.

use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;
use tabula_geom::Vec3;

/// A named closed mesh.
#[derive(Debug, Clone)]
pub struct ObjectMesh {
    pub name: String,
    /// Boxes, cubes and cylinders; the rest are "complex".
    pub simple: bool,
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl ObjectMesh {
    fn new(name: &str, simple: bool) -> Self {
        Self {
            name: name.into(),
            simple,
            vertices: Vec::new(),
            triangles: Vec::new(),
        }
    }

    /// A mesh from its parts.
    pub fn from_parts(
        name: &str,
        simple: bool,
        (vertices, triangles): (Vec<Vec3>, Vec<[u32; 3]>),
    ) -> Self {
        Self {
            name: name.into(),
            simple,
            vertices,
            triangles,
        }
    }

    /// Appends another closed part (disjoint from the rest or touching it on a face).
    fn add(mut self, part: (Vec<Vec3>, Vec<[u32; 3]>)) -> Self {
        let off = self.vertices.len() as u32;
        self.vertices.extend(part.0);
        self.triangles
            .extend(part.1.into_iter().map(|t| t.map(|i| i + off)));
        self
    }

    /// The mesh as Wavefront OBJ text.
    pub fn to_obj(&self) -> String {
        let mut s = format!("# tabula test object `{}`\n", self.name);
        for v in &self.vertices {
            let _ = writeln!(s, "v {:.6} {:.6} {:.6}", v.x, v.y, v.z);
        }
        for t in &self.triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    }

    /// Half the largest horizontal extent (m): how far it reaches from its axis.
    pub fn radius(&self) -> f64 {
        self.vertices
            .iter()
            .map(|v| v.truncate().length())
            .fold(0.0, f64::max)
    }

    pub fn height(&self) -> f64 {
        let (lo, hi) = self
            .vertices
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v.z), b.max(v.z))
            });
        hi - lo
    }
}

/// An axis-aligned box with its minimum corner at `lo`.
pub fn cuboid(lo: Vec3, size: Vec3) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let v: Vec<Vec3> = (0..8)
        .map(|i| {
            lo + Vec3::new(
                if i & 1 == 0 { 0.0 } else { size.x },
                if i & 2 == 0 { 0.0 } else { size.y },
                if i & 4 == 0 { 0.0 } else { size.z },
            )
        })
        .collect();
    let t = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    (v, t)
}

/// A solid of revolution about z: `profile` is (radius, z) from the bottom pole to the
/// top pole (first and last radius 0), counter-clockwise in the (r, z) half-plane.
pub fn lathe(profile: &[(f64, f64)], segments: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    // Index of each profile point's ring (a pole is one vertex).
    let mut ring: Vec<(u32, bool)> = Vec::new();
    for &(r, z) in profile {
        ring.push((v.len() as u32, r == 0.0));
        if r == 0.0 {
            v.push(Vec3::new(0.0, 0.0, z));
        } else {
            for k in 0..segments {
                let a = TAU * k as f64 / segments as f64;
                v.push(Vec3::new(r * a.cos(), r * a.sin(), z));
            }
        }
    }
    let at = |(start, pole): (u32, bool), k: usize| {
        if pole {
            start
        } else {
            start + (k % segments) as u32
        }
    };
    let mut t = Vec::new();
    for w in ring.windows(2) {
        let (a, b) = (w[0], w[1]);
        for k in 0..segments {
            let (a0, a1, b0, b1) = (at(a, k), at(a, k + 1), at(b, k), at(b, k + 1));
            if !a.1 {
                t.push([a0, a1, b1]);
            }
            if !b.1 {
                t.push([a0, b1, b0]);
            }
            if a.1 && b.1 {
                break;
            }
        }
    }
    (v, t)
}

/// Every object the placing benchmark and the stable-pose comparison use, at their
/// nominal sizes (the placing suite scales them).
pub fn catalogue() -> Vec<ObjectMesh> {
    vec![
        ObjectMesh::new("cube", true)
            .add(cuboid(Vec3::new(-0.025, -0.025, 0.0), Vec3::splat(0.05))),
        ObjectMesh::new("box", true).add(cuboid(
            Vec3::new(-0.15, -0.05, 0.0),
            Vec3::new(0.3, 0.1, 0.05),
        )),
        ObjectMesh::new("cylinder", true).add(lathe(
            &[(0.0, 0.0), (0.03, 0.0), (0.03, 0.12), (0.0, 0.12)],
            32,
        )),
        pyramid(),
        l_prism(),
        ObjectMesh::new("cone", false).add(lathe(&[(0.0, 0.0), (0.04, 0.0), (0.0, 0.1)], 32)),
        drill(),
        mug(),
        bottle(),
        pocket_sphere(),
        door_handle(),
    ]
}

/// The catalogue object called `name`.
pub fn object(name: &str) -> Option<ObjectMesh> {
    catalogue().into_iter().find(|o| o.name == name)
}

fn pyramid() -> ObjectMesh {
    let v = vec![
        Vec3::new(-0.04, -0.04, 0.0),
        Vec3::new(0.04, -0.04, 0.0),
        Vec3::new(0.04, 0.04, 0.0),
        Vec3::new(-0.04, 0.04, 0.0),
        Vec3::new(0.0, 0.0, 0.07),
    ];
    let t = vec![
        [0, 2, 1],
        [0, 3, 2],
        [0, 1, 4],
        [1, 2, 4],
        [2, 3, 4],
        [3, 0, 4],
    ];
    ObjectMesh::new("pyramid", false).add((v, t))
}

/// An L whose long arm lies on the table and whose short arm stands at one end.
fn l_prism() -> ObjectMesh {
    ObjectMesh::new("l_prism", false)
        .add(cuboid(
            Vec3::new(-0.06, -0.025, 0.0),
            Vec3::new(0.12, 0.05, 0.025),
        ))
        .add(cuboid(
            Vec3::new(0.035, -0.025, 0.025),
            Vec3::new(0.025, 0.05, 0.06),
        ))
}

/// A cordless drill standing on its battery: battery, grip, and a body with a chuck
/// overhanging forward.
fn drill() -> ObjectMesh {
    ObjectMesh::new("drill", false)
        .add(cuboid(
            Vec3::new(-0.04, -0.03, 0.0),
            Vec3::new(0.08, 0.06, 0.03),
        ))
        .add(cuboid(
            Vec3::new(-0.02, -0.02, 0.03),
            Vec3::new(0.04, 0.04, 0.09),
        ))
        .add(cuboid(
            Vec3::new(-0.04, -0.025, 0.12),
            Vec3::new(0.14, 0.05, 0.05),
        ))
        .add(cuboid(
            Vec3::new(0.10, -0.012, 0.133),
            Vec3::new(0.035, 0.024, 0.024),
        ))
}

/// A hollow mug (wall 5 mm, bottom 8 mm) with a loop handle.
fn mug() -> ObjectMesh {
    let (r, h) = (0.035, 0.09);
    ObjectMesh::new("mug", false)
        .add(lathe(
            &[
                (0.0, 0.0),
                (r, 0.0),
                (r, h),
                (r - 0.005, h),
                (r - 0.005, 0.008),
                (0.0, 0.008),
            ],
            32,
        ))
        .add(cuboid(
            Vec3::new(r + 0.001, -0.006, 0.065),
            Vec3::new(0.028, 0.012, 0.01),
        ))
        .add(cuboid(
            Vec3::new(r + 0.019, -0.006, 0.025),
            Vec3::new(0.01, 0.012, 0.04),
        ))
        .add(cuboid(
            Vec3::new(r + 0.001, -0.006, 0.015),
            Vec3::new(0.028, 0.012, 0.01),
        ))
}

fn bottle() -> ObjectMesh {
    ObjectMesh::new("bottle", false).add(lathe(
        &[
            (0.0, 0.0),
            (0.032, 0.0),
            (0.034, 0.006),
            (0.034, 0.13),
            (0.028, 0.16),
            (0.014, 0.185),
            (0.013, 0.215),
            (0.0, 0.215),
        ],
        24,
    ))
}

/// A ball with a flat-bottomed cylindrical pocket cut into one side (seed 000's own
/// example of a concavity that cannot rest on a table): 730 vertices. It stands as it
/// rests, on the pocket's rim — the only way a ball with a pocket stays put on a table —
/// so a generated grip "as if picked up from a table" (hand above the base) leaves
/// the pocket free to be set down on again.
fn pocket_sphere() -> ObjectMesh {
    let r = 0.045;
    let rings = 27;
    let profile: Vec<(f64, f64)> = (0..=rings)
        .map(|i| {
            let a = PI * i as f64 / rings as f64;
            let s = if i == 0 || i == rings {
                0.0
            } else {
                r * a.sin()
            };
            (s, r - r * a.cos())
        })
        .collect();
    let (mut v, t) = lathe(&profile, 28);
    // The pocket: radius 2.2 cm around the +x axis, its floor 1.5 cm inside the ball.
    let centre = Vec3::new(0.0, 0.0, r);
    for p in &mut v {
        let q = *p - centre;
        if q.x > 0.0 && (q.y * q.y + q.z * q.z).sqrt() < 0.022 {
            p.x = p.x.min(centre.x + r - 0.015);
        }
    }
    // Turned a quarter about y (+x to −z: a proper rotation, so the faces stay outward)
    // and lowered onto the rim.
    for p in &mut v {
        let q = *p - centre;
        *p = centre + Vec3::new(q.z, q.y, -q.x) - Vec3::new(0.0, 0.0, 0.015);
    }
    ObjectMesh::new("pocket_sphere", false).add((v, t))
}

/// A lever door handle lying as it comes off the door: the rose, the neck, the lever.
fn door_handle() -> ObjectMesh {
    ObjectMesh::new("door_handle", false)
        .add(lathe(
            &[(0.0, 0.0), (0.03, 0.0), (0.03, 0.01), (0.0, 0.01)],
            24,
        ))
        .add(cuboid(
            Vec3::new(-0.01, -0.01, 0.01),
            Vec3::new(0.02, 0.02, 0.05),
        ))
        .add(cuboid(
            Vec3::new(-0.01, -0.01, 0.06),
            Vec3::new(0.12, 0.02, 0.016),
        ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use tabula_geom::mesh::mesh_volume;

    #[test]
    fn every_object_is_closed_with_positive_volume() {
        for o in catalogue() {
            let mut edges = std::collections::HashMap::new();
            for t in &o.triangles {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    *edges.entry((a, b)).or_insert(0) += 1;
                }
            }
            for (&(a, b), &n) in &edges {
                assert_eq!(n, 1, "{}: edge {a}-{b} used {n} times one way", o.name);
                assert_eq!(
                    edges.get(&(b, a)),
                    Some(&1),
                    "{}: edge {a}-{b} open",
                    o.name
                );
            }
            let signed: f64 = o
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| o.vertices[i as usize]);
                    a.dot(b.cross(c)) / 6.0
                })
                .sum();
            assert!(signed > 0.0, "{} faces inward", o.name);
            assert!((signed - mesh_volume(&o.vertices, &o.triangles)).abs() < 1e-12);
        }
        assert_eq!(object("pocket_sphere").unwrap().vertices.len(), 730);
        assert_eq!(object("cylinder").unwrap().vertices.len(), 66);
    }
}
