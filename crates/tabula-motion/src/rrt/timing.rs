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
