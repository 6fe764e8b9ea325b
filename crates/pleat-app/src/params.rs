//! Every physics parameter the panels show, in one table: its name (for
//! the page's test hook and the command line), label, range and how a
//! change applies: live (read at the next step, state untouched) or by a
//! rebuild that keeps the state (values baked into constraints).

use crate::session::{Pending, Session};
use pleat::constraint::ComplianceKind;
use pleat::force::Wind;
use pleat::scene::MeshSpec;
use pleat::solver::SolverKind;

/// The panel section a parameter sits in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    Solver,
    Material,
    Paper,
    Contact,
    Forces,
    Fold,
}

/// How a change takes effect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Effect {
    /// At the next step.
    Live,
    /// Through a rebuild from the edited scene that keeps the state.
    Rebuild,
}

/// One parameter.
pub struct Param {
    pub name: &'static str,
    pub label: &'static str,
    pub section: Section,
    pub min: f64,
    pub max: f64,
    /// Values span decades: the slider is logarithmic.
    pub logarithmic: bool,
    pub integer: bool,
    /// The current value; `None` where the scene has no such thing.
    pub get: fn(&Session) -> Option<f64>,
    set: fn(&mut Session, f64) -> Effect,
}

impl Param {
    /// Sets the parameter to `value` (clamped to its range). A value baked
    /// into constraints goes into the scene at once and into the simulation
    /// (by a rebuild) once `settled`: not at every step of a slider's drag.
    pub fn apply(&self, session: &mut Session, value: f64, settled: bool) {
        let mut value = value.clamp(self.min, self.max);
        if self.integer {
            value = value.round();
        }
        if (self.set)(session, value) == Effect::Rebuild && settled {
            session.request(Pending::Rebuild);
        }
    }
}

/// Sets the parameter `name`, or says there is none of that name.
pub fn set(session: &mut Session, name: &str, value: f64) -> Result<(), String> {
    if !value.is_finite() {
        return Err(format!("{name}: {value} is not a number"));
    }
    let param = PARAMS
        .iter()
        .find(|p| p.name == name)
        .ok_or_else(|| format!("no parameter named '{name}'"))?;
    if (param.get)(session).is_none() {
        return Err(format!("{name}: this scene has none"));
    }
    param.apply(session, value, true);
    Ok(())
}

fn first_cloth(s: &Session) -> Option<&pleat::scene::ClothSpec> {
    s.scene.cloths.first()
}

fn cloth_unless_paper(s: &Session) -> Option<&pleat::scene::ClothSpec> {
    first_cloth(s).filter(|_| !s.is_paper())
}

/// The first collider's friction, which the friction sliders show.
fn first_friction(s: &Session) -> Option<&pleat::collide::Friction> {
    s.scene.colliders.first().map(|c| &c.friction)
}

fn each_material(s: &mut Session, f: impl Fn(&mut pleat::Material)) {
    for cloth in &mut s.scene.cloths {
        f(&mut cloth.material);
    }
}

/// Sets the compliance `kind` of every cloth, live (the simulation's
/// table, read at each step) and in the scene (for a reset).
fn live_compliance(s: &mut Session, kind: ComplianceKind, value: f64) -> Effect {
    for cloth in 0..s.sim.model.cloths.len() {
        if let Some(c) = s.sim.compliances.get_mut(cloth, kind) {
            *c = value as f32;
        }
    }
    for cloth in &mut s.scene.cloths {
        match (kind, &mut cloth.mesh) {
            (ComplianceKind::Crease, MeshSpec::Pattern(p)) => {
                p.stiffness.crease_compliance = value as f32
            }
            (ComplianceKind::Facet, MeshSpec::Pattern(p)) => {
                p.stiffness.facet_compliance = value as f32
            }
            (ComplianceKind::Stretch, _) => cloth.material.stretch_compliance = value as f32,
            (ComplianceKind::Shear, _) => cloth.material.shear_compliance = value as f32,
            (ComplianceKind::Bend, _) => cloth.material.bend_compliance = value as f32,
            _ => {}
        }
    }
    Effect::Live
}

