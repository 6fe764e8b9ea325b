//! Axis-aligned boxes, shared by every spatial query: the hash grid of the
//! self-collision broad phase, the mesh collider's hierarchy and the
//! self-intersection count.

use glam::Vec3;

/// A closed axis-aligned box; touching boxes overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
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

    /// The box around the segment `a b`.
    pub fn around(a: Vec3, b: Vec3) -> Aabb {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The box around `points` ([`Aabb::EMPTY`] when there are none).
    pub fn of_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        points
            .into_iter()
            .fold(Aabb::EMPTY, |b, p| b.union(Aabb::around(p, p)))
    }

    /// The box grown by `r` on every side.
    pub fn expanded(self, r: f32) -> Aabb {
        Aabb {
            min: self.min - r,
            max: self.max + r,
        }
    }

    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.cmple(o.max).all() && o.min.cmple(self.max).all()
    }

    pub fn contains(&self, p: Vec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

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
