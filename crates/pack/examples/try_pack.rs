//! Scratch driver: pack a spec and print analysis figures.
use grains_analysis::sample::{Sample, SampleKind};
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut spec = grains_pack::parse(&text, &path).unwrap();
    if let Some(r) = std::env::args().nth(2) {
        spec.protocol.rate = r.parse().unwrap();
    }
    let v = grains_pack::validate(&spec).unwrap();
    let t = std::time::Instant::now();
    let p = grains_pack::pack(&spec, &v, &mut |s| eprintln!("{s}"));
    eprintln!("pack {:.2}s", t.elapsed().as_secs_f64());
    let s = Sample {
        pos: p.pos.clone(),
        radius: p.radius.clone(),
        lining: p.lining,
        region: Some(p.region),
        kind: SampleKind::Packing,
    };
    let a = grains_analysis::analyze(&s);
    println!("N={} d0={:.4e} delta={:.4} phi_bulk={:.4} local_all={:.3} local_int={:.3} global_int={:.3} z={:.3} aniso={:.4} rattlers={:.3} ({:.2}s)",
      s.pos.len(), a.sizes.mean, a.sizes.polydispersity, a.packing_fraction_bulk, a.order_all.local, a.order_interior.local, a.order_interior.global, a.mean_coordination, a.fabric.anisotropy(), a.rattler_fraction, t.elapsed().as_secs_f64());
    if let Some(out) = std::env::args().nth(3) {
        let vals: Vec<f64> = a.psi6.iter().map(|v| v.length()).collect();
        grains_core::plot::scatter_disks_png(
            std::path::Path::new(&out),
            "psi6",
            &s.pos,
            &s.radius,
            &vals,
            "|psi6|",
        )
        .unwrap();
    }
}
