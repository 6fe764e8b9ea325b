// The workgroup counts of the self-contacts' indirect dispatches, written
// on the GPU so that no frame waits on a read back: the build's kernels
// (contact_grid.wgsl) run on theirs when a particle has moved half the
// margin since the last build and on none otherwise; the solve
// (self_contact.wgsl) on as many as the candidates need. After a frame's
// substeps `choose_margin` sets the margin of the next frame.

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
        atomicAdd(&candidates[FRAME_BUILDS], 1u);
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
    arm(true);
}

// Arms the solve of a round of the held limits' sweeps (record.rs) as
// `arm_solve`, but over no candidate where the round moved no particle:
// once the limits are met the rounds left sweep once, find no edge beyond
// its limit and leave the contacts be (as the CPU backend's rounds stop).
@compute @workgroup_size(1)
fn arm_round_solve() {
    var moved = false;
    for (var i = 0u; i < params.particle_count && !moved; i++) {
        moved = any(pos[i].xyz != prev[i].xyz);
    }
    arm(moved);
}

// The solve's workgroup counts: over the candidates kept if `solve`, else
// none.
fn arm(solve: bool) {
    let found = atomicLoad(&candidates[FOUND]);
    let kept = select(0u, min(found, params.contact_capacity), solve);
    atomicAdd(&candidates[SOLVED], kept);
    // Once a build: the counts stay until the next.
    if found > params.contact_capacity && atomicLoad(&candidates[FRESH]) == 1u {
        atomicStore(&candidates[FRESH], 2u);
        atomicMax(&candidates[OVERFLOWED], found);
    }
    let groups = (kept + WORKGROUP - 1u) / WORKGROUP;
    let slot = 3u * BUILD_KERNELS;
    args[slot] = min(groups, MAX_GROUPS);
    args[slot + 1u] = max((groups + MAX_GROUPS - 1u) / MAX_GROUPS, 1u);
    args[slot + 2u] = 1u;
}

// The margin, chosen frame by frame on the GPU, so that a run's path does
// not depend on when its counts reach the host. Candidate pairs found
// within the thickness plus a margin are kept until a particle has moved
// half the margin (contact_grid.wgsl): that pays where builds are rare,
// but a wider search costs every build more, and a fine, restless cloth
// (a 1024 x 1024 sheet swinging) moves that far every substep anyway. So
// the margin is dropped after a frame that built at nearly every
// substep, and tried again a while later: soon at first (a cloth that has
// fallen comes to rest), then twice as late after each try that is
// dropped again at once.

// Builds per substep above which the margin is dropped.
const BUSY: f32 = 0.7;
// Frames without the margin before the first try, and the most.
const FIRST_WAIT: u32 = 15u;
const LONGEST_WAIT: u32 = 480u;
// A try dropped again within this many frames has failed.
const FAILED_TRY: u32 = 10u;

// Run with the parameters of the frame's last substep; a new margin makes
// the candidates stale (a list found without the margin does not hold
// with it).
@compute @workgroup_size(1)
fn choose_margin() {
    let substeps = params.substep + 1u;
    let busy = f32(atomicExchange(&candidates[FRAME_BUILDS], 0u)) > BUSY * f32(substeps);
    var dropped = atomicLoad(&candidates[DROPPED]);
    var since_try = atomicLoad(&candidates[SINCE_TRY]);
    var wait = max(atomicLoad(&candidates[WAIT]), FIRST_WAIT);
    var changed = false;
    if dropped == 0u {
        if busy {
            let failed = since_try != 0u && since_try - 1u < FAILED_TRY;
            wait = select(FIRST_WAIT, min(2u * wait, LONGEST_WAIT), failed);
            dropped = 1u;
            changed = true;
        } else if since_try != 0u {
            since_try += 1u;
        }
    } else {
        dropped += 1u;
        if dropped - 1u >= wait {
            dropped = 0u;
            since_try = 1u;
            changed = true;
        }
    }
    atomicStore(&candidates[DROPPED], dropped);
    atomicStore(&candidates[SINCE_TRY], since_try);
    atomicStore(&candidates[WAIT], wait);
    if changed {
        atomicStore(&candidates[FRESH], 0u);
    }
}
