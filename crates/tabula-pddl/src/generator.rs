//! Seeded table-clearing instances in the style of seed 002 (SPEC §3.3): random
//! rectangles on a table, some touching, some stacked, turned into `on`,
//! `block_grasp`, `block_dirK` and `ik_unfeasible_*` facts by the seed's geometric rules.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// An object's footprint on the table: centre and half sizes (m), axis-aligned.
#[derive(Debug, Clone, Copy)]
struct Rect {
    cx: f64,
    cy: f64,
    hx: f64,
    hy: f64,
}

impl Rect {
    fn overlaps(&self, o: &Rect) -> bool {
        (self.cx - o.cx).abs() < self.hx + o.hx && (self.cy - o.cy).abs() < self.hy + o.hy
    }

    fn grown(&self, gx: f64, gy: f64) -> Rect {
        Rect {
            hx: self.hx + gx,
            hy: self.hy + gy,
            ..*self
        }
    }
}

/// Finger width (m) swept beside the object when grasping (SPEC §6, seed 002).
const FINGER_WIDTH: f64 = 0.03;
/// Gripper clearance behind an object when pushing (SPEC §3.2: 5 cm behind).
const PUSH_STANDOFF: f64 = 0.05;

/// Seed 002's domain (`pddl/tablewclear-domain.pddl`), against which generated tables
/// are checked.
const DOMAIN: &str = include_str!("../../../pddl/tablewclear-domain.pddl");

/// The PDDL problem text of a random `n`-object table for seed 002's domain, solvable:
/// a draw whose IK-infeasible facts and blocks leave some object with no way off the
/// table (a stacked object whose grasp is IK-infeasible, say) is drawn again, so every
/// generated table can be cleared. Solvable draws are the same as they always were.
pub fn table_clearing_problem(n: usize, seed: u64) -> String {
    let domain = crate::parse_domain(DOMAIN).ok();
    let mut text = draw_problem(n, seed, 0);
    for draw in 1..=20u64 {
        let solvable = domain.as_ref().is_none_or(|d| {
            crate::parse_problem(&text, d)
                .ok()
                .and_then(|p| crate::Planner::new(d.clone(), p, Default::default()).ok())
                .is_none_or(|planner| {
                    !matches!(
                        planner.plan(
                            crate::SearchMode::Fast,
                            Some(std::time::Duration::from_secs(2))
                        ),
                        Err(crate::NoPlan::Unsolvable)
                    )
                })
        });
        if solvable {
            break;
        }
        text = draw_problem(n, seed, draw);
    }
    text
}

fn draw_problem(n: usize, seed: u64, draw: u64) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ draw.wrapping_mul(0x2545_F491_4F6C_DD1D));
    let table = draw_table(n, &mut rng);
    let mut facts: Vec<String> = Vec::new();
    for &(top, base) in &table.on {
        facts.push(format!("(on o{} o{})", top + 1, base + 1));
    }
    facts.extend(table.blocking_facts());
    for o in 0..n {
        for k in 1..=4 {
            if rng.random_bool(0.1) {
                facts.push(format!("(ik_unfeasible_dir{k} o{})", o + 1));
            }
        }
        if rng.random_bool(0.1) {
            facts.push(format!("(ik_unfeasible_grasp o{})", o + 1));
        }
    }
    let objects: Vec<String> = (1..=n).map(|i| format!("o{i}")).collect();
    let goal: Vec<String> = objects.iter().map(|o| format!("(removed {o})")).collect();
    format!(
        "(define (problem table-{n}-{seed})\n  (:domain tablewclear)\n  (:objects {} - obj)\n  (:init\n    {})\n  (:goal (and {})))\n",
        objects.join(" "),
        facts.join("\n    "),
        goal.join(" ")
    )
}

/// A drawn table: each object's footprint, which stand on which, which are stacked.
struct DrawnTable {
    rects: Vec<Rect>,
    on: Vec<(usize, usize)>,
    stacked: Vec<bool>,
}

