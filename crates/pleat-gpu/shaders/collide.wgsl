// Cloth-collider contacts with Coulomb friction (crate::collide::contact):
// each particle against every collider in turn, at the collider's pose over
// the substep. Shapes: plane, sphere, box, capsule and distance fields on a
// grid (meshes are baked into one before upload).

@group(1) @binding(0) var<storage, read_write> colliders: array<Collider>;
@group(1) @binding(1) var<storage, read_write> poses: array<Pose>;
@group(1) @binding(2) var<storage, read_write> sdf_values: array<f32>;
@group(1) @binding(3) var<storage, read_write> thickness: array<f32>;

const PLANE: u32 = 0u;
const SPHERE: u32 = 1u;
const BOX: u32 = 2u;
const CAPSULE: u32 = 3u;
const SDF: u32 = 4u;

fn point_to(m: Affine, p: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(m.r0, h), dot(m.r1, h), dot(m.r2, h));
}

fn vector_to(m: Affine, v: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(v, 0.0);
    return vec3<f32>(dot(m.r0, h), dot(m.r1, h), dot(m.r2, h));
}

fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

fn signum(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(-1.0), vec3<f32>(1.0), v >= vec3<f32>(0.0));
}

// Signed distance (w) and outward normal (xyz) of a sphere of radius r around the origin.
fn sphere(d: vec3<f32>, r: f32) -> vec4<f32> {
    let len = length(d);
    var n = vec3<f32>(0.0, 1.0, 0.0);
    if len > 0.0 {
        n = d / len;
    }
    return vec4<f32>(n, len - r);
}

fn oriented_box(p: vec3<f32>, half: vec3<f32>) -> vec4<f32> {
    let q = abs(p) - half;
    let m = max(q.x, max(q.y, q.z));
    if m > 0.0 {
        let outside = max(q, vec3<f32>(0.0));
        let len = length(outside);
        return vec4<f32>(outside * signum(p) / len, len);
    }
    var axis = vec3<f32>(0.0, 0.0, 1.0);
    if q.x >= q.y && q.x >= q.z {
        axis = vec3<f32>(1.0, 0.0, 0.0);
    } else if q.y >= q.z {
        axis = vec3<f32>(0.0, 1.0, 0.0);
    }
    return vec4<f32>(axis * signum(p), m);
}

fn sdf_value(c: Collider, i: u32, j: u32, k: u32) -> f32 {
    return sdf_values[c.sdf_offset + i + c.dims.x * (j + c.dims.y * k)];
}

// Trilinear interpolant (w) and its gradient (xyz) at q inside the grid (crate::collide::SdfGrid).
fn trilinear(c: Collider, q: vec3<f32>) -> vec4<f32> {
    let cell_size = c.a.w;
    let g = (q - c.a.xyz) / cell_size;
    let cell = min(vec3<u32>(max(floor(g), vec3<f32>(0.0))), c.dims.xyz - vec3<u32>(2u));
    let f = g - vec3<f32>(cell);
    let i = cell.x;
    let j = cell.y;
    let k = cell.z;
    let e0 = vec2<f32>(sdf_value(c, i, j, k), sdf_value(c, i + 1u, j, k));
    let e1 = vec2<f32>(sdf_value(c, i, j + 1u, k), sdf_value(c, i + 1u, j + 1u, k));
    let e2 = vec2<f32>(sdf_value(c, i, j, k + 1u), sdf_value(c, i + 1u, j, k + 1u));
    let e3 = vec2<f32>(sdf_value(c, i, j + 1u, k + 1u), sdf_value(c, i + 1u, j + 1u, k + 1u));
    let x = vec4<f32>(mix(e0.x, e0.y, f.x), mix(e1.x, e1.y, f.x), mix(e2.x, e2.y, f.x), mix(e3.x, e3.y, f.x));
    let dx = vec4<f32>(e0.y - e0.x, e1.y - e1.x, e2.y - e2.x, e3.y - e3.x);
    let y0 = mix(x[0], x[1], f.y);
    let y1 = mix(x[2], x[3], f.y);
    let gradient = vec3<f32>(
        mix(mix(dx[0], dx[1], f.y), mix(dx[2], dx[3], f.y), f.z),
        mix(x[1] - x[0], x[3] - x[2], f.z),
        y1 - y0,
    ) / cell_size;
    return vec4<f32>(gradient, mix(y0, y1, f.z));
}

