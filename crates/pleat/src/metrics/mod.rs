//! Quality figures of a simulated state: stretch, penetrations,
//! self-intersections, facet strain and the layer order of folded paper.

pub mod intersections;
pub mod layer_order;
pub mod strain;

use crate::model::Model;
use crate::particles::Particles;
use crate::world::World;

/// What report.json says about the state at the last frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Largest edge length over its rest length.
    pub max_stretch: f32,
    /// Mean edge length over its rest length.
    pub mean_stretch: f32,
    /// Whether some position, velocity or body state is NaN or infinite.
    pub nan: bool,
    /// NaN/inf or runaway energy now, or (through [`crate::Simulation::metrics`]) at any frame so far.
    pub unstable: bool,
    /// Pairs of triangles sharing no vertex that intersect.
    pub self_intersections: usize,
    /// Particles deeper than their thickness inside a collider.
    pub collider_penetrations: usize,
    /// Kinetic energy of the particles (J).
    pub kinetic_energy: f32,
}

impl Metrics {
    /// The figures of the state `particles` of `model` in `world`.
    pub fn measure(model: &Model, world: &World, particles: &Particles) -> Self {
        let nan = particles.has_non_finite() || !world.bodies_are_finite();
        let (max_stretch, mean_stretch) = stretch(model, particles);
        Metrics {
            max_stretch,
            mean_stretch,
            nan,
            unstable: crate::stability::instability(model, world, particles).is_some(),
            self_intersections: if nan {
                0
            } else {
                intersections::count_self_intersections(&particles.x, &model.triangles)
            },
            collider_penetrations: collider_penetrations(model, world, particles),
            kinetic_energy: particles.kinetic_energy(),
        }
    }
}

/// Largest and mean ratio of edge length to rest length.
pub fn stretch(model: &Model, particles: &Particles) -> (f32, f32) {
    let ratios = model.edges.iter().filter(|e| e.rest_length > 0.0).map(|e| {
        particles.x[e.v[0] as usize].distance(particles.x[e.v[1] as usize]) / e.rest_length
    });
    let (max, sum, count) = ratios.fold((0.0f32, 0.0f64, 0usize), |(m, s, c), r| {
        (m.max(r), s + r as f64, c + 1)
    });
    (
        max,
        if count > 0 {
            (sum / count as f64) as f32
        } else {
            1.0
        },
    )
}

/// Particles deeper than their thickness inside any collider at the world's
/// time (dynamic colliders where their bodies are now).
pub fn collider_penetrations(model: &Model, world: &World, particles: &Particles) -> usize {
    particles
        .x
        .iter()
        .zip(&model.thickness)
        .filter(|(x, &thickness)| {
            world
                .colliders
                .iter()
                .any(|c| c.signed_distance_at(**x, world.time) < -thickness)
        })
        .count()
}
