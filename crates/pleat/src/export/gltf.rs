//! Animated binary glTF 2.0 (`.glb`) writer for a simulated cloth: one mesh
//! whose vertices move, as Blender imports it (shape keys driven by an action).
//!
//! # Encoding
//!
//! The topology never changes, so the animation is stored as morph targets:
//! - the base mesh is frame 0 (positions, area-weighted normals, indices);
//! - each later frame k (1..F) is morph target k-1 holding the position
//!   deltas `frame_k - frame_0`;
//! - one animation channel drives the node's `weights` with one key per
//!   frame at time `k * frame_dt` and LINEAR interpolation. Key 0 has every
//!   weight 0 (the base mesh); key k >= 1 has weight 1 for target k-1 and 0
//!   elsewhere, so between two keys the vertices move on straight lines from
//!   frame k to frame k+1.
//!
//! With a single frame the file holds a static mesh with no targets and no
//! animation. Every POSITION accessor (base and targets) carries `min`/`max`
//! as the specification requires; buffer views and chunks are 4-byte aligned.
//! Morph targets hold no normals: importers recompute them (Blender does).
//!
//! # Memory and size
//!
//! [`GlbAnimation`] keeps every pushed frame in memory until
//! [`GlbAnimation::write`], and the file stores them all, so both grow as
//! `frames x vertices x 12 bytes` (300 frames of a 128 x 128 cloth: about
//! 59 MB), plus the key weights, `frames x (frames - 1) x 4 bytes` (0.36 MB
//! for 300 frames, 36 MB for 3000). Export every K-th simulated frame (with
//! `frame_dt` scaled by K) to trade time resolution for size; for very long
//! runs an OBJ or PLY sequence keeps memory flat.
//!
//! Positions must be finite: glTF JSON cannot hold NaN in `min`/`max`, so
//! [`GlbAnimation::write`] refuses a NaN or infinite coordinate.

use super::{check_triangles, invalid_input, vertex_normals};
use glam::Vec3;
use serde_json::{json, Value};
use std::io::{self, Write};

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const GLB_VERSION: u32 = 2;
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// An animated mesh being recorded frame by frame, written as one `.glb`.
#[derive(Clone, Debug)]
pub struct GlbAnimation {
    triangles: Vec<[u32; 3]>,
    rest: Vec<Vec3>,
    /// Frames 1.. (frame 0 is `rest`), concatenated: `rest.len()` each.
    later_frames: Vec<Vec3>,
    frame_dt: f32,
}

impl GlbAnimation {
    /// Starts an animation whose frame 0 (and base mesh) is `rest_positions`;
    /// later frames are `frame_dt` seconds apart.
    ///
    /// The mesh is checked by [`GlbAnimation::write`], which reports bad
    /// indices, an empty mesh or a non-positive `frame_dt` as errors.
    pub fn new(triangles: &[[u32; 3]], rest_positions: &[Vec3], frame_dt: f32) -> Self {
        Self {
            triangles: triangles.to_vec(),
            rest: rest_positions.to_vec(),
            later_frames: Vec::new(),
            frame_dt,
        }
    }

    /// Appends the next frame. Returns an `InvalidInput` error (and records
    /// nothing) if `positions` does not have one entry per vertex.
    pub fn push_frame(&mut self, positions: &[Vec3]) -> io::Result<()> {
        if positions.len() != self.rest.len() {
            return Err(invalid_input(format!(
                "frame {} has {} positions, but the mesh has {} vertices",
                self.frame_count(),
                positions.len(),
                self.rest.len()
            )));
        }
        self.later_frames.extend_from_slice(positions);
        Ok(())
    }

    /// Number of frames recorded, frame 0 included.
    pub fn frame_count(&self) -> usize {
        1 + self.later_frames.len() / self.rest.len().max(1)
    }

