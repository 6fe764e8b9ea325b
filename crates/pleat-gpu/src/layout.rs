//! Tests that each Pod struct the kernels read or write has the layout of
//! its WGSL struct in `shaders/structs.wgsl`, as naga computes it: the same
//! size and every WGSL member at the offset of the Rust field it mirrors.

use crate::backend::persistent::Program;
use crate::data::{Attachment, GpuCollider, GpuPose, Params, Range};
use crate::health::{Summary, TearEdge};
use crate::shaders::STRUCTS;
use pleat::constraint::{
    DihedralBending, DistanceConstraint, IsometricBending, LongRangeLimit, OrigamiHinge, Tether,
};
use pleat::solver::hierarchy::Prolongation;
use std::mem::{offset_of, size_of, size_of_val};

/// `structs.wgsl` as naga parses it, and the layout naga computes for its types.
fn wgsl_layout() -> (naga::Module, naga::proc::Layouter) {
    let module = naga::front::wgsl::parse_str(STRUCTS)
        .unwrap_or_else(|e| panic!("structs.wgsl: {}", e.emit_to_string(STRUCTS)));
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .expect("naga lays out structs.wgsl");
    (module, layouter)
}

/// Asserts that the WGSL struct `wgsl` is `size` bytes and has exactly
/// `members` (name, offset), in order; `rust` names the Rust side.
fn assert_layout(rust: &str, wgsl: &str, size: usize, members: &[(String, usize)]) {
    let (module, layouter) = wgsl_layout();
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(wgsl))
        .unwrap_or_else(|| panic!("structs.wgsl has no struct {wgsl}"));
    let naga::TypeInner::Struct {
        members: wgsl_members,
        span,
    } = &ty.inner
    else {
        panic!("{wgsl} is not a struct");
    };
    let layout = &layouter[handle];
    assert_eq!(layout.size, *span, "{wgsl}: naga's size and span");
    let wgsl_members: Vec<(String, usize)> = wgsl_members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    assert_eq!(
        wgsl_members, members,
        "{wgsl} (WGSL, left) and {rust} (Rust, right): members and offsets differ"
    );
    assert_eq!(
        *span as usize, size,
        "{wgsl} is {span} bytes in WGSL, {rust} is {size} in Rust"
    );
}

/// Checks the Rust struct `$rust` against the WGSL struct `$wgsl`. Its
/// fields are listed in order: `field` mirrors the WGSL member of the same
/// name, `field => ["m0", "m1"]` an array spelled as consecutive WGSL
/// members. The list is also a struct pattern, so a Rust field left out of
/// it (added on the Rust side alone) stops the build (rustc: "pattern
/// requires `..`"), and a WGSL member added alone fails the comparison.
macro_rules! assert_mirrors {
    ($rust:ident as $wgsl:literal { $($field:ident $(=> [$($member:literal),+])?),+ $(,)? }) => {{
        let value: $rust = bytemuck::Zeroable::zeroed();
        let $rust { $($field: _),+ } = value;
        let mut members: Vec<(String, usize)> = Vec::new();
        $(
            let names: &[&str] = assert_mirrors!(@names $field $(, [$($member),+])?);
            let step = size_of_val(&value.$field) / names.len();
            for (k, name) in names.iter().enumerate() {
                members.push((name.to_string(), offset_of!($rust, $field) + k * step));
            }
        )+
        assert_layout(stringify!($rust), $wgsl, size_of::<$rust>(), &members);
    }};
    (@names $field:ident) => { &[stringify!($field)] };
    (@names $field:ident, [$($member:literal),+]) => { &[$($member),+] };
}

#[test]
fn params_match_wgsl() {
    assert_mirrors!(Params as "Params" {
        gravity, dt, wind_velocity, inv_dt2, t, keep, progress, substep,
        particle_count, triangle_count, pin_count, collider_count, wind_on,
        drag, lift, air_density, turbulence, turbulence_scale,
        turbulence_frequency, grab_particle, grab_target, grab_compliance,
        relaxation, contact_cell, contact_thickness, contact_buckets,
        contact_static, contact_kinetic, fold_held, opaque_zero,
        contact_margin, contact_exclusion, contact_capacity, max_fold_angle,
    });
}

#[test]
fn persistent_program_matches_wgsl() {
    assert_mirrors!(Program as "Program" {
        substeps, iterations, hinge_colours, distance_colours, hinge_count,
        distance_count, strain_limit_sweeps, free_parts, contact_pairs,
        contact_pairs_start, contact_iterations, contact_counts, slices,
    });
}

#[test]
fn range_and_attachment_match_wgsl() {
    assert_mirrors!(Range as "Range" { first, count });
    assert_mirrors!(Attachment as "Attachment" { particle, compliance, slot, pad });
}

#[test]
fn collider_and_pose_match_wgsl() {
    assert_mirrors!(GpuCollider as "Collider" {
        kind, sdf_offset, static_friction, kinetic_friction, a, b, c, dims,
    });
    assert_mirrors!(GpuPose as "Pose" { start, end, start_inverse, end_inverse });
    // Each pose member is an Affine: three rows of four.
    let row = size_of::<[f32; 4]>();
    let rows = ["r0", "r1", "r2"].map(String::from).into_iter();
    let members: Vec<(String, usize)> = rows.zip([0, row, 2 * row]).collect();
    assert_layout(
        "[[f32; 4]; 3]",
        "Affine",
        size_of::<[[f32; 4]; 3]>(),
        &members,
    );
}

#[test]
fn health_structs_match_wgsl() {
    assert_mirrors!(Summary as "Summary" {
        non_finite, first_bad, fastest, speed2, kinetic, potential, tear, pad,
    });
    assert_mirrors!(TearEdge as "TearEdge" { a, b, tear_length, pad });
}

/// The core's constraints, uploaded as they are.
#[test]
fn core_constraints_match_wgsl() {
    assert_mirrors!(DistanceConstraint as "Distance" {
        v => ["a", "b"], rest_length, compliance, slot, max_stretch,
    });
    assert_mirrors!(DihedralBending as "Bending" { v, rest_angle, compliance, slot });
    assert_mirrors!(IsometricBending as "Isometric" { v, k, compliance, slot });
    assert_mirrors!(OrigamiHinge as "Hinge" {
        v, full_angle, start_angle, compliance, angle, slot,
    });
    assert_mirrors!(Tether as "Tether" { particle => ["particle"], pin, max_length });
    assert_mirrors!(LongRangeLimit as "LongRangeLimit" {
        v => ["a", "b"], max_length, inv_mass => ["wa", "wb"], slot, floor,
    });
    assert_mirrors!(Prolongation as "Prolongation" { particle, parents, weights });
}
