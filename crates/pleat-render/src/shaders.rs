//! The WGSL shaders (in `shaders/`): each drawing shader is `common.wgsl`
//! (uniforms, shadows, Blinn-Phong) followed by its own file.

/// Per-frame uniforms, shadow map, environment and lighting functions.
pub const COMMON: &str = include_str!("../shaders/common.wgsl");
/// The cloth: storage-buffer positions, displacement, bump, two-sided shading.
pub const CLOTH: &str = include_str!("../shaders/cloth.wgsl");
/// Lines between particles (wireframe and constraint views).
pub const LINES: &str = include_str!("../shaders/lines.wgsl");
/// Colliders, ground and sky.
pub const MESHES: &str = include_str!("../shaders/meshes.wgsl");
/// Compute pass: smooth normals and edge strain per particle.
pub const NORMALS: &str = include_str!("../shaders/normals.wgsl");

/// The full source of a drawing shader: `common.wgsl` then `body`.
pub fn with_common(body: &str) -> String {
    format!("{COMMON}\n{body}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses and validates WGSL with naga, as wgpu does when it creates the module.
    fn validate(name: &str, source: &str) {
        let module = naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    }

    #[test]
    fn cloth_shader_is_valid_wgsl() {
        validate("cloth.wgsl", &with_common(CLOTH));
    }

    #[test]
    fn lines_shader_is_valid_wgsl() {
        validate("lines.wgsl", &with_common(LINES));
    }

    #[test]
    fn meshes_shader_is_valid_wgsl() {
        validate("meshes.wgsl", &with_common(MESHES));
    }

    #[test]
    fn normals_shader_is_valid_wgsl() {
        validate("normals.wgsl", NORMALS);
    }
}
