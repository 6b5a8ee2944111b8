//! The depth camera: one ray per pixel cast against the world's collision shapes.
//!
//! Rays are only tested against shapes whose projected bounding box covers the pixel's
//! 16×16 tile (screen-space culling), so a frame costs about one ray–shape test per
//! visible surface instead of one per shape; rows run in parallel (rayon) with one
//! seeded noise stream per row, so frames are identical whatever the thread count.
//! The same tracer renders shaded PNG snapshots for reports.

use crate::scene::CameraSpec;
use crate::world::{SimError, SimWorld};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rapier3d_f64::parry::query::Ray;
use rapier3d_f64::parry::shape::ShapeType;
use rapier3d_f64::prelude::SharedShape;
use rayon::prelude::*;
use tabula_geom::{Mat3, PointCloud, Pose, Quat, Vec3};

/// A pinhole depth camera; poses are of its optical frame (z forward, x right, y down).
#[derive(Debug, Clone)]
pub struct Camera {
    pub world_from_camera: Pose,
    pub width: usize,
    pub height: usize,
    pub hfov_deg: f64,
    pub vfov_deg: f64,
    pub min_range: f64,
    pub max_range: f64,
    /// σ(z) = noise_coefficient · z² (m); 0.0015 ≈ Kinect (SPEC §5). 0 = noiseless.
    pub noise_coefficient: f64,
    /// Returns where the ray meets the surface more obliquely than this (rad from the
    /// normal) are missing, as on a real structured-light sensor.
    pub max_incidence: f64,
    /// Fraction of returns replaced by spurious ones at a random depth along the ray
    /// (labelled 0), like a real sensor's flying pixels. 0 = none.
    pub outlier_fraction: f64,
}

/// `world_from_camera` (optical frame) looking from `eye` at `target`, world z up.
pub fn optical_frame_look_at(eye: Vec3, target: Vec3) -> Pose {
    let z = (target - eye).normalize_or(Vec3::X);
    let up = if z.cross(Vec3::Z).length() < 1e-6 {
        Vec3::X
    } else {
        Vec3::Z
    };
    let x = z.cross(up).normalize();
    let y = z.cross(x);
    Pose::from_parts(eye, Quat::from_mat3(&Mat3::from_cols(x, y, z)))
}

impl Camera {
    /// A Kinect-like camera (640×480, 57°×43°, 0.5–4 m) at `world_from_camera`.
    pub fn kinect(world_from_camera: Pose) -> Self {
        Self {
            world_from_camera,
            width: 640,
            height: 480,
            hfov_deg: 57.0,
            vfov_deg: 43.0,
            min_range: 0.5,
            max_range: 4.0,
            noise_coefficient: 0.0015,
            max_incidence: 80f64.to_radians(),
            outlier_fraction: 0.0,
        }
    }

    /// The camera of a scene entry, placed in `world`.
    pub fn from_spec(spec: &CameraSpec, world: &SimWorld) -> Result<Self, SimError> {
        let world_from_camera = match (&spec.look_at, &spec.robot, &spec.link) {
            (Some(l), _, _) => {
                optical_frame_look_at(Vec3::from_array(l.eye), Vec3::from_array(l.target))
            }
            (None, Some(robot), Some(link)) => world.link_pose(robot, link)?,
            _ => {
                return Err(SimError::UnknownEntity(format!(
                    "camera `{}` has no pose",
                    spec.name.get_ref()
                )));
            }
        };
        Ok(Self {
            world_from_camera,
            width: spec.width,
            height: spec.height,
            hfov_deg: spec.hfov_deg,
            vfov_deg: spec.vfov_deg,
            min_range: spec.min_range,
            max_range: spec.max_range,
            noise_coefficient: spec.noise_coefficient,
            max_incidence: 80f64.to_radians(),
            outlier_fraction: spec.outlier_fraction,
        })
    }

    /// Focal lengths and principal point (pixels).
    pub fn intrinsics(&self) -> (f64, f64, f64, f64) {
        let fx = self.width as f64 / 2.0 / (self.hfov_deg.to_radians() / 2.0).tan();
        let fy = self.height as f64 / 2.0 / (self.vfov_deg.to_radians() / 2.0).tan();
        (fx, fy, self.width as f64 / 2.0, self.height as f64 / 2.0)
    }

