//! Within-margin: must agree exactly with the full query of the same variant (squared distance
//! when within the margin, +inf beyond), for every variant and precision.
#![no_main]
use libfuzzer_sys::fuzz_target;
use tridist::{Engine, Isa};
use tridist_fuzz::PairInput;

fuzz_target!(|data: (PairInput, u16)| {
    let (input, m) = data;
    if let Some((c, _)) = input.build::<f64>() {
        let margin = m as f64 / 4096.0;
        for isa in Isa::ALL {
            let Ok(e) = Engine::new(isa) else { continue };
            let (mut full, mut w) = ([0.0f64], [0.0f64]);
            e.sqdist_triangle_triangle(&c.a, &c.b, &mut full).unwrap();
            e.within_margin_triangle_triangle(&c.a, &c.b, margin, &mut w).unwrap();
            if full[0] <= margin * margin {
                assert_eq!(
                    w[0].to_bits(),
                    full[0].to_bits(),
                    "{isa}: within {} full {} margin {margin} {c:?}",
                    w[0],
                    full[0]
                );
            } else {
                assert_eq!(
                    w[0],
                    f64::INFINITY,
                    "{isa}: within {} full {} margin {margin} {c:?}",
                    w[0],
                    full[0]
                );
            }
        }
    }
});
