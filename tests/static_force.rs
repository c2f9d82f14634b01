//! LuGre's static force follows the load: `F_S` is given at the scene's load (its start values of
//! `F_N` and `mu`) and the law uses `F_S·(F_N/F_N_ref)·(mu/mu_ref)`, keeping `F_S/F_C`; the
//! damping ratio `zeta_t` scales with `F_N`. A normal force given as an input held at a value
//! gives the numbers of the same scene with that value as a parameter; a static force below the
//! Coulomb force at the scene's load is refused, naming both.

use vibrofric::description::scene::Scene;
use vibrofric::model::{build, InputId, Integrator, Outputs, Setup, Simulator};
use vibrofric::table::ParamId;

const TOL: f64 = 1e-8;

fn scene(normal: &str, start: &str) -> Scene {
    let text = format!(
        "model_identifier = \"S\"\nlaw = \"lugre\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nsupport = [\"input\"]\nnormal = \"{normal}\"\n[start]\n{start}\n"
    );
    Scene::parse(&text, "s.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The simulator of a scene with parameters `p`, its input F_d at the scene's start value.
fn start(s: &Scene, p: vibrofric::table::Params) -> Box<dyn Simulator> {
    let mut sim = build(s.config, p, 0.0, TOL).unwrap();
    sim.set_input(InputId::FD, s.inputs.f_d).unwrap();
    sim
}

/// Runs a simulator from 0 to `t_end` in steps of 1 ms; the outputs at the end.
fn run(sim: &mut Box<dyn Simulator>, t_end: f64) -> Outputs {
    run_from(sim, 0.0, t_end)
}

fn run_from(sim: &mut Box<dyn Simulator>, t0: f64, t_end: f64) -> Outputs {
    let (k0, n) = (
        (t0 / 1e-3).round() as usize,
        (t_end / 1e-3).round() as usize,
    );
    for k in k0..n {
        sim.step_to((k + 1) as f64 * 1e-3).unwrap();
    }
    sim.outputs()
}

/// The case: 1000 N on the contact (F_C = 200 N) pushed with 100 N and no vibration.
/// With F_S fixed at 14.3 N the body slid away; following the load (F_S = 260 N) it sticks: after
/// the pre-sliding transient (the elastic F_d/k_t = 1 µm and a little micro-slip) it stays put.
#[test]
fn a_heavier_load_holds_the_body_as_the_defaults_do() {
    let s = scene("parameter", "F_d = 100.0");
    let mut p = s.start;
    ParamId::FN.set(&mut p, 1000.0).unwrap();
    assert_eq!(p.static_force(), 14.3 * (1000.0 / 55.0));
    let mut sim = start(&s, p);
    let x_1 = run(&mut sim, 0.1).x;
    let o = run_from(&mut sim, 0.1, 0.2);
    assert!(o.x > 1e-6 && o.x < 2e-6, "x = {}", o.x);
    assert!((o.x - x_1).abs() < 1e-10, "drift {} m in 0.1 s", o.x - x_1);
    assert!(o.v_x.abs() < 1e-6, "v_x = {}", o.v_x);
    assert!((o.f_fx - 100.0).abs() < 1e-3, "F_Fx = {}", o.f_fx);
    // Above the static force at that load (260 N) it slides, as at the defaults above 14.3 N.
    let s = scene("parameter", "F_d = 270.0");
    let mut p = s.start;
    ParamId::FN.set(&mut p, 1000.0).unwrap();
    let mut sim = start(&s, p);
    let o = run(&mut sim, 0.2);
    assert!(o.v_x > 1e-3, "v_x = {}", o.v_x);
}

/// At the scene's load the static force is F_S itself, bit for bit; mu scales it as F_N does.
#[test]
fn the_static_force_is_f_s_at_the_scene_load_and_follows_mu_and_f_n() {
    let s = scene("parameter", "F_N = 80.0\nmu = 0.3\nF_S = 30.0");
    let mut p = s.start;
    assert_eq!((p.f_n_ref, p.mu_ref), (80.0, 0.3));
    assert_eq!(p.static_force(), 30.0);
    assert_eq!(p.damping_ratio(), 1.0);
    ParamId::Mu.set(&mut p, 0.6).unwrap();
    assert!((p.static_force() - 60.0).abs() < 1e-12);
    ParamId::FN.set(&mut p, 40.0).unwrap();
    assert!((p.static_force() - 30.0).abs() < 1e-12);
    assert!((p.damping_ratio() - 0.5).abs() < 1e-15);
    // F_S/F_C is kept: 30/24 at the scene's load, 30/24 at mu = 0.6, F_N = 40.
    assert!((p.static_force() / p.f_c() - 1.25).abs() < 1e-12);
}

/// A held normal-force input and a parameter F_N of the same value give the same contact: on
/// the same integrator (Radau IIA, the one that takes a load input; a constant load may take
/// the explicit path), so that only the models differ.
#[test]
fn an_input_load_and_a_parameter_load_agree() {
    let by_param = scene("parameter", "F_d = 20.0");
    let by_input = scene("input", "F_d = 20.0");
    let on_radau = |s: &Scene, p| {
        let mut sim = Setup::new(s.config, p)
            .tolerance(TOL)
            .force_radau(true)
            .build()
            .unwrap();
        sim.set_input(InputId::FD, s.inputs.f_d).unwrap();
        sim
    };
    for f_n in [55.0, 30.0, 400.0] {
        let mut p = by_param.start;
        ParamId::FN.set(&mut p, f_n).unwrap();
        let mut a = on_radau(&by_param, p);
        let mut b = on_radau(&by_input, by_input.start);
        // Left to itself the parameter load takes the explicit path, but at 400 N, where the
        // contact damping (which follows the load) is too fast for a held body.
        let path = start(&by_param, p).integrator();
        let own = if f_n < 400.0 {
            Integrator::ExplicitPlanar
        } else {
            Integrator::Radau
        };
        assert_eq!(path, own, "F_N {f_n}");
        b.set_input(InputId::FN, f_n).unwrap();
        for sim in [&mut a, &mut b] {
            sim.set_input(InputId::VSx, 0.02).unwrap();
        }
        let (oa, ob) = (run(&mut a, 0.05), run(&mut b, 0.05));
        for (name, x, y, scale) in [
            ("x", oa.x, ob.x, oa.x.abs().max(1e-6)),
            ("v_x", oa.v_x, ob.v_x, 0.02),
            ("F_Fx", oa.f_fx, ob.f_fx, 0.2 * f_n),
            ("F_mean", oa.f_mean, ob.f_mean, 0.2 * f_n),
        ] {
            assert!(
                (x - y).abs() <= 1e-9 * scale,
                "F_N = {f_n}: {name} {x} vs {y}"
            );
        }
    }
}

/// F_S below F_C at the scene's load inverts the Stribeck curve: refused by the scene reader
/// and by the model, naming both forces.
#[test]
fn a_static_force_below_the_coulomb_force_is_refused() {
    let text = "model_identifier = \"S\"\nlaw = \"lugre\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nsupport = [\"input\"]\n[start]\nF_S = 5.0\n";
    let e = Scene::parse(text, "s.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("s.toml:7: start.F_S = 5: F_S = 5 N is below the Coulomb force F_C = mu·F_N = 11 N (mu = 0.2, F_N = 55 N"),
        "{e}"
    );
    let s = scene("parameter", "");
    let mut p = s.start;
    ParamId::FS.set(&mut p, 10.0).unwrap();
    let e = build(s.config, p, 0.0, TOL)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        e.starts_with("F_S = 10 N is below the Coulomb force F_C = mu·F_N = 11 N"),
        "{e}"
    );
    // Equal is a law without a Stribeck peak, and valid; so is any F_S once F_N is changed.
    ParamId::FS.set(&mut p, 11.0).unwrap();
    ParamId::FN.set(&mut p, 1.0).unwrap();
    assert!(build(s.config, p, 0.0, TOL).is_ok());
}