    /// Direction (camera frame, z = 1) of the ray through the centre of pixel (u, v).
    pub fn pixel_ray(&self, u: usize, v: usize) -> Vec3 {
        pixel_ray(self.intrinsics(), u, v)
    }
}

fn pixel_ray((fx, fy, cx, cy): (f64, f64, f64, f64), u: usize, v: usize) -> Vec3 {
    Vec3::new((u as f64 + 0.5 - cx) / fx, (v as f64 + 0.5 - cy) / fy, 1.0)
}

/// One captured frame.
#[derive(Debug, Clone)]
pub struct DepthFrame {
    pub width: usize,
    pub height: usize,
    /// Depth along the optical axis (m), NaN where there is no return.
    pub depth: Vec<f64>,
    /// Ground-truth entity label per pixel (entity index + 1; 0 = nothing), also where
    /// the depth is missing.
    pub labels: Vec<u32>,
    /// Organized cloud in the camera's optical frame.
    pub cloud: PointCloud,
    pub world_from_camera: Pose,
    /// `label_names[l - 1]` is the entity of label `l`.
    pub label_names: Vec<String>,
}

/// Shapes with a closed-form ray intersection, in their own frame (parry's: cylinders
/// along y). Everything else goes through parry's general (GJK) ray cast.
#[derive(Clone, Copy)]
enum Closed {
    Cuboid(Vec3),
    Ball(f64),
    Cylinder { half_height: f64, radius: f64 },
    General,
}

struct Target {
    shape: SharedShape,
    world_from_shape: Pose,
    label: u32,
    closed: Closed,
    /// Rotation world → shape, and the ray origin (the camera centre, the same for
    /// every pixel) in the shape frame.
    shape_from_world: Mat3,
    origin_in_shape: Vec3,
}

impl Target {
    /// First hit of the ray `origin + t·dir` (origin fixed per frame) with this shape:
    /// `t` in units of `dir`, outward unit normal in the world frame.
    fn cast(&self, origin: Vec3, dir: Vec3, max_t: f64) -> Option<(f64, Vec3)> {
        let o = self.origin_in_shape;
        let d = self.shape_from_world * dir;
        let world = |n: Vec3| self.world_from_shape.rotation * n;
        match self.closed {
            Closed::Cuboid(h) => {
                let (mut t0, mut t1, mut axis, mut sign) =
                    (f64::NEG_INFINITY, f64::INFINITY, 0usize, 0.0);
                for k in 0..3 {
                    if d[k].abs() < 1e-300 {
                        if o[k].abs() > h[k] {
                            return None;
                        }
                        continue;
                    }
                    let (a, b) = ((-h[k] - o[k]) / d[k], (h[k] - o[k]) / d[k]);
                    let (near, far) = if a < b { (a, b) } else { (b, a) };
                    if near > t0 {
                        t0 = near;
                        axis = k;
                        sign = -d[k].signum();
                    }
                    t1 = t1.min(far);
                }
                if t0 > t1 || t1 < 0.0 || t0 > max_t {
                    return None;
                }
                if t0 < 0.0 {
                    return Some((0.0, -dir.normalize()));
                }
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                Some((t0, world(n)))
            }
            Closed::Ball(r) => {
                let a = d.dot(d);
                let b = o.dot(d);
                let c = o.dot(o) - r * r;
                let disc = b * b - a * c;
                if disc < 0.0 {
                    return None;
                }
                let t = (-b - disc.sqrt()) / a;
                if t < 0.0 {
                    return (c <= 0.0).then(|| (0.0, -dir.normalize()));
                }
                (t <= max_t).then(|| (t, world((o + d * t) / r)))
            }
            Closed::Cylinder {
                half_height,
                radius,
            } => {
                let mut best: Option<(f64, Vec3)> = None;
                let mut consider = |t: f64, n: Vec3| {
                    if t >= 0.0 && t <= max_t && best.is_none_or(|b| t < b.0) {
                        best = Some((t, n));
                    }
                };
                // Side: (ox + t dx)² + (oz + t dz)² = r², |oy + t dy| ≤ h.
                let a = d.x * d.x + d.z * d.z;
                if a > 1e-300 {
                    let b = o.x * d.x + o.z * d.z;
                    let c = o.x * o.x + o.z * o.z - radius * radius;
                    let disc = b * b - a * c;
                    if disc >= 0.0 {
                        let t = (-b - disc.sqrt()) / a;
                        let p = o + d * t;
                        if p.y.abs() <= half_height {
                            consider(t, Vec3::new(p.x, 0.0, p.z) / radius);
                        }
                    }
                }
                // Caps.
                if d.y.abs() > 1e-300 {
                    for s in [1.0, -1.0] {
                        let t = (s * half_height - o.y) / d.y;
                        let p = o + d * t;
                        if p.x * p.x + p.z * p.z <= radius * radius {
                            consider(t, Vec3::new(0.0, s, 0.0));
                        }
                    }
                }
                if best.is_none()
                    && o.x * o.x + o.z * o.z <= radius * radius
                    && o.y.abs() <= half_height
                {
                    return Some((0.0, -dir.normalize()));
                }
                best.map(|(t, n)| (t, world(n)))
            }
            Closed::General => {
                let ray = Ray::new(origin, dir);
                self.shape
                    .cast_ray_and_get_normal(&self.world_from_shape, &ray, max_t, true)
                    .map(|h| (h.time_of_impact, h.normal))
            }
        }
    }
}

