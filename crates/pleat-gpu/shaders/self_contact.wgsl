// Self-collision and cloth-cloth contact: the candidate pairs of the last
// build (contact_grid.wgsl) as particle-particle, vertex-triangle and
// (paper's) edge-edge proximity contacts within the contact thickness, solved in
// CONTACT_ITERATIONS Jacobi iterations a substep (the CPU backend's): each
// contact's corrections summed per particle in fixed point with integer
// atomics (WGSL has no float atomics; integer sums do not depend on the
// order, so two runs are bit-identical however the candidates were
// listed), then averaged.

@group(1) @binding(0) var<storage, read_write> candidates: array<atomic<u32>>;
@group(1) @binding(1) var<storage, read_write> topology: array<u32>;
// Per particle: correction x, y, z in fixed point, and the contact count
// (zero again once applied).
@group(1) @binding(3) var<storage, read_write> accum: array<atomic<i32>>;

// Contacts of the workgroup that acted.
var<workgroup> acted: atomic<u32>;

// Candidate k's contact, if its pair is within the thickness; whether it
// acted.
fn contact(k: u32) -> bool {
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

// One candidate's contact: an iteration before the last.
@compute @workgroup_size(256)
fn contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    contact(flat_index(gid, groups));
}

// One candidate's contact in the substep's last iteration, counted if it
// acted (as the CPU backend counts the contacts acting).
@compute @workgroup_size(256)
fn counted_contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    if contact(flat_index(gid, groups)) {
        atomicAdd(&acted, 1u);
    }
    workgroupBarrier();
    if lid == 0u {
        atomicAdd(&candidates[ACTED], atomicLoad(&acted));
    }
}

@compute @workgroup_size(256)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        apply_correction(i);
    }
}
