//! `sim.settings`: the parameters a step reads each time (solver
//! iterations, gravity, wind, fold progress, compliances), changed live
//! without rebuilding or resetting the simulation, on either backend.

use crate::errors::value_error;
use crate::simulation::PySimulation;
use pleat::constraint::ComplianceKind;
use pleat::force::wind::Wind;
use pleat::glam::Vec3;
use pyo3::prelude::*;

/// The live settings of one simulation.
#[pyclass(module = "pleat._pleat", name = "Settings", frozen)]
pub struct PySettings {
    sim: Py<PySimulation>,
}

impl PySettings {
    /// The settings of `sim`.
    pub fn of(sim: Py<PySimulation>) -> Self {
        PySettings { sim }
    }

    /// Runs `f` on the simulation.
    fn with<R>(&self, f: impl FnOnce(&mut pleat::Simulation) -> R) -> PyResult<R> {
        Ok(f(&mut self.sim.get().lock()?.sim))
    }
}

/// Refuses `value` outside `ok`, naming the setting as a scene file's path.
fn check(ok: bool, name: &str, reason: &str, value: impl std::fmt::Display) -> PyResult<()> {
    if ok {
        Ok(())
    } else {
        Err(value_error(format!(
            "settings.{name}: {reason}, got {value}"
        )))
    }
}

/// The compliance kind named `kind`.
fn compliance_kind(kind: &str) -> PyResult<ComplianceKind> {
    Ok(match kind {
        "stretch" => ComplianceKind::Stretch,
        "shear" => ComplianceKind::Shear,
        "bend" => ComplianceKind::Bend,
        "crease" => ComplianceKind::Crease,
        "facet" => ComplianceKind::Facet,
        other => {
            return Err(value_error(format!(
                "unknown compliance '{other}': use stretch, shear, bend, crease or facet"
            )))
        }
    })
}

#[pymethods]
impl PySettings {
    /// Substeps per frame (1 to 1000).
    #[getter]
    fn substeps(&self) -> PyResult<u32> {
        self.with(|s| s.settings.substeps)
    }

    #[setter]
    fn set_substeps(&self, value: u32) -> PyResult<()> {
        check(
            (1..=1000).contains(&value),
            "substeps",
            "must be between 1 and 1000",
            value,
        )?;
        self.with(|s| s.settings.substeps = value)
    }

    /// Constraint iterations per substep (1 to 1000).
    #[getter]
    fn iterations(&self) -> PyResult<u32> {
        self.with(|s| s.settings.iterations)
    }

    #[setter]
    fn set_iterations(&self, value: u32) -> PyResult<()> {
        check(
            (1..=1000).contains(&value),
            "iterations",
            "must be between 1 and 1000",
            value,
        )?;
        self.with(|s| s.settings.iterations = value)
    }

    /// Velocity damping rate (1/s), zero or positive.
    #[getter]
    fn damping(&self) -> PyResult<f32> {
        self.with(|s| s.settings.damping)
    }

    #[setter]
    fn set_damping(&self, value: f32) -> PyResult<()> {
        check(
            value >= 0.0 && value.is_finite(),
            "damping",
            "must be zero or positive",
            value,
        )?;
        self.with(|s| s.settings.damping = value)
    }

    /// Gravitational acceleration (m/s^2), a 3-vector.
    #[getter]
    fn gravity(&self) -> PyResult<[f32; 3]> {
        self.with(|s| s.world.gravity.to_array())
    }

    #[setter]
    fn set_gravity(&self, value: [f32; 3]) -> PyResult<()> {
        let finite = value.iter().all(|v| v.is_finite());
        check(finite, "gravity", "must be finite", format!("{value:?}"))?;
        self.with(|s| s.world.gravity = Vec3::from(value))
    }

    /// Mean wind velocity (m/s), or None for still air. Setting it on a
    /// scene without wind starts a wind with the default drag, lift and no
    /// turbulence.
    #[getter]
    fn wind(&self) -> PyResult<Option<[f32; 3]>> {
        self.with(|s| s.world.wind.as_ref().map(|w| w.velocity.to_array()))
    }

    #[setter]
    fn set_wind(&self, value: Option<[f32; 3]>) -> PyResult<()> {
        if let Some(v) = value {
            let finite = v.iter().all(|c| c.is_finite());
            check(finite, "wind", "must be finite", format!("{v:?}"))?;
        }
        self.with(|s| match value {
            None => s.world.wind = None,
            Some(v) => s.world.wind.get_or_insert_with(Wind::default).velocity = Vec3::from(v),
        })
    }

    /// Fold progress in [0, 1]: every origami hinge is driven to this
    /// fraction of its fold angle. Setting it stops the scene's own fold
    /// ramp, if any, so the value holds.
    #[getter]
    fn fold_progress(&self) -> PyResult<f32> {
        self.with(|s| s.fold_progress())
    }

    #[setter]
    fn set_fold_progress(&self, value: f32) -> PyResult<()> {
        check(
            (0.0..=1.0).contains(&value),
            "fold_progress",
            "must be between 0 and 1",
            value,
        )?;
        self.with(|s| {
            s.fold_ramp = None;
            s.set_fold_progress(value);
        })
    }

    /// Cloth `cloth`'s compliance of `kind` (`stretch`, `shear`, `bend`,
    /// `crease` or `facet`).
    #[pyo3(signature = (kind, cloth = 0))]
    fn compliance(&self, kind: &str, cloth: usize) -> PyResult<f32> {
        let kind = compliance_kind(kind)?;
        self.with(|s| s.compliances.get(cloth, kind))?
            .ok_or_else(|| value_error(format!("no cloth {cloth}")))
    }

    /// Sets cloth `cloth`'s compliance of `kind` from the next step on.
    #[pyo3(signature = (kind, value, cloth = 0))]
    fn set_compliance(&self, kind: &str, value: f32, cloth: usize) -> PyResult<()> {
        let kind = compliance_kind(kind)?;
        check(
            value >= 0.0 && value.is_finite(),
            "compliance",
            "must be zero or positive",
            value,
        )?;
        let slot = self.with(|s| s.compliances.get_mut(cloth, kind).map(|c| *c = value))?;
        slot.ok_or_else(|| value_error(format!("no cloth {cloth}")))
    }

    fn __repr__(&self) -> PyResult<String> {
        self.with(|s| {
            format!(
                "Settings(substeps={}, iterations={}, damping={}, gravity={:?}, wind={:?}, fold_progress={})",
                s.settings.substeps,
                s.settings.iterations,
                s.settings.damping,
                s.world.gravity.to_array(),
                s.world.wind.as_ref().map(|w| w.velocity.to_array()),
                s.fold_progress()
            )
        })
    }
}
