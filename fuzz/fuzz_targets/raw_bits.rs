//! Arbitrary f32/f64 bit patterns (NaN, inf, subnormals, huge values) through the batch API of
//! every variant: no panic, no UB (run with the address sanitizer), and the documented outcome:
//! NaN (None for intersection) exactly for pairs with a non-finite coordinate, otherwise a
//! non-negative squared distance or +inf (overflow).
#![no_main]
use libfuzzer_sys::fuzz_target;
use tridist::{Engine, Isa, Real, TriangleBatch};

fn check<T: Real>(words: &[u64]) {
    let coords: Vec<T> = words.iter().map(|&w| T::from_bits_u64(w)).collect();
    let tris: Vec<[[T; 3]; 3]> = coords
        .chunks_exact(9)
        .map(|c| [[c[0], c[1], c[2]], [c[3], c[4], c[5]], [c[6], c[7], c[8]]])
        .collect();
    let n = tris.len() / 2;
    let (a, b) = (&tris[..n], &tris[n..2 * n]);
    let (ba, bb) = (TriangleBatch::from_slice(a), TriangleBatch::from_slice(b));
    for isa in Isa::ALL {
        let Ok(e) = Engine::new(isa) else { continue };
        let mut d = vec![T::ZERO; n];
        let (mut p, mut q) = (vec![[T::ZERO; 3]; n], vec![[T::ZERO; 3]; n]);
        let mut f = vec![None; n];
        e.closest_points_triangle_triangle(&ba, &bb, &mut d, &mut p, &mut q).unwrap();
        e.intersect_triangle_triangle(&ba, &bb, &mut f).unwrap();
        let mut db = vec![T::ZERO; n];
        e.sqdist_triangle_triangle_brute(a, b, &mut db).unwrap();
        for i in 0..n {
            let finite = a[i].iter().chain(b[i].iter()).flatten().all(|x| x.is_finite());
            if finite {
                assert!(
                    d[i] >= T::ZERO && db[i] >= T::ZERO,
                    "{isa} pair {i}: {} {} for {:?} {:?}",
                    d[i],
                    db[i],
                    a[i],
                    b[i]
                );
                assert!(f[i].is_some());
                if d[i].is_finite() {
                    assert!(
                        p[i].iter().chain(q[i].iter()).all(|x| x.is_finite()),
                        "{isa}: non-finite points"
                    );
                }
            } else {
                assert!(
                    d[i] != d[i] && db[i] != db[i] && f[i].is_none(),
                    "{isa} pair {i}: non-finite input must give NaN/None"
                );
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let w64: Vec<u64> = data.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap())).collect();
    check::<f64>(&w64);
    let w32: Vec<u64> =
        data.chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap()) as u64).collect();
    check::<f32>(&w32);
});
