//! Gravity from the scene when no world pose says where up is (SPEC §3.1's tabletop
//! pipeline assumes a world frame; real frames from a bag file or PCL's sample data are
//! in the camera's optical frame). As PCL's tabletop tutorials do, the support is a
//! dominant plane with the camera on its open side; an up hint decides between a floor
//! or table and the walls around it: the optical frame's convention (REP-103: y down)
//! when nothing better is known, or a user's `--up`.
//!
//! The result is a *support frame*: z along the support's normal, the support at z = 0,
//! the sensor straight above the origin and looking along +x. The tabletop pipeline then
//! runs in that frame as it does in a robot's world frame.

use crate::plane::{Plane, RansacParams, ransac_round};
use crate::surfaces::{SurfaceParams, grid_sample, split};
use std::f64::consts::PI;
use tabula_geom::{PointCloud, Pose, Quat, Vec3};

/// Parameters of the support search.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SupportParams {
    /// Plane fitting. The threshold is wider than the table search's 1 cm (SPEC §6)
    /// because a floor seen at 3–4 m by a structured-light sensor is quantised in
    /// steps of 2–4 cm; the support is then refitted by least squares.
    pub ransac: RansacParams,
    /// Most planes peeled off the cloud while looking for the support.
    pub max_planes: usize,
    /// Smallest support (m² of connected surface): a floor or a table, not a box's lid.
    pub min_area: f64,
    /// The support's normal must be within this angle (rad) of the up hint: the camera
    /// may be pitched or rolled up to this much. (A wall ahead of a camera pitched down
    /// by θ is 90° + θ from the optical up, a wall to the side 90°.)
    pub max_angle_from_hint: f64,
    /// Organized clouds are searched on every `stride`-th pixel of every `stride`-th row
    /// (unorganized ones on as many of their points).
    pub stride: usize,
    /// Grid cell (m) that decides which inliers are one connected surface.
    pub cell: f64,
    /// Planes within this angle (rad) of the dominant one and at least this share of its
    /// area are levels of the same scene (a table over a floor); the support is the
    /// highest level.
    pub level_angle: f64,
    pub min_level_share: f64,
    /// … and at least this much (m) above it: nearer ones are the same surface fitted
    /// again (a far floor's depth steps).
    pub min_level_rise: f64,
    /// Only points this near the sensor (m) are searched: a structured-light sensor
    /// quantises depth in steps of 3 cm at 3.5 m and 10 cm at 6 m, where a wall falls
    /// apart into slabs that each pass for a plane.
    pub max_range: f64,
}

impl Default for SupportParams {
    fn default() -> Self {
        Self {
            ransac: RansacParams {
                threshold: 0.02,
                ..RansacParams::default()
            },
            max_planes: 16,
            min_area: 0.1,
            max_angle_from_hint: 80f64.to_radians(),
            stride: 4,
            cell: 0.04,
            max_range: 6.0,
            level_angle: 10f64.to_radians(),
            min_level_share: 0.25,
            min_level_rise: 0.15,
        }
    }
}

/// The support found and the frame built on it.
#[derive(Debug, Clone)]
pub struct Support {
    /// The support plane in the cloud's frame, its normal toward the sensor.
    pub plane: Plane,
    /// Connected area of its largest piece (m²).
    pub area: f64,
    /// Angle between its normal and the up hint (rad).
    pub angle_from_hint: f64,
    /// Support frame from the cloud's frame (see the module's doc).
    pub support_from_cloud: Pose,
    /// The planes looked at: normal (cloud frame, toward the sensor), connected area
    /// (m²) and angle from the hint (rad).
    pub planes: Vec<(Plane, f64, f64)>,
    /// Nothing faced the up hint and the support faces its opposite: the cloud is
    /// saved upside down from the optical convention (y up).
    pub hint_flipped: bool,
}

/// Why no support was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SupportError {
    #[error("the cloud has fewer than three finite points")]
    Empty,
    #[error(
        "no plane of {min_area} m² or more within {max_angle_deg:.0}° of the up direction \
         or of its opposite ({planes} planes looked at); give the sensor's pose or `--up`"
    )]
    NoSupport {
        min_area: f64,
        max_angle_deg: f64,
        planes: usize,
    },
}

