// Aerodynamic wind (crate::force::wind): the force on each triangle from its
// velocity relative to the air, then per vertex the mean of its triangles'
// forces as a velocity change capped at the speed relative to the air.

@group(1) @binding(0) var<storage, read_write> triangles: array<u32>;
@group(1) @binding(1) var<storage, read_write> triangle_force: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read_write> around_start: array<u32>;
@group(1) @binding(3) var<storage, read_write> around: array<u32>;

const MIN_POSITIVE: f32 = 1.17549435e-38;

fn is_normal(x: f32) -> bool {
    return abs(x) >= MIN_POSITIVE && abs(x) <= MAX_FINITE;
}

// Hash of a lattice point mapped to [-1, 1] (crate::force::noise).
fn lattice(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    var h = (bitcast<u32>(x) * 0x8da6b343u) ^ (bitcast<u32>(y) * 0xd8163841u)
        ^ (bitcast<u32>(z) * 0xcb1ab31fu) ^ (seed * 0x2545f491u);
    h ^= h >> 15u;
    h *= 0x2c1b3c6du;
    h ^= h >> 12u;
    h *= 0x297a2d39u;
    h ^= h >> 15u;
    return (f32(h) / 4294967296.0) * 2.0 - 1.0;
}

// Smooth value noise in [-1, 1] (crate::force::noise::value_noise).
fn value_noise(p: vec3<f32>, seed: u32) -> f32 {
    let cell = floor(p);
    let f = p - cell;
    let s = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let c = vec3<i32>(cell);
    let x00 = mix(lattice(c.x, c.y, c.z, seed), lattice(c.x + 1, c.y, c.z, seed), s.x);
    let x10 = mix(lattice(c.x, c.y + 1, c.z, seed), lattice(c.x + 1, c.y + 1, c.z, seed), s.x);
    let x01 = mix(lattice(c.x, c.y, c.z + 1, seed), lattice(c.x + 1, c.y, c.z + 1, seed), s.x);
    let x11 = mix(lattice(c.x, c.y + 1, c.z + 1, seed), lattice(c.x + 1, c.y + 1, c.z + 1, seed), s.x);
    return mix(mix(x00, x10, s.y), mix(x01, x11, s.y), s.z);
}

// Air velocity at p and time t (crate::force::Wind::air_velocity).
fn air_velocity(p: vec3<f32>, t: f32) -> vec3<f32> {
    if params.turbulence == 0.0 {
        return params.wind_velocity;
    }
    let speed = length(params.wind_velocity);
    let q = (p - params.wind_velocity * t) / params.turbulence_scale;
    let w = params.turbulence_frequency * t;
    let swirl = vec3<f32>(
        value_noise(q + vec3<f32>(w, 0.0, 0.0), 1u),
        value_noise(q + vec3<f32>(0.0, w, 0.0), 2u),
        value_noise(q + vec3<f32>(0.0, 0.0, w), 3u),
    );
    return params.wind_velocity + swirl * (params.turbulence * speed);
}

@compute @workgroup_size(256)
fn triangle_forces(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= params.triangle_count {
        return;
    }
    let i = vec3<u32>(triangles[3u * k], triangles[3u * k + 1u], triangles[3u * k + 2u]);
    let p0 = position(i.x);
    let p1 = position(i.y);
    let p2 = position(i.z);
    var force = vec3<f32>(0.0);
    let c = cross(p1 - p0, p2 - p0);
    let double_area = length(c);
    if is_normal(double_area) {
        let n = c / double_area;
        let centroid = (p0 + p1 + p2) / 3.0;
        let u = (vel[i.x].xyz + vel[i.y].xyz + vel[i.z].xyz) / 3.0 - air_velocity(centroid, params.t);
        let speed2 = dot(u, u);
        if is_normal(speed2) {
            let u_hat = u / sqrt(speed2);
            let cos_theta = dot(n, u_hat);
            let q = 0.25 * params.air_density * double_area * speed2;
            let drag = -params.drag * q * abs(cos_theta) * u_hat;
            let lift = params.lift * q * cos_theta * cross(cross(n, u_hat), u_hat);
            force = drag + lift;
        }
    }
    triangle_force[k] = vec4<f32>(force, 0.0);
}

@compute @workgroup_size(256)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count {
        return;
    }
    let w = inv_mass(i);
    if w == 0.0 {
        return;
    }
    var force = vec3<f32>(0.0);
    for (var a = around_start[i]; a < around_start[i + 1u]; a++) {
        force += triangle_force[around[a]].xyz;
    }
    let dv = force / 3.0 * (w * params.dt);
    let v = vel[i].xyz;
    let cap = length(v - air_velocity(position(i), params.t));
    let len = length(dv);
    vel[i] = vec4<f32>(v + select(dv, dv * (cap / len), len > cap), 0.0);
}
