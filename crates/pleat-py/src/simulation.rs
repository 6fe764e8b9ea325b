//! `pleat.Simulation`: a scene on a backend, stepped from Python with the
//! GIL released, its state as numpy arrays.
//!
//! On the CPU backend the particles live in this process and `positions`
//! and `velocities` are read-only views of them, tied to the simulation
//! (no copy per read; they follow the simulation as it steps). The GPU
//! backend keeps its state on the device: each read is a readback into a
//! new array.

use crate::errors::{check_backend, scene_error, value_error, BackendError};
use crate::export::write_mesh;
use crate::json;
use crate::scene::PyScene;
use crate::settings::PySettings;
use numpy::ndarray::ArrayView2;
use numpy::Element;
use numpy::{AllowTypeChange, PyArray2, PyArrayLike2, PyArrayMethods, PyUntypedArrayMethods};
use pleat::constraint::Grab;
use pleat::glam::Vec3;
use pleat::Simulation;
use pleat_cli::report::Report;
use pyo3::exceptions::{PyIndexError, PyRuntimeError};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// A simulation and what its report needs.
pub struct Session {
    /// The simulation.
    pub sim: Simulation,
    /// The scene's name, for the report.
    name: String,
    /// Seconds per frame.
    frame_dt: f32,
    /// How long each frame stepped so far took.
    frame_times: Vec<Duration>,
    /// The threads the CPU backend works on (all cores unless asked).
    pool: rayon::ThreadPool,
}

impl Session {
    /// Steps one frame on the session's threads, timed as `pleat run`
    /// times it (the step and the wait for the device).
    fn step(&mut self) {
        let Session {
            sim,
            frame_dt,
            frame_times,
            pool,
            ..
        } = self;
        pool.install(|| {
            let start = Instant::now();
            sim.step(*frame_dt);
            sim.finish();
            frame_times.push(start.elapsed());
        });
    }

    /// Whether `positions` and `velocities` can be views of the particles
    /// (the backend steps them in place, in this process).
    fn in_place(&self) -> bool {
        self.sim.backend().steps_in_place()
    }
}

/// A scene simulated on the CPU or the GPU backend.
#[pyclass(module = "pleat._pleat", name = "Simulation", frozen)]
pub struct PySimulation {
    session: Mutex<Session>,
}

impl PySimulation {
    /// The session, locked (only steps hold the lock for long).
    pub fn lock(&self) -> PyResult<MutexGuard<'_, Session>> {
        self.session
            .lock()
            .map_err(|_| PyRuntimeError::new_err("a step of this simulation failed"))
    }

    /// One of the particle arrays (`x` or `v`) as an (n, 3) float32 array:
    /// a read-only view on a backend that steps in place, else a readback.
    fn particle_array<'py>(
        slf: &Bound<'py, Self>,
        field: fn(&pleat::Particles) -> &[Vec3],
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let py = slf.py();
        let mut session = slf.get().lock()?;
        let in_place = session.in_place();
        let values = field(session.sim.sync());
        if !in_place {
            return Ok(PyArray2::from_owned_array(py, rows(values).to_owned()));
        }
        // SAFETY: the particle arrays keep their length (and so their
        // memory) for the simulation's life: nothing in this module
        // resizes them, and the simulation object is the array's base, so
        // it outlives the view.
        let array = unsafe { PyArray2::borrow_from_array(&rows(values), slf.clone().into_any()) };
        array.readwrite().make_nonwriteable();
        Ok(array)
    }

    /// Writes an (n, 3) array into one of the particle arrays and hands
    /// the state to the backend.
    fn write_particles(
        &self,
        values: PyArrayLike2<'_, f32, AllowTypeChange>,
        field: fn(&mut pleat::Particles) -> &mut Vec<Vec3>,
    ) -> PyResult<()> {
        let mut session = self.lock()?;
        let n = session.sim.particles.len();
        if values.shape() != [n, 3] {
            return Err(value_error(format!(
                "expected an array of shape ({n}, 3), got {:?}",
                values.shape()
            )));
        }
        let values = values.as_array();
        session.sim.sync();
        let target = field(&mut session.sim.particles);
        for (p, row) in target.iter_mut().zip(values.rows()) {
            *p = Vec3::new(row[0], row[1], row[2]);
        }
        session.sim.upload();
        Ok(())
    }
}

