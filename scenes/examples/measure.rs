//! Prints the measured table (max / p99 excess E, classification errors) for every query,
//! variant, precision and family. `cargo run --release -p tridist-scenes --example measure [n]`
use tridist_scenes::eval::{sweep_family, Query};
use tridist_scenes::Family;

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(300);
    let only: Option<String> = std::env::args().nth(2);
    for q in Query::ALL {
        if only.as_deref().is_some_and(|o| o != q.name()) {
            continue;
        }
        for f in Family::ALL {
            for rows in [
                sweep_family::<f32>(q, f, tridist_scenes::seed(), n, |_, _| {}),
                sweep_family::<f64>(q, f, tridist_scenes::seed(), n, |_, _| {}),
            ] {
                for r in rows {
                    let s = &r.stats;
                    println!(
                        "{:14} {:8} {} {:14} max {:10.3e} p99 {:9.3e} med {:8.2e} miss {:3} fz {:3} nf {:3} pt {:9.3e}",
                        q.name(), r.variant.name(), r.precision, f.name(), s.max_excess, s.p99, s.median,
                        s.contact_misses, s.false_zeros, s.nonfinite, s.max_point_error
                    );
                }
            }
        }
    }
}
