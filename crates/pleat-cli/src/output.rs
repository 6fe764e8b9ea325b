//! Writing simulated frames: an OBJ or PLY file per exported frame
//! (`frame_00000.obj`, ...), or one animated binary glTF (`anim.glb`).

use pleat::export::{gltf::GlbAnimation, obj::write_obj, ply::write_ply, vertex_normals};
use pleat::Simulation;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Where a run's frames and report go, and on how many threads it runs
/// (shared by `pleat run` and `pleat fold`).
#[derive(clap::Args, Default)]
pub struct OutputArgs {
    /// Folder for the meshes and report.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Mesh format: an OBJ or PLY file per exported frame, or one animated glb.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
    /// Export every K-th frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub every: u32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Mesh format of `pleat run --format`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    #[default]
    Obj,
    Ply,
    Glb,
}

/// What receives the frames of a run as they are simulated: meshes
/// ([`Output`]) or pictures ([`crate::render::Pictures`]).
pub trait FrameSink {
    /// Writes (or records) frame `index` of `sim`.
    fn frame(&mut self, index: u32, sim: &Simulation) -> Result<(), String>;

    /// Whether [`FrameSink::frame`] reads `sim.particles` (then a GPU
    /// backend's state is read back first); a renderer drawing from the
    /// GPU's own buffers does not.
    fn reads_particles(&self) -> bool {
        true
    }

    /// Whether frame `index` must be handed over even when it is not one
    /// of every `every`-th (the end of a fold's step).
    fn wants(&self, _index: u32) -> bool {
        false
    }
}

impl FrameSink for Output {
    fn frame(&mut self, index: u32, sim: &Simulation) -> Result<(), String> {
        Output::frame(self, index, sim)
    }
}

/// Where exported frames go.
pub struct Output {
    dir: PathBuf,
    format: Format,
    animation: Option<GlbAnimation>,
}

impl Output {
    /// Creates `dir` (and its parents) for a run of `sim`.
    pub fn create(
        dir: &Path,
        format: Format,
        sim: &Simulation,
        frame_dt: f32,
    ) -> Result<Self, String> {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
        let animation = (format == Format::Glb)
            .then(|| GlbAnimation::new(&sim.model.triangles, &sim.particles.x, frame_dt));
        Ok(Output {
            dir: dir.to_path_buf(),
            format,
            animation,
        })
    }

    /// Writes (or records) frame `index` of `sim`.
    pub fn frame(&mut self, index: u32, sim: &Simulation) -> Result<(), String> {
        let (x, triangles) = (&sim.particles.x, &sim.model.triangles);
        if let Some(animation) = &mut self.animation {
            // Frame 0 is the animation's base mesh, given at creation.
            return match index {
                0 => Ok(()),
                _ => animation.push_frame(x).map_err(|e| e.to_string()),
            };
        }
        let ext = if self.format == Format::Ply {
            "ply"
        } else {
            "obj"
        };
        let path = self.dir.join(format!("frame_{index:05}.{ext}"));
        let normals = vertex_normals(x, triangles);
        let file = File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let w = &mut BufWriter::new(file);
        match self.format {
            Format::Ply => write_ply(w, x, triangles, Some(&normals)),
            _ => write_obj(w, x, triangles, Some(&normals), None),
        }
        .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Writes what is written once at the end (the animated glb).
    pub fn finish(self) -> Result<(), String> {
        if let Some(animation) = &self.animation {
            let path = self.dir.join("anim.glb");
            let file = File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            animation
                .write(&mut BufWriter::new(file))
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        Ok(())
    }
}
