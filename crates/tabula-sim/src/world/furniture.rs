//! Furniture's collision parts in its own frame (on the floor, centred), by kind, with
//! the colour each kind has unless the scene gives one.

use super::{SimError, y_to_z};
use crate::scene::{FurnitureKind, FurnitureSpec};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};

type Parts = Vec<(SharedShape, Pose)>;

/// A box of half extents `hx`, `hy`, `hz` centred at `at`.
fn boxed(hx: f64, hy: f64, hz: f64, at: Vec3) -> (SharedShape, Pose) {
    (SharedShape::cuboid(hx, hy, hz), Pose::from_translation(at))
}

/// A box of full size `sx` × `sy` × `h` standing on the floor.
fn standing_box(sx: f64, sy: f64, h: f64) -> (SharedShape, Pose) {
    boxed(sx / 2.0, sy / 2.0, h / 2.0, Vec3::new(0.0, 0.0, h / 2.0))
}

/// A cylinder (or cone) whose axis is z, its centre at height `z`.
fn upright(shape: SharedShape, z: f64) -> (SharedShape, Pose) {
    (
        shape,
        Pose::from_translation(Vec3::new(0.0, 0.0, z)) * y_to_z(),
    )
}

/// The parts and default colour of furniture `f` (called `name` in errors).
pub(super) fn parts(f: &FurnitureSpec, name: &str) -> Result<(Parts, [f64; 3]), SimError> {
    Ok(match f.kind {
        FurnitureKind::Table => (table(f.size.unwrap_or([0.8, 1.2, 0.72])), [0.55, 0.4, 0.25]),
        FurnitureKind::Bookshelf => {
            let shelves = f.shelves.unwrap_or(4).clamp(1, 20);
            let size = f.size.unwrap_or([0.35, 0.9, 1.6]);
            (bookshelf(size, shelves), [0.6, 0.45, 0.3])
        }
        FurnitureKind::Cabinet => {
            let [sx, sy, h] = f.size.unwrap_or([0.5, 0.6, 0.9]);
            (vec![standing_box(sx, sy, h)], [0.7, 0.7, 0.72])
        }
        FurnitureKind::Drum => {
            let [sx, _, h] = f.size.unwrap_or([0.58, 0.58, 0.88]);
            let drum = upright(SharedShape::cylinder(h / 2.0, sx / 2.0), h / 2.0);
            (vec![drum], [0.2, 0.35, 0.7])
        }
        FurnitureKind::SignDrum => (
            sign_drum(f.size.unwrap_or([0.58, 0.58, 1.0])),
            [0.95, 0.5, 0.1],
        ),
        FurnitureKind::TrafficCone => {
            let [sx, _, h] = f.size.unwrap_or([0.36, 0.36, 0.7]);
            let cone = SharedShape::cone(h / 2.0, sx / 2.0 * 0.8);
            let parts = vec![
                boxed(sx / 2.0, sx / 2.0, 0.015, Vec3::new(0.0, 0.0, 0.015)),
                upright(cone, h / 2.0 + 0.03),
            ];
            (parts, [0.95, 0.35, 0.05])
        }
        FurnitureKind::Ramp => (ramp(f, name)?, [0.5, 0.5, 0.55]),
        FurnitureKind::Wall => {
            let [sx, sy, h] = f.size.unwrap_or([0.1, 4.0, 2.5]);
            (vec![standing_box(sx, sy, h)], [0.85, 0.85, 0.8])
        }
        FurnitureKind::Bin => (bin(f.size.unwrap_or([0.4, 0.4, 0.4])), [0.3, 0.3, 0.3]),
    })
}

/// A top 4 cm thick on four legs.
fn table([sx, sy, h]: [f64; 3]) -> Parts {
    let t = 0.04;
    let mut parts = vec![boxed(
        sx / 2.0,
        sy / 2.0,
        t / 2.0,
        Vec3::new(0.0, 0.0, h - t / 2.0),
    )];
    for (x, y) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        let leg = Vec3::new(x * (sx / 2.0 - 0.04), y * (sy / 2.0 - 0.04), (h - t) / 2.0);
        parts.push(boxed(0.025, 0.025, (h - t) / 2.0, leg));
    }
    parts
}

