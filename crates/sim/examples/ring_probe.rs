//! Diagnostic: runs a FEM–DEM scenario and reports the charge–particle contact as it
//! goes: every microsecond the step, the deepest penetration and the edges' stretch;
//! every step whose deepest penetration exceeds a threshold, that contact in full.
//!
//! `cargo run --release -p grains-sim --example ring_probe SCENARIO [THRESHOLD]`

use grains_sim::blast::{assemble::assemble, Blast};
use grains_sim::scenario::{self, Scenario};
use grains_sim::{Simulation, Source};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("scenario");
    let threshold: f64 = args.next().map_or(0.5, |s| s.parse().unwrap());
    let src = Source::read(path.as_ref()).map_err(anyhow::Error::msg)?;
    let Scenario::FemDem(s) = scenario::parse(&src).map_err(anyhow::Error::msg)? else {
        anyhow::bail!("{path}: not a FEM-DEM scenario");
    };
    let a = assemble(&s, &src.base).map_err(anyhow::Error::msg)?;
    let mut sim = Blast::new(&s, a);
    let c0: Vec<f64> = {
        let c = &sim.charge;
        c.boundary
            .iter()
            .map(|e| (c.nodes.pos[e[1] as usize] - c.nodes.pos[e[0] as usize]).length())
            .collect()
    };
    let end = s.run.duration;
    let mut next = 0.0;
    let mut reported = 0;
    loop {
        let t = sim.clock().time;
        if t >= end * (1.0 - 1e-12) {
            break;
        }
        let res = sim.advance();
        let r = sim.ring.as_ref().unwrap();
        let cp = &r.coupling;
        let c = &sim.charge;
        if sim.clock().time >= next {
            let st: Vec<f64> = c
                .boundary
                .iter()
                .zip(&c0)
                .map(|(e, l0)| {
                    (c.nodes.pos[e[1] as usize] - c.nodes.pos[e[0] as usize]).length() / l0
                })
                .collect();
            let mean = st.iter().sum::<f64>() / st.len() as f64;
            let max = st.iter().copied().fold(0.0, f64::max);
            println!(
                "t {:8.3} us step {:7} dt {:.3e} pen {:.3} contacts {:6} stretch mean {:.2} max {:.2} dt_pen {:.3e}",
                sim.clock().time * 1e6,
                sim.clock().step,
                sim.dt,
                cp.max_penetration_ratio,
                cp.contacts,
                mean,
                max,
                cp.stable_dt()
            );
            while next <= sim.clock().time {
                next += 1e-6;
            }
        }
        if cp.max_penetration_ratio > threshold && reported < 400 {
            reported += 1;
            let d = cp.deepest.unwrap();
            let p = &r.state.particles;
            let i =
                p.id.iter()
                    .position(|&k| k == d.id)
                    .expect("the deepest grain");
            let [na, nb] = c.boundary[d.edge];
            let (na, nb) = (na as usize, nb as usize);
            let rel =
                p.vel[i] - (c.nodes.vel[na] * (1.0 - d.touch.at) + c.nodes.vel[nb] * d.touch.at);
            println!(
                "  step {} t {:.4} us pen {:.3} id {} r {:.3e} m {:.3e} x ({:.6e},{:.6e}) v ({:.1},{:.1}) | edge {} corner {} at {:.3} stretch {:.2} k {:.3e} n ({:.3},{:.3}) | vrel.n {:.1} | node a v ({:.1},{:.1}) m {:.3e} f_ext {:.3e} f_int {:.3e} | node b v ({:.1},{:.1}) m {:.3e} f_ext {:.3e} f_int {:.3e} | pforce {:.3e}",
                sim.clock().step,
                sim.clock().time * 1e6,
                d.touch.overlap / p.radius[i],
                p.id[i],
                p.radius[i],
                p.mass(i),
                p.pos[i].x,
                p.pos[i].y,
                p.vel[i].x,
                p.vel[i].y,
                d.edge,
                d.corner,
                d.touch.at,
                d.stretch,
                d.stiffness,
                d.touch.normal.x,
                d.touch.normal.y,
                rel.dot(d.touch.normal),
                c.nodes.vel[na].x,
                c.nodes.vel[na].y,
                c.nodes.mass[na],
                c.nodes.f_ext[na].length(),
                c.nodes.f_int[na].length(),
                c.nodes.vel[nb].x,
                c.nodes.vel[nb].y,
                c.nodes.mass[nb],
                c.nodes.f_ext[nb].length(),
                c.nodes.f_int[nb].length(),
                p.force[i].length(),
            );
        }
        if let Err(e) = res {
            println!("stopped: {e}");
            break;
        }
    }
    Ok(())
}
