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
        }
    }

    /// The camera of a scene entry, placed in `world`.
    pub fn from_spec(spec: &CameraSpec, world: &SimWorld) -> Result<Self, SimError> {
        let world_from_camera = match (&spec.look_at, &spec.robot, &spec.link) {
            (Some(l), _, _) => {
                optical_frame_look_at(Vec3::from_array(l.eye), Vec3::from_array(l.target))
            }
            (None, Some(robot), Some(link)) => world
                .pose(&format!("{robot}/{link}"))
                .or_else(|_| world.link_pose(robot, link))?,
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
        let (fx, fy, cx, cy) = self.intrinsics();
        Vec3::new((u as f64 + 0.5 - cx) / fx, (v as f64 + 0.5 - cy) / fy, 1.0)
    }
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

struct Target {
    shape: SharedShape,
    world_from_shape: Pose,
    label: u32,
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
            let world_from_shape = match c.parent() {
                Some(b) => {
                    *world.physics.bodies[b].position()
                        * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY)
                }
                None => *c.position(),
            };
            targets.push(Target {
                shape: c.shared_shape().clone(),
                world_from_shape,
                label: c.user_data as u32,
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

    fn cast(&self, u: usize, v: usize, ray: &Ray, max_toi: f64) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for &i in &self.tiles[(v / TILE) * self.tiles_x + u / TILE] {
            let t = &self.targets[i as usize];
            let limit = best.map_or(max_toi, |b| b.0);
            if let Some(hit) =
                t.shape
                    .cast_ray_and_get_normal(&t.world_from_shape, ray, limit, true)
                && best.is_none_or(|b| hit.time_of_impact < b.0)
            {
                best = Some((hit.time_of_impact, hit.normal, t.label));
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
    let rows: Vec<(Vec<f64>, Vec<u32>, Vec<Vec3>)> = (0..h)
        .into_par_iter()
        .map(|v| {
            let mut rng =
                ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ v as u64);
            let mut depth = Vec::with_capacity(w);
            let mut labels = Vec::with_capacity(w);
            let mut points = Vec::with_capacity(w);
            for u in 0..w {
                let dir_c = camera.pixel_ray(u, v);
                let ray = Ray::new(origin, rot * dir_c);
                // z = time of impact, since the camera-frame ray has z = 1.
                let hit = tracer.cast(u, v, &ray, camera.max_range * 1.5);
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
    let light = Vec3::new(0.4, 0.3, 1.0).normalize();
    let pixels: Vec<[u8; 3]> = (0..height)
        .into_par_iter()
        .flat_map_iter(|v| {
            let tracer = &tracer;
            let camera = &camera;
            (0..width).map(move |u| {
                let dir = rot * camera.pixel_ray(u, v);
                let ray = Ray::new(eye, dir);
                match tracer.cast(u, v, &ray, 100.0) {
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
    let mut img = image::RgbImage::new(width as u32, height as u32);
    for (i, p) in pixels.into_iter().enumerate() {
        img.put_pixel((i % width) as u32, (i / width) as u32, image::Rgb(p));
    }
    img
}