/// A ray hit: distance along the (unnormalised) ray, world normal, label.
type Hit = (f64, Vec3, u32);

struct Tracer {
    targets: Vec<Target>,
    tiles: Vec<Vec<u32>>,
    tiles_x: usize,
}

const TILE: usize = 16;

impl Tracer {
    fn new(
        world: &SimWorld,
        world_from_camera: &Pose,
        width: usize,
        height: usize,
        intr: (f64, f64, f64, f64),
    ) -> Self {
        let (fx, fy, cx, cy) = intr;
        let camera_from_world = world_from_camera.inverse();
        let mut targets = Vec::new();
        for (_, c) in world.physics.colliders.iter() {
            if crate::world::is_support_piece(c.user_data) {
                continue;
            }
            let world_from_shape = match c.parent() {
                Some(b) => {
                    *world.physics.bodies[b].position()
                        * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY)
                }
                None => *c.position(),
            };
            let shape = c.shared_shape().clone();
            // A camera looks out of its own housing: a shape it sits inside (the head
            // link it is mounted on) is not in its view.
            if shape.contains_point(&world_from_shape, world_from_camera.translation) {
                continue;
            }
            let closed = match shape.shape_type() {
                ShapeType::Cuboid => shape
                    .as_cuboid()
                    .map_or(Closed::General, |b| Closed::Cuboid(b.half_extents)),
                ShapeType::Ball => shape
                    .as_ball()
                    .map_or(Closed::General, |b| Closed::Ball(b.radius)),
                ShapeType::Cylinder => {
                    shape
                        .as_cylinder()
                        .map_or(Closed::General, |c| Closed::Cylinder {
                            half_height: c.half_height,
                            radius: c.radius,
                        })
                }
                _ => Closed::General,
            };
            let shape_from_world = Mat3::from_quat(world_from_shape.rotation.inverse());
            let origin_in_shape =
                world_from_shape.inverse_transform_point(world_from_camera.translation);
            targets.push(Target {
                shape,
                world_from_shape,
                label: c.user_data as u32,
                closed,
                shape_from_world,
                origin_in_shape,
            });
        }
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        let mut tiles = vec![Vec::new(); tiles_x * tiles_y];
        for (i, t) in targets.iter().enumerate() {
            let aabb = t.shape.compute_aabb(&t.world_from_shape);
            let (lo, hi) = (aabb.mins, aabb.maxs);
            let mut rect = (
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            );
            let mut behind = false;
            for k in 0..8 {
                let corner = Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                let p = camera_from_world * corner;
                if p.z < 1e-3 {
                    behind = true;
                    continue;
                }
                let (u, v) = (fx * p.x / p.z + cx, fy * p.y / p.z + cy);
                rect = (rect.0.min(u), rect.1.min(v), rect.2.max(u), rect.3.max(v));
            }
            // A box reaching behind the camera may cover any pixel.
            let (u0, v0, u1, v1) = if behind {
                (0, 0, width - 1, height - 1)
            } else {
                if rect.2 < 0.0 || rect.3 < 0.0 || rect.0 > width as f64 || rect.1 > height as f64 {
                    continue;
                }
                let clamp = |x: f64, n: usize| (x.max(0.0) as usize).min(n - 1);
                (
                    clamp(rect.0.floor(), width),
                    clamp(rect.1.floor(), height),
                    clamp(rect.2.ceil(), width),
                    clamp(rect.3.ceil(), height),
                )
            };
            for ty in v0 / TILE..=v1 / TILE {
                for tx in u0 / TILE..=u1 / TILE {
                    tiles[ty * tiles_x + tx].push(i as u32);
                }
            }
        }
        Self {
            targets,
            tiles,
            tiles_x,
        }
    }

    fn cast(&self, u: usize, v: usize, origin: Vec3, dir: Vec3, max_toi: f64) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for &i in &self.tiles[(v / TILE) * self.tiles_x + u / TILE] {
            let t = &self.targets[i as usize];
            let limit = best.map_or(max_toi, |b| b.0);
            if let Some((toi, normal)) = t.cast(origin, dir, limit)
                && best.is_none_or(|b| toi < b.0)
            {
                best = Some((toi, normal, t.label));
            }
        }
        best
    }
}