/// `values` as an (n, 3) array view.
fn rows<T: Element + bytemuck::Pod, V: bytemuck::Pod>(values: &[V]) -> ArrayView2<'_, T> {
    let flat: &[T] = bytemuck::cast_slice(values);
    let columns = std::mem::size_of::<V>() / std::mem::size_of::<T>();
    ArrayView2::from_shape((values.len(), columns), flat).expect("rows of whole elements")
}

/// Issues `message` as a Python `UserWarning` (a crease pattern's importer
/// warning, say), attributed to the caller.
fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let message = std::ffi::CString::new(message.replace('\0', ""))
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    PyErr::warn(py, category.as_any(), &message, 1)
}

#[pymethods]
impl PySimulation {
    /// Builds `scene` on the `backend` ("cpu" or "gpu") with `threads`
    /// worker threads for the CPU backend (all cores when None).
    #[new]
    #[pyo3(signature = (scene, backend = "cpu", threads = None))]
    fn new(
        py: Python<'_>,
        scene: PyRef<'_, PyScene>,
        backend: &str,
        threads: Option<usize>,
    ) -> PyResult<Self> {
        check_backend(backend)?;
        if threads == Some(0) {
            return Err(value_error("threads must be at least 1"));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.unwrap_or(0))
            .build()
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start threads: {e}")))?;
        let spec = &scene.scene;
        let (model, world, warnings) = spec
            .model_and_warnings(&scene.base_dir, &scene.file)
            .map_err(|e| scene_error(py, &e))?;
        for w in warnings {
            warn(py, &w.to_string())?;
        }
        let built = py.detach(|| pleat_cli::backend_for(&model, &world, &spec.solver, backend));
        let backend = built.map_err(BackendError::new_err)?;
        Ok(PySimulation {
            session: Mutex::new(Session {
                sim: spec.simulation(model, world, backend),
                name: spec.name.clone(),
                frame_dt: spec.frame_dt(),
                frame_times: Vec::new(),
                pool,
            }),
        })
    }

    /// Advances `frames` frames of the scene's frame time, the GIL
    /// released; Ctrl-C stops between frames.
    #[pyo3(signature = (frames = 1))]
    fn step(&self, py: Python<'_>, frames: u32) -> PyResult<()> {
        for _ in 0..frames {
            py.detach(|| self.lock().map(|mut s| s.step()))?;
            py.check_signals()?;
        }
        Ok(())
    }

