//! tabula-motion's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod mbm_panda;
mod mesh_geometry;
mod moveit_yaml;
mod planning;

/// The first configuration (and its edge's index) along `path` that touches something on
/// the exact geometry (no padding), sampled every `step` metres of motion.
pub(crate) fn first_touch(
    world: &tabula_motion::CollisionWorld,
    path: &[Vec<f64>],
    step: f64,
) -> Option<(usize, Vec<f64>)> {
    for (e, w) in path.windows(2).enumerate() {
        let n = (world.displacement_bound(&w[0], &w[1]) / step)
            .ceil()
            .max(1.0) as usize;
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let q: Vec<f64> = w[0]
                .iter()
                .zip(&w[1])
                .map(|(a, b)| a + (b - a) * t)
                .collect();
            if !matches!(world.exact_collision(&q), Ok(None)) {
                return Some((e, q));
            }
        }
    }
    None
}
