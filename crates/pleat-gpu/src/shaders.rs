//! The WGSL sources of the compute kernels. Each module is the shared
//! prelude, the libraries it uses and one kernel file: `structs.wgsl`,
//! every struct the host writes or reads (each mirrors a Pod type, checked
//! by `crate::layout`'s tests), `state.wgsl`, the particle state's bindings
//! (`pos` among them) and `colour_barrier` (a persistent kernel declares
//! its own: `pos` in workgroup memory), then `common.wgsl`, the helpers
//! every kernel shares (the XPBD multiplier update among them). A library
//! (`shaders/lib/`) holds a constraint kind's work on one index, so that a
//! kernel dispatched per colour and the persistent kernel run the same
//! code; it names the buffers its includer binds.
//!
//! A generated preamble rather than a module system (naga_oil, wesl): the
//! kernels share one flat prelude and nothing else, which concatenation
//! does exactly, with no build step, no dependency tied to wgpu's naga
//! version, and the same source on native and wasm32.

/// One compute module: its name (the file) and its entry points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Module {
    /// The kernel file's stem.
    pub name: &'static str,
    /// The state's bindings: [`STATE`], or none where the kernel binds its own.
    state: &'static str,
    /// The libraries the kernel calls.
    libs: &'static [&'static str],
    /// The kernel file's text.
    body: &'static str,
    /// Compute entry points it defines.
    pub entry_points: &'static [&'static str],
}

/// The structs every kernel shares, laid out as the host's Pod types.
pub(crate) const STRUCTS: &str = include_str!("../shaders/structs.wgsl");
/// The particle state's bindings for kernels dispatched per stage.
const STATE: &str = include_str!("../shaders/state.wgsl");
/// The shared constants and helpers.
const COMMON: &str = include_str!("../shaders/common.wgsl");

/// A particle's prediction and velocity update.
const MOTION_LIB: &str = include_str!("../shaders/lib/motion.wgsl");
/// Distance constraints and their strain limits.
const DISTANCE_LIB: &str = include_str!("../shaders/lib/distance.wgsl");
/// Origami hinges.
const HINGE_LIB: &str = include_str!("../shaders/lib/hinge.wgsl");
/// The free cloths' turn.
const MOMENTUM_LIB: &str = include_str!("../shaders/lib/momentum.wgsl");
/// Self-contacts' candidate layout and closest points.
const CONTACT_LIB: &str = include_str!("../shaders/lib/contact.wgsl");
const CONTACT_SOLVE_LIB: &str = include_str!("../shaders/lib/contact_solve.wgsl");

macro_rules! module {
    ($name:literal, [$($entry:literal),+]) => {
        module!($name, STATE, [], [$($entry),+])
    };
    ($name:literal, [$($lib:ident),*], [$($entry:literal),+]) => {
        module!($name, STATE, [$($lib),*], [$($entry),+])
    };
    ($name:literal, $state:expr, [$($lib:ident),*], [$($entry:literal),+]) => {
        Module {
            name: $name,
            state: $state,
            libs: &[$($lib),*],
            body: include_str!(concat!("../shaders/", $name, ".wgsl")),
            entry_points: &[$($entry),+],
        }
    };
}

/// Prediction, velocity update and the grabbed particle.
pub const PREDICT: Module = module!(
    "predict",
    [MOTION_LIB],
    ["predict", "update_velocities", "grab"]
);
/// Hard pins placed on their targets.
pub const PINS: Module = module!("pins", ["place_pins"]);
/// Aerodynamic wind.
pub const WIND: Module = module!("wind", ["triangle_forces", "gather"]);
/// Collider contacts with friction.
pub const COLLIDE: Module = module!("collide", ["resolve"]);
/// Stretch, shear and skip-one distance constraints.
pub const DISTANCE: Module = module!(
    "distance",
    [DISTANCE_LIB],
    [
        "solve",
        "limit",
        "limit_measured",
        "limit_further",
        "limit_held"
    ]
);
/// Dihedral bending.
pub const BENDING: Module = module!("bending", ["solve"]);
/// Isometric bending.
pub const ISOMETRIC: Module = module!("isometric", ["solve"]);
/// Origami hinges and their angle tracking.
pub const HINGE: Module = module!("hinge", [HINGE_LIB], ["solve", "track"]);
/// Long-range attachments.
pub const TETHER: Module = module!("tether", ["solve"]);
/// The hierarchy's coarse edges.
pub const LONG_RANGE: Module = module!("long_range", ["solve"]);
/// The hierarchy's prolongation.
pub const PROLONGATION: Module = module!("prolongation", ["snapshot", "prolongate"]);
/// Long-range attachments to the grabbed particle.
pub const GRAB_REACH: Module = module!("grab_reach", ["reach"]);
/// Soft attachments.
pub const ATTACHMENT: Module = module!("attachment", ["solve"]);

/// Jacobi PBD's corrections and their gather.
pub const JACOBI: Module = module!("jacobi", ["correct", "gather"]);

