// The workgroup counts of the self-contacts' indirect dispatches, written
// on the GPU so that no frame waits on a read back: the build's kernels
// (contact_grid.wgsl) run on theirs when a particle has moved half the
// margin since the last build and on none otherwise; the solve
// (self_contact.wgsl) on as many as the candidates need.

// args: [0, 3 BUILD_KERNELS) the build's counts, then the solve's three,
// then the build's counts when it runs (written once by the host).
@group(1) @binding(0) var<storage, read_write> args: array<u32>;
// The triangles lib/contact.wgsl names (unread here).
@group(1) @binding(1) var<storage, read_write> topology: array<u32>;
@group(1) @binding(3) var<storage, read_write> candidates: array<atomic<u32>>;

const BUILD_KERNELS: u32 = 7u;
const MAX_GROUPS: u32 = 65535u;

// Arms the build if the candidates are stale, and starts it afresh.
@compute @workgroup_size(1)
fn arm_build() {
    let stale = atomicLoad(&candidates[FRESH]) == 0u;
    let solve = 3u * BUILD_KERNELS;
    for (var k = 0u; k < 3u * BUILD_KERNELS; k += 3u) {
        args[k] = select(0u, args[solve + 3u + k], stale);
        args[k + 1u] = args[solve + 3u + k + 1u];
        args[k + 2u] = 1u;
    }
    if stale {
        atomicStore(&candidates[FOUND], 0u);
        atomicStore(&candidates[FRESH], 1u);
        atomicAdd(&candidates[BUILDS], 1u);
    }
    // The next substep's range of displacements, empty.
    for (var axis = 0u; axis < 3u; axis++) {
        atomicStore(&candidates[LEAST + axis], 0xffffffffu);
        atomicStore(&candidates[GREATEST + axis], 0u);
    }
}

// Arms the solve over the candidates kept.
@compute @workgroup_size(1)
fn arm_solve() {
    let found = atomicLoad(&candidates[FOUND]);
    let kept = min(found, params.contact_capacity);
    atomicAdd(&candidates[SOLVED], kept);
    // Once a build: the counts stay until the next.
    if found > params.contact_capacity && atomicLoad(&candidates[FRESH]) == 1u {
        atomicStore(&candidates[FRESH], 2u);
        atomicMax(&candidates[OVERFLOWED], found);
    }
    let groups = (kept + WORKGROUP - 1u) / WORKGROUP;
    let solve = 3u * BUILD_KERNELS;
    args[solve] = min(groups, MAX_GROUPS);
    args[solve + 1u] = max((groups + MAX_GROUPS - 1u) / MAX_GROUPS, 1u);
    args[solve + 2u] = 1u;
}
