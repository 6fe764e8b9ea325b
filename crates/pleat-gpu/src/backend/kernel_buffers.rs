//! The buffers the kernels bind besides the state: per kernel
//! ([`KernelBuffers`], the self-contacts' and the strain limits' among
//! them), per substep ([`PerSubstep`]), and the frame's data written on
//! the CPU before upload ([`FrameData`]).

use super::projection::ConstraintBuffers;
use crate::buffers::{storage, zeroed};
use crate::data::{Counts, GpuCollider, GpuPose, Range};
use crate::kernels::{workgroups, BUILD_KERNELS, UNIFORM_STRIDE};
use pleat::mesh::incidence::Incidence;
use pleat::model::Model;
use wgpu::util::DeviceExt;

/// Buffers whose size depends on the number of substeps per frame.
pub(super) struct PerSubstep {
    pub(super) capacity: u32,
    pub(super) params: wgpu::Buffer,
    pub(super) targets: wgpu::Buffer,
    pub(super) poses: wgpu::Buffer,
}

/// Buffers of the kernels of group 1, by kernel.
pub(super) struct KernelBuffers {
    /// Items and lambdas of each constraint kind, in projection order.
    pub(super) constraints: Vec<ConstraintBuffers>,
    /// The distances' strain limits, where an edge has one.
    pub(super) strain_limit: Option<StrainLimitBuffers>,
    pub(super) hard_pins: wgpu::Buffer,
    pub(super) pin_dispatch: (u32, u32),
    pub(super) track_dispatch: (u32, u32),
    pub(super) triangles: wgpu::Buffer,
    pub(super) triangle_force: wgpu::Buffer,
    pub(super) around_start: wgpu::Buffer,
    pub(super) around: wgpu::Buffer,
    pub(super) colliders: wgpu::Buffer,
    /// What `colliders` holds, its friction refreshed from the world.
    pub(super) collider_shapes: Vec<GpuCollider>,
    pub(super) sdf_values: wgpu::Buffer,
    pub(super) thickness: wgpu::Buffer,
    pub(super) whole: (u32, u32),
    pub(super) self_contact: Option<SelfContactBuffers>,
    /// The grabbed particle's reach (XPBD): rest positions with reach
    /// factors, each particle's cloth, the dispatch over the particles.
    pub(super) grab_reach: Option<([wgpu::Buffer; 2], (u32, u32))>,
}

/// The self-contacts' hash grid, candidates and dispatch counts, and their
/// inputs and outputs.
pub(super) struct SelfContactBuffers {
    /// Bucket counts and starts, fill counters, sorted particles, scan sums.
    pub(super) grid: wgpu::Buffer,
    /// Triangles, then the triangles each vertex owns and the edges at
    /// each vertex (compressed rows), then the edges' ends.
    pub(super) topology: wgpu::Buffer,
    /// Rest positions with the cloth's index in w, then the positions at
    /// the last build with how far each vertex's owned triangles reached
    /// from it then in w, then the vertices' edge summaries at that build
    /// (each one's normal where it is flat, and its longest edge).
    pub(super) rest: wgpu::Buffer,
    /// Fixed-point corrections and contact counts per particle.
    pub(super) accum: wgpu::Buffer,
    /// Header (pairs found, fresh, counters, the margin's state), then the pairs.
    pub(super) candidates: wgpu::Buffer,
    /// The indirect dispatches' workgroup counts: the build's, the solve's,
    /// then the build's when it runs.
    pub(super) args: wgpu::Buffer,
    /// Hash grid cell size with the margin (less the margin without it).
    pub(super) cell: f32,
    /// Hash table size: a power of two, a multiple of the scan block.
    pub(super) buckets: u32,
    pub(super) margin: f32,
    /// The rest distance below which a cloth's pairs never collide: the CPU
    /// backend's, by thickness ([`exclusion`]).
    pub(super) exclusion: f32,
    /// Most candidate pairs kept.
    pub(super) capacity: u32,
    /// Jacobi iterations a substep, the CPU backend's
    /// ([`pleat::collide::self_contact::iterations`]).
    pub(super) iterations: u32,
    /// Whether builds take edge pairs: some edges are listed under their
    /// ends (paper's, [`incident_edges`]).
    pub(super) edge_pairs: bool,
    /// Whether each contact's corrections are scaled as one, keeping the
    /// momentum (paper), or averaged per particle (cloth):
    /// lib/contact_solve.wgsl.
    pub(super) scaled: bool,
    /// Whether it has been said that they cannot grow.
    pub(super) told_full: bool,
}

