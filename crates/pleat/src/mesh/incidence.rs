//! Particle-to-element incidence in compressed rows: for each particle, the
//! elements (springs, constraints) that touch it and at which end. Solvers
//! compute one result per element in parallel, then gather them per particle
//! in parallel: no two tasks write the same particle, and every sum runs in
//! a fixed order, so results do not depend on the thread count.

/// One element touching a particle: its index and which of its particles it is.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Slot {
    /// The element's index.
    pub element: u32,
    /// Which of the element's particles this one is.
    pub end: u32,
}

/// For each particle, the elements that touch it, in compressed rows.
#[derive(Clone, Debug, Default)]
pub struct Incidence {
    /// Slots of particle `i` are `slots[start[i]..start[i + 1]]`.
    start: Vec<u32>,
    slots: Vec<Slot>,
}

impl Incidence {
    /// The incidence of `elements`, whose particles `particles` lists.
    pub fn new<E>(elements: &[E], particle_count: usize, particles: impl Fn(&E) -> &[u32]) -> Self {
        let mut start = vec![0u32; particle_count + 1];
        for e in elements {
            for &i in particles(e) {
                start[i as usize + 1] += 1;
            }
        }
        for i in 0..particle_count {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut slots = vec![Slot { element: 0, end: 0 }; start[particle_count] as usize];
        for (k, e) in elements.iter().enumerate() {
            for (end, &i) in particles(e).iter().enumerate() {
                slots[fill[i as usize] as usize] = Slot {
                    element: k as u32,
                    end: end as u32,
                };
                fill[i as usize] += 1;
            }
        }
        Incidence { start, slots }
    }

    /// The compressed rows: `(start, slots)`, the slots of particle `i`
    /// being `slots[start[i]..start[i + 1]]`.
    pub fn rows(&self) -> (&[u32], &[Slot]) {
        (&self.start, &self.slots)
    }

    /// The elements touching particle `i`.
    #[inline]
    pub fn of(&self, i: usize) -> &[Slot] {
        &self.slots[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_each_element_at_each_of_its_particles() {
        let elements = [[0u32, 1], [1, 2], [2, 0]];
        let inc = Incidence::new(&elements, 4, |e| e.as_slice());
        assert_eq!(
            inc.of(1),
            &[Slot { element: 0, end: 1 }, Slot { element: 1, end: 0 }]
        );
        assert!(inc.of(3).is_empty());
    }
}