/// Finds the support of a cloud whose up direction is only roughly known: `viewpoint`
/// is the sensor's pose in the cloud's frame (its position orients normals, its forward
/// axis names the support frame's x), `up_hint` a unit direction in the cloud's frame.
///
/// Planes are peeled off the cloud largest first; among those whose normal (toward the
/// sensor) is within `max_angle_from_hint` of the hint and whose connected piece covers
/// `min_area`, the dominant one has the largest area weighted by cos² of its angle from
/// the hint (a floor or table seen from a camera pitched by θ is θ from the hint, a
/// wall ahead 90° + θ and one to the side 90°). The support is the highest level
/// parallel to it (see `level_angle`).
pub fn find_support(
    cloud: &PointCloud,
    viewpoint: &Pose,
    up_hint: Vec3,
    p: &SupportParams,
) -> Result<Support, SupportError> {
    let all = &cloud.points;
    let stride = p.stride.max(1);
    let eye = viewpoint.translation;
    let usable = |i: usize| all[i].is_finite() && all[i].distance(eye) <= p.max_range;
    // The search runs on a sample (every `stride`-th pixel of every `stride`-th row, or
    // as many of an unorganized cloud's points): planes, their areas and pieces are all
    // measured on it, so each of the planes peeled costs a pass over the sample only.
    let mut picked = grid_sample(cloud, stride, usable);
    if !cloud.is_organized() {
        let step = (picked.len() / (640 * 480 / (stride * stride)).max(1)).max(1);
        picked = picked.into_iter().step_by(step).collect();
    }
    let sample: Vec<Vec3> = picked.iter().map(|&i| all[i]).collect();
    let points = &sample;
    let mut remaining: Vec<usize> = (0..sample.len()).collect();
    if remaining.len() < 3 {
        return Err(SupportError::Empty);
    }
    let up_hint = up_hint.normalize_or(Vec3::Z);
    let split_params = SurfaceParams {
        ransac: p.ransac.clone(),
        min_area: p.min_area,
        min_inscribed_radius: 0.0,
        cell: p.cell,
        ..SurfaceParams::default()
    };
    let mut planes = Vec::new();
    // Where each plane's biggest piece is.
    let mut centres: Vec<Vec3> = Vec::new();
    let mut taken = vec![false; points.len()];
    for round in 0..p.max_planes {
        if remaining.len() < 3 {
            break;
        }
        let Some((plane, inliers)) = ransac_round(points, &remaining, &p.ransac, round) else {
            break;
        };
        if inliers.len() < 3 {
            break;
        }
        let plane = if plane.distance(eye) < 0.0 {
            plane.flipped()
        } else {
            plane
        };
        let pieces = split(points, &plane, &inliers, &split_params);
        let (area, centre) = pieces
            .first()
            .map_or((0.0, Vec3::NAN), |s| (s.area, s.centroid));
        let angle = plane.normal.angle_between(up_hint);
        planes.push((plane, area, angle));
        centres.push(centre);
        for &i in &inliers {
            taken[i] = true;
        }
        remaining.retain(|&i| !taken[i]);
    }
    // Clouds saved y-up (PCL's own tutorial scenes) show nothing near the optical
    // frame's up: the opposite hint is taken then, never in preference.
    let hint_flipped = dominant_plane(&planes, p, false).is_none();
    let Some((dominant, dominant_area, dominant_angle)) = dominant_plane(&planes, p, hint_flipped)
    else {
        return Err(SupportError::NoSupport {
            min_area: p.min_area,
            max_angle_deg: p.max_angle_from_hint.to_degrees(),
            planes: planes.len(),
        });
    };
    // Levels parallel to the dominant plane and a good share of its size: a table over
    // a floor that shows more area. What one manipulates stands on the highest level,
    // the one nearest the sensor along up.
    // Its rise is measured where it is (planes a few degrees apart diverge by
    // centimetres at the sensor: a box's lid 10 cm over a table rose 16 cm there).
    let level = |&(k, (q, area, _)): &(usize, &(Plane, f64, f64))| {
        *area >= p.min_area.max(p.min_level_share * dominant_area)
            && q.normal.angle_between(dominant.normal) <= p.level_angle
            && q.distance(eye) > 0.0
            && dominant.distance(centres[k]) >= p.min_level_rise
    };
    let &(plane, area, angle) = planes
        .iter()
        .enumerate()
        .filter(level)
        .map(|(_, e)| e)
        .min_by(|a, b| a.0.distance(eye).total_cmp(&b.0.distance(eye)))
        .unwrap_or(&(dominant, dominant_area, dominant_angle));
    Ok(Support {
        plane,
        area,
        angle_from_hint: if hint_flipped { PI - angle } else { angle },
        support_from_cloud: support_frame(&plane, viewpoint),
        planes,
        hint_flipped,
    })
}

