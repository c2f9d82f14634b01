//! Eight instances of two FMUs of the same library, stepped from eight threads at once, give
//! exactly the results of the same runs made one after another on one thread: instances share
//! nothing.

#[macro_use]
mod support;

use support::fmu::*;
use support::scenes::*;
use vibrofric_import::Fmu;

const H: f64 = 1e-3;
const STEPS: usize = 15;

/// Run `n`: its own normal force, stiffness and a drive scaled by `n`.
fn experiment(fmu: &Fmu, vrs: &[u32], n: usize) -> Vec<Vec<u64>> {
    let mut i = started(
        fmu,
        &format!("run{n}"),
        &[
            (vr::F_N, 20.0 + 5.0 * n as f64),
            (vr::K_T, 1e8 * (1.0 + 0.1 * n as f64)),
        ],
    );
    let mut rows = Vec::new();
    let mut t = 0.0;
    for k in 0..STEPS {
        ok!(
            i,
            i.set_real(&[vr::F_D], &[drive(k) * (1.0 + n as f64 / 4.0)])
        );
        ok!(i, i.do_step(t, H));
        t += H;
        rows.push(bits(&i.get_real(vrs).unwrap()));
    }
    ok!(i, i.terminate());
    rows
}

#[test]
fn eight_threads_give_exactly_the_single_threaded_results() {
    let fmus = [
        load("contact.toml", "threads-dahl"),
        load("contact-lugre.toml", "threads-lugre"),
    ];
    let vrs = [
        all_vrs(&scene("contact.toml")),
        all_vrs(&scene("contact-lugre.toml")),
    ];
    let sequential: Vec<_> = (0..8)
        .map(|n| experiment(&fmus[n % 2], &vrs[n % 2], n))
        .collect();
    let parallel: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..8)
            .map(|n| {
                let (fmu, v) = (&fmus[n % 2], &vrs[n % 2]);
                s.spawn(move || experiment(fmu, v, n))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for n in 0..8 {
        assert_eq!(parallel[n], sequential[n], "run {n}");
    }
    // The runs differ from each other, so the comparison means something.
    assert_ne!(sequential[0], sequential[2]);
}

#[test]
fn an_instance_may_move_between_threads() {
    let fmu = load("contact.toml", "threads-move");
    let vrs = all_vrs(&scene("contact.toml"));
    let mut i = started(&fmu, "mover", &[]);
    let mut t = 0.0;
    let mut rows = Vec::new();
    for k in 0..6 {
        // Each step on a new thread.
        let (r, tt) = std::thread::scope(|s| {
            s.spawn(|| {
                let t2 = step(&mut i, k, t, H);
                (bits(&i.get_real(&vrs).unwrap()), t2)
            })
            .join()
            .unwrap()
        });
        rows.push(r);
        t = tt;
    }
    let mut j = started(&fmu, "stay", &[]);
    assert_eq!(run(&mut j, &vrs, 0, 6, 0.0, H), rows);
}