/// Standard normal sample (Box–Muller), from a seeded stream.
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
    let u2: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Captures a depth frame; `seed` drives the noise (same seed, same frame).
pub fn capture(world: &SimWorld, camera: &Camera, seed: u64) -> DepthFrame {
    let (w, h) = (camera.width, camera.height);
    let tracer = Tracer::new(world, &camera.world_from_camera, w, h, camera.intrinsics());
    let origin = camera.world_from_camera.translation;
    let rot = camera.world_from_camera.rotation;
    let cos_limit = camera.max_incidence.cos();
    let intr = camera.intrinsics();
    let rows: Vec<(Vec<f64>, Vec<u32>, Vec<Vec3>)> = (0..h)
        .into_par_iter()
        .map(|v| {
            let mut rng =
                ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ v as u64);
            let mut depth = Vec::with_capacity(w);
            let mut labels = Vec::with_capacity(w);
            let mut points = Vec::with_capacity(w);
            for u in 0..w {
                let dir_c = pixel_ray(intr, u, v);
                // z = time of impact, since the camera-frame ray has z = 1.
                let hit = tracer.cast(u, v, origin, rot * dir_c, camera.max_range * 1.5);
                let (z, label) = match hit {
                    Some((z, normal, label)) => {
                        let incidence = normal.dot(-(rot * dir_c).normalize());
                        let visible = z >= camera.min_range
                            && z <= camera.max_range
                            && incidence >= cos_limit;
                        (if visible { z } else { f64::NAN }, label)
                    }
                    None => (f64::NAN, 0),
                };
                let z = if z.is_finite() && camera.noise_coefficient > 0.0 {
                    z + camera.noise_coefficient * z * z * gaussian(&mut rng)
                } else {
                    z
                };
                let (z, label) = if camera.outlier_fraction > 0.0
                    && rng.random_range(0.0..1.0) < camera.outlier_fraction
                {
                    let far = if z.is_finite() { z } else { camera.max_range };
                    (
                        rng.random_range(camera.min_range..far.max(camera.min_range + 0.01)),
                        0,
                    )
                } else {
                    (z, label)
                };
                depth.push(z);
                labels.push(label);
                points.push(if z.is_finite() { dir_c * z } else { Vec3::NAN });
            }
            (depth, labels, points)
        })
        .collect();
    let mut depth = Vec::with_capacity(w * h);
    let mut labels = Vec::with_capacity(w * h);
    let mut points = Vec::with_capacity(w * h);
    for (d, l, p) in rows {
        depth.extend(d);
        labels.extend(l);
        points.extend(p);
    }
    DepthFrame {
        width: w,
        height: h,
        depth,
        labels,
        cloud: PointCloud {
            width: w,
            height: h,
            points,
        },
        world_from_camera: camera.world_from_camera,
        label_names: world.entities.iter().map(|e| e.name.clone()).collect(),
    }
}

