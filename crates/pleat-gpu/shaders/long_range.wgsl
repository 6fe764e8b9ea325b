// The coarse edges of the hierarchy (pleat::solver::hierarchy), one colour
// per dispatch: two particles of a level pulled together, by the level's
// inverse masses, until they are no farther apart than the limit; pushed
// apart only where they are closer than `floor` times their distance when
// the hierarchy began (capped at the limit), so that its pulls never
// squeeze the cloth (LongRangeLimit::project_within).

@group(1) @binding(0) var<storage, read_write> items: array<LongRangeLimit>;
@group(1) @binding(1) var<storage, read_write> start: array<vec4<f32>>;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j == NONE { return; }
    let c = items[j];
    if c.slot != NONE && compliances[c.slot / 4u][c.slot % 4u] != 0.0 {
        return;
    }
    let wa = c.wa;
    let wb = c.wb;
    let d = position(c.a) - position(c.b);
    let len = length(d);
    let excess = len - c.max_length;
    let least = min(c.floor * distance(start[c.a].xyz, start[c.b].xyz), c.max_length);
    var e = min(len - least, 0.0);
    if excess > 0.0 {
        e = excess;
    }
    if e != 0.0 && len > 0.0 && wa + wb > 0.0 {
        let n = d / len;
        let s = e / (wa + wb);
        move_by(c.a, n * (-wa * s));
        move_by(c.b, n * (wb * s));
    }
}