    /// Writes the `.glb` file to `w`. Returns an `InvalidInput` error, having
    /// written nothing, if the mesh is empty, an index is out of range, a
    /// position is not finite, `frame_dt` is not positive, or the file would
    /// pass the 4 GiB limit of the GLB format.
    pub fn write(&self, w: &mut impl Write) -> io::Result<()> {
        self.check()?;
        let blocks = self.blocks();
        let mut bin = BinLayout::default();
        for block in &blocks {
            let (byte_length, target, accessor) = self.describe(block)?;
            bin.push(byte_length, target, accessor);
        }
        let json = self.document(&bin);
        let mut json_bytes = serde_json::to_vec(&json).map_err(io::Error::other)?;
        pad(&mut json_bytes, b' ');
        let bin_padded = bin.byte_length.next_multiple_of(4);
        let total = 12 + 8 + json_bytes.len() + 8 + bin_padded;
        let total = u32::try_from(total)
            .map_err(|_| invalid_input("the animation passes the 4 GiB limit of a .glb file"))?;

        let mut out = io::BufWriter::new(w);
        write_u32s(&mut out, &[GLB_MAGIC, GLB_VERSION, total])?;
        write_u32s(&mut out, &[json_bytes.len() as u32, CHUNK_JSON])?;
        out.write_all(&json_bytes)?;
        write_u32s(&mut out, &[bin_padded as u32, CHUNK_BIN])?;
        let mut scratch = Vec::new();
        for block in &blocks {
            scratch.clear();
            self.encode(block, &mut scratch);
            out.write_all(&scratch)?;
        }
        out.write_all(&[0; 3][..bin_padded - bin.byte_length])?;
        out.flush()
    }

    fn check(&self) -> io::Result<()> {
        if self.rest.is_empty() || self.triangles.is_empty() {
            return Err(invalid_input("cannot write an empty mesh to glTF"));
        }
        check_triangles(self.rest.len(), &self.triangles)?;
        let all = self.rest.iter().chain(&self.later_frames);
        if let Some(i) = all.clone().position(|p| !p.is_finite()) {
            let (frame, vertex) = (i / self.rest.len(), i % self.rest.len());
            return Err(invalid_input(format!(
                "frame {frame} vertex {vertex} is not finite; glTF cannot store it"
            )));
        }
        if self.frame_count() > 1 {
            let times = self.times();
            if !(self.frame_dt.is_finite() && times.windows(2).all(|t| t[0] < t[1])) {
                return Err(invalid_input(format!(
                    "frame_dt {} does not give increasing key times",
                    self.frame_dt
                )));
            }
        }
        Ok(())
    }

    fn targets(&self) -> usize {
        self.frame_count() - 1
    }

    fn frame(&self, k: usize) -> &[Vec3] {
        let n = self.rest.len();
        &self.later_frames[(k - 1) * n..k * n]
    }

