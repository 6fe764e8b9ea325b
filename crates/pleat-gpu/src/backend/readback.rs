//! Readback: the state copied back to the CPU, blocking or asked for and
//! taken when it has arrived.

use super::{GpuBackend, PARTICLE_BYTES};
use crate::context::GpuError;
use crate::readback::Readback;
use glam::Vec3;
use pleat::Particles;

/// Polls a blocking read of the state makes before it reports the state
/// lost ([`GpuBackend::read_state`]), and a frame's finish before it leaves
/// the health on its way: eight were not always enough on
/// lavapipe with the devices of parallel tests busy (a CI check lost the
/// crane's state after 30 frames); a poll of an idle device is cheap.
pub(super) const READBACK_POLLS: u32 = 10_000;

impl GpuBackend {
    /// Reads the state back into `particles`, blocking until it arrives.
    pub(super) fn read_into(&mut self, particles: &mut Particles) {
        let state = self.read_state();
        Self::unpack(state, particles);
    }

    /// Asks for the state, unless a read is already on its way.
    pub(super) fn request_read(&mut self) {
        if self.pending.is_none() {
            self.pending = Some(self.start_readback());
        }
    }

    /// Puts the state asked for into `particles` if it has arrived; whether it had.
    pub(super) fn try_read_into(&mut self, particles: &mut Particles) -> bool {
        let _ = self.context.device.poll(wgpu::PollType::Poll);
        let Some(state) = self.pending.as_ref().and_then(Readback::try_take) else {
            return false;
        };
        self.pending = None;
        Self::unpack(state, particles);
        true
    }

    /// Starts copying the three state buffers back.
    fn start_readback(&self) -> Readback {
        let size = self.counts.particles as u64 * PARTICLE_BYTES;
        Readback::start(
            (&self.context.device, &self.context.queue),
            &self.staging,
            &[&self.pos, &self.prev, &self.vel],
            size,
        )
    }

    /// Copies the three state buffers back, blocking until they arrive;
    /// a read asked for before is waited for and dropped first (it used
    /// the same buffer, and is older).
    fn read_state(&mut self) -> Result<Vec<[f32; 4]>, GpuError> {
        if let Some(older) = self.pending.take() {
            self.wait()?;
            let _ = older.try_take();
        }
        let readback = self.start_readback();
        // The map callback may only run on a later poll than the one that
        // saw the copy finish (seen once, in a CI check on lavapipe, with
        // several devices polled from parallel tests): poll again a few
        // times before giving up.
        for _ in 0..READBACK_POLLS {
            self.wait()?;
            if let Some(state) = readback.try_take() {
                return state;
            }
            std::thread::yield_now();
        }
        Err(GpuError::Readback("the state did not arrive".into()))
    }

    /// Waits until the device has run everything handed to it.
    fn wait(&self) -> Result<(), GpuError> {
        self.context
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }

    /// Puts `state` (positions, previous positions, velocities) into
    /// `particles`; a failed read leaves them NaN, so the run ends flagged,
    /// never silently wrong.
    fn unpack(state: Result<Vec<[f32; 4]>, GpuError>, particles: &mut Particles) {
        let n = particles.len();
        match state {
            Ok(state) => {
                let xyz = |k: usize| Vec3::new(state[k][0], state[k][1], state[k][2]);
                for i in 0..n {
                    particles.x[i] = xyz(i);
                    particles.x_prev[i] = xyz(n + i);
                    particles.v[i] = xyz(2 * n + i);
                }
            }
            Err(e) => {
                eprintln!("error: {e}");
                particles.x.fill(Vec3::NAN);
            }
        }
    }
}
