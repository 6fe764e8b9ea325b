//! `pleat.Scene`: a scene read from a file, JSON text or a dict, checked
//! as the command checks it (same validation, same messages).

use crate::errors::scene_error;
use crate::json;
use pleat::scene::Scene;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// A validated scene and where it came from.
#[pyclass(module = "pleat._pleat", name = "Scene", frozen)]
pub struct PyScene {
    /// The scene as the core reads it.
    pub scene: Scene,
    /// Its name in messages: the path of its file, or what the caller chose.
    pub file: String,
    /// The folder the scene's relative paths (meshes, patterns) start from.
    pub base_dir: PathBuf,
}

impl PyScene {
    /// Parses and validates `text`, naming it `file` in errors.
    fn parse(py: Python<'_>, text: &str, file: &str, base_dir: Option<PathBuf>) -> PyResult<Self> {
        let scene = Scene::parse(text, file).map_err(|e| scene_error(py, &e))?;
        Ok(PyScene {
            scene,
            file: file.to_string(),
            base_dir: base_dir.unwrap_or_else(|| PathBuf::from(".")),
        })
    }
}

#[pymethods]
impl PyScene {
    /// Reads and validates a scene file; its relative paths start from its folder.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let (scene, file, base_dir) =
            pleat_cli::run::load(Some(&path)).map_err(|e| scene_error(py, &e))?;
        Ok(PyScene {
            scene,
            file,
            base_dir,
        })
    }

    /// Parses and validates scene JSON; `file` names it in errors.
    #[staticmethod]
    #[pyo3(signature = (text, file = "<string>", base_dir = None))]
    fn from_json(
        py: Python<'_>,
        text: &str,
        file: &str,
        base_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        Self::parse(py, text, file, base_dir)
    }

    /// Validates a scene given as a dict (the JSON of a scene file).
    #[staticmethod]
    #[pyo3(signature = (data, file = "<dict>", base_dir = None))]
    fn from_dict(data: &Bound<'_, PyAny>, file: &str, base_dir: Option<PathBuf>) -> PyResult<Self> {
        Self::parse(data.py(), &json::dumps(data)?, file, base_dir)
    }

    /// The scene `pleat run` runs when given none: a cloth draped over a
    /// sphere onto the ground.
    #[staticmethod]
    fn default(py: Python<'_>) -> PyResult<Self> {
        let (scene, file, base_dir) =
            pleat_cli::run::load(None).map_err(|e| scene_error(py, &e))?;
        Ok(PyScene {
            scene,
            file,
            base_dir,
        })
    }

    /// The cloth `pleat bench` times: `n` x `n` particles, 1 m square,
    /// hanging from its two top corners, with `substeps` substeps and,
    /// with `tethers`, long-range attachments from the pins.
    #[staticmethod]
    #[pyo3(signature = (n, substeps = 10, tethers = false))]
    fn hanging_cloth(n: u32, substeps: u32, tethers: bool) -> PyResult<Self> {
        if !(2..=4096).contains(&n) || !(1..=1000).contains(&substeps) {
            return Err(crate::errors::value_error(format!(
                "n must be 2 to 4096 and substeps 1 to 1000, got {n} and {substeps}"
            )));
        }
        let scene = pleat::scene::presets::hanging_cloth(n, substeps, tethers);
        Ok(PyScene {
            file: scene.name.clone(),
            scene,
            base_dir: PathBuf::from("."),
        })
    }

    /// The scene as a dict, every default written out (what a sweep's
    /// JSON paths point into).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json::to_py(py, &self.scene)
    }

    /// The scene's name (its file's stem when it has none).
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// Frames a run simulates.
    #[getter]
    fn frames(&self) -> u32 {
        self.scene.frames
    }

    /// Seconds per frame.
    #[getter]
    fn frame_dt(&self) -> f32 {
        self.scene.frame_dt()
    }

    /// The scene's name in messages.
    #[getter]
    fn file(&self) -> &str {
        &self.file
    }

    /// The folder the scene's relative paths start from.
    #[getter]
    fn base_dir(&self) -> &Path {
        &self.base_dir
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(name={:?}, file={:?}, frames={})",
            self.scene.name, self.file, self.scene.frames
        )
    }
}
