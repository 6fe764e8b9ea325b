// Jacobi PBD (crate::solver::jacobi): every distance constraint corrected
// against the same positions, then per particle the mean of its
// corrections, relaxed by omega, gathered over its constraints in a fixed
// order (no atomics: bit-identical runs).

@group(1) @binding(0) var<storage, read_write> items: array<Distance>;
@group(1) @binding(1) var<storage, read_write> corrections: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read_write> incidence_start: array<u32>;
// Per slot: constraint index times two plus the end (0 or 1).
@group(1) @binding(3) var<storage, read_write> incidence: array<u32>;

@compute @workgroup_size(256)
fn correct(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = flat_index(gid, groups);
    if j >= range.count {
        return;
    }
    let c = items[j];
    let wa = inv_mass(c.a);
    let wb = inv_mass(c.b);
    let w = wa + wb;
    let d = position(c.a) - position(c.b);
    let len = length(d);
    var da = vec3<f32>(0.0);
    var db = vec3<f32>(0.0);
    if w > 0.0 && len > 1.1920929e-7 * max(c.rest_length, 1e-6) {
        let n = d / len;
        // Jacobi PBD's stiffness travels in the compliance field.
        let s = c.compliance * (len - c.rest_length) / w;
        da = n * (-s * wa);
        db = n * (s * wb);
    }
    corrections[2u * j] = vec4<f32>(da, 0.0);
    corrections[2u * j + 1u] = vec4<f32>(db, 0.0);
}

@compute @workgroup_size(256)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count {
        return;
    }
    let first = incidence_start[i];
    let last = incidence_start[i + 1u];
    if inv_mass(i) == 0.0 || first == last {
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var s = first; s < last; s++) {
        sum += corrections[incidence[s]].xyz;
    }
    move_by(i, sum * (params.relaxation / f32(last - first)));
}
