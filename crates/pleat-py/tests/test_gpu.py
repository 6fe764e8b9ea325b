"""The GPU backend from Python (on Mesa lavapipe where there is no GPU):
the same API, the state read back, live settings, the CPU's figures."""

import numpy as np
import pytest

import pleat


@pytest.fixture
def scenes(small_hanging):
    return pleat.Scene.from_dict(small_hanging)


def test_gpu_steps_and_reads_back(scenes):
    sim = pleat.Simulation(scenes, backend="gpu")
    assert sim.backend == "gpu" and sim.device
    before = sim.positions
    sim.step(5)
    after = sim.positions
    assert after.shape == (256, 3) and after.dtype == np.float32
    # A readback is a new array: the old one keeps the state it was read at.
    assert not np.shares_memory(before, after)
    assert after[:, 1].mean() < before[:, 1].mean()
    report = sim.report()
    assert report["backend"] == "gpu" and report["frames"] == 5 and not report["unstable"]


def test_gpu_follows_the_cpu(scenes):
    cpu, gpu = pleat.Simulation(scenes), pleat.Simulation(scenes, backend="gpu")
    cpu.step(1)
    gpu.step(1)
    np.testing.assert_allclose(gpu.positions, cpu.positions, atol=1e-5)
    cpu.step(30)
    gpu.step(30)
    extent = np.ptp(cpu.positions, axis=0).max()
    assert np.abs(gpu.positions - cpu.positions).max() < 0.01 * extent


def test_gpu_live_settings_and_writes(small_drape):
    # A level cloth falling freely: without gravity and velocity, nothing moves it.
    sim = pleat.Simulation(pleat.Scene.from_dict(small_drape), backend="gpu")
    sim.step(5)
    sim.settings.gravity = (0.0, 0.0, 0.0)
    sim.set_velocities(np.zeros((len(sim), 3)))
    at = sim.positions
    sim.step(5)
    # No gravity, no motion: the settings and the written state reached the device.
    np.testing.assert_allclose(sim.positions, at, atol=1e-5)
    lifted = at + [0.0, 1.0, 0.0]
    sim.set_positions(lifted)
    np.testing.assert_allclose(sim.positions, lifted, atol=1e-6)
