// Prediction: x_prev = x, then for dynamic particles v = (v + g dt) keep and
// x += v dt (crate::solver::xpbd::predict).

@compute @workgroup_size(256)
fn predict(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count {
        return;
    }
    let x = pos[i];
    prev[i] = x;
    if x.w > 0.0 {
        let v = (vel[i].xyz + params.gravity * params.dt) * params.keep;
        vel[i] = vec4<f32>(v, 0.0);
        pos[i] = vec4<f32>(x.xyz + v * params.dt, x.w);
    }
}

// v = (x - x_prev) / dt (crate::solver::xpbd::update_velocities).
@compute @workgroup_size(256)
fn update_velocities(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count {
        return;
    }
    vel[i] = vec4<f32>((pos[i].xyz - prev[i].xyz) / params.dt, 0.0);
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
