//! Prints the worst case of one (query, family) sweep for every variant and precision:
//! `cargo run --release -p tridist-scenes --example worst -- tri_tri random [n]`
use tridist::Query;
use tridist_scenes::eval::sweep_family;
use tridist_scenes::Family;

fn main() {
    let mut a = std::env::args().skip(1);
    let q = Query::parse(&a.next().unwrap_or_default()).expect("query name");
    let f = Family::parse(&a.next().unwrap_or_default()).expect("family name");
    let n: usize = a.next().and_then(|s| s.parse().ok()).unwrap_or(300);
    let pr =
        |r: &tridist_scenes::eval::Row, d: String| println!("== {} {}\n{d}\n", r.variant.name(), r.precision);
    sweep_family::<f32>(q, f, tridist_scenes::seed(), n, pr);
    sweep_family::<f64>(q, f, tridist_scenes::seed(), n, pr);
}
