//! The self-contacts' margin, chosen frame by frame. Candidate pairs found
//! within the thickness plus a margin are kept until a particle has moved
//! half the margin (contact_grid.wgsl): that pays where builds are rare,
//! but a wider search costs every build more, and a fine, restless cloth
//! (a 1024 x 1024 sheet swinging) moves that far every substep anyway.
//! So the margin is dropped while the builds read back come at nearly
//! every substep, and tried again a while later: soon at first (a cloth
//! that has fallen comes to rest), then twice as late after each try
//! that is dropped again at once.

use crate::health::ContactCounts;

/// Builds per substep above which the margin is dropped.
const BUSY: f64 = 0.7;
/// Frames without the margin before the first try, and the most.
const FIRST_WAIT: u32 = 15;
const LONGEST_WAIT: u32 = 480;
/// A try dropped again within this many frames has failed.
const FAILED_TRY: u32 = 10;

/// The margin in use and what decides it.
pub(super) struct ContactMargin {
    /// Margin and hash grid cell size with the margin, and without.
    wide: (f32, f32),
    narrow: (f32, f32),
    /// Frames since the margin was dropped, while it is.
    dropped: Option<u32>,
    /// Frames since the margin was last tried again.
    since_try: Option<u32>,
    /// Frames to go without the margin before trying it again.
    wait: u32,
    /// Substeps recorded since the counts last came back.
    substeps: u64,
}

impl ContactMargin {
    pub(super) fn new(wide: (f32, f32), narrow: (f32, f32)) -> Self {
        ContactMargin {
            wide,
            narrow,
            dropped: None,
            since_try: None,
            wait: FIRST_WAIT,
            substeps: 0,
        }
    }

    /// The margin and cell size to use now.
    pub(super) fn current(&self) -> (f32, f32) {
        match self.dropped {
            Some(_) => self.narrow,
            None => self.wide,
        }
    }

    /// Takes a frame of `substeps` substeps and the counts that came back
    /// before it, if any; whether the margin changed (the candidates are
    /// then stale: a list found without the margin does not hold with it).
    pub(super) fn frame(&mut self, substeps: u32, counts: Option<ContactCounts>) -> bool {
        let busy = counts.is_some_and(|c| {
            let busy = c.builds as f64 > BUSY * self.substeps.max(1) as f64;
            self.substeps = 0;
            busy
        });
        self.substeps += u64::from(substeps);
        match &mut self.dropped {
            None if busy => {
                let failed = self.since_try.is_some_and(|f| f < FAILED_TRY);
                self.wait = match failed {
                    true => (2 * self.wait).min(LONGEST_WAIT),
                    false => FIRST_WAIT,
                };
                self.dropped = Some(0);
                true
            }
            None => {
                if let Some(f) = &mut self.since_try {
                    *f += 1;
                }
                false
            }
            Some(frames) => {
                *frames += 1;
                let retry = *frames >= self.wait;
                if retry {
                    self.dropped = None;
                    self.since_try = Some(0);
                }
                retry
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(builds: u64) -> Option<ContactCounts> {
        Some(ContactCounts {
            builds,
            ..ContactCounts::default()
        })
    }

    /// Frames of 10 substeps, each with `builds` come back.
    fn frames(m: &mut ContactMargin, n: u32, builds: u64) -> Vec<bool> {
        (0..n).map(|_| m.frame(10, counts(builds))).collect()
    }

    #[test]
    fn the_margin_is_dropped_while_builds_come_every_substep_and_tried_again() {
        let wide = (0.003, 0.01);
        let mut m = ContactMargin::new(wide, (0.0, 0.007));
        // Rare builds keep it.
        assert!(!m.frame(10, None));
        assert!(frames(&mut m, 5, 2).iter().all(|&c| !c));
        assert_eq!(m.current(), wide);
        // A build at nearly every substep drops it until the first try.
        assert!(m.frame(10, counts(9)));
        assert_eq!(m.current(), (0.0, 0.007));
        let changes = frames(&mut m, FIRST_WAIT, 10);
        assert_eq!(changes.iter().filter(|&&c| c).count(), 1);
        assert!(changes[FIRST_WAIT as usize - 1]);
        assert_eq!(m.current(), wide);
        // A try dropped again at once waits twice as long next time.
        assert!(m.frame(10, counts(10)));
        let changes = frames(&mut m, 2 * FIRST_WAIT, 10);
        assert_eq!(
            changes.iter().position(|&c| c),
            Some(2 * FIRST_WAIT as usize - 1)
        );
        // A try that holds resets the wait.
        assert!(frames(&mut m, FAILED_TRY + 1, 1).iter().all(|&c| !c));
        assert!(m.frame(10, counts(10)));
        let changes = frames(&mut m, FIRST_WAIT, 10);
        assert!(changes[FIRST_WAIT as usize - 1]);
    }
}
