//! What a user of the command can do about a GPU error: the libraries'
//! errors say what happened, and the command, which knows its own options
//! (`--backend cpu`) and where it runs, adds the advice.

use pleat_gpu::GpuError;
use pleat_render::RenderError;

/// How to get an adapter on a machine without a GPU.
const SOFTWARE_DRIVER: &str = "on a machine without a GPU, install a software Vulkan driver \
     such as Mesa lavapipe (Debian/Ubuntu: apt-get install mesa-vulkan-drivers)";

/// The GPU backend's error with what to do about it.
pub fn gpu_error(e: GpuError) -> String {
    match e {
        GpuError::NoAdapter(_) => format!("{e}; {SOFTWARE_DRIVER}, or use --backend cpu"),
        GpuError::Unsupported { .. } => format!("{e}; use --backend cpu"),
        _ => e.to_string(),
    }
}

/// The renderer's error with what to do about it.
pub fn render_error(e: RenderError) -> String {
    match e {
        RenderError::NoAdapter(_) => format!("{e}; {SOFTWARE_DRIVER}"),
        _ => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advice_follows_what_happened() {
        let e = gpu_error(GpuError::Unsupported {
            field: "solver.kind".into(),
            reason: "the vbd solver runs on the CPU backend only".into(),
        });
        assert_eq!(
            e,
            "solver.kind: the vbd solver runs on the CPU backend only; use --backend cpu"
        );
        let e = gpu_error(GpuError::NoAdapter("none".into()));
        assert!(e.starts_with("no GPU adapter found (none); on a machine without a GPU"));
        assert!(e.ends_with("mesa-vulkan-drivers), or use --backend cpu"));
        let e = render_error(RenderError::NoAdapter("none".into()));
        assert!(
            e.starts_with("no usable GPU adapter (none); on a machine"),
            "{e}"
        );
        assert!(e.ends_with("apt-get install mesa-vulkan-drivers)"), "{e}");
    }
}
