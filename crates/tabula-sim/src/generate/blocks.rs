//! Clearing families beyond what the seed's generator makes (issue 32): blocks that are
//! not boxes or cylinders packed against each other or boxed in, grids of every spacing
//! from touching to a finger's width, and objects at the gripper's limits (thin and
//! tall, short and wide). Each object is `(shape TOML, xyz, rpy)` resting on the table.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

/// An object to write: its shape (TOML), position and roll-pitch-yaw.
pub(super) type Written = (String, [f64; 3], [f64; 3]);

/// A block at rest in its own frame: its shape, its footprint's extents along the
/// frame's x and y (centred on the origin), how high its origin sits above the table
/// and the roll that sets it down that way.
struct Block {
    shape: String,
    footprint: [f64; 2],
    origin_z: f64,
    roll: f64,
}

/// Where the objects go: the centre and half-sizes of the region the arm reaches, the
/// table top's height.
#[derive(Clone, Copy)]
pub(super) struct Area {
    pub(super) center: [f64; 2],
    pub(super) half: [f64; 2],
    pub(super) top: f64,
}

fn outline_toml(outline: &[[f64; 2]], length: f64) -> String {
    let points: Vec<String> = outline
        .iter()
        .map(|p| format!("[{:.5}, {:.5}]", p[0], p[1]))
        .collect();
    format!(
        "{{ prism = {{ outline = [{}], length = {length:.4} }} }}",
        points.join(", ")
    )
}

fn box_toml(s: [f64; 3]) -> String {
    format!("{{ box = [{:.4}, {:.4}, {:.4}] }}", s[0], s[1], s[2])
}

/// A profile `w` wide (x, centred) and standing on y = 0, extruded `length` and laid
/// down with the profile upright (its length along the table).
fn lying(outline: Vec<[f64; 2]>, w: f64, length: f64) -> Block {
    Block {
        shape: outline_toml(&outline, length),
        footprint: [w, length],
        origin_z: 0.0,
        roll: FRAC_PI_2,
    }
}

/// An arch `w` wide and `h` high with a half-round notch of radius `r` from below.
fn arch(w: f64, h: f64, r: f64) -> Vec<[f64; 2]> {
    let mut p = vec![[w / 2.0, 0.0], [w / 2.0, h], [-w / 2.0, h], [-w / 2.0, 0.0]];
    for k in 0..=12 {
        let t = PI * (1.0 - k as f64 / 12.0);
        p.push([r * t.cos(), r * t.sin()]);
    }
    p
}

/// One block 4.5–5 cm across in its grip direction: a triangular prism lying or
/// standing, an arch, a half-cylinder, a square tile on edge or a long bar.
fn random_block(rng: &mut ChaCha8Rng) -> Block {
    let w = rng.random_range(0.045..0.05);
    match rng.random_range(0..6) {
        0 => {
            let h = rng.random_range(0.03..0.045);
            let length = rng.random_range(0.05..0.1);
            lying(vec![[-w / 2.0, 0.0], [w / 2.0, 0.0], [0.0, h]], w, length)
        }
        1 => {
            // A triangle face down: its bounding box centred on the origin.
            let h = rng.random_range(0.04..0.05);
            let length = rng.random_range(0.04..0.08);
            let outline = [[-w / 2.0, -h / 2.0], [w / 2.0, -h / 2.0], [0.0, h / 2.0]];
            Block {
                shape: outline_toml(&outline, length),
                footprint: [w, h],
                origin_z: length / 2.0,
                roll: 0.0,
            }
        }
        2 => {
            let h: f64 = rng.random_range(0.03..0.045);
            let r = rng.random_range(0.3..0.38) * w;
            let length = rng.random_range(0.05..0.09);
            lying(arch(w, h.max(r + 0.012), r), w, length)
        }
        3 => {
            let outline: Vec<[f64; 2]> = (0..=16)
                .map(|k| {
                    let t = PI * k as f64 / 16.0;
                    [w / 2.0 * t.cos(), w / 2.0 * t.sin()]
                })
                .collect();
            lying(outline, w, rng.random_range(0.05..0.1))
        }
        4 => {
            let (t, h) = (rng.random_range(0.01..0.016), rng.random_range(0.045..0.05));
            Block {
                shape: box_toml([w, t, h]),
                footprint: [w, t],
                origin_z: h / 2.0,
                roll: 0.0,
            }
        }
        _ => {
            let (length, h) = (rng.random_range(0.1..0.15), rng.random_range(0.02..0.035));
            Block {
                shape: box_toml([w, length, h]),
                footprint: [w, length],
                origin_z: h / 2.0,
                roll: 0.0,
            }
        }
    }
}

/// Cells `rows × cols` of `cell` size, `gap` apart, turned by `yaw` and put at a
/// random place of `area` where they all fit: each cell's centre.
fn grid_centres(
    rng: &mut ChaCha8Rng,
    area: &Area,
    (rows, cols): (usize, usize),
    (cell, gap): ([f64; 2], f64),
    yaw: f64,
) -> Vec<[f64; 2]> {
    let (s, c) = yaw.sin_cos();
    let reach = 0.5 * ((rows as f64) * (cell[0] + gap)).hypot((cols as f64) * (cell[1] + gap));
    let center = [
        area.center[0] + rng.random_range(-1.0..1.0) * (area.half[0] - reach).max(0.0),
        area.center[1] + rng.random_range(-1.0..1.0) * (area.half[1] - reach).max(0.0),
    ];
    let mut out = Vec::with_capacity(rows * cols);
    for r in 0..rows {
        for k in 0..cols {
            let lx = (r as f64 - (rows as f64 - 1.0) / 2.0) * (cell[0] + gap);
            let ly = (k as f64 - (cols as f64 - 1.0) / 2.0) * (cell[1] + gap);
            out.push([center[0] + c * lx - s * ly, center[1] + s * lx + c * ly]);
        }
    }
    out
}

