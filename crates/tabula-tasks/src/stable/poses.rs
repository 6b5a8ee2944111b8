//! Stable poses of a hull (Algs 3, 5, 7): landing probabilities along the topple graph,
//! patches grown from resting facets, and each patch's contact polygon and margin.

use super::hull::{Hull, basis, polygon_centroid, solid_angle};
use super::{ComMethod, StableParams, StablePose, StablePoses};
use std::collections::VecDeque;
use tabula_geom::polygon::{convex_hull_2d, distance_to_boundary, inside_convex, polygon_area};
use tabula_geom::{Vec2, Vec3};

/// Per-facet quantities the patches are grown from and scored with.
struct Facets {
    normals: Vec<Vec3>,
    areas: Vec<f64>,
    /// The landing probability each resting facet collects.
    sink_prob: Vec<f64>,
    /// The facet each one topples onto (`None`: it rests).
    next: Vec<Option<usize>>,
    adjacent: Vec<Vec<usize>>,
}

/// How a pose is scored against its centre of mass.
struct Against<'a> {
    com: Vec3,
    tolerance: f64,
    params: &'a StableParams,
}

impl Hull {
    /// Quasi-static landing: each triangle's solid angle from the centre of mass,
    /// summed per facet, flows along the topple graph to a resting facet.
    fn facets_about(&self, com: Vec3) -> Facets {
        let nf = self.facets.len();
        let mut prob = vec![0.0; nf];
        for (t, tri) in self.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| self.vertices[i as usize] - com);
            prob[self.facet_of[t]] += solid_angle(a, b, c) / (4.0 * std::f64::consts::PI);
        }
        let next: Vec<Option<usize>> = (0..nf).map(|f| self.topples_to(f, com)).collect();
        let mut sink_prob = vec![0.0; nf];
        for (f, &p) in prob.iter().enumerate() {
            let mut at = f;
            // Toppling lowers the centre of mass, so chains end; the bound guards
            // against numerical ties.
            for _ in 0..nf {
                match next[at] {
                    Some(g) if g != at => at = g,
                    _ => break,
                }
            }
            sink_prob[at] += p;
        }
        let mut adjacent: Vec<Vec<usize>> = vec![Vec::new(); nf];
        for (t, ac) in self.across.iter().enumerate() {
            for &o in ac {
                if o != usize::MAX && self.facet_of[o] != self.facet_of[t] {
                    let (a, b) = (self.facet_of[t], self.facet_of[o]);
                    if !adjacent[a].contains(&b) {
                        adjacent[a].push(b);
                    }
                }
            }
        }
        Facets {
            normals: (0..nf).map(|f| self.facet_normal(f)).collect(),
            areas: (0..nf).map(|f| self.facet_area(f)).collect(),
            sink_prob,
            next,
            adjacent,
        }
    }

    /// The patch grown from resting facet `seed`: adjacent facets that lie as flat
    /// (within the relaxation angle, and no vertex beyond `tolerance` of its plane).
    fn grow_patch(
        &self,
        seed: usize,
        f: &Facets,
        claimed: &mut [bool],
        tolerance: f64,
        cos: f64,
    ) -> Vec<usize> {
        let normal = f.normals[seed];
        let mut patch = vec![seed];
        claimed[seed] = true;
        let mut queue = VecDeque::from([seed]);
        let top = self.support_offset(normal);
        let flat = |g: usize| {
            self.facets[g].iter().all(|&t| {
                self.triangles[t]
                    .iter()
                    .all(|&i| self.vertices[i as usize].dot(normal) >= top - tolerance)
            })
        };
        while let Some(at) = queue.pop_front() {
            for &g in &f.adjacent[at] {
                if !claimed[g] && f.normals[g].dot(normal) >= cos && flat(g) {
                    claimed[g] = true;
                    patch.push(g);
                    queue.push_back(g);
                }
            }
        }
        patch
    }

    pub(super) fn stable_poses(
        &self,
        com: Vec3,
        method: ComMethod,
        tolerance: f64,
        params: &StableParams,
    ) -> StablePoses {
        let nf = self.facets.len();
        let f = self.facets_about(com);
        let against = Against {
            com,
            tolerance,
            params,
        };
        // Alg. 3 with adjacency: patches grown from the largest resting facets (a body
        // rests on a facet exactly when the centre of mass projects into it; patches add
        // the neighbours that lie as flat, so a scanned face's many small facets count
        // as the one face they are).
        let cos = params.relaxation_angle.cos();
        let mut order: Vec<usize> = (0..nf).filter(|&g| f.next[g].is_none()).collect();
        order.sort_by(|&a, &b| f.areas[b].total_cmp(&f.areas[a]).then(a.cmp(&b)));
        let mut claimed = vec![false; nf];
        let mut poses = Vec::new();
        for &seed in &order {
            if claimed[seed] {
                continue;
            }
            let patch = self.grow_patch(seed, &f, &mut claimed, tolerance, cos);
            let pose = self.patch_pose(&patch, &f, &against).or_else(|| {
                // The patch's mean plane may tip the centre of mass out; the resting
                // facet's own plane holds it.
                self.patch_pose(&[seed], &f, &against).map(|mut p| {
                    p.probability = patch.iter().map(|&g| f.sink_prob[g]).sum();
                    p
                })
            });
            poses.extend(pose);
        }
        poses.sort_by(|a: &StablePose, b| {
            b.topple_deg
                .total_cmp(&a.topple_deg)
                .then(b.probability.total_cmp(&a.probability))
        });
        let most_likely = (0..poses.len()).max_by(|&a, &b| {
            poses[a]
                .probability
                .total_cmp(&poses[b].probability)
                .then(b.cmp(&a))
        });
        let hull_volume = self
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize] - self.centre);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        StablePoses {
            poses,
            most_likely,
            center_of_mass: com.to_array(),
            com_method: method,
            hull_vertices: self.vertices.len(),
            hull_facets: nf,
            hull_volume_m3: hull_volume,
        }
    }

    /// Algs 5 and 7 for one patch: the plane (the patch's area-weighted normal, pushed
    /// out to touch the hull), its contact polygon, and the centre of mass against it.
    fn patch_pose(&self, patch: &[usize], f: &Facets, against: &Against<'_>) -> Option<StablePose> {
        let (com, tolerance, params) = (against.com, against.tolerance, against.params);
        let n = patch
            .iter()
            .map(|&g| f.normals[g] * f.areas[g])
            .sum::<Vec3>()
            .try_normalize()?;
        let d = self.support_offset(n);
        let (u, v) = basis(n);
        let contact: Vec<Vec3> = self
            .vertices
            .iter()
            .copied()
            .filter(|p| p.dot(n) >= d - tolerance)
            .collect();
        let flat: Vec<Vec2> = contact
            .iter()
            .map(|p| Vec2::new(p.dot(u), p.dot(v)))
            .collect();
        let ring = convex_hull_2d(&flat);
        if ring.len() < 3 {
            return None;
        }
        let poly: Vec<Vec2> = ring.iter().map(|&i| flat[i]).collect();
        let com2 = Vec2::new(com.dot(u), com.dot(v));
        if !inside_convex(&poly, com2) {
            return None;
        }
        let margin = distance_to_boundary(&poly, com2);
        let height = d - com.dot(n);
        let topple_deg = margin.atan2(height).to_degrees();
        if topple_deg < params.min_topple_deg {
            return None;
        }
        let area = polygon_area(&poly);
        let centroid2 = polygon_centroid(&poly);
        let lift = |q: Vec2| (u * q.x + v * q.y + n * d).to_array();
        Some(StablePose {
            support_normal: n.to_array(),
            probability: patch.iter().map(|&g| f.sink_prob[g]).sum(),
            margin_m: margin,
            topple_deg,
            area_m2: area,
            com_height_m: height,
            contact_centroid: lift(centroid2),
            perimeter: poly.iter().map(|&q| lift(q)).collect(),
        })
    }
}