    fn delta(&self, k: usize) -> impl Iterator<Item = Vec3> + '_ {
        self.frame(k).iter().zip(&self.rest).map(|(p, r)| *p - *r)
    }

    fn times(&self) -> Vec<f32> {
        (0..self.frame_count())
            .map(|k| k as f32 * self.frame_dt)
            .collect()
    }

    /// The binary blocks in file order, one buffer view and accessor each.
    fn blocks(&self) -> Vec<Block> {
        let mut blocks = vec![Block::Indices, Block::RestPositions, Block::RestNormals];
        if self.targets() > 0 {
            blocks.extend((1..self.frame_count()).map(Block::Delta));
            blocks.extend([Block::Times, Block::Weights]);
        }
        blocks
    }

    /// Byte length, buffer-view target and accessor JSON of a block.
    fn describe(&self, block: &Block) -> io::Result<(usize, Option<u32>, Value)> {
        let n = self.rest.len();
        Ok(match *block {
            Block::Indices => {
                let count = 3 * self.triangles.len();
                let accessor =
                    json!({"componentType": UNSIGNED_INT, "count": count, "type": "SCALAR"});
                (4 * count, Some(ELEMENT_ARRAY_BUFFER), accessor)
            }
            Block::RestPositions => {
                let accessor = vec3_accessor(n, Some(bounds(self.rest.iter().copied())?));
                (12 * n, Some(ARRAY_BUFFER), accessor)
            }
            Block::RestNormals => (12 * n, Some(ARRAY_BUFFER), vec3_accessor(n, None)),
            Block::Delta(k) => {
                let accessor = vec3_accessor(n, Some(bounds(self.delta(k))?));
                (12 * n, Some(ARRAY_BUFFER), accessor)
            }
            Block::Times => {
                let times = self.times();
                let last = times.last().copied().unwrap_or(0.0);
                let accessor = json!({"componentType": FLOAT, "count": times.len(),
                    "type": "SCALAR", "min": [0.0], "max": [last]});
                (4 * times.len(), None, accessor)
            }
            Block::Weights => {
                let count = self.frame_count() * self.targets();
                let accessor = json!({"componentType": FLOAT, "count": count, "type": "SCALAR"});
                (4 * count, None, accessor)
            }
        })
    }

    /// Appends the little-endian bytes of a block to `out`.
    fn encode(&self, block: &Block, out: &mut Vec<u8>) {
        match *block {
            Block::Indices => put_u32s(out, self.triangles.iter().flatten().copied()),
            Block::RestPositions => put_vec3s(out, self.rest.iter().copied()),
            Block::RestNormals => put_vec3s(out, vertex_normals(&self.rest, &self.triangles)),
            Block::Delta(k) => put_vec3s(out, self.delta(k)),
            Block::Times => put_f32s(out, self.times()),
            Block::Weights => {
                let targets = self.targets();
                let weight = |key: usize, target: usize| f32::from(u8::from(key == target + 1));
                let weights = (0..self.frame_count())
                    .flat_map(|key| (0..targets).map(move |target| weight(key, target)));
                put_f32s(out, weights);
            }
        }
    }

    /// The glTF JSON document for the laid-out binary buffer.
    fn document(&self, bin: &BinLayout) -> Value {
        let mut primitive = json!({
            "attributes": {"POSITION": 1, "NORMAL": 2},
            "indices": 0,
            "mode": 4,
        });
        let mut mesh = json!({"name": "cloth"});
        let mut doc = json!({
            "asset": {"version": "2.0", "generator": "pleat"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "name": "cloth"}],
            "accessors": bin.accessors,
            "bufferViews": bin.views,
            "buffers": [{"byteLength": bin.byte_length}],
        });
        let targets = self.targets();
        if targets > 0 {
            // Accessors 0..3 are indices, base positions and normals; then targets.
            let first_target = 3;
            primitive["targets"] = (0..targets)
                .map(|t| json!({"POSITION": first_target + t}))
                .collect();
            mesh["weights"] = json!(vec![0.0; targets]);
            let names: Vec<String> = (1..=targets).map(|k| format!("frame_{k:05}")).collect();
            // Blender names the shape keys from `extras.targetNames`.
            mesh["extras"] = json!({"targetNames": names});
            let (times, weights) = (first_target + targets, first_target + targets + 1);
            doc["animations"] = json!([{
                "name": "simulation",
                "samplers": [{"input": times, "output": weights, "interpolation": "LINEAR"}],
                "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
            }]);
        }
        mesh["primitives"] = json!([primitive]);
        doc["meshes"] = json!([mesh]);
        doc
    }
}

/// One buffer view of the binary chunk.
enum Block {
    Indices,
    RestPositions,
    RestNormals,
    /// Position deltas of frame k (k >= 1), morph target k-1.
    Delta(usize),
    Times,
    Weights,
}

/// Buffer views and accessors, laid out back to back in one buffer.
#[derive(Default)]
struct BinLayout {
    views: Vec<Value>,
    accessors: Vec<Value>,
    byte_length: usize,
}

impl BinLayout {
    /// Adds a buffer view of `byte_length` bytes and its accessor.
    fn push(&mut self, byte_length: usize, target: Option<u32>, mut accessor: Value) {
        let mut view =
            json!({"buffer": 0, "byteOffset": self.byte_length, "byteLength": byte_length});
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        accessor["bufferView"] = json!(self.views.len());
        self.views.push(view);
        self.accessors.push(accessor);
        // Every element is 4-byte, so offsets stay 4-byte aligned.
        self.byte_length += byte_length;
    }
}