fn normalize_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len = length(v);
    if len > 0.0 && len <= MAX_FINITE {
        return v / len;
    }
    return fallback;
}

fn grid_distance(c: Collider, p: vec3<f32>) -> vec4<f32> {
    let far = c.a.xyz + vec3<f32>(c.dims.xyz - vec3<u32>(1u)) * c.a.w;
    let q = clamp(p, c.a.xyz, far);
    let s = trilinear(c, q);
    let outside = p - q;
    let gap = length(outside);
    if gap > 0.0 {
        let free = select(vec3<f32>(0.0), s.xyz, outside == vec3<f32>(0.0));
        return vec4<f32>(normalize_or(outside / gap + free, outside / gap), gap + s.w);
    }
    return vec4<f32>(normalize_or(s.xyz, vec3<f32>(0.0, 1.0, 0.0)), s.w);
}

// Signed distance (w, negative inside) and outward normal (xyz) in the collider's frame.
fn signed_distance(c: Collider, p: vec3<f32>) -> vec4<f32> {
    switch c.kind {
        case PLANE: {
            return vec4<f32>(c.b.xyz, dot(p - c.a.xyz, c.b.xyz));
        }
        case SPHERE: {
            return sphere(p - c.a.xyz, c.a.w);
        }
        case BOX: {
            let inverse = vec4<f32>(-c.c.xyz, c.c.w);
            let d = oriented_box(rotate(inverse, p - c.a.xyz), c.b.xyz);
            return vec4<f32>(rotate(c.c, d.xyz), d.w);
        }
        case CAPSULE: {
            let ab = c.b.xyz - c.a.xyz;
            let t = clamp(dot(p - c.a.xyz, ab) / max(dot(ab, ab), 1.17549435e-38), 0.0, 1.0);
            return sphere(p - (c.a.xyz + ab * t), c.a.w);
        }
        default: {
            return grid_distance(c, p);
        }
    }
}

// Resolves one particle against one collider; true if they touched.
fn contact(x: ptr<function, vec3<f32>>, x_prev: vec3<f32>, reach: f32, c: Collider, pose: Pose) -> bool {
    let local = point_to(pose.end_inverse, *x);
    let s = signed_distance(c, local);
    if !(s.w < reach) {
        return false;
    }
    let depth = reach - s.w;
    if !(depth > 0.0) {
        return false;
    }
    let normal = vector_to(pose.end, s.xyz);
    let surface_motion = *x - point_to(pose.start, local);
    *x += normal * depth;
    let relative = (*x - x_prev) - surface_motion;
    let tangential = relative - normal * dot(relative, normal);
    let slide = length(tangential);
    if slide < c.static_friction * depth {
        *x -= tangential;
    } else if slide > 0.0 {
        *x -= tangential * min(c.kinetic_friction * depth / slide, 1.0);
    }
    push_out(x, reach, c, pose);
    return true;
}

// Most further pushes out of a collider a contact makes (contact.rs's PUSHES).
const PUSHES: u32 = 8u;

// Pushes again, along the surface's normal, a particle that its contact
// left within `reach` of the collider: a distance field's interpolated
// gradient only approximates the normal, and friction moves a particle
// along the tangent, inside a concave surface (contact.rs's `push_out`).
fn push_out(x: ptr<function, vec3<f32>>, reach: f32, c: Collider, pose: Pose) {
    for (var k = 0u; k < PUSHES; k++) {
        let s = signed_distance(c, point_to(pose.end_inverse, *x));
        if !(s.w < reach) {
            return;
        }
        *x += vector_to(pose.end, s.xyz) * (reach - s.w);
    }
}

@compute @workgroup_size(256)
fn resolve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count || inv_mass(i) == 0.0 {
        return;
    }
    var x = position(i);
    let x_prev = prev[i].xyz;
    for (var k = 0u; k < params.collider_count; k++) {
        contact(&x, x_prev, thickness[i], colliders[k], poses[params.substep * params.collider_count + k]);
    }
    pos[i] = vec4<f32>(x, pos[i].w);
}
