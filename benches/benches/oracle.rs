//! Oracle throughput on unit-scale random triangle pairs (f32 input), one core: the filtered
//! query users call, and the unfiltered one it must agree with.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn rng(state: &mut u64) -> f32 {
    *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    ((*state >> 40) as f32) / (1u64 << 24) as f32
}

type Tri = [[f32; 3]; 3];

fn bench(c: &mut Criterion) {
    let mut s = 42u64;
    let pairs: Vec<(Tri, Tri)> = (0..256)
        .map(|_| {
            let mut t = || {
                [
                    [rng(&mut s), rng(&mut s), rng(&mut s)],
                    [rng(&mut s), rng(&mut s), rng(&mut s)],
                    [rng(&mut s), rng(&mut s), rng(&mut s)],
                ]
            };
            (t(), t())
        })
        .collect();
    let mut g = c.benchmark_group("oracle");
    g.throughput(Throughput::Elements(pairs.len() as u64));
    // from floats, as the tests and reports call it (includes the exact conversion)
    g.bench_function("tri_tri_random_unit", |b| {
        b.iter(|| {
            pairs.iter().filter(|(a, b)| tridist_oracle::sqdist_triangle_triangle(a, b).unwrap() == 0).count()
        })
    });
    g.bench_function("tri_tri_random_unit_unfiltered", |b| {
        b.iter(|| {
            pairs
                .iter()
                .filter(|(a, b)| {
                    let (a, b) =
                        (tridist_oracle::exact_points(a).unwrap(), tridist_oracle::exact_points(b).unwrap());
                    tridist_oracle::triangle_triangle_unfiltered(&a, &b).d2 == 0
                })
                .count()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
