//! A particle as the words a message carries: every field, bit for bit, and for a
//! particle changing rank its wall springs and its (partner id, spring) rows.

use crate::math::{AngVector, Components, Tangent, Vector};
use crate::particles::Particles;

/// Words as little-endian bytes.
pub fn bytes_of(words: &[u64]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Little-endian bytes as words.
pub fn words_of(bytes: &[u8]) -> Vec<u64> {
    bytes
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// Appends components as their bits.
fn put<C: Components>(out: &mut Vec<u64>, v: C) {
    out.extend((0..C::N).map(|a| v.get(a).to_bits()));
}

/// Reads words in order.
pub struct Reader<'a> {
    words: &'a [u64],
    at: usize,
}

impl<'a> Reader<'a> {
    /// Reads `words` from the start.
    pub fn new(words: &'a [u64]) -> Self {
        Reader { words, at: 0 }
    }

    /// Whether every word has been read.
    pub fn done(&self) -> bool {
        self.at >= self.words.len()
    }

    /// The next word.
    pub fn word(&mut self) -> u64 {
        self.at += 1;
        self.words[self.at - 1]
    }

    fn f64(&mut self) -> f64 {
        f64::from_bits(self.word())
    }

    fn get<C: Components>(&mut self) -> C {
        let c: Vec<f64> = (0..C::N).map(|_| self.f64()).collect();
        C::from_slice(&c)
    }
}

/// Appends particle `i`'s every field.
pub fn put_particle(out: &mut Vec<u64>, p: &Particles, i: usize) {
    out.push(p.id[i] as u64);
    put(out, p.pos[i]);
    put(out, p.vel[i]);
    put(out, p.omega[i]);
    out.push(p.radius[i].to_bits());
    out.push(p.inv_mass[i].to_bits());
    out.push(p.inv_inertia[i].to_bits());
    out.push(p.material[i] as u64);
    put(out, p.force[i]);
    put(out, p.torque[i]);
}

/// Reads one particle written by [`put_particle`] onto the end of `p`.
pub fn get_particle(r: &mut Reader, p: &mut Particles) {
    p.id.push(r.word() as u32);
    p.pos.push(r.get());
    p.vel.push(r.get());
    p.omega.push(r.get());
    p.radius.push(r.f64());
    p.inv_mass.push(r.f64());
    p.inv_inertia.push(r.f64());
    p.material.push(r.word() as u16);
    p.force.push(r.get());
    p.torque.push(r.get());
}

/// Appends particle `i` of `p` to `out`, every field.
pub fn copy_particle(p: &Particles, i: usize, out: &mut Particles) {
    out.id.push(p.id[i]);
    out.pos.push(p.pos[i]);
    out.vel.push(p.vel[i]);
    out.omega.push(p.omega[i]);
    out.radius.push(p.radius[i]);
    out.inv_mass.push(p.inv_mass[i]);
    out.inv_inertia.push(p.inv_inertia[i]);
    out.material.push(p.material[i]);
    out.force.push(p.force[i]);
    out.torque.push(p.torque[i]);
}

/// Appends what changes every step: position, velocity, spin, force, torque.
pub fn put_motion(out: &mut Vec<u64>, p: &Particles, i: usize) {
    put(out, p.pos[i]);
    put(out, p.vel[i]);
    put(out, p.omega[i]);
    put(out, p.force[i]);
    put(out, p.torque[i]);
}

/// Reads what [`put_motion`] wrote into particle `i`.
pub fn get_motion(r: &mut Reader, p: &mut Particles, i: usize) {
    p.pos[i] = r.get::<Vector>();
    p.vel[i] = r.get::<Vector>();
    p.omega[i] = r.get::<AngVector>();
    p.force[i] = r.get::<Vector>();
    p.torque[i] = r.get::<AngVector>();
}

/// Appends a particle's contact history: its wall springs, then the number of its
/// springs and each as (partner id, spring as seen from it).
pub fn put_history(out: &mut Vec<u64>, walls: &[Tangent], rows: &[(u32, Tangent)]) {
    for &w in walls {
        put(out, w);
    }
    out.push(rows.len() as u64);
    for &(j, xi) in rows {
        out.push(j as u64);
        put(out, xi);
    }
}

/// Reads what [`put_history`] wrote, for `walls` walls.
pub fn get_history(r: &mut Reader, walls: usize) -> (Vec<Tangent>, Vec<(u32, Tangent)>) {
    let w = (0..walls).map(|_| r.get()).collect();
    let n = r.word() as usize;
    let rows = (0..n).map(|_| (r.word() as u32, r.get())).collect();
    (w, rows)
}
