//! Time parameterisation of a path under velocity and acceleration limits.

/// A timed trajectory: samples `(t, q, q̇)`.
#[derive(Debug, Clone)]
pub struct Trajectory {
    pub times: Vec<f64>,
    pub positions: Vec<Vec<f64>>,
    /// Joint velocities at each sample (exact, from the profile).
    pub velocities: Vec<Vec<f64>>,
}

impl Trajectory {
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

/// The most samples a timed trajectory may have: 200,000 (over 2.7 hours at the 0.05 s
/// default, half an hour at 0.01 s). More means a velocity or acceleration limit too
/// small to be meant (a URDF's `velocity="1e-300"`), and a sampler that would fill the
/// memory; such a path is refused with the limit named.
pub const MAX_TRAJECTORY_SAMPLES: usize = 200_000;

/// A path whose timing would exceed [`MAX_TRAJECTORY_SAMPLES`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the trajectory would last {} s ({samples} samples, over the bound of {MAX_TRAJECTORY_SAMPLES}): \
     joint {joint}'s velocity limit {} or the acceleration limit {} is too small",
    tabula_geom::input::shown(*.seconds),
    tabula_geom::input::shown(*.velocity),
    tabula_geom::input::shown(*.acceleration)
)]
pub struct TrajectoryTooLong {
    pub seconds: f64,
    pub samples: f64,
    /// The joint (index in the path) that sets the slowest segment's time.
    pub joint: usize,
    pub velocity: f64,
    pub acceleration: f64,
}

/// Each segment's duration under the limits and the joint that sets it.
fn segment_durations(path: &[Vec<f64>], vmax: &[f64], amax: &[f64]) -> Vec<(f64, usize)> {
    path.windows(2)
        .map(|w| {
            let (a, b) = (&w[0], &w[1]);
            let mut slowest = (0.0f64, 0);
            for k in 0..a.len() {
                let d = (b[k] - a[k]).abs();
                let (v, acc) = (vmax[k].max(1e-9), amax[k].max(1e-9));
                let t = (d / (0.75 * v)).max((d / (0.1875 * acc)).sqrt());
                if t > slowest.0 {
                    slowest = (t, k);
                }
            }
            slowest
        })
        .collect()
}

/// Times a path under per-joint velocity and acceleration limits: each segment follows
/// one fixed rest-to-rest profile in the path parameter (accelerate for a quarter of the
/// segment, cruise, decelerate for a quarter), stretched until every joint's peak
/// velocity `d/(0.75 T)` and acceleration `d/(0.1875 T²)` are within its limits, so all
/// joints stay on the straight segment. Sampled every `dt` seconds, at most
/// [`MAX_TRAJECTORY_SAMPLES`] samples.
pub fn time_parameterize(
    path: &[Vec<f64>],
    vmax: &[f64],
    amax: &[f64],
    dt: f64,
) -> Result<Trajectory, TrajectoryTooLong> {
    let dt = dt.max(1e-6);
    let durations = segment_durations(path, vmax, amax);
    let samples: f64 = durations.iter().map(|(d, _)| (d / dt).ceil()).sum();
    if samples.is_nan() || samples > MAX_TRAJECTORY_SAMPLES as f64 {
        let (_, joint) = durations
            .iter()
            .copied()
            .fold((0.0, 0), |m, x| if x.0 > m.0 { x } else { m });
        return Err(TrajectoryTooLong {
            seconds: durations.iter().map(|(d, _)| d).sum(),
            samples,
            joint,
            velocity: vmax.get(joint).copied().unwrap_or(f64::NAN),
            acceleration: amax.get(joint).copied().unwrap_or(f64::NAN),
        });
    }
    let mut times = vec![0.0];
    let mut positions = vec![path.first().cloned().unwrap_or_default()];
    let mut velocities = vec![vec![0.0; positions[0].len()]];
    let mut t_start = 0.0;
    for (w, &(duration, _)) in path.windows(2).zip(&durations) {
        let (a, b) = (&w[0], &w[1]);
        if duration <= 0.0 {
            continue;
        }
        let ta = duration / 4.0;
        let vs = 1.0 / (duration - ta);
        let s_of = |t: f64| {
            if t < ta {
                0.5 * vs / ta * t * t
            } else if t < duration - ta {
                0.5 * vs * ta + vs * (t - ta)
            } else {
                let r = duration - t;
                1.0 - 0.5 * vs / ta * r * r
            }
        };
        let ds_of = |t: f64| {
            if t < ta {
                vs / ta * t
            } else if t < duration - ta {
                vs
            } else {
                vs / ta * (duration - t).max(0.0)
            }
        };
        let n = (duration / dt).ceil().max(1.0) as usize;
        for i in 1..=n {
            let t = (i as f64 * duration / n as f64).min(duration);
            let s = s_of(t).clamp(0.0, 1.0);
            // Rest at every waypoint: the segment's last sample exactly, not by rounding.
            let ds = if i == n { 0.0 } else { ds_of(t) };
            times.push(t_start + t);
            positions.push(a.iter().zip(b).map(|(x, y)| x + (y - x) * s).collect());
            velocities.push(a.iter().zip(b).map(|(x, y)| (y - x) * ds).collect());
        }
        t_start += duration;
    }
    Ok(Trajectory {
        times,
        positions,
        velocities,
    })
}