/// The dominant entry of `planes` (plane, area, angle from the hint): the largest area
/// weighted by cos² of its angle from the hint — or from the opposite hint (`flipped`);
/// the first of equals.
fn dominant_plane(
    planes: &[(Plane, f64, f64)],
    p: &SupportParams,
    flipped: bool,
) -> Option<(Plane, f64, f64)> {
    let from_hint = |angle: f64| if flipped { PI - angle } else { angle };
    let score = |e: &&(Plane, f64, f64)| e.1 * from_hint(e.2).cos().powi(2);
    planes
        .iter()
        .filter(|&&(_, area, angle)| {
            area >= p.min_area && from_hint(angle) <= p.max_angle_from_hint
        })
        .min_by(|a, b| score(b).total_cmp(&score(a)))
        .copied()
}

/// The support frame of a plane (normal toward the sensor) seen from `viewpoint`.
pub fn support_frame(plane: &Plane, viewpoint: &Pose) -> Pose {
    let up = plane.normal;
    let flat = |d: Vec3| (d - up * d.dot(up)).normalize_or_zero();
    // The sensor's forward axis along the plane; straight down, its image "up" (-y).
    let mut x = flat(viewpoint.rotation * Vec3::Z);
    if x.length_squared() < 0.5 {
        x = flat(viewpoint.rotation * Vec3::NEG_Y);
    }
    if x.length_squared() < 0.5 {
        x = up.any_orthonormal_vector();
    }
    let y = up.cross(x);
    let cloud_from_support_rot = Quat::from_mat3(&tabula_geom::Mat3::from_cols(x, y, up));
    let origin = viewpoint.translation - up * plane.distance(viewpoint.translation);
    Pose::from_parts(origin, cloud_from_support_rot).inverse()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A camera 1.2 m above a floor, pitched down by `pitch`, with a wall 3 m ahead:
    /// points in the optical frame (x right, y down, z forward), organized.
    fn room(pitch: f64, floor_extent: f64) -> (PointCloud, Pose) {
        // world: z up, camera at (0, 0, 1.2) looking along +x pitched down.
        let world_from_optical = Pose::from_parts(
            Vec3::new(0.0, 0.0, 1.2),
            Quat::from_rotation_z(0.0)
                * Quat::from_rotation_y(pitch)
                * Quat::from_mat3(&tabula_geom::Mat3::from_cols(
                    Vec3::new(0.0, -1.0, 0.0),
                    Vec3::new(0.0, 0.0, -1.0),
                    Vec3::new(1.0, 0.0, 0.0),
                )),
        );
        let mut pts = Vec::new();
        for i in 0..60 {
            for j in 0..60 {
                let (a, b) = (i as f64 / 59.0, j as f64 / 59.0);
                pts.push(Vec3::new(0.5 + a * floor_extent, -1.0 + 2.0 * b, 0.0));
                pts.push(Vec3::new(3.0, -2.0 + 4.0 * a, 0.05 + 2.5 * b));
            }
        }
        let optical_from_world = world_from_optical.inverse();
        let cloud = PointCloud::unorganized(pts.iter().map(|q| optical_from_world * *q).collect());
        (cloud, world_from_optical)
    }

    /// The support of `cloud` (optical frame) under the optical frame's up, defaults.
    fn support_of(cloud: &PointCloud) -> Support {
        find_support(
            cloud,
            &Pose::IDENTITY,
            Vec3::NEG_Y,
            &SupportParams::default(),
        )
        .unwrap()
    }

    #[test]
    fn the_floor_not_the_bigger_wall_from_the_optical_convention() {
        for pitch in [0.1f64, 0.4, 0.7] {
            // The wall (10 m²) is five times the floor (2 m²).
            let (cloud, world_from_optical) = room(pitch, 1.0);
            let s = support_of(&cloud);
            let up_in_optical = world_from_optical.inverse().rotation * Vec3::Z;
            assert!(
                s.plane.normal.angle_between(up_in_optical) < 0.02,
                "pitch {pitch}: {:?}",
                s.plane
            );
            // The sensor sits 1.2 m above the support frame's origin, looking along +x.
            let eye = s.support_from_cloud * Vec3::ZERO;
            assert!((eye - Vec3::new(0.0, 0.0, 1.2)).length() < 0.02, "{eye}");
            let forward = s.support_from_cloud.rotation * Vec3::Z;
            assert!(forward.x > 0.5 && forward.y.abs() < 1e-9, "{forward}");
        }
    }

    /// A floor saved upside down from the optical convention (turned half a turn about
    /// the view axis: y up): nothing faces the hint, the floor faces its opposite.
    #[test]
    fn a_cloud_saved_y_up_finds_its_floor_under_the_opposite_hint() {
        // The floor alone: a wall seen by the pitched camera is within 80° of either
        // hint, and the flip is for clouds with nothing near the hint.
        let (cloud, world_from_optical) = room(0.4, 1.0);
        let turned = Quat::from_rotation_z(std::f64::consts::PI);
        let floor = cloud
            .points
            .iter()
            .filter(|q| (world_from_optical * **q).z < 0.01)
            .map(|q| turned * *q);
        let cloud = PointCloud::unorganized(floor.collect());
        let s = support_of(&cloud);
        assert!(s.hint_flipped);
        let up = turned * (world_from_optical.inverse().rotation * Vec3::Z);
        assert!(s.plane.normal.angle_between(up) < 0.02, "{:?}", s.plane);
        assert!(
            (s.angle_from_hint - 0.4).abs() < 0.02,
            "{}",
            s.angle_from_hint
        );
        // The optical convention keeps its answer unflipped.
        let (cloud, _) = room(0.4, 1.0);
        let s = support_of(&cloud);
        assert!(!s.hint_flipped);
    }

    #[test]
    fn no_support_is_a_typed_error() {
        let empty = PointCloud::unorganized(vec![Vec3::NAN; 10]);
        let p = SupportParams::default();
        assert_eq!(
            find_support(&empty, &Pose::IDENTITY, Vec3::NEG_Y, &p).unwrap_err(),
            SupportError::Empty
        );
        // Only the wall ahead: 90° from the hint.
        let (cloud, world_from_optical) = room(0.0, 1.0);
        let cloud = PointCloud::unorganized(
            cloud
                .points
                .iter()
                .copied()
                .filter(|q| (world_from_optical * *q).x > 2.9)
                .collect(),
        );
        assert!(matches!(
            find_support(&cloud, &Pose::IDENTITY, Vec3::NEG_Y, &p),
            Err(SupportError::NoSupport { .. })
        ));
    }
}

