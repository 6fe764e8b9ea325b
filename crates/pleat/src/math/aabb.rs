//! Axis-aligned boxes, closed (touching boxes overlap), as the broad phases
//! of contacts, colliders and the metrics use them.

use glam::Vec3;

/// A closed axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The lowest corner.
    pub min: Vec3,
    /// The highest corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The box that contains nothing; the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The smallest box around `points` ([`Aabb::EMPTY`] if none).
    pub fn of_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, |b, p| Aabb {
            min: b.min.min(p),
            max: b.max.max(p),
        })
    }

    /// The box around the segment `a b`.
    pub fn around(a: Vec3, b: Vec3) -> Aabb {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The box grown by `r` on every side.
    pub fn expanded(self, r: f32) -> Aabb {
        Aabb {
            min: self.min - r,
            max: self.max + r,
        }
    }

    /// The smallest box containing both.
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Whether the two boxes share a point (closed boxes: touching counts).
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.cmple(o.max).all() && o.min.cmple(self.max).all()
    }

    /// Whether the two boxes, each shrunk by `depth / 2` on every side,
    /// still share a point.
    pub fn overlaps_by(&self, o: &Aabb, depth: f32) -> bool {
        (self.min + depth).cmple(o.max).all() && (o.min + depth).cmple(self.max).all()
    }

    /// Whether `p` lies in the box or on its boundary.
    pub fn contains(&self, p: Vec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// The centre.
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The longest side.
    pub fn extent(&self) -> f32 {
        (self.max - self.min).max_element()
    }

    /// Squared distance from `p` to the box (zero inside).
    pub fn distance_squared(&self, p: Vec3) -> f32 {
        (p - p.clamp(self.min, self.max)).length_squared()
    }

    /// Where the segment `from + t * delta`, `t` in `[0, limit]`, enters the
    /// box (0 if it starts inside), by slabs; `None` if it misses.
    pub fn segment_entry(&self, from: Vec3, delta: Vec3, limit: f32) -> Option<f32> {
        let (mut enter, mut exit) = (0.0f32, limit);
        for axis in 0..3 {
            let (lo, hi, o, d) = (self.min[axis], self.max[axis], from[axis], delta[axis]);
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let (t1, t2) = ((lo - o) / d, (hi - o) / d);
            enter = enter.max(t1.min(t2));
            exit = exit.min(t1.max(t2));
        }
        (enter <= exit).then_some(enter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_boxes_overlap_and_shrunk_ones_part() {
        let a = Aabb::of_points([Vec3::ZERO, Vec3::ONE]);
        let b = Aabb::of_points([Vec3::new(1.0, 0.5, 0.5), Vec3::splat(2.0)]);
        assert!(a.overlaps(&b) && b.overlaps(&a));
        assert!(!a.overlaps_by(&b, 0.1));
        let c = Aabb::of_points([Vec3::new(0.8, 0.0, 0.0), Vec3::splat(2.0)]);
        assert!(a.overlaps_by(&c, 0.1) && !a.overlaps_by(&c, 0.3));
        assert!(!a.overlaps(&Aabb::EMPTY));
        assert_eq!(a.union(Aabb::EMPTY), a);
    }

    #[test]
    fn a_segment_enters_where_it_meets_the_box() {
        let unit = Aabb::of_points([Vec3::ZERO, Vec3::ONE]);
        let from = Vec3::new(-1.0, 0.5, 0.5);
        let entry = unit.segment_entry(from, Vec3::X, 4.0).unwrap();
        assert!((entry - 1.0).abs() < 1e-6);
        assert_eq!(unit.segment_entry(from, Vec3::X, 0.5), None);
        assert_eq!(unit.segment_entry(from, Vec3::Y, 4.0), None);
        assert_eq!(
            unit.segment_entry(Vec3::splat(0.5), Vec3::X, 1.0),
            Some(0.0)
        );
        assert_eq!(unit.distance_squared(Vec3::new(2.0, 0.5, 3.0)), 5.0);
    }
}