/// Times a dense path (a straight line's IK waypoints, 1 cm apart) as one motion rather
/// than resting at every waypoint: one trapezoidal profile in a path parameter `u` that
/// grows along each segment by its slowest joint's time at full speed, so `u̇ ≤ 0.75`
/// keeps every joint under its velocity limit and `ü ≤ 0.75 · min(amax / vmax)` under
/// its acceleration limit along the segments. The turns between segments (a few
/// milliradians on a line) are not limited: on a path with sharp corners use
/// [`time_parameterize`].
pub fn time_parameterize_along(
    path: &[Vec<f64>],
    vmax: &[f64],
    amax: &[f64],
    dt: f64,
) -> Result<Trajectory, TrajectoryTooLong> {
    let dt = dt.max(1e-6);
    if path.len() < 2 {
        let rest = |q: &Vec<f64>| vec![0.0; q.len()];
        return Ok(Trajectory {
            times: path.iter().map(|_| 0.0).collect(),
            positions: path.to_vec(),
            velocities: path.iter().map(rest).collect(),
        });
    }
    let v = |k: usize| vmax.get(k).copied().unwrap_or(1.0).max(1e-9);
    let a = |k: usize| amax.get(k).copied().unwrap_or(1.0).max(1e-9);
    let dims = path.first().map_or(0, Vec::len);
    let mut u = vec![0.0];
    for w in path.windows(2) {
        let du = w[0]
            .iter()
            .zip(&w[1])
            .enumerate()
            .map(|(k, (a, b))| (b - a).abs() / v(k))
            .fold(0.0, f64::max);
        u.push(u.last().copied().unwrap_or(0.0) + du);
    }
    let total = u.last().copied().unwrap_or(0.0);
    let rate: f64 = 0.75;
    let accel = 0.75 * (0..dims).map(|k| a(k) / v(k)).fold(f64::INFINITY, f64::min);
    // Trapezoid, or a triangle on a path too short to reach `rate`.
    let peak = rate.min((total * accel).sqrt());
    let ramp = if accel.is_finite() { peak / accel } else { 0.0 };
    let duration = if peak > 0.0 { total / peak + ramp } else { 0.0 };
    let samples = (duration / dt).ceil();
    if samples.is_nan() || samples > MAX_TRAJECTORY_SAMPLES as f64 {
        let joint = (0..dims)
            .min_by(|&i, &j| (a(i) / v(i)).total_cmp(&(a(j) / v(j))))
            .unwrap_or(0);
        return Err(TrajectoryTooLong {
            seconds: duration,
            samples,
            joint,
            velocity: v(joint),
            acceleration: a(joint),
        });
    }
    let u_of = |t: f64| {
        if t < ramp {
            0.5 * accel * t * t
        } else if t < duration - ramp {
            0.5 * peak * ramp + peak * (t - ramp)
        } else {
            total - 0.5 * accel * (duration - t).powi(2)
        }
    };
    let du_of = |t: f64| peak.min(accel * t).min(accel * (duration - t)).max(0.0);
    let n = samples.max(1.0) as usize;
    let mut out = Trajectory {
        times: Vec::with_capacity(n + 1),
        positions: Vec::with_capacity(n + 1),
        velocities: Vec::with_capacity(n + 1),
    };
    for i in 0..=n {
        let t = (i as f64 * duration / n as f64).min(duration);
        let at = u_of(t).clamp(0.0, total);
        // The segment `at` lies on, and how far along it.
        let seg = u.partition_point(|&x| x <= at).clamp(1, path.len() - 1);
        let (u0, u1) = (u[seg - 1], u[seg]);
        let (q0, q1) = (&path[seg - 1], &path[seg]);
        let s = if u1 > u0 { (at - u0) / (u1 - u0) } else { 1.0 };
        let ds = if u1 > u0 && i < n {
            du_of(t) / (u1 - u0)
        } else {
            0.0
        };
        out.times.push(t);
        out.positions
            .push(q0.iter().zip(q1).map(|(x, y)| x + (y - x) * s).collect());
        out.velocities
            .push(q0.iter().zip(q1).map(|(x, y)| (y - x) * ds).collect());
    }
    Ok(out)
}

#[cfg(test)]
mod along_tests {
    use super::*;

    /// A 1 m line's worth of 1 cm waypoints, one joint moving 0.01 rad per waypoint and a
    /// second bending gently.
    fn dense() -> Vec<Vec<f64>> {
        (0..=100)
            .map(|i| {
                let s = i as f64 / 100.0;
                vec![s, 0.2 * (3.0 * s).sin()]
            })
            .collect()
    }

    #[test]
    fn a_dense_line_is_one_motion_within_the_limits() {
        let (vmax, amax) = ([1.0, 1.0], [2.0, 2.0]);
        let path = dense();
        let along = time_parameterize_along(&path, &vmax, &amax, 0.01).unwrap();
        let resting = time_parameterize(&path, &vmax, &amax, 0.01).unwrap();
        assert!(
            along.duration() < resting.duration() / 4.0,
            "{} s against {} s resting at every waypoint",
            along.duration(),
            resting.duration()
        );
        assert_eq!(along.positions.first(), path.first());
        assert_eq!(along.positions.last(), path.last());
        for (t, q) in along.times.windows(2).zip(along.positions.windows(2)) {
            for k in 0..2 {
                let v = (q[1][k] - q[0][k]).abs() / (t[1] - t[0]);
                assert!(v <= vmax[k] * 1.001, "joint {k} at {v} rad/s");
            }
        }
        assert!(along.velocities.last().unwrap().iter().all(|v| *v == 0.0));
    }

    #[test]
    fn a_path_of_one_point_or_none_takes_no_time() {
        let one =
            time_parameterize_along(&[vec![0.3, 0.1]], &[1.0, 1.0], &[2.0, 2.0], 0.01).unwrap();
        assert_eq!(one.duration(), 0.0);
        assert_eq!(one.positions, vec![vec![0.3, 0.1]]);
        let none = time_parameterize_along(&[], &[1.0], &[1.0], 0.01).unwrap();
        assert_eq!(none.duration(), 0.0);
    }
}
