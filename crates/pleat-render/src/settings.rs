//! What a picture shows and how: size, view, camera, light and the cloth's
//! look, from defaults or a scene file's `render` section.

use crate::camera::{Camera, Light};
use crate::error::RenderError;
use crate::textures::{self, Texture};
use glam::Vec3;
use pleat::scene::RenderSpec;
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// What is drawn on the cloth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum View {
    /// Textured Blinn-Phong with shadows.
    #[default]
    Shaded,
    /// The mesh's edges over a pale surface.
    Wireframe,
    /// The constraints as lines coloured by kind (stretch, shear, bend,
    /// mountain, valley, facet).
    Constraints,
    /// Edge strain `|length / rest length - 1|` as a colour map, with a legend.
    Strain,
}

impl View {
    /// Every view, by name.
    pub const ALL: [(&'static str, View); 4] = [
        ("shaded", View::Shaded),
        ("wireframe", View::Wireframe),
        ("constraints", View::Constraints),
        ("strain", View::Strain),
    ];

    pub(crate) fn index(self) -> u32 {
        match self {
            View::Shaded => 0,
            View::Wireframe => 1,
            View::Constraints => 2,
            View::Strain => 3,
        }
    }
}

impl FromStr for View {
    type Err = RenderError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        View::ALL
            .iter()
            .find(|(name, _)| *name == s)
            .map(|&(_, view)| view)
            .ok_or_else(|| {
                RenderError::Setting(format!(
                    "unknown view '{s}': use shaded, wireframe, constraints or strain"
                ))
            })
    }
}

impl fmt::Display for View {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = View::ALL.iter().find(|(_, v)| v == self).map(|(n, _)| *n);
        f.write_str(name.unwrap_or("shaded"))
    }
}

/// Everything that decides how a frame looks.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Picture width in pixels.
    pub width: u32,
    /// Picture height in pixels.
    pub height: u32,
    /// What is drawn on the cloth.
    pub view: View,
    /// `None` frames the scene.
    pub camera: Option<Camera>,
    /// The sun: a directional light that casts the shadows.
    pub light: Light,
    /// Colour texture of the cloth (sRGB); `None`: fabric for cloth, plain for paper.
    pub texture: Option<Texture>,
    /// Height map of the cloth (its red channel); `None`: the fabric weave's
    /// for cloth, flat for paper.
    pub height_map: Option<Texture>,
    /// Bump mapping: height (m) of the height map's full range; `None`:
    /// 1.5 mm for cloth, 0 for paper.
    pub bump: Option<f32>,
    /// Displacement along the normal by the height map (m, peak to peak).
    pub displacement: f32,
    /// sRGB colour of the cloth's front; `None`: by cloth or paper.
    pub front_color: Option<Vec3>,
    /// sRGB colour of the cloth's back; `None`: by cloth or paper.
    pub back_color: Option<Vec3>,
    /// Colliders drawn as mirrors of the environment.
    pub mirror_colliders: bool,
    /// Samples per pixel (1 or 4).
    pub msaa: u32,
    /// Strain drawn red in the strain view; `None`: 10 % for cloth, 2 % for paper.
    pub strain_range: Option<f32>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            view: View::Shaded,
            camera: None,
            light: Light::default(),
            texture: None,
            height_map: None,
            bump: None,
            displacement: 0.0,
            front_color: None,
            back_color: None,
            mirror_colliders: false,
            msaa: 4,
            strain_range: None,
        }
    }
}

impl RenderSettings {
    /// Defaults overridden by a scene's `render` section; files are read
    /// relative to `base_dir`.
    pub fn from_scene(spec: Option<&RenderSpec>, base_dir: &Path) -> Result<Self, RenderError> {
        let mut settings = RenderSettings::default();
        let Some(spec) = spec else {
            return Ok(settings);
        };
        settings.camera = spec.camera.map(|c| Camera {
            position: c.position,
            target: c.target,
            fov_y_degrees: c.fov_degrees,
        });
        if let Some(light) = spec.light {
            settings.light = Light {
                direction: light.direction.normalize(),
                color: Vec3::from_array(light.color),
            };
        }
        settings.texture = match spec.texture.as_deref() {
            None => None,
            Some("fabric") => Some(textures::fabric().0),
            Some("checker") => Some(textures::checker()),
            Some("plain") => Some(textures::plain(255)),
            Some(file) => Some(Texture::load(&base_dir.join(file))?),
        };
        if let Some(file) = &spec.height_map {
            settings.height_map = Some(Texture::load(&base_dir.join(file))?);
        }
        settings.bump = spec.bump;
        settings.displacement = spec.displacement.unwrap_or(0.0);
        settings.front_color = spec.front_color.map(Vec3::from_array);
        settings.back_color = spec.back_color.map(Vec3::from_array);
        settings.mirror_colliders = spec.mirror_colliders;
        Ok(settings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_parse_and_print_by_name() {
        for (name, view) in View::ALL {
            assert_eq!(name.parse::<View>().unwrap(), view);
            assert_eq!(view.to_string(), name);
        }
        assert!("solid".parse::<View>().is_err());
    }
}
