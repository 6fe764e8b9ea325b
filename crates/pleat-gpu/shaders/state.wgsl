// The bindings of a kernel dispatched once per colour or stage: the
// particle state (group 0), the substep's parameters and the live
// compliance table, and the slice of its array a dispatch works on.
// Positions carry the inverse mass in w (zero for pinned particles).

@group(0) @binding(0) var<storage, read_write> pos: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> prev: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> vel: array<vec4<f32>>;
@group(0) @binding(3) var<uniform> params: Params;
// The live compliance table (crate::constraint::compliances), four slots a
// vector; slot 0 is 1.
@group(0) @binding(4) var<uniform> compliances: array<vec4<f32>, 256>;
// The slice of its array a dispatch works on (the kernel layout's dynamic
// uniform; kernels that need none leave it unread).
@group(1) @binding(4) var<uniform> range: Range;

// The index in the whole array of this invocation's item of the dispatch's
// range, or NONE past the range's end.
fn range_item(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    let k = flat_index(gid, groups);
    return select(NONE, range.first + k, k < range.count);
}

// Orders the positions' writes before a workgroup's invocations read
// them (between colours of a kernel that sweeps them all in one
// workgroup).
fn colour_barrier() {
    storageBarrier();
}