fn vec3_accessor(count: usize, bounds: Option<(Vec3, Vec3)>) -> Value {
    let mut accessor = json!({"componentType": FLOAT, "count": count, "type": "VEC3"});
    if let Some((min, max)) = bounds {
        accessor["min"] = json!(min.to_array());
        accessor["max"] = json!(max.to_array());
    }
    accessor
}

/// Component-wise min and max; an error if a value is not finite.
fn bounds(values: impl Iterator<Item = Vec3>) -> io::Result<(Vec3, Vec3)> {
    let (min, max) = values.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if min.is_finite() && max.is_finite() {
        Ok((min, max))
    } else {
        Err(invalid_input(
            "a position or frame-to-frame delta is not finite",
        ))
    }
}

fn pad(bytes: &mut Vec<u8>, with: u8) {
    bytes.resize(bytes.len().next_multiple_of(4), with);
}

fn write_u32s(out: &mut impl Write, values: &[u32]) -> io::Result<()> {
    values
        .iter()
        .try_for_each(|v| out.write_all(&v.to_le_bytes()))
}

fn put_u32s(out: &mut Vec<u8>, values: impl IntoIterator<Item = u32>) {
    out.extend(values.into_iter().flat_map(u32::to_le_bytes));
}

fn put_f32s(out: &mut Vec<u8>, values: impl IntoIterator<Item = f32>) {
    out.extend(values.into_iter().flat_map(f32::to_le_bytes));
}

