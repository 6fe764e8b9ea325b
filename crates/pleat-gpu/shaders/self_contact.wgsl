// Self-collision and cloth-cloth contact: the candidate pairs of the last
// build (contact_grid.wgsl) as particle-particle, vertex-triangle and
// (paper's) edge-edge proximity contacts within the contact thickness, solved in
// CONTACT_ITERATIONS Jacobi iterations a substep (the CPU backend's):
// paper's in two passes, the first counting the contacts that move each
// particle, the second summing each contact's corrections per particle
// scaled by the relaxation over the count of its busiest particle; cloth's
// in one, the corrections summed and counted per particle, then averaged
// (lib/contact_solve.wgsl). Sums are in fixed point with integer atomics
// (WGSL has no float atomics; integer sums do not depend on the order, so
// two runs are bit-identical however the candidates were listed).

@group(1) @binding(0) var<storage, read_write> candidates: array<atomic<u32>>;
@group(1) @binding(1) var<storage, read_write> topology: array<u32>;
// Per particle: correction x, y, z in fixed point, and the count of the
// contacts that move it (zero again once applied).
@group(1) @binding(3) var<storage, read_write> accum: array<atomic<i32>>;

// Contacts of the workgroup that acted.
var<workgroup> acted: atomic<u32>;

// Candidate k's contact, if its pair is within the thickness, its
// corrections listed (lib/contact_solve.wgsl); whether it acted.
fn contact(k: u32) -> bool {
    touches = 0u;
    if k >= min(atomicLoad(&candidates[FOUND]), params.contact_capacity) {
        return false;
    }
    let i = atomicLoad(&candidates[HEADER + 2u * k]);
    let other = atomicLoad(&candidates[HEADER + 2u * k + 1u]);
    if (i & EDGE_PAIR) != 0u {
        return edge_contact(edge(i & ~EDGE_PAIR), edge(other));
    }
    if (other & PARTICLE_PAIR) != 0u {
        return particle_contact(i, other & ~PARTICLE_PAIR);
    }
    return triangle_contact(i, triangle(other));
}

// Counts the workgroup's contacts that acted (`acting` in this
// invocation) into the header, as the CPU backend counts those acting in
// a substep's last iteration.
fn tally(acting: bool, lid: u32) {
    if acting {
        atomicAdd(&acted, 1u);
    }
    workgroupBarrier();
    if lid == 0u {
        atomicAdd(&candidates[ACTED], atomicLoad(&acted));
    }
}

// Paper's first pass of an iteration: one candidate's contact, counted for each
// particle it moves.
@compute @workgroup_size(256)
fn count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    if contact(flat_index(gid, groups)) {
        count_contact();
    }
}

// Paper's second pass of an iteration before the last: one candidate's
// contact, its corrections scaled and summed.
@compute @workgroup_size(256)
fn contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    if contact(flat_index(gid, groups)) {
        scaled_contact();
    }
}

// Paper's second pass of the substep's last iteration, the contacts
// that acted counted.
@compute @workgroup_size(256)
fn counted_contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let acting = contact(flat_index(gid, groups));
    if acting {
        scaled_contact();
    }
    tally(acting, lid);
}

// Paper's: each particle moved by its sum.
@compute @workgroup_size(256)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        apply_correction(i);
    }
}

// Cloth's iteration before the last: one candidate's contact, summed and
// counted per particle.
@compute @workgroup_size(256)
fn averaged_contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    if contact(flat_index(gid, groups)) {
        sum_contact();
    }
}

// Cloth's last iteration, each contact that acted counted.
@compute @workgroup_size(256)
fn counted_averaged_contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let acting = contact(flat_index(gid, groups));
    if acting {
        sum_contact();
    }
    tally(acting, lid);
}

// Cloth's: each particle moved by its average.
@compute @workgroup_size(256)
fn apply_averaged(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        apply_average(i);
    }
}
