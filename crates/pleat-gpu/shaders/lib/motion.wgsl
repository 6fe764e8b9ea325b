// A particle's prediction and velocity update (crate::solver::xpbd):
// x_prev = x, then for dynamic particles v = (v + g dt) keep and
// x += v dt; after the projection v = (x - x_prev) / dt.

fn predict_particle(i: u32) {
    let x = pos[i];
    prev[i] = x;
    if x.w > 0.0 {
        let v = (vel[i].xyz + params.gravity * params.dt) * params.keep;
        vel[i] = vec4<f32>(v, 0.0);
        pos[i] = vec4<f32>(x.xyz + v * params.dt, x.w);
    }
}

fn update_velocity(i: u32) {
    vel[i] = vec4<f32>((pos[i].xyz - prev[i].xyz) / params.dt, 0.0);
}
