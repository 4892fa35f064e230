//! Prints the measured table (max / p99 / median excess E, classification errors, certified
//! widths, intervals that miss, paths taken) for every query, variant, precision and family:
//! `cargo run --release -p tridist-scenes --example measure [n] [query]`
use tridist::Query;
use tridist_scenes::eval::sweep_family;
use tridist_scenes::Family;

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(300);
    let only: Option<String> = std::env::args().nth(2);
    for &q in Query::ALL {
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
                    let c = &s.counts;
                    println!(
                        "{:14} {:8} {} {:14} max {:9.3e} p99 {:9.3e} med {:8.2e} miss {:2} fz {:2} nf {:2} mj {:2} pt {:9.3e} ivmiss {:2} w {:8.2e}/{:8.2e} rec {:4} comp {:4} del {:4} wide {:4} unc {:3}",
                        q.name(), r.variant.name(), r.precision, f.name(), s.max_excess, s.p99, s.median,
                        s.contact_misses, s.false_zeros, s.nonfinite, s.misjudged, s.max_point_error,
                        s.interval_misses, s.median_width, s.max_width, c.recertified, c.compacted, c.delegated, c.widened,
                        c.uncertified
                    );
                }
            }
        }
    }
}
