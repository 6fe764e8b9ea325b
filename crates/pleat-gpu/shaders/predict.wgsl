// Prediction and velocity update over the particles (lib/motion.wgsl),
// and the grabbed particle.

@compute @workgroup_size(256)
fn predict(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        predict_particle(i);
    }
}

@compute @workgroup_size(256)
fn update_velocities(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        update_velocity(i);
    }
}

// The grabbed particle pulled towards its target (crate::constraint::Grab).
@compute @workgroup_size(1)
fn grab() {
    let i = params.grab_particle;
    if i >= params.particle_count {
        return;
    }
    let w = inv_mass(i);
    let d = position(i) - params.grab_target;
    let c = length(d);
    if w == 0.0 || c <= 1.1920929e-7 {
        return;
    }
    let alpha = params.grab_compliance * params.inv_dt2;
    move_by(i, -d / c * (w * c / (w + alpha)));
}
