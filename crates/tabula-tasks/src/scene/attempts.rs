//! What was tried where: objects have no identity across frames without a tracker, so
//! failed attempts are counted by place.

use tabula_geom::Vec3;

/// Failed attempts counted per place (objects within `radius` of a place are one).
#[derive(Debug, Clone)]
pub struct Attempts {
    radius: f64,
    places: Vec<(Vec3, usize)>,
}

impl Attempts {
    pub fn new(radius: f64) -> Self {
        Self {
            radius,
            places: Vec::new(),
        }
    }

    /// How often something at `at` failed.
    pub fn at(&self, at: Vec3) -> usize {
        self.places
            .iter()
            .filter(|(q, _)| q.distance(at) < self.radius)
            .map(|(_, n)| *n)
            .sum()
    }

    /// Counts one more failure at `at`.
    pub fn failed(&mut self, at: Vec3) {
        match self
            .places
            .iter_mut()
            .find(|(q, _)| q.distance(at) < self.radius)
        {
            Some(t) => t.1 += 1,
            None => self.places.push((at, 1)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_by_place() {
        let mut a = Attempts::new(0.05);
        a.failed(Vec3::ZERO);
        a.failed(Vec3::new(0.01, 0.0, 0.0));
        a.failed(Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(a.at(Vec3::ZERO), 2);
        assert_eq!(a.at(Vec3::new(1.0, 0.0, 0.0)), 1);
        assert_eq!(a.at(Vec3::new(0.5, 0.0, 0.0)), 0);
    }
}
