//! Timings of the scene pipeline's front end on demo scenes: building the
//! scene (hulls included), the broad phase, and islands over its pairs.

use constraint_stabilization::internals::broad_phase::candidate_pairs;
use constraint_stabilization::internals::contact::islands;
use constraint_stabilization::testbed::demo::demo_scene;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;

/// Contact margin of the benchmark, in the demo's length unit (bodies are
/// 0.3 to 1.4 across).
const MARGIN: f64 = 0.01;

fn front_end(c: &mut Criterion) {
    let mut group = c.benchmark_group("scene");
    for n in [10, 100, 1000] {
        group.bench_with_input(BenchmarkId::new("demo_scene", n), &n, |b, &n| {
            b.iter(|| demo_scene(black_box(n), 1))
        });
        let scene = demo_scene(n, 1);
        group.bench_with_input(
            BenchmarkId::new("candidate_pairs", n),
            &scene,
            |b, scene| b.iter(|| candidate_pairs(black_box(scene), MARGIN)),
        );
        let pairs = candidate_pairs(&scene, MARGIN).unwrap_or_default();
        let fixed = scene.fixed_flags();
        group.bench_with_input(BenchmarkId::new("islands", n), &pairs, |b, pairs| {
            b.iter(|| islands(black_box(&fixed), black_box(pairs)))
        });
    }
    group.finish();
}

criterion_group!(benches, front_end);
criterion_main!(benches);