/// Where a cloud's world frame came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameSource {
    /// The caller gave the sensor's world pose (`--world-from-camera`).
    GivenPose,
    /// The file's `VIEWPOINT` placed the sensor in the cloud's own frame, z up.
    Viewpoint,
    /// The support found under the up hint (the optical frame's −y, or `--up`).
    Support,
}

/// A cloud's world frame: z up, and where the sensor is in it.
#[derive(Debug, Clone)]
pub struct Framing {
    pub world_from_cloud: Pose,
    /// The sensor's position in the world frame.
    pub eye: Vec3,
    pub source: FrameSource,
    /// The support, when the frame was built on it (the support is then at z = 0).
    pub support: Option<Support>,
}

/// Whether a `VIEWPOINT` says "the points are in the sensor's own frame": the sensor
/// at the origin, unrotated or turned 180° about x (PCL's grabbers write
/// `0 0 0 0 1 0 0` over optical-frame points).
pub fn is_sensor_frame(viewpoint: &Pose) -> bool {
    let q = viewpoint.rotation;
    let flipped_x = Quat::from_xyzw(1.0, 0.0, 0.0, 0.0);
    viewpoint.translation.length() < 1e-6
        && (q.dot(Quat::IDENTITY).abs() > 1.0 - 1e-6 || q.dot(flipped_x).abs() > 1.0 - 1e-6)
}

/// Decides a cloud's world frame: the caller's sensor pose if given; else with an up
/// direction given (cloud frame), the support under it; else a `VIEWPOINT` that places
/// the sensor away from the origin means the points are already in a z-up world;
/// else the points are in the sensor's optical frame (REP-103: y down) and the
/// support is found under the optical up.
pub fn frame_cloud(
    cloud: &PointCloud,
    viewpoint: &Pose,
    world_from_sensor: Option<Pose>,
    up: Option<Vec3>,
    p: &SupportParams,
) -> Result<Framing, SupportError> {
    if let Some(world_from_sensor) = world_from_sensor {
        return Ok(Framing {
            world_from_cloud: world_from_sensor,
            eye: world_from_sensor.translation,
            source: FrameSource::GivenPose,
            support: None,
        });
    }
    let sensor_frame = is_sensor_frame(viewpoint);
    if up.is_none() && !sensor_frame {
        return Ok(Framing {
            world_from_cloud: Pose::IDENTITY,
            eye: viewpoint.translation,
            source: FrameSource::Viewpoint,
            support: None,
        });
    }
    let cloud_from_sensor = if sensor_frame {
        Pose::IDENTITY
    } else {
        *viewpoint
    };
    let hint = up.unwrap_or(cloud_from_sensor.rotation * Vec3::NEG_Y);
    let support = find_support(cloud, &cloud_from_sensor, hint, p)?;
    let world_from_cloud = support.support_from_cloud;
    Ok(Framing {
        world_from_cloud,
        eye: world_from_cloud * cloud_from_sensor.translation,
        source: FrameSource::Support,
        support: Some(support),
    })
}
