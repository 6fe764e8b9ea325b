// Every struct the host writes or reads back, in one place: each mirrors a
// #[repr(C)] Pod type on the Rust side, and a test (src/layout.rs) checks
// its size and field offsets against the layout naga computes here.

// Per-substep parameters (crate::data::Params).
struct Params {
    gravity: vec3<f32>,
    dt: f32,
    wind_velocity: vec3<f32>,
    inv_dt2: f32,
    t: f32,
    keep: f32,
    progress: f32,
    substep: u32,
    particle_count: u32,
    triangle_count: u32,
    pin_count: u32,
    collider_count: u32,
    wind_on: u32,
    drag: f32,
    lift: f32,
    air_density: f32,
    turbulence: f32,
    turbulence_scale: f32,
    turbulence_frequency: f32,
    grab_particle: u32,
    grab_target: vec3<f32>,
    grab_compliance: f32,
    // Jacobi PBD's omega.
    relaxation: f32,
    // Self-contact: hash grid cell size, distance kept between layers,
    // buckets of the hash table (a power of two).
    contact_cell: f32,
    contact_thickness: f32,
    contact_buckets: u32,
    // Coulomb friction between layers.
    contact_static: f32,
    contact_kinetic: f32,
    // 1 while the fold progress is held: driven creases stiffen.
    fold_held: u32,
    // Always 0, unknown to the compiler (momentum.wgsl).
    opaque_zero: u32,
    // Self-contact candidates (contact_grid.wgsl): how much farther than
    // the thickness a pair is kept, the rest distance below which a cloth's
    // pairs never collide, and how many pairs fit.
    contact_margin: f32,
    contact_exclusion: f32,
    contact_capacity: u32,
    max_fold_angle: f32,
}

// The slice of a constraint array one dispatch works on (one colour;
// crate::data::Range).
struct Range {
    first: u32,
    count: u32,
}

// A distance constraint (crate::constraint::DistanceConstraint). Jacobi PBD
// (jacobi.wgsl) carries its stiffness in [0, 1] in `compliance` and reads
// neither `slot` nor `max_stretch`.
struct Distance {
    a: u32,
    b: u32,
    rest_length: f32,
    compliance: f32,
    slot: u32,
    // Largest change of length (m); f32::MAX for no limit.
    max_stretch: f32,
}

// Dihedral bending (crate::constraint::DihedralBending).
struct Bending {
    v: array<u32, 4>,
    rest_angle: f32,
    compliance: f32,
    slot: u32,
}

// Isometric bending (crate::constraint::IsometricBending).
struct Isometric {
    v: array<u32, 4>,
    k: array<f32, 4>,
    compliance: f32,
    slot: u32,
}

// An origami hinge (crate::constraint::OrigamiHinge).
struct Hinge {
    v: array<u32, 4>,
    full_angle: f32,
    start_angle: f32,
    compliance: f32,
    angle: f32,
    slot: u32,
}

// A long-range attachment (crate::constraint::Tether).
struct Tether {
    particle: u32,
    pin: u32,
    max_length: f32,
}

// A soft attachment (crate::data::Attachment).
struct Attachment {
    particle: u32,
    compliance: f32,
    // Index among the pins' targets of a substep.
    slot: u32,
    pad: u32,
}

// A collider shape (crate::data::GpuCollider).
struct Collider {
    kind: u32,
    sdf_offset: u32,
    static_friction: f32,
    kinetic_friction: f32,
    // Plane: point, normal. Sphere: centre, w radius. Box: centre, half
    // extents, rotation (x, y, z, w). Capsule: a with w radius, b.
    // Distance field: origin with w cell size, dims in `dims`.
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    dims: vec4<u32>,
}

// Rows of the 3 x 4 matrices of an affine map.
struct Affine {
    r0: vec4<f32>,
    r1: vec4<f32>,
    r2: vec4<f32>,
}

// A collider's placement over a substep (crate::data::GpuPose).
struct Pose {
    start: Affine,
    end: Affine,
    start_inverse: Affine,
    end_inverse: Affine,
}

// The health reduction's result (crate::health::Summary).
struct Summary {
    non_finite: u32,
    first_bad: u32,
    fastest: u32,
    speed2: f32,
    kinetic: f32,
    potential: f32,
    tear: f32,
    pad: u32,
}

// A paper edge whose stretch beyond its tear length is a tear
// (crate::health::TearEdge).
struct TearEdge {
    a: u32,
    b: u32,
    tear_length: f32,
    pad: u32,
}

// A coarse edge of the hierarchy (pleat::constraint::LongRangeLimit).
struct LongRangeLimit {
    a: u32,
    b: u32,
    max_length: f32,
    wa: f32,
    wb: f32,
    // The live stretch compliance that must be zero for the limit to hold;
    // NONE: always held (a strain limit).
    slot: u32,
    // The share of the ends' distance when the hierarchy began that they
    // keep: 1 from level 2 up on a held cloth, 0 (never pushed) on level 1
    // and on a free cloth.
    floor: f32,
}

// How a particle follows the level above it
// (pleat::solver::hierarchy::Prolongation); unused parents weigh 0.
struct Prolongation {
    particle: u32,
    parents: array<u32, 4>,
    weights: array<f32, 4>,
}

// What a frame of the persistent kernel runs (persistent.wgsl;
// crate::backend::persistent::Program): counts, then each colour's slice
// (first, count in xy) of the hinges, then of the distances, then each
// free cloth's particles.
struct Program {
    substeps: u32,
    iterations: u32,
    hinge_colours: u32,
    distance_colours: u32,
    hinge_count: u32,
    distance_count: u32,
    // Sweeps of the strain limits before the further ones; 0 for none.
    strain_limit_sweeps: u32,
    free_parts: u32,
    // Self-contacts (`frame_with_contacts`): the pairs, where they start in
    // `topology`, the Jacobi iterations a substep, and where the frame's
    // counts of pairs solved and contacts acted go in `topology`.
    contact_pairs: u32,
    contact_pairs_start: u32,
    contact_iterations: u32,
    contact_counts: u32,
    slices: array<vec4<u32>, 256>,
}