/// Self-contacts' broad phase: the displacements' range and the stale
/// check, then a build's hash grid (clear, count, prefix sum, scatter) and
/// candidate pairs, then paper's edge pairs.
pub const CONTACT_GRID: Module = module!(
    "contact_grid",
    [CONTACT_LIB],
    [
        "bound",
        "check",
        "clear",
        "count",
        "scan_blocks",
        "scan_sums",
        "scan_add",
        "scatter",
        "find",
        "find_edges"
    ]
);
/// The self-contacts' indirect dispatch counts, the build's and the
/// solve's, and the margin chosen after each frame.
pub const CONTACT_DISPATCH: Module = module!(
    "contact_dispatch",
    [CONTACT_LIB],
    ["arm_build", "arm_solve", "choose_margin", "arm_round_solve"]
);
/// Self-contacts' Jacobi solve over the candidates.
pub const SELF_CONTACT: Module = module!(
    "self_contact",
    [CONTACT_LIB, CONTACT_SOLVE_LIB],
    [
        "count",
        "contacts",
        "counted_contacts",
        "apply",
        "averaged_contacts",
        "counted_averaged_contacts",
        "apply_averaged"
    ]
);

/// The health reduction: non-finite values, energy, paper strain.
pub const HEALTH: Module = module!("health", ["reduce_blocks", "reduce_sums"]);

/// The free cloths' angular momentum kept through the projection.
pub const MOMENTUM: Module = module!("momentum", [MOMENTUM_LIB], ["sum_blocks", "solve", "apply"]);

/// A whole frame of a small sheet in one workgroup.
pub const PERSISTENT: Module = module!(
    "persistent",
    "",
    [
        MOTION_LIB,
        DISTANCE_LIB,
        HINGE_LIB,
        MOMENTUM_LIB,
        CONTACT_LIB,
        CONTACT_SOLVE_LIB
    ],
    ["frame", "frame_with_contacts"]
);

/// Every module of the backend.
pub const ALL: [Module; 20] = [
    PREDICT,
    PINS,
    WIND,
    COLLIDE,
    DISTANCE,
    BENDING,
    ISOMETRIC,
    HINGE,
    TETHER,
    LONG_RANGE,
    PROLONGATION,
    GRAB_REACH,
    ATTACHMENT,
    JACOBI,
    CONTACT_GRID,
    CONTACT_DISPATCH,
    SELF_CONTACT,
    HEALTH,
    MOMENTUM,
    PERSISTENT,
];

impl Module {
    /// The whole WGSL source: the prelude, then the kernel.
    pub fn source(&self) -> String {
        let libs: String = self.libs.concat();
        format!(
            "{STRUCTS}\n{}\n// ---- common.wgsl ----\n{COMMON}\n{libs}\n// ---- {}.wgsl ----\n{}",
            self.state, self.name, self.body
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every module parses and validates with naga, the front end wgpu
    /// uses, and defines its entry points.
    #[test]
    fn every_shader_validates() {
        for m in ALL {
            let module = naga::front::wgsl::parse_str(&m.source())
                .unwrap_or_else(|e| panic!("{}.wgsl: {}", m.name, e.emit_to_string(&m.source())));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::empty(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}.wgsl: {e:?}", m.name));
            for entry in m.entry_points {
                assert!(
                    module.entry_points.iter().any(|e| e.name == *entry),
                    "{}.wgsl has no entry point {entry}",
                    m.name
                );
            }
        }
    }

    /// A constant of `m` as naga evaluates it.
    fn constant(m: Module, name: &str) -> f64 {
        let module = naga::front::wgsl::parse_str(&m.source()).expect("parses");
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{}.wgsl has no constant {name}", m.name));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::F32(v)) => v as f64,
            naga::Expression::Literal(naga::Literal::U32(v)) => v as f64,
            ref e => panic!("{name} is not a literal: {e:?}"),
        }
    }

    /// The kernels' copies of the core's constants are the core's (and of
    /// the backend's, its own).
    #[test]
    fn constants_are_the_cores() {
        use pleat::constraint::hinge::STIFFENING_ANGLE;
        use pleat::solver::xpbd::{
            FOLD_HOLD_SWEEPS, MAX_STRAIN_LIMIT_SWEEPS, STRAIN_LIMIT_SLACK, STRAIN_LIMIT_SWEEPS,
        };
        let pairs = [
            (DISTANCE, "STRAIN_LIMIT_SWEEPS", STRAIN_LIMIT_SWEEPS as f64),
            (
                DISTANCE,
                "MAX_STRAIN_LIMIT_SWEEPS",
                MAX_STRAIN_LIMIT_SWEEPS as f64,
            ),
            (DISTANCE, "STRAIN_LIMIT_SLACK", STRAIN_LIMIT_SLACK as f64),
            (DISTANCE, "FOLD_HOLD_SWEEPS", FOLD_HOLD_SWEEPS as f64),
            (
                DISTANCE,
                "HOLD_ROUND_SWEEPS",
                crate::kernels::HOLD_ROUND_SWEEPS as f64,
            ),
            (HINGE, "STIFFENING_ANGLE", STIFFENING_ANGLE as f64),
        ];
        for (m, name, core) in pairs {
            assert_eq!(constant(m, name), core, "{}.wgsl's {name}", m.name);
        }
    }
}
