//! Angle conventions: URDF roll-pitch-yaw and angle wrapping.

use crate::{Mat3, Pose, Quat, Vec3};
use std::f64::consts::PI;

/// Wraps an angle to (-π, π].
pub fn wrap_angle(a: f64) -> f64 {
    if a > -PI && a <= PI {
        return a;
    }
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w <= -PI { w + 2.0 * PI } else { w }
}

/// Rotation from URDF roll-pitch-yaw: `R = Rz(yaw) · Ry(pitch) · Rx(roll)` (fixed axes x, y, z).
pub fn quat_from_rpy(roll: f64, pitch: f64, yaw: f64) -> Quat {
    Quat::from_rotation_z(yaw) * Quat::from_rotation_y(pitch) * Quat::from_rotation_x(roll)
}

/// Matrix form of [`quat_from_rpy`], exact to rounding (no quaternion round trip).
pub fn mat3_from_rpy(roll: f64, pitch: f64, yaw: f64) -> Mat3 {
    Mat3::from_rotation_z(yaw) * Mat3::from_rotation_y(pitch) * Mat3::from_rotation_x(roll)
}

/// URDF roll-pitch-yaw of a rotation matrix, pitch in [-π/2, π/2].
///
/// Near pitch = ±π/2 roll and yaw are coupled; roll is then set to 0.
pub fn rpy_from_mat3(m: &Mat3) -> [f64; 3] {
    // glam matrices are column-major: m.col(j)[i] is row i, column j.
    let r = |i: usize, j: usize| m.col(j)[i];
    let pitch = (-r(2, 0)).atan2(r(0, 0).hypot(r(1, 0)));
    if r(0, 0).hypot(r(1, 0)) < 1e-12 {
        let yaw = (-r(0, 1)).atan2(r(1, 1));
        [0.0, pitch, yaw]
    } else {
        [r(2, 1).atan2(r(2, 2)), pitch, r(1, 0).atan2(r(0, 0))]
    }
}

/// URDF roll-pitch-yaw of a unit quaternion.
pub fn rpy_from_quat(q: Quat) -> [f64; 3] {
    rpy_from_mat3(&Mat3::from_quat(q))
}

/// A pose from a position and URDF roll-pitch-yaw.
pub fn pose_from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Pose {
    Pose::from_parts(Vec3::from_array(xyz), quat_from_rpy(rpy[0], rpy[1], rpy[2]))
}

/// Rotation angle (rad, in [0, π]) between two orientations.
pub fn rotation_angle_between(a: Quat, b: Quat) -> f64 {
    let d = (a.inverse() * b).normalize();
    2.0 * d.xyz().length().atan2(d.w.abs())
}

/// Rotation vector (axis × angle, angle in [0, π]) of a unit quaternion.
pub fn rotation_vector(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    let v = q.xyz();
    let s = v.length();
    if s < 1e-300 {
        return Vec3::ZERO;
    }
    v * (2.0 * s.atan2(q.w) / s)
}

/// True when every component of the pose is finite.
pub fn pose_is_finite(p: &Pose) -> bool {
    p.translation.is_finite() && p.rotation.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_keeps_range() {
        for a in [-10.0, -PI, -1.0, 0.0, 1.0, PI, 3.5, 10.0, 1e6] {
            let w = wrap_angle(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
            assert!(((a - w) / (2.0 * PI)).round() * 2.0 * PI - (a - w) < 1e-6);
        }
    }

    #[test]
    fn rpy_round_trip() {
        for &(r, p, y) in &[(0.1, 0.2, 0.3), (-2.0, 1.2, 3.0), (3.0, -1.5, -2.9)] {
            let m = mat3_from_rpy(r, p, y);
            let [r2, p2, y2] = rpy_from_mat3(&m);
            let m2 = mat3_from_rpy(r2, p2, y2);
            assert!(m.abs_diff_eq(m2, 1e-12));
        }
    }

    #[test]
    fn rotation_vector_matches_angle() {
        let q = Quat::from_axis_angle(Vec3::new(0.0, 0.6, 0.8), 2.5);
        let v = rotation_vector(q);
        assert!((v.length() - 2.5).abs() < 1e-12);
        assert!((rotation_angle_between(Quat::IDENTITY, q) - 2.5).abs() < 1e-12);
    }
}
