//! A fingerprint of the model's behaviour, for restructurings that must change nothing: every
//! standard scene through [`Setup`] at `k_t` 1e8 and 1e12, tolerances 1e-6 and 1e-8, on the
//! fastest path and on Radau forced, over communication steps of several lengths (some spanning
//! many averaging windows); each output's bits at every communication point, the work counters,
//! the path and the saved state at the end go into one FNV-1a hash per run. Two builds that
//! behave the same print the same text.
//!
//! cargo run --release --example output_hash

#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use vibrofric::model::{OutputId, Setup};

/// FNV-1a over bytes.
struct Fnv(u64);

impl Fnv {
    fn bytes(&mut self, b: &[u8]) {
        for x in b {
            self.0 ^= *x as u64;
            self.0 = self.0.wrapping_mul(0x100_0000_01b3);
        }
    }

    fn f64(&mut self, x: f64) {
        self.bytes(&x.to_bits().to_le_bytes());
    }
}

/// Communication steps: short and long, off the window grid and over many windows.
const STEPS: [f64; 8] = [1e-3, 3.7e-4, 2e-3, 1e-5, 5e-3, 1e-3, 0.01, 2.5e-3];

fn main() {
    let mut all = Fnv(0xcbf2_9ce4_8422_2325);
    for (file, scene) in scenes::standard_scenes() {
        for k_t in [1e8, 1e12] {
            for tol in [1e-6, 1e-8] {
                for radau in [false, true] {
                    let mut p = scene.start;
                    p.k_t = k_t;
                    let setup = Setup::new(scene.config, p)
                        .inputs(scene.inputs)
                        .tolerance(tol);
                    let setup = setup.force_radau(radau);
                    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
                    let line = match setup.build() {
                        Ok(mut sim) => {
                            let mut t = 0.0;
                            let mut failed = None;
                            for _ in 0..2 {
                                for dt in STEPS {
                                    t += dt;
                                    if let Err(e) = sim.step_to(t) {
                                        failed = Some(format!("{e}"));
                                        break;
                                    }
                                    let o = sim.outputs();
                                    for id in OutputId::ALL {
                                        h.f64(id.get(&o));
                                    }
                                }
                            }
                            let s = sim.stats();
                            h.bytes(format!("{s:?} {:?}", sim.integrator()).as_bytes());
                            h.bytes(format!("{:?}", sim.snapshot()).as_bytes());
                            format!(
                                "{:016x} {:?} steps {} {}",
                                h.0,
                                sim.integrator(),
                                s.steps,
                                failed.unwrap_or_default()
                            )
                        }
                        Err(e) => format!("refused: {e}"),
                    };
                    all.bytes(line.as_bytes());
                    println!("{file} k_t {k_t:e} tol {tol:e} radau {radau}: {line}");
                }
            }
        }
    }
    println!("all {:016x}", all.0);
}