/// `n` objects on a table about √n × 16 cm wide: some touching, a few stacked on an
/// object that is on the table.
fn draw_table(n: usize, rng: &mut ChaCha8Rng) -> DrawnTable {
    let side = (n.max(1) as f64).sqrt() * 0.16;
    let mut t = DrawnTable {
        rects: Vec::with_capacity(n),
        on: Vec::new(),
        stacked: vec![false; n],
    };
    for i in 0..n {
        let hx = rng.random_range(0.015..0.035);
        let hy = rng.random_range(0.015..0.06);
        if i > 0 && rng.random_bool(0.1) {
            let base = rng.random_range(0..i);
            if !t.stacked[base] && !t.on.iter().any(|&(_, b)| b == base) {
                let b = t.rects[base];
                t.rects.push(Rect {
                    cx: b.cx,
                    cy: b.cy,
                    hx,
                    hy,
                });
                t.on.push((i, base));
                t.stacked[i] = true;
                continue;
            }
        }
        let placed = t.place(i, (hx, hy), side, rng);
        t.rects.push(placed.unwrap_or(Rect {
            cx: side + i as f64,
            cy: 0.0,
            hx,
            hy,
        }));
    }
    t
}

impl DrawnTable {
    /// A free spot for object `i` of half sizes `(hx, hy)`: touching a previous object
    /// along x or y now and then, else anywhere on the table; `None` after 200 tries.
    fn place(
        &self,
        i: usize,
        (hx, hy): (f64, f64),
        side: f64,
        rng: &mut ChaCha8Rng,
    ) -> Option<Rect> {
        for attempt in 0..200 {
            let r = if i > 0 && attempt < 100 && rng.random_bool(0.3) {
                let o = self.rects[rng.random_range(0..i)];
                let sx = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                if rng.random_bool(0.5) {
                    Rect {
                        cx: o.cx + sx * (o.hx + hx + 0.001),
                        cy: o.cy,
                        hx,
                        hy,
                    }
                } else {
                    Rect {
                        cx: o.cx,
                        cy: o.cy + sx * (o.hy + hy + 0.001),
                        hx,
                        hy,
                    }
                }
            } else {
                Rect {
                    cx: rng.random_range(-side / 2.0..side / 2.0),
                    cy: rng.random_range(-side / 2.0..side / 2.0),
                    hx,
                    hy,
                }
            };
            if !self
                .rects
                .iter()
                .enumerate()
                .any(|(j, o)| !self.stacked[j] && o.overlaps(&r))
            {
                return Some(r);
            }
        }
        None
    }

    /// Which objects block pushing another along ±x, ±y (dir1..dir4: the object swept
    /// by its own length, and the gripper behind it) and grasping it (fingers close
    /// along x: they sweep a finger width beside both x faces).
    fn blocking_facts(&self) -> Vec<String> {
        let (rects, stacked, n) = (&self.rects, &self.stacked, self.rects.len());
        let dirs = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)];
        let mut facts = Vec::new();
        let blocks =
            |a: usize, b: usize, zone: &Rect| a != b && !stacked[a] && zone.overlaps(&rects[a]);
        for b in (0..n).filter(|&b| !stacked[b]) {
            let rb = rects[b];
            for (k, &(dx, dy)) in dirs.iter().enumerate() {
                let len = if dx != 0.0 { 2.0 * rb.hx } else { 2.0 * rb.hy };
                let swept = Rect {
                    cx: rb.cx + dx * len / 2.0,
                    cy: rb.cy + dy * len / 2.0,
                    hx: rb.hx + dx.abs() * len / 2.0,
                    hy: rb.hy + dy.abs() * len / 2.0,
                };
                let half = PUSH_STANDOFF / 2.0;
                let behind = Rect {
                    cx: rb.cx - dx * (rb.hx + half),
                    cy: rb.cy - dy * (rb.hy + half),
                    hx: if dx != 0.0 { half } else { rb.hx },
                    hy: if dy != 0.0 { half } else { rb.hy },
                };
                for a in (0..n).filter(|&a| blocks(a, b, &swept) || blocks(a, b, &behind)) {
                    facts.push(format!("(block_dir{} o{} o{})", k + 1, a + 1, b + 1));
                }
            }
            let grasp_zone = rb.grown(FINGER_WIDTH, 0.0);
            for a in (0..n).filter(|&a| blocks(a, b, &grasp_zone)) {
                facts.push(format!("(block_grasp o{} o{})", a + 1, b + 1));
            }
        }
        facts
    }
}
