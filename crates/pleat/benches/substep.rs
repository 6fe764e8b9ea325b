//! Criterion benches: one XPBD substep of the standard hanging cloth, and the
//! constraint kinds on their own.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use pleat::scene::presets::hanging_cloth;
use pleat::Simulation;
use std::hint::black_box;
use std::path::Path;

fn hanging(n: u32, bending: pleat::material::BendingModel) -> Simulation {
    let mut scene = hanging_cloth(n, 1, false);
    scene.cloths[0].material.bending = bending;
    let mut sim = scene.build(Path::new("."), "bench").expect("valid preset");
    // Let it start moving so the constraints have work to do.
    for _ in 0..5 {
        sim.step(1.0 / 600.0);
    }
    sim
}

fn substep(c: &mut Criterion) {
    use pleat::material::BendingModel::{Dihedral, Isometric, SkipOne};
    let mut group = c.benchmark_group("xpbd_substep");
    for n in [64, 128] {
        for (name, bending) in [
            ("isometric", Isometric),
            ("dihedral", Dihedral),
            ("skip_one", SkipOne),
        ] {
            let mut sim = hanging(n, bending);
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| black_box(&mut sim).step(1.0 / 600.0))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, substep);
criterion_main!(benches);