fn put_vec3s(out: &mut Vec<u8>, values: impl IntoIterator<Item = Vec3>) {
    put_f32s(out, values.into_iter().flat_map(|v| v.to_array()));
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: usize = 5; // vertices per side of the test grid
    const DT: f32 = 1.0 / 30.0;

    fn grid_triangles() -> Vec<[u32; 3]> {
        let mut triangles = Vec::new();
        for j in 0..N as u32 - 1 {
            for i in 0..N as u32 - 1 {
                let a = j * N as u32 + i;
                let (b, c, d) = (a + 1, a + N as u32, a + N as u32 + 1);
                triangles.extend([[a, b, d], [a, d, c]]);
            }
        }
        triangles
    }

    /// The grid at frame k: a travelling wave, so every frame differs.
    fn grid_frame(k: usize) -> Vec<Vec3> {
        let t = k as f32 * 0.37;
        (0..N * N)
            .map(|v| {
                let (x, y) = ((v % N) as f32 / 4.0, (v / N) as f32 / 4.0);
                Vec3::new(x, y, 0.2 * (3.0 * x + t).sin() * y + 0.01 * k as f32)
            })
            .collect()
    }

    fn animation(frames: usize) -> GlbAnimation {
        let mut anim = GlbAnimation::new(&grid_triangles(), &grid_frame(0), DT);
        for k in 1..frames {
            anim.push_frame(&grid_frame(k)).unwrap();
        }
        anim
    }

    fn write(anim: &GlbAnimation) -> Vec<u8> {
        let mut bytes = Vec::new();
        anim.write(&mut bytes).unwrap();
        bytes
    }

    #[test]
    fn animated_grid_reads_back_exactly() {
        const FRAMES: usize = 6;
        let bytes = write(&animation(FRAMES));
        let gltf = ::gltf::Gltf::from_slice(&bytes).expect("valid glb");
        let blob = gltf.blob.as_deref().expect("binary chunk");
        let buffers = |b: ::gltf::Buffer| (b.index() == 0).then_some(blob);

        assert_eq!(gltf.as_json().asset.generator.as_deref(), Some("pleat"));
        let mesh = gltf.meshes().next().unwrap();
        let primitive = mesh.primitives().next().unwrap();
        let reader = primitive.reader(buffers);
        let base: Vec<Vec3> = reader.read_positions().unwrap().map(Vec3::from).collect();
        assert_eq!(base.len(), N * N);
        assert_eq!(base, grid_frame(0));
        let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        assert_eq!(indices.len(), 3 * grid_triangles().len());
        assert_eq!(reader.read_normals().unwrap().count(), N * N);

        let targets: Vec<Vec<Vec3>> = reader
            .read_morph_targets()
            .map(|(positions, _, _)| positions.unwrap().map(Vec3::from).collect())
            .collect();
        assert_eq!(targets.len(), FRAMES - 1);
        for (t, delta) in targets.iter().enumerate() {
            let expected = grid_frame(t + 1);
            for ((b, d), e) in base.iter().zip(delta).zip(&expected) {
                assert!(
                    (*b + *d - *e).abs().max_element() <= 1e-6,
                    "frame {}",
                    t + 1
                );
            }
        }

        let animation = gltf.animations().next().expect("an animation");
        let channel = animation.channels().next().unwrap();
        assert_eq!(
            channel.target().property(),
            ::gltf::animation::Property::MorphTargetWeights
        );
        assert_eq!(channel.target().node().index(), 0);
        let reader = channel.reader(buffers);
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        assert_eq!(times.len(), FRAMES);
        for (k, t) in times.iter().enumerate() {
            assert_eq!(*t, k as f32 * DT);
        }
        let weights: Vec<f32> = match reader.read_outputs().unwrap() {
            ::gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
            _ => panic!("weights expected"),
        };
        assert_eq!(weights.len(), FRAMES * (FRAMES - 1));
        for (k, key) in weights.chunks(FRAMES - 1).enumerate() {
            let ones: Vec<usize> = (0..key.len()).filter(|&t| key[t] == 1.0).collect();
            let expected_ones = if k == 0 { vec![] } else { vec![k - 1] };
            assert_eq!(ones, expected_ones, "key {k}");
            assert!(key.iter().all(|&w| w == 0.0 || w == 1.0));
        }
    }

    #[test]
    fn every_position_accessor_has_bounds_and_views_are_aligned() {
        let bytes = write(&animation(4));
        assert_eq!(bytes.len() % 4, 0);
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        assert_eq!(json_len % 4, 0);
        let doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let primitive = &doc["meshes"][0]["primitives"][0];
        let mut position_accessors = vec![&primitive["attributes"]["POSITION"]];
        position_accessors.extend(
            primitive["targets"]
                .as_array()
                .unwrap()
                .iter()
                .map(|t| &t["POSITION"]),
        );
        assert_eq!(position_accessors.len(), 4);
        for index in position_accessors {
            let accessor = &doc["accessors"][index.as_u64().unwrap() as usize];
            assert_eq!(accessor["min"].as_array().unwrap().len(), 3);
            assert_eq!(accessor["max"].as_array().unwrap().len(), 3);
        }
        for view in doc["bufferViews"].as_array().unwrap() {
            assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
        }
        assert_eq!(doc["meshes"][0]["weights"].as_array().unwrap().len(), 3);
    }

    #[test]
    fn a_single_frame_is_a_static_mesh() {
        let bytes = write(&animation(1));
        let gltf = ::gltf::Gltf::from_slice(&bytes).expect("valid glb");
        assert_eq!(gltf.animations().count(), 0);
        let primitive = gltf.meshes().next().unwrap().primitives().next().unwrap();
        assert_eq!(primitive.morph_targets().count(), 0);
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let mut anim = animation(2);
        let err = anim.push_frame(&grid_frame(0)[1..]).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(anim.frame_count(), 2);

        let mut nan = grid_frame(3);
        nan[7].y = f32::NAN;
        anim.push_frame(&nan).unwrap();
        let mut bytes = Vec::new();
        let err = anim.write(&mut bytes).unwrap_err();
        assert!(err.to_string().contains("frame 2 vertex 7"), "{err}");
        assert!(bytes.is_empty());

        let cases = [
            GlbAnimation::new(&[[0, 1, 25]], &grid_frame(0), DT),
            GlbAnimation::new(&[], &[], DT),
            {
                let mut a = GlbAnimation::new(&grid_triangles(), &grid_frame(0), 0.0);
                a.push_frame(&grid_frame(1)).unwrap();
                a
            },
        ];
        for anim in cases {
            let err = anim.write(&mut bytes).unwrap_err();
            assert_eq!(err.kind(), io::ErrorKind::InvalidInput, "{err}");
            assert!(bytes.is_empty());
        }
    }
}