/// What the strain limits' sweeps need besides the distances' items.
pub(super) struct StrainLimitBuffers {
    /// The sweeps after the iterations before the further ones: the CPU's
    /// [`pleat::solver::xpbd::STRAIN_LIMIT_SWEEPS`].
    pub(super) sweeps: u32,
    /// Each colour's slice of the distances, for the further sweeps.
    pub(super) colours: wgpu::Buffer,
    /// Whether the last sweep found an edge far beyond its limit.
    pub(super) beyond: wgpu::Buffer,
}

impl StrainLimitBuffers {
    pub(super) fn new(device: &wgpu::Device, sweeps: u32, colours: &[Range]) -> Option<Self> {
        (sweeps > 0).then(|| StrainLimitBuffers {
            sweeps,
            colours: storage(device, "distance colours", colours),
            beyond: zeroed(device, "beyond the slack", 4),
        })
    }
}

/// Most a rest edge may stretch and still find its triangles' contacts.
const CONTACT_EDGE_STRETCH: f32 = 1.5;
/// How much farther than the thickness a candidate pair may lie, in
/// thicknesses: below 0.875 times `FACING` in contact_grid.wgsl (2) less
/// one, so that flat cloth, and cloth compressed by up to an eighth, gives
/// no candidates.
const CONTACT_MARGIN: f32 = 0.75;
/// Candidate pairs per particle kept at most.
const CANDIDATES_PER_PARTICLE: u64 = 16;
/// Words of the candidates' header (`HEADER` in lib/contact.wgsl).
const CANDIDATE_HEADER: u64 = 16;
/// The first word of the margin's state in that header (`FRAME_BUILDS`),
/// and its words.
const MARGIN_STATE: (u64, u64) = (12, 4);

impl SelfContactBuffers {
    pub(super) fn new(
        device: &wgpu::Device,
        model: &Model,
        thickness: f32,
        triangles: &[u32],
    ) -> Self {
        let n = model.particle_count() as u32;
        let longest = model
            .edges
            .iter()
            .map(|e| e.rest_length)
            .fold(0.0, f32::max);
        let exclusion = exclusion(model) * thickness;
        let margin = CONTACT_MARGIN * thickness;
        let buckets = (2 * n).next_power_of_two().max(crate::kernels::WORKGROUP);
        let grid_len = 2 * buckets as u64 + n as u64 + (buckets / crate::kernels::WORKGROUP) as u64;
        let topology = contact_topology(model, triangles);
        // The rows' last start: how many edges are listed under their ends.
        let edge_pairs = incident_edges(model)[model.particle_count()] > 0;
        // Rest positions, then the positions at the build and, where there
        // are edge pairs, the vertices' edge summaries (written on the GPU;
        // a cloth-only model saves their N x 16 bytes).
        let blocks = if edge_pairs { 3 } else { 2 };
        let mut rest = vec![[0.0; 4]; blocks * n as usize];
        for (k, cloth) in model.cloths.iter().enumerate() {
            for i in cloth.particles() {
                rest[i] = model.rest[i].extend(k as f32).to_array();
            }
        }
        let capacity = (CANDIDATES_PER_PARTICLE * u64::from(n))
            .min(largest_capacity(device))
            .max(1);
        let narrow_cell = CONTACT_EDGE_STRETCH * longest + thickness;
        SelfContactBuffers {
            grid: zeroed(device, "contact grid", grid_len * 4),
            topology: storage(device, "topology", &topology),
            rest: storage(device, "rest positions", &rest),
            accum: zeroed(device, "contact corrections", n as u64 * 16),
            args: indirect_args(device, build_workgroups(n, buckets)),
            candidates: candidates(device, capacity),
            cell: narrow_cell + margin,
            buckets,
            margin,
            exclusion,
            capacity: capacity as u32,
            iterations: pleat::collide::self_contact::iterations(model) as u32,
            edge_pairs,
            scaled: pleat::collide::self_contact::all_paper(model),
            told_full: false,
        }
    }

    /// After a build found `found` pairs, more than the candidates hold
    /// (those beyond were not solved), a buffer for [`GROWTH`] times as
    /// many (twice the last at least), up to the largest a binding takes,
    /// zeroed so that the next substep builds afresh but for the margin's
    /// state, carried over. False when it is that large already.
    pub(super) fn grow(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        found: u64,
    ) -> bool {
        let wanted = (found as f64 * GROWTH) as u64;
        let capacity = wanted
            .max(2 * u64::from(self.capacity))
            .min(largest_capacity(device));
        if capacity <= u64::from(self.capacity) {
            return false;
        }
        let grown = candidates(device, capacity);
        let mut encoder = device.create_command_encoder(&Default::default());
        let (first, words) = MARGIN_STATE;
        encoder.copy_buffer_to_buffer(&self.candidates, 4 * first, &grown, 4 * first, 4 * words);
        queue.submit([encoder.finish()]);
        self.candidates = grown;
        self.capacity = capacity as u32;
        true
    }
}