fn paper_stiffness(s: &Session) -> Option<pleat::folding::PaperStiffness> {
    s.scene.cloths.iter().find_map(|c| match &c.mesh {
        MeshSpec::Pattern(p) => Some(p.stiffness),
        _ => None,
    })
}

fn wind(s: &mut Session) -> &mut Wind {
    s.sim.world.wind.get_or_insert_with(Wind::default)
}

fn sync_wind(s: &mut Session) -> Effect {
    s.scene.wind = s.sim.world.wind;
    Effect::Live
}

fn each_friction(s: &mut Session, f: impl Fn(&mut pleat::collide::Friction)) -> Effect {
    for c in &mut s.scene.colliders {
        f(&mut c.friction);
    }
    for c in &mut s.sim.world.colliders {
        f(&mut c.friction);
    }
    Effect::Live
}

/// Every parameter, in panel order.
pub const PARAMS: &[Param] = &[
    Param {
        name: "substeps",
        label: "substeps",
        section: Section::Solver,
        min: 1.0,
        max: 200.0,
        logarithmic: true,
        integer: true,
        get: |s| Some(s.sim.settings.substeps as f64),
        set: |s, v| {
            s.sim.settings.substeps = v as u32;
            s.scene.solver.substeps = v as u32;
            Effect::Live
        },
    },
    Param {
        name: "iterations",
        label: "iterations",
        section: Section::Solver,
        min: 1.0,
        max: 50.0,
        logarithmic: true,
        integer: true,
        get: |s| Some(s.sim.settings.iterations as f64),
        set: |s, v| {
            s.sim.settings.iterations = v as u32;
            s.scene.solver.iterations = v as u32;
            Effect::Live
        },
    },
    Param {
        name: "damping",
        label: "damping (1/s)",
        section: Section::Solver,
        min: 0.0,
        max: 100.0,
        logarithmic: true,
        integer: false,
        get: |s| Some(s.sim.settings.damping as f64),
        set: |s, v| {
            s.sim.settings.damping = v as f32;
            s.scene.solver.damping = v as f32;
            Effect::Live
        },
    },
    Param {
        name: "relaxation",
        label: "Jacobi relaxation",
        section: Section::Solver,
        min: 0.05,
        max: 2.0,
        logarithmic: false,
        integer: false,
        get: |s| {
            (s.sim.settings.kind == SolverKind::JacobiPbd)
                .then_some(s.sim.settings.relaxation as f64)
        },
        set: |s, v| {
            s.sim.settings.relaxation = v as f32;
            s.scene.solver.relaxation = v as f32;
            Effect::Live
        },
    },
    Param {
        name: "stretch_compliance",
        label: "stretch compliance (m/N; per metre on paper)",
        section: Section::Material,
        min: 0.0,
        max: 1e-1,
        logarithmic: true,
        integer: false,
        get: |s| first_cloth(s).map(|c| c.material.stretch_compliance as f64),
        set: |s, v| live_compliance(s, ComplianceKind::Stretch, v),
    },
    Param {
        name: "max_strain",
        label: "strain limit (0: none)",
        section: Section::Material,
        min: 0.0,
        max: 0.2,
        logarithmic: false,
        integer: false,
        get: |s| first_cloth(s).map(|c| c.material.max_strain.unwrap_or(0.0) as f64),
        set: |s, v| {
            each_material(s, |m| m.max_strain = (v > 0.0).then_some(v as f32));
            Effect::Rebuild
        },
    },
    Param {
        name: "shear_compliance",
        label: "shear compliance (m/N)",
        section: Section::Material,
        min: 0.0,
        max: 1e-1,
        logarithmic: true,
        integer: false,
        // Paper has no grid diagonals.
        get: |s| cloth_unless_paper(s).map(|c| c.material.shear_compliance as f64),
        set: |s, v| live_compliance(s, ComplianceKind::Shear, v),
    },
    Param {
        name: "bend_compliance",
        label: "bend compliance (1/(N m))",
        section: Section::Material,
        min: 0.0,
        max: 1e3,
        logarithmic: true,
        integer: false,
        // Paper bends at its hinges (crease and facet compliances).
        get: |s| cloth_unless_paper(s).map(|c| c.material.bend_compliance as f64),
        set: |s, v| live_compliance(s, ComplianceKind::Bend, v),
    },
    Param {
        name: "density",
        label: "density (kg/m²)",
        section: Section::Material,
        min: 0.001,
        max: 10.0,
        logarithmic: true,
        integer: false,
        // Paper's vertices weigh pleat::folding::PAPER_VERTEX_MASS each.
        get: |s| cloth_unless_paper(s).map(|c| c.material.density as f64),
        set: |s, v| {
            each_material(s, |m| m.density = v as f32);
            Effect::Rebuild
        },
    },
    Param {
        name: "crease_compliance",
        label: "crease compliance",
        section: Section::Paper,
        min: 1e-4,
        max: 1e2,
        logarithmic: true,
        integer: false,
        get: |s| paper_stiffness(s).map(|p| p.crease_compliance as f64),
        set: |s, v| live_compliance(s, ComplianceKind::Crease, v),
    },
    Param {
        name: "facet_compliance",
        label: "facet compliance",
        section: Section::Paper,
        min: 1e-5,
        max: 1e1,
        logarithmic: true,
        integer: false,
        get: |s| paper_stiffness(s).map(|p| p.facet_compliance as f64),
        set: |s, v| live_compliance(s, ComplianceKind::Facet, v),
    },
    Param {
        name: "friction_static",
        label: "static friction",
        section: Section::Contact,
        min: 0.0,
        max: 2.0,
        logarithmic: false,
        integer: false,
        get: |s| first_friction(s).map(|f| f.static_coefficient as f64),
        set: |s, v| each_friction(s, |f| f.static_coefficient = v as f32),
    },
    Param {
        name: "friction_kinetic",
        label: "kinetic friction",
        section: Section::Contact,
        min: 0.0,
        max: 2.0,
        logarithmic: false,
        integer: false,
        get: |s| first_friction(s).map(|f| f.kinetic_coefficient as f64),
        set: |s, v| each_friction(s, |f| f.kinetic_coefficient = v as f32),
    },
    Param {
        name: "thickness",
        label: "thickness (m)",
        section: Section::Contact,
        min: 0.0,
        max: 0.1,
        logarithmic: true,
        integer: false,
        get: |s| first_cloth(s).map(|c| c.material.thickness as f64),
        set: |s, v| {
            each_material(s, |m| m.thickness = v as f32);
            Effect::Rebuild
        },
    },
    Param {
        name: "gravity",
        label: "gravity y (m/s²)",
        section: Section::Forces,
        min: -50.0,
        max: 50.0,
        logarithmic: false,
        integer: false,
        get: |s| Some(s.sim.world.gravity.y as f64),
        set: |s, v| {
            s.sim.world.gravity.y = v as f32;
            s.scene.gravity.y = v as f32;
            Effect::Live
        },
    },
    Param {
        name: "wind_x",
        label: "wind x (m/s)",
        section: Section::Forces,
        min: -50.0,
        max: 50.0,
        logarithmic: false,
        integer: false,
        get: |s| Some(s.sim.world.wind.map_or(0.0, |w| w.velocity.x as f64)),
        set: |s, v| {
            wind(s).velocity.x = v as f32;
            sync_wind(s)
        },
    },
    Param {
        name: "wind_z",
        label: "wind z (m/s)",
        section: Section::Forces,
        min: -50.0,
        max: 50.0,
        logarithmic: false,
        integer: false,
        get: |s| Some(s.sim.world.wind.map_or(0.0, |w| w.velocity.z as f64)),
        set: |s, v| {
            wind(s).velocity.z = v as f32;
            sync_wind(s)
        },
    },
    Param {
        name: "turbulence",
        label: "turbulence",
        section: Section::Forces,
        min: 0.0,
        max: 2.0,
        logarithmic: false,
        integer: false,
        get: |s| Some(s.sim.world.wind.map_or(0.0, |w| w.turbulence as f64)),
        set: |s, v| {
            wind(s).turbulence = v as f32;
            sync_wind(s)
        },
    },
    Param {
        name: "fold_progress",
        label: "fold progress",
        section: Section::Fold,
        min: 0.0,
        max: 1.0,
        logarithmic: false,
        integer: false,
        get: |s| s.is_paper().then_some(s.fold_target as f64),
        set: |s, v| {
            s.fold_target = v as f32;
            Effect::Live
        },
    },
    Param {
        name: "fold_speed",
        label: "fold speed (1/s, 0: at once)",
        section: Section::Fold,
        min: 0.0,
        max: 10.0,
        logarithmic: true,
        integer: false,
        get: |s| s.is_paper().then_some(s.fold_speed as f64),
        set: |s, v| {
            s.fold_speed = v as f32;
            Effect::Live
        },
    },
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::demo_on_cpu as session;

    #[test]
    fn every_parameter_reads_back_what_was_set() {
        for id in ["wind", "fold"] {
            let mut s = session(id);
            for p in PARAMS {
                let Some(before) = (p.get)(&s) else { continue };
                let value = if before == p.max {
                    p.min
                } else {
                    (before + p.max) / 2.0
                };
                set(&mut s, p.name, value).unwrap();
                s.poll().unwrap();
                let expected = if p.integer { value.round() } else { value };
                let got = (p.get)(&s).unwrap();
                assert!(
                    (got - expected).abs() <= 1e-6 * expected.abs().max(1.0),
                    "{id} {}: {got} != {expected}",
                    p.name
                );
            }
        }
    }

    #[test]
    fn a_live_change_changes_the_motion_and_a_rebuild_keeps_the_state() {
        let run = |gravity: Option<f64>| {
            let mut s = session("wind");
            if let Some(g) = gravity {
                set(&mut s, "gravity", g).unwrap();
            }
            for _ in 0..10 {
                s.step(1.0 / 60.0);
            }
            s.sim.particles.x.iter().map(|p| p.y).sum::<f32>()
        };
        assert!(run(Some(9.81)) > run(None) + 1.0);
        let mut s = session("wind");
        s.step(1.0 / 60.0);
        let x = s.sim.particles.x.clone();
        set(&mut s, "stretch_compliance", 1e-3).unwrap();
        assert!(!s.is_pending(), "a compliance is live");
        assert_eq!(
            s.sim.compliances.get(0, ComplianceKind::Stretch),
            Some(1e-3)
        );
        let inv_mass = s.sim.particles.inv_mass.clone();
        set(&mut s, "density", 0.5).unwrap();
        s.poll().unwrap();
        assert_eq!(s.sim.particles.x, x);
        assert_eq!(s.scene.cloths[0].material.density, 0.5);
        let heavier = |(new, old): (&f32, &f32)| *old == 0.0 || new < old;
        assert!(s.sim.particles.inv_mass.iter().zip(&inv_mass).all(heavier));
        assert_ne!(s.sim.particles.inv_mass, inv_mass);
    }

    #[test]
    fn bad_names_and_values_are_refused() {
        let mut s = session("wind");
        assert!(set(&mut s, "warp_speed", 1.0)
            .unwrap_err()
            .contains("no parameter"));
        assert!(set(&mut s, "gravity", f64::NAN).is_err());
        assert!(set(&mut s, "fold_progress", 0.5)
            .unwrap_err()
            .contains("none"));
        set(&mut s, "substeps", 1e9).unwrap();
        assert_eq!(s.sim.settings.substeps, 200);
    }
}