/// A shaded picture of the world seen from `eye` towards `target` (for reports).
pub fn snapshot(
    world: &SimWorld,
    eye: Vec3,
    target: Vec3,
    width: usize,
    height: usize,
) -> image::RgbImage {
    let camera = Camera {
        width,
        height,
        hfov_deg: 60.0,
        vfov_deg: 2.0
            * ((height as f64 / width as f64) * (30f64.to_radians()).tan())
                .atan()
                .to_degrees(),
        ..Camera::kinect(optical_frame_look_at(eye, target))
    };
    let tracer = Tracer::new(
        world,
        &camera.world_from_camera,
        width,
        height,
        camera.intrinsics(),
    );
    let rot = camera.world_from_camera.rotation;
    let intr = camera.intrinsics();
    let light = Vec3::new(0.4, 0.3, 1.0).normalize();
    let pixels: Vec<[u8; 3]> = (0..height)
        .into_par_iter()
        .flat_map_iter(|v| {
            let tracer = &tracer;
            (0..width).map(move |u| {
                let dir = rot * pixel_ray(intr, u, v);
                match tracer.cast(u, v, eye, dir, 100.0) {
                    Some((_, normal, label)) => {
                        let color = world
                            .entities
                            .get(label as usize - 1)
                            .map_or([0.7; 3], |e| e.color);
                        let shade = 0.3 + 0.7 * normal.dot(light).max(0.0);
                        color.map(|c| (c * shade * 255.0).clamp(0.0, 255.0) as u8)
                    }
                    None => {
                        let sky = 0.75 + 0.2 * (1.0 - v as f64 / height as f64);
                        [
                            (sky * 200.0) as u8,
                            (sky * 220.0) as u8,
                            (sky * 245.0) as u8,
                        ]
                    }
                }
            })
        })
        .collect();
    image::RgbImage::from_raw(width as u32, height as u32, pixels.concat())
        .unwrap_or_else(|| image::RgbImage::new(width as u32, height as u32))
}

impl SimWorld {
    /// The scene camera called `name`, placed where it is now (a camera on a robot link
    /// follows the link).
    pub fn camera(&self, name: &str) -> Result<Camera, SimError> {
        let spec = self
            .cameras
            .iter()
            .find(|c| c.name.get_ref() == name)
            .ok_or_else(|| SimError::UnknownEntity(format!("camera `{name}`")))?;
        Camera::from_spec(spec, self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// The closed-form casts agree with parry's general ones (same hit, same normal).
    #[test]
    fn closed_form_casts_match_parry() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let shapes = [
            (
                SharedShape::cuboid(0.3, 0.2, 0.1),
                Closed::Cuboid(Vec3::new(0.3, 0.2, 0.1)),
            ),
            (SharedShape::ball(0.25), Closed::Ball(0.25)),
            (
                SharedShape::cylinder(0.2, 0.1),
                Closed::Cylinder {
                    half_height: 0.2,
                    radius: 0.1,
                },
            ),
        ];
        let mut hits = 0;
        for _ in 0..3000 {
            let (shape, closed) = shapes[rng.random_range(0..3)].clone();
            let closed_name = match closed {
                Closed::Cuboid(_) => "cuboid",
                Closed::Ball(_) => "ball",
                _ => "cylinder",
            };
            let r = |rng: &mut ChaCha8Rng| rng.random_range(-1.0..1.0);
            let pose = Pose::from_parts(
                Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 0.3,
                Quat::from_scaled_axis(Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 2.0),
            );
            let origin = Vec3::new(r(&mut rng), r(&mut rng), 2.0);
            let aim = pose.translation + Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 0.3;
            let dir = aim - origin;
            let target = Target {
                shape: shape.clone(),
                world_from_shape: pose,
                label: 1,
                closed,
                shape_from_world: Mat3::from_quat(pose.rotation.inverse()),
                origin_in_shape: pose.inverse_transform_point(origin),
            };
            let mine = target.cast(origin, dir, 10.0);
            let theirs = shape.cast_ray_and_get_normal(&pose, &Ray::new(origin, dir), 10.0, true);
            match (mine, theirs) {
                (Some((t, n)), Some(h)) => {
                    assert!(
                        (t - h.time_of_impact).abs() < 1e-7,
                        "{t} vs {}",
                        h.time_of_impact
                    );
                    // parry casts cylinders by GJK, whose normals are good to ~1e-4 rad.
                    let tol = if closed_name == "cylinder" {
                        1e-3
                    } else {
                        1e-6
                    };
                    assert!(
                        n.angle_between(h.normal) < tol,
                        "{closed_name} t {t}: {n:?} vs {:?}",
                        h.normal
                    );
                    hits += 1;
                }
                (None, None) => {}
                other => panic!("disagree: {other:?}"),
            }
        }
        assert!(hits > 300, "{hits}");
    }
}