/// The rest distance, in thicknesses, below which `model`'s pairs never
/// collide, as on the CPU backend: paper's where any cloth is paper (the
/// kernels take one radius for all).
fn exclusion(model: &Model) -> f32 {
    use pleat::collide::self_contact::{CLOTH_EXCLUSION, PAPER_EXCLUSION};
    if model.cloths.iter().any(|c| c.paper.is_some()) {
        PAPER_EXCLUSION
    } else {
        CLOTH_EXCLUSION
    }
}

/// Room for how many times the pairs a build found, when they overflowed
/// the candidates: a cloth that settles into more layers finds more.
const GROWTH: f64 = 1.5;

/// The most candidate pairs one binding of `device` holds.
fn largest_capacity(device: &wgpu::Device) -> u64 {
    let words = device.limits().max_storage_buffer_binding_size / 4;
    ((words - CANDIDATE_HEADER) / 2).min(u64::from(u32::MAX))
}

/// A candidates buffer of `capacity` pairs, zeroed: not fresh, so the
/// first substep builds.
fn candidates(device: &wgpu::Device, capacity: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("contact candidates"),
        size: (CANDIDATE_HEADER + 2 * capacity) * 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// The workgroups of the build's kernels over `n` particles and `buckets`
/// buckets: clear, count, scan_blocks, scan_sums, scan_add, scatter, find.
fn build_workgroups(n: u32, buckets: u32) -> [(u32, u32); BUILD_KERNELS] {
    [
        workgroups(2 * buckets),
        workgroups(n),
        workgroups(buckets / crate::kernels::WORKGROUP),
        (1, 1),
        workgroups(buckets),
        workgroups(n),
        workgroups(n),
    ]
}

/// The indirect dispatches' buffer: the build's and the solve's counts
/// (written on the GPU), then the build's when it runs.
fn indirect_args(device: &wgpu::Device, build: [(u32, u32); BUILD_KERNELS]) -> wgpu::Buffer {
    let mut words = vec![0u32; 3 * (BUILD_KERNELS + 1)];
    words.extend(build.iter().flat_map(|&(x, y)| [x, y, 1]));
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("contact dispatches"),
        contents: bytemuck::cast_slice(&words),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
    })
}

/// Each triangle under its vertex of lowest index, in compressed rows
/// (starts, then triangles): a particle's contact search takes the
/// triangles its neighbours own, so it meets each triangle once.
fn owned_triangles(model: &Model) -> (Vec<u32>, Vec<u32>) {
    fn lowest(t: &[u32; 3]) -> &[u32] {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        &t[k..k + 1]
    }
    let incidence = Incidence::new(&model.triangles, model.particle_count(), lowest);
    let (start, slots) = incidence.rows();
    (start.to_vec(), slots.iter().map(|s| s.element).collect())
}

/// Each edge of paper under both its ends, in compressed rows (starts,
/// then edges), then each edge's two ends and the vertices opposite it in
/// its triangles (`u32::MAX` where it has one): the edge-edge search takes
/// the edges at either end of a pair of neighbouring particles, and culls
/// flat edges in parallel layers.
///
/// Only paper takes edge pairs: its facets are large against its
/// thickness, so two layers' edges cross where no corner comes near the
/// other layer (a flap's edge across another's), and it folds slowly,
/// rebuilding its candidates about one substep in seven. Cloth finer than
/// a few thicknesses is held by its vertex-triangle contacts (the shipped
/// scenes end with no crossing at any 10th frame on the GPU), and its
/// builds at nearly every substep paid twice the frame's time for edge
/// pairs (fold_onto_itself, lavapipe).
/// The self-contacts' topology (lib/contact.wgsl): the flat `triangles`,
/// the triangles each vertex owns and the edges at each vertex, in
/// compressed rows, then the edges' ends and wings.
pub(super) fn contact_topology(model: &Model, triangles: &[u32]) -> Vec<u32> {
    let (start, owned) = owned_triangles(model);
    [triangles, &start, &owned, &incident_edges(model)].concat()
}

/// Most particles of a sheet whose self-contacts the persistent kernel
/// solves (`accum` in its workgroup memory, four words a particle).
pub(super) const MAX_CONTACT_PARTICLES: usize = 512;
/// Most contact pairs the persistent kernel lists (16 MiB of them): it
/// walks them all at each build of the pairs it keeps.
const MAX_CONTACT_PAIRS: usize = 1 << 21;