/// Two sides and a back, and `shelves` + 1 boards from the floor to the top.
fn bookshelf([sx, sy, h]: [f64; 3], shelves: u32) -> Parts {
    let t = 0.02;
    let mut parts = vec![
        boxed(
            sx / 2.0,
            t / 2.0,
            h / 2.0,
            Vec3::new(0.0, sy / 2.0 - t / 2.0, h / 2.0),
        ),
        boxed(
            sx / 2.0,
            t / 2.0,
            h / 2.0,
            Vec3::new(0.0, -sy / 2.0 + t / 2.0, h / 2.0),
        ),
        boxed(
            t / 2.0,
            sy / 2.0,
            h / 2.0,
            Vec3::new(-sx / 2.0 + t / 2.0, 0.0, h / 2.0),
        ),
    ];
    for i in 0..=shelves {
        let z = (h - t) * i as f64 / shelves as f64 + t / 2.0;
        parts.push(boxed(
            sx / 2.0,
            sy / 2.0 - t,
            t / 2.0,
            Vec3::new(0.0, 0.0, z),
        ));
    }
    parts
}

/// A traffic channelizer drum: a barrel whose top tapers to a handle and carries a
/// vertical sign — nothing on it is a flat place to put things.
fn sign_drum([sx, _, h]: [f64; 3]) -> Parts {
    let body = 0.8 * h;
    vec![
        upright(SharedShape::cylinder(body / 2.0, sx / 2.0), body / 2.0),
        upright(SharedShape::cone(0.1 * h, sx / 2.0), body + 0.1 * h),
        boxed(
            0.3 * sx,
            0.01,
            0.15,
            Vec3::new(0.0, 0.0, body + 0.12 * h + 0.15),
        ),
    ]
}

/// A wedge rising along +x: its top face is `angle_deg` from the floor measured across
/// the ramp, i.e. 180° − angle from horizontal.
fn ramp(f: &FurnitureSpec, name: &str) -> Result<Parts, SimError> {
    let [sx, sy, _] = f.size.unwrap_or([0.4, 0.6, 0.0]);
    let slope = (180.0 - f.angle_deg.unwrap_or(120.0)).to_radians();
    let h = sx * slope.tan();
    let pts: Vec<Vec3> = [(0.0, 0.0), (sx, 0.0), (sx, h)]
        .iter()
        .flat_map(|&(x, z)| {
            [
                Vec3::new(x - sx / 2.0, -sy / 2.0, z),
                Vec3::new(x - sx / 2.0, sy / 2.0, z),
            ]
        })
        .collect();
    let shape = SharedShape::convex_hull(&pts).ok_or_else(|| SimError::Mesh {
        path: name.to_string(),
        message: "degenerate ramp".into(),
    })?;
    Ok(vec![(shape, Pose::IDENTITY)])
}

/// A floor and four walls 1 cm thick.
fn bin([sx, sy, h]: [f64; 3]) -> Parts {
    let t = 0.01;
    vec![
        boxed(sx / 2.0, sy / 2.0, t / 2.0, Vec3::new(0.0, 0.0, t / 2.0)),
        boxed(
            t / 2.0,
            sy / 2.0,
            h / 2.0,
            Vec3::new(sx / 2.0, 0.0, h / 2.0),
        ),
        boxed(
            t / 2.0,
            sy / 2.0,
            h / 2.0,
            Vec3::new(-sx / 2.0, 0.0, h / 2.0),
        ),
        boxed(
            sx / 2.0,
            t / 2.0,
            h / 2.0,
            Vec3::new(0.0, sy / 2.0, h / 2.0),
        ),
        boxed(
            sx / 2.0,
            t / 2.0,
            h / 2.0,
            Vec3::new(0.0, -sy / 2.0, h / 2.0),
        ),
    ]
}