/// Blocks packed 1–4 mm apart: a full grid of 2–3 × 2–3, or a cross of five where the
/// middle one is boxed in on every side. Every block in a scene has the same
/// footprint cell (the largest), so neighbours touch where the blocks are largest.
pub(super) fn blocks(rng: &mut ChaCha8Rng, area: &Area) -> Vec<Written> {
    let cross = rng.random_bool(0.4);
    let (rows, cols) = if cross {
        (3, 3)
    } else {
        (rng.random_range(2..=3usize), rng.random_range(2..=3usize))
    };
    let drawn: Vec<Block> = (0..rows * cols).map(|_| random_block(rng)).collect();
    let cell = drawn.iter().fold([0.0f64; 2], |m, b| {
        [m[0].max(b.footprint[0]), m[1].max(b.footprint[1])]
    });
    let gap = rng.random_range(0.001..0.004);
    let yaw = rng.random_range(-0.8..0.8);
    let centres = grid_centres(rng, area, (rows, cols), (cell, gap), yaw);
    drawn
        .into_iter()
        .zip(centres)
        .enumerate()
        .filter(|(k, _)| !cross || (k / cols == 1 || k % cols == 1))
        .map(|(_, (b, c))| {
            let z = area.top + b.origin_z + 5e-4;
            (b.shape, [c[0], c[1], z], [b.roll, 0.0, yaw])
        })
        .collect()
}

/// Boxes and cylinders 4–6 cm across in a grid 2–3 × 2–4 whose spacing is anything
/// from touching (1 mm) to a finger's width (2.5 cm).
pub(super) fn spaced_grid(rng: &mut ChaCha8Rng, area: &Area) -> Vec<Written> {
    let (rows, cols) = (rng.random_range(2..=3usize), rng.random_range(2..=4usize));
    let cell = [rng.random_range(0.04..0.06), rng.random_range(0.04..0.06)];
    let gap = rng.random_range(0.001..0.025);
    let yaw = rng.random_range(-0.8..0.8);
    let centres = grid_centres(rng, area, (rows, cols), (cell, gap), yaw);
    centres
        .into_iter()
        .map(|c| {
            let h = rng.random_range(0.05..0.11);
            let shape = if rng.random_bool(0.3) {
                let r = cell[0].min(cell[1]) / 2.0 - rng.random_range(0.0..0.004);
                format!("{{ cylinder = {{ radius = {r:.4}, height = {h:.4} }} }}")
            } else {
                box_toml([
                    cell[0] - rng.random_range(0.0..0.004),
                    cell[1] - rng.random_range(0.0..0.004),
                    h,
                ])
            };
            (
                shape,
                [c[0], c[1], area.top + h / 2.0 + 5e-4],
                [0.0, 0.0, yaw],
            )
        })
        .collect()
}

/// 4–8 objects at the grip's limits — thin tall cylinders and boxes (3.2–4.5 cm
/// across, 10–15 cm tall) and short wide ones (6–6.8 cm across, 1.5–3 cm tall) —
/// scattered, a third of them 1–3 mm from a neighbour.
pub(super) fn limits(rng: &mut ChaCha8Rng, area: &Area) -> Vec<Written> {
    let n = rng.random_range(4..=8usize);
    let mut placed: Vec<([f64; 2], f64)> = Vec::new();
    let mut out = Vec::new();
    for _ in 0..n {
        let tall = rng.random_bool(0.6);
        let (across, h): (f64, f64) = if tall {
            (rng.random_range(0.032..0.045), rng.random_range(0.1..0.15))
        } else {
            (rng.random_range(0.06..0.068), rng.random_range(0.015..0.03))
        };
        let round = rng.random_bool(0.5);
        let long = if round {
            across
        } else {
            across + rng.random_range(0.0..0.01)
        };
        let radius = 0.5 * across.hypot(long);
        let yaw = rng.random_range(-PI..PI);
        let beside = rng.random_bool(0.33) && !placed.is_empty();
        let spot = (0..200).find_map(|_| {
            let xy = if beside {
                let (c, r) = placed[rng.random_range(0..placed.len())];
                let t = rng.random_range(-PI..PI);
                let d = r + radius + rng.random_range(0.001..0.003);
                [c[0] + d * t.cos(), c[1] + d * t.sin()]
            } else {
                [
                    area.center[0] + rng.random_range(-area.half[0]..area.half[0]),
                    area.center[1] + rng.random_range(-area.half[1]..area.half[1]),
                ]
            };
            let inside = (xy[0] - area.center[0]).abs() <= area.half[0]
                && (xy[1] - area.center[1]).abs() <= area.half[1];
            let free = placed
                .iter()
                .all(|(c, r)| (c[0] - xy[0]).hypot(c[1] - xy[1]) >= r + radius + 0.001);
            (inside && free).then_some(xy)
        });
        let Some(xy) = spot else { continue };
        placed.push((xy, radius));
        let shape = if round {
            format!(
                "{{ cylinder = {{ radius = {:.4}, height = {h:.4} }} }}",
                across / 2.0
            )
        } else {
            box_toml([across, long, h])
        };
        out.push((
            shape,
            [xy[0], xy[1], area.top + h / 2.0 + 5e-4],
            [0.0, 0.0, yaw],
        ));
    }
    out
}