    /// Particle positions (m), an (n, 3) float32 array: on the CPU
    /// backend a read-only view that follows the simulation, on the GPU
    /// a new array read back from the device.
    #[getter]
    fn positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        Self::particle_array(slf, |p| &p.x)
    }

    /// Particle velocities (m/s), as [`positions`](Self::positions).
    #[getter]
    fn velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        Self::particle_array(slf, |p| &p.v)
    }

    /// Moves the particles to `positions`, an (n, 3) array (velocities
    /// are kept).
    fn set_positions(&self, positions: PyArrayLike2<'_, f32, AllowTypeChange>) -> PyResult<()> {
        self.write_particles(positions, |p| &mut p.x)
    }

    /// Sets the particles' velocities, an (n, 3) array.
    fn set_velocities(&self, velocities: PyArrayLike2<'_, f32, AllowTypeChange>) -> PyResult<()> {
        self.write_particles(velocities, |p| &mut p.v)
    }

    /// The triangles, an (m, 3) uint32 array of particle indices
    /// (read-only, a view: they never change).
    #[getter]
    fn triangles<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let session = slf.get().lock()?;
        // SAFETY: the model's triangles are never changed after the build;
        // the simulation object is the array's base, so it outlives the view.
        let array = unsafe {
            PyArray2::borrow_from_array(&rows(&session.sim.model.triangles), slf.clone().into_any())
        };
        array.readwrite().make_nonwriteable();
        Ok(array)
    }

    /// The settings read at every step (substeps, gravity, wind, fold
    /// progress, ...): changing one takes effect at the next step, without
    /// a rebuild.
    #[getter]
    fn settings(slf: Py<Self>) -> PySettings {
        PySettings::of(slf)
    }

    /// Drags `particle` towards `target` (m) from the next step on, until
    /// [`release`](Self::release); `compliance` (m/N) zero puts it there.
    /// The target moves there at a hand's speed (`pleat::GRAB_SPEED`).
    #[pyo3(signature = (particle, target, compliance = 0.0))]
    fn grab(&self, particle: u32, target: [f32; 3], compliance: f32) -> PyResult<()> {
        let mut session = self.lock()?;
        let n = session.sim.particles.len();
        if particle as usize >= n {
            return Err(PyIndexError::new_err(format!(
                "particle {particle} out of range: the simulation has {n} particles"
            )));
        }
        if !(compliance >= 0.0 && compliance.is_finite()) {
            return Err(value_error(format!(
                "compliance must be finite and at least 0, got {compliance}"
            )));
        }
        session.sim.grab(Some(Grab {
            particle,
            target: Vec3::from(target),
            compliance,
        }));
        Ok(())
    }

    /// Lets go of the grabbed particle, if any.
    fn release(&self) -> PyResult<()> {
        self.lock()?.sim.grab(None);
        Ok(())
    }

    /// The run so far as report.json's fields (a dict): what `pleat run
    /// SCENE --frames N --out DIR` writes after the same frames.
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = {
            let mut session = self.lock()?;
            session.sim.sync();
            let threads = session.pool.current_num_threads();
            let s = &*session;
            let report = Report::named(&s.sim, &s.name, s.frame_dt, &s.frame_times, threads);
            serde_json::to_string(&report).map_err(|e| PyRuntimeError::new_err(e.to_string()))?
        };
        json::loads(py, &text)
    }

    /// Writes the current mesh to `path`: OBJ or PLY (with vertex
    /// normals) or binary glTF, by the file's extension.
    fn export(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let mut session = self.lock()?;
        session.sim.sync();
        let (x, triangles) = (
            &session.sim.particles.x[..],
            &session.sim.model.triangles[..],
        );
        let frame_dt = session.frame_dt;
        py.detach(|| write_mesh(&path, x, triangles, frame_dt))
    }

    /// Number of particles.
    #[getter]
    fn particles(&self) -> PyResult<usize> {
        Ok(self.lock()?.sim.particles.len())
    }

    /// Frames stepped so far.
    #[getter]
    fn frames(&self) -> PyResult<usize> {
        Ok(self.lock()?.frame_times.len())
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> PyResult<f32> {
        Ok(self.lock()?.sim.world.time)
    }

    /// `"cpu"` or `"gpu"`.
    #[getter]
    fn backend(&self) -> PyResult<&'static str> {
        Ok(self.lock()?.sim.backend_name())
    }

    /// The device stepping the simulation (a GPU adapter's name).
    #[getter]
    fn device(&self) -> PyResult<String> {
        Ok(self.lock()?.sim.device())
    }

    fn __len__(&self) -> PyResult<usize> {
        self.particles()
    }

    fn __repr__(&self) -> PyResult<String> {
        let s = self.lock()?;
        Ok(format!(
            "Simulation(scene={:?}, backend={:?}, particles={}, frames={})",
            s.name,
            s.sim.backend_name(),
            s.sim.particles.len(),
            s.frame_times.len()
        ))
    }
}