/// Every particle, vertex-triangle and edge-edge pair of paper `model` that the rest
/// mesh does not keep apart (sharing a particle, or of one cloth and closer
/// at rest than `exclusion`), two words each as
/// self_contact.wgsl's candidates; `None` where they are more than
/// [`MAX_CONTACT_PAIRS`] or the model is not all paper, or too large.
pub(super) fn contact_pairs(model: &Model, exclusion: f32) -> Option<Vec<u32>> {
    use pleat::collide::ccd::{point_triangle_distance, segment_distance};
    let n = model.particle_count();
    if n > MAX_CONTACT_PARTICLES || model.cloths.iter().any(|c| c.paper.is_none()) {
        return None;
    }
    let mut cloth = vec![0; n];
    for (k, c) in model.cloths.iter().enumerate() {
        cloth[c.particles()].fill(k);
    }
    let rest = &model.rest;
    let mut pairs = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            if cloth[i] != cloth[j] || rest[i].distance(rest[j]) >= exclusion {
                pairs.extend([i as u32, j as u32 | PARTICLE_PAIR]);
            }
        }
        for (t, v) in model.triangles.iter().enumerate() {
            let kept_apart = v.contains(&(i as u32))
                || (cloth[i] == cloth[v[0] as usize]
                    && point_triangle_distance(
                        rest[i],
                        rest[v[0] as usize],
                        rest[v[1] as usize],
                        rest[v[2] as usize],
                    ) < exclusion);
            if !kept_apart {
                pairs.extend([i as u32, t as u32]);
            }
        }
        if pairs.len() > 2 * MAX_CONTACT_PAIRS {
            return None;
        }
    }
    let edges = &model.edges;
    for (a, ea) in edges.iter().enumerate() {
        for (b, eb) in edges.iter().enumerate().skip(a + 1) {
            let [p0, p1] = ea.v.map(|k| k as usize);
            let [q0, q1] = eb.v.map(|k| k as usize);
            let kept_apart = ea.v.iter().any(|k| eb.v.contains(k))
                || (cloth[p0] == cloth[q0]
                    && segment_distance(rest[p0], rest[p1], rest[q0], rest[q1]) < exclusion);
            if !kept_apart {
                pairs.extend([a as u32 | EDGE_PAIR, b as u32]);
            }
        }
        if pairs.len() > 2 * MAX_CONTACT_PAIRS {
            return None;
        }
    }
    Some(pairs)
}

/// Marks a pair's first word as an edge (`EDGE_PAIR` in lib/contact.wgsl).
const EDGE_PAIR: u32 = 0x8000_0000;
/// Marks a pair's second word as a particle (`PARTICLE_PAIR`).
const PARTICLE_PAIR: u32 = 0x8000_0000;

fn incident_edges(model: &Model) -> Vec<u32> {
    let mut paper = vec![false; model.particle_count()];
    for cloth in model.cloths.iter().filter(|c| c.paper.is_some()) {
        paper[cloth.particles()].fill(true);
    }
    let incidence = Incidence::new(&model.edges, model.particle_count(), |e| {
        if paper[e.v[0] as usize] {
            &e.v
        } else {
            &[]
        }
    });
    let (start, slots) = incidence.rows();
    let edges = slots.iter().map(|s| s.element);
    // The cloths' edges, in the model's order; none without paper (a
    // large cloth's would fill a buffer that nothing reads).
    let wings: Vec<[u32; 4]> = if paper.contains(&true) {
        (model.cloths.iter())
            .flat_map(|c| {
                c.topology.edges.iter().map(move |e| {
                    let local = [Some(e.v[0]), Some(e.v[1]), e.opposite[0], e.opposite[1]];
                    local.map(|k| k.map_or(u32::MAX, |k| k + c.offset))
                })
            })
            .collect()
    } else {
        Vec::new()
    };
    debug_assert!(wings.iter().zip(&model.edges).all(|(w, e)| w[..2] == e.v));
    let wings = wings.into_iter().flatten();
    start.iter().copied().chain(edges).chain(wings).collect()
}

impl PerSubstep {
    pub(super) fn new(device: &wgpu::Device, counts: &Counts, capacity: u32) -> Self {
        let buffer = |label, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let c = capacity as u64;
        PerSubstep {
            capacity,
            params: buffer("params", c * UNIFORM_STRIDE, wgpu::BufferUsages::UNIFORM),
            targets: buffer(
                "pin targets",
                c * counts.pins as u64 * 16,
                wgpu::BufferUsages::STORAGE,
            ),
            poses: buffer(
                "collider poses",
                c * counts.colliders as u64 * size_of::<GpuPose>() as u64,
                wgpu::BufferUsages::STORAGE,
            ),
        }
    }
}

/// The per-substep parameters, pin targets and collider poses of a frame,
/// written on the CPU before upload.
#[derive(Default)]
pub(super) struct FrameData {
    /// One [`crate::data::Params`] every [`UNIFORM_STRIDE`] bytes.
    pub(super) params: Vec<u8>,
    pub(super) targets: Vec<[f32; 4]>,
    pub(super) poses: Vec<GpuPose>,
    /// The live compliance table, [`crate::kernels::COMPLIANCE_SLOTS`] long.
    pub(super) compliances: Vec<f32>,
}
