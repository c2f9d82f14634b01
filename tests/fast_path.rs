//! The fast paths against the general integrator: every standard scene stepped on the path it
//! takes and on Radau IIA alone, at tolerances 1e-6 and 1e-9, with held and with ramped inputs
//! (the explicit path against Radau at 1e-12, closer to the truth than Radau at the same
//! tolerance); the explicit path at 1e-10 against Radau at 1e-12; the exponential path on LuGre
//! against Radau at 1e-12; the planar path's step on a stiff Dahl contact's slow manifold, and
//! on a stiff LuGre contact's on the x axis, at `k_t` = 1e11 and 1e12 against Radau at 1e-10;
//! the explicit paths at loose tolerances; and a step over a million vibration periods against
//! stepping them one by one.

mod support;

use support::scenes::{scene, standard_scenes};
use vibrofric::description::scene::Scene;
use vibrofric::model::{build, InputId, Integrator, Outputs, Setup, Simulator};
use vibrofric::table::{Drive, Law, Motion, Params};

fn scenes() -> Vec<Scene> {
    standard_scenes().into_iter().map(|(_, s)| s).collect()
}

/// Runs `scene` on `path` for 0.05 s (100 periods at 2 kHz) in communication steps of 1 ms,
/// ramping the drive input over the second half through its derivative when `ramp`.
fn run(scene: &Scene, path: Integrator, tol: f64, ramp: bool) -> (Vec<Outputs>, Integrator) {
    let mut sim = Setup::new(scene.config, scene.start)
        .inputs(scene.inputs)
        .tolerance(tol)
        .force_radau(path == Integrator::Radau)
        .build()
        .unwrap();
    let drive = [InputId::VD, InputId::FD]
        .into_iter()
        .find(|id| id.present(&scene.config));
    let mut out = vec![];
    for k in 1..=50 {
        if let (true, Some(id), true) = (ramp, drive, k > 25) {
            // +20 % of the drive per 25 ms, as a master extrapolating its output would.
            let v0 = id.get(&scene.inputs);
            let v = v0 * (1.0 + 0.2 * (k - 26) as f64 / 25.0);
            sim.set_input(id, v).unwrap();
            sim.set_input_derivative(id, 0.2 * v0 / 0.025).unwrap();
        }
        sim.step_to(k as f64 * 1e-3).unwrap();
        out.push(sim.outputs());
    }
    (out, sim.integrator())
}

#[test]
fn every_standard_scene_agrees_with_radau_at_tolerances_1e_6_and_1e_9() {
    compare(scenes());
}

/// The fast paths at `k_t` = 1e11, where a relaxation spans a thousandth of a period: the
/// standard scenes that still take one there (DrillStringAxial, a held LuGre body of 267 kg,
/// takes Radau from about 5e10).
#[test]
fn stiff_fast_paths_agree_with_radau() {
    let stiff: Vec<Scene> = scenes()
        .into_iter()
        .map(|mut s| {
            s.start.k_t = 1e11;
            s
        })
        .filter(|s| {
            let sim = build(s.config, s.start, 0.0, 1e-6).unwrap();
            sim.integrator() != Integrator::Radau
        })
        .collect();
    assert_eq!(stiff.len(), 8);
    compare(stiff);
}

/// The exponential path on the other law it takes, LuGre (its target, decay and force
/// coefficients vary with `v_r`): PaperTransverseGuided's drive with LuGre, the body guided, in
/// planar and in longitudinal motion, at the scene's stiffness and at 1e11.
#[test]
fn lugre_on_the_exponential_path_agrees_with_radau() {
    let mut cases = vec![];
    for motion in [Motion::Planar, Motion::Longitudinal] {
        for k_t in [None, Some(1e11)] {
            let mut s = scene("paper-transverse-guided.toml");
            s.config.law = Law::LuGre;
            s.config.motion = motion;
            if motion == Motion::Longitudinal {
                s.start.angle = 0.0;
            }
            if let Some(k) = k_t {
                s.start.k_t = k;
            }
            s.model_identifier = format!("LuGre {motion:?} velocity guided k_t {}", s.start.k_t);
            let path = build(s.config, s.start, 0.0, 1e-6).unwrap().integrator();
            assert_eq!(path, Integrator::Exponential, "{}", s.model_identifier);
            cases.push(s);
        }
    }
    compare(cases);
}

fn compare(scenes: Vec<Scene>) {
    for scene in scenes {
        let f_c = scene.start.f_c();
        let s_ss = f_c / scene.start.k_t;
        for tol in [1e-6, 1e-9] {
            for ramp in [false, true] {
                let (fast, path) = run(&scene, Integrator::ClosedForm, tol, ramp);
                // The explicit path is about 100× more accurate than Radau at equal tolerance
                // (with a ramped force, Radau at 1e-9 is 8e-8·F_C from the truth): it is held
                // to Radau at 1e-12 instead.
                // So is the exponential path on LuGre: with k_t = 1e11 Radau at 1e-9 is 1e-7·F_C
                // from it (and from Radau at 1e-12).
                let reference_tol =
                    if matches!(path, Integrator::Explicit | Integrator::ExplicitPlanar)
                        || scene.config.law == Law::LuGre
                    {
                        1e-12
                    } else {
                        tol
                    };
                let (radau, _) = run(&scene, Integrator::Radau, reference_tol, ramp);
                let name = &scene.model_identifier;
                for (k, (a, b)) in fast.iter().zip(&radau).enumerate() {
                    let what = format!("{name} ({path:?}) tol {tol} ramp {ramp} at {} ms", k + 1);
                    // Radau's global error is of the order of its tolerance: 20·tol of F_C
                    // bounds both runs' errors together.
                    for (q, x, y) in [
                        ("F_Fx", a.f_fx, b.f_fx),
                        ("F_mean", a.f_mean, b.f_mean),
                        ("F_Fy", a.f_fy, b.f_fy),
                    ] {
                        assert!((x - y).abs() <= 20.0 * tol * f_c, "{what}: {q} {x} vs {y}");
                    }
                    assert!((a.s_x - b.s_x).abs() <= 20.0 * tol * s_ss, "{what}: s_x");
                    // Positions on the scale of the vibration amplitude (the integrators' nominal
                    // position) or of the deformation, whichever is larger.
                    let x_nom = s_ss.max(scene.start.u0);
                    assert!(
                        (a.x - b.x).abs() <= 20.0 * tol * (x_nom + b.x.abs()),
                        "{what}: x {} vs {}",
                        a.x,
                        b.x
                    );
                }
            }
        }
    }
}

#[test]
fn each_standard_scene_takes_the_path_its_structure_allows() {
    for scene in scenes() {
        let sim = build(scene.config, scene.start, 0.0, 1e-6).unwrap();
        let expected = match scene.model_identifier.as_str() {
            "PaperLongitudinal" => Integrator::ClosedForm,
            "PaperTransverseGuided" => Integrator::Exponential,
            "VibratingContact" | "RigLongitudinal" | "VibratingContactDupont" => {
                Integrator::Explicit
            }
            "PaperTransverse" | "RigTransverse" | "VibratingContactLuGre" | "DrillStringAxial" => {
                Integrator::ExplicitPlanar
            }
            _ => Integrator::Radau,
        };
        assert_eq!(sim.integrator(), expected, "{}", scene.model_identifier);
    }
}

/// The standard scenes that take `integrator` at their start values.
fn scenes_on(integrator: Integrator) -> Vec<Scene> {
    scenes()
        .into_iter()
        .filter(|s| build(s.config, s.start, 0.0, 1e-6).unwrap().integrator() == integrator)
        .collect()
}

/// The scales a scene's comparisons are relative to: the friction force `F_C`, the
/// deformation `s_ss`, velocities on the scale of the vibration's or of the contact's
/// oscillation, positions on the scale of `s_ss` or the vibration amplitude.
struct Nominal {
    f_c: f64,
    s_ss: f64,
    v_nom: f64,
    x_nom: f64,
}

impl Nominal {
    fn of(scene: &Scene) -> Nominal {
        let p = &scene.start;
        let f_c = p.f_c();
        let s_ss = f_c / p.k_t;
        let v_a = std::f64::consts::TAU * p.f * p.u0;
        Nominal {
            f_c,
            s_ss,
            v_nom: v_a.max(s_ss * (p.k_t / p.m).sqrt()),
            x_nom: s_ss.max(p.u0),
        }
    }
}

/// The explicit paths at loose tolerances (1e-3 to 1e-5), where their error control weighs the
/// deformation's error by its own measure only: the friction force `F_Fx` at every
/// communication point over 50 ms within the tolerance times `F_C` of Radau at 1e-11. (Weighed
/// by its effect on the body, as at 1e-6 and below, VibratingContact was 1.6e-4 of `F_C` off
/// at 1e-4.) Not held to it, and known: `F_Fy` on RigTransverse (the planar path 2.9e-3 of
/// `F_C` off at 1e-4, 1.5e-5 at 1e-5, as before the weighing) and LuGre's contact
/// (VibratingContactLuGre 1.4e-2 of `F_C` off at 1e-3, 2.3e-4 at 1e-4, 1.7e-5 at 1e-5; 8.8e-7 at
/// 1e-6).
#[test]
fn explicit_paths_keep_loose_tolerances() {
    let mut cases = scenes_on(Integrator::Explicit);
    cases.extend(scenes_on(Integrator::ExplicitPlanar));
    cases.retain(|s| s.config.law != Law::LuGre);
    assert_eq!(cases.len(), 5);
    for scene in cases {
        let f_c = scene.start.f_c();
        let (reference, _) = run(&scene, Integrator::Radau, 1e-11, false);
        for tol in [1e-3, 1e-4, 1e-5] {
            let (fast, path) = run(&scene, Integrator::ClosedForm, tol, false);
            let worst = fast
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a.f_fx - b.f_fx).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= tol * f_c,
                "{} ({path:?}) tol {tol}: F_Fx {:.2e} of F_C",
                scene.model_identifier,
                worst / f_c
            );
        }
    }
}

/// The explicit path (a moving body on a Dahl or Dupont contact) at tolerance 1e-10 against Radau at
/// 1e-12, at the default contact stiffness and at 1e11 (a reversal's relaxation then spans a
/// thousandth of a period), with held inputs: the friction force, its window and step means,
/// the deformation and the body's position and velocity.
#[test]
fn explicit_path_agrees_with_radau_at_tolerance_1e_12() {
    let mut explicit = scenes_on(Integrator::Explicit);
    assert_eq!(explicit.len(), 3);
    // The spring drive on a Dupont contact (no standard scene has it).
    let mut rig = scene("rig-longitudinal.toml");
    rig.config.law = Law::Dupont;
    explicit.push(rig);
    for mut scene in explicit {
        for k_t in [1e8, 1e11] {
            scene.start.k_t = k_t;
            for (what, a) in agrees_with_radau_at_1e_12(&scene, Integrator::Explicit) {
                assert_eq!((a.f_fy, a.s_y, a.v_y), (0.0, 0.0, 0.0), "{what}: lateral");
            }
        }
    }
}

/// The planar explicit path's standard scenes (planar Dahl off the x axis, LuGre on it, the
/// held longitudinal LuGre body of DrillStringAxial) at tolerance 1e-10 against Radau at
/// 1e-12, at `k_t` = 1e8 and at a stiffness the path still takes (Dahl 1e11, the deformation
/// then advanced exponentially in the relaxation arc length; LuGre 1e10), with held inputs:
/// both friction components, their window and step means, the deformation and the body's
/// position and velocity in x and y.
#[test]
fn explicit_planar_path_agrees_with_radau_at_tolerance_1e_12() {
    let planar = scenes_on(Integrator::ExplicitPlanar);
    assert_eq!(planar.len(), 4);
    for mut scene in planar {
        // LuGre's contact damping makes a stuck body's motion fast on the scale of the window
        // from about k_t = 1e10 at 2 kHz on: from there Radau takes it off the x axis (a
        // vibration at an angle), while on the axis the path keeps it (its stiff sliding on
        // the slow manifold: `lugre_coulomb_limit_agrees_with_radau_at_1e_10`). A body that
        // no vibration keeps sliding (DrillStringAxial, held by its drive) may stick for long:
        // Radau takes it from a tenth of that on (the rate sqrt(k_t/m): `k_t` = 1e9 at 5.6 kg,
        // the same product at DrillStringAxial's 267 kg of drill pipe at 4.8e10).
        let lugre = scene.config.law == Law::LuGre;
        let held = lugre && !scene.config.harmonic;
        let stiffness = if held {
            vec![1e8]
        } else if lugre {
            vec![1e8, 1e10]
        } else {
            vec![1e8, 1e11]
        };
        if held {
            let mut at = scene.start;
            at.k_t = 1e9 * at.m / 5.6;
            let sim = build(scene.config, at, 0.0, 1e-6).unwrap();
            assert_eq!(sim.integrator(), Integrator::Radau);
        } else if lugre {
            let mut at = scene.start;
            at.k_t = 1e11;
            let sim = build(scene.config, at, 0.0, 1e-6).unwrap();
            assert_eq!(sim.integrator(), Integrator::ExplicitPlanar);
            // Below tolerance 1e-8 Radau keeps it.
            let sim = build(scene.config, at, 0.0, 1e-9).unwrap();
            assert_eq!(sim.integrator(), Integrator::Radau);
            at.angle = 0.3;
            let sim = build(scene.config, at, 0.0, 1e-6).unwrap();
            assert_eq!(sim.integrator(), Integrator::Radau);
        }
        for k_t in stiffness {
            scene.start.k_t = k_t;
            agrees_with_radau_at_1e_12(&scene, Integrator::ExplicitPlanar);
        }
    }
}

/// An output's name, how to read it, and its scale.
type Quantity<'a> = (&'a str, &'a dyn Fn(&Outputs) -> f64, f64);

/// The bodies the planar explicit path took over from Radau in this form, each at tolerance
/// 1e-10 on the path throughout (no Jacobian taken) with the friction components, their
/// window mean, the deformation and the body's position and velocity no further from Radau at
/// 1e-12 than Radau at 1e-10 is (or within 1e-10 of their scales, a position's the vibration
/// amplitude and the distance travelled):
///
/// - a Dupont contact off the x axis (its plastic relaxation one more component of the
///   explicit method; the direction test `s·v_r > 0`, which switches the relaxation on and off
///   off the axis, a jump of the rate the path does not locate, where Radau does):
///   VibratingContactDupont with its vibration across the sliding direction and at 0.5 rad,
///   the same under a spring drive, and PaperTransverse's velocity drive with the lateral
///   motion free on a Dupont contact;
/// - a LuGre contact in longitudinal motion under a spring drive: RigLongitudinal on LuGre.
///
/// A stiff Dupont contact (`k_t` = 1e10), and one whose weight rises steeply to `s_ss`
/// (breakaway ratio 0.95), take Radau.
#[test]
fn bodies_new_to_the_planar_path_agree_with_radau() {
    let mut across = scene("contact-dupont.toml");
    across.start.angle = std::f64::consts::FRAC_PI_2;
    let (mut stiff, mut steep) = (across.start, across.start);
    stiff.k_t = 1e10;
    steep.r_ba = 0.95;
    for p in [stiff, steep] {
        let sim = build(across.config, p, 0.0, 1e-6).unwrap();
        assert_eq!(sim.integrator(), Integrator::Radau);
    }
    let mut slanted = across.clone();
    slanted.start.angle = 0.5;
    let mut sprung = across.clone();
    sprung.config.drive = Drive::Spring;
    sprung.inputs.v_d = 0.01;
    sprung.model_identifier = "VibratingContactDupont, spring drive".into();
    let mut free = scene("paper-transverse.toml");
    free.config.law = Law::Dupont;
    free.model_identifier = "PaperTransverse on Dupont".into();
    let mut lugre = scene("rig-longitudinal.toml");
    lugre.config.law = Law::LuGre;
    lugre.model_identifier = "RigLongitudinal on LuGre".into();
    for scene in [across, slanted, sprung, free, lugre] {
        let name = format!("{} at {} rad", scene.model_identifier, scene.start.angle);
        let Nominal {
            f_c,
            s_ss,
            v_nom,
            x_nom,
        } = Nominal::of(&scene);
        let mut sim = Setup::new(scene.config, scene.start)
            .inputs(scene.inputs)
            .tolerance(1e-10)
            .build()
            .unwrap();
        let mut fast = vec![];
        for k in 1..=50 {
            sim.step_to(k as f64 * 1e-3).unwrap();
            assert_eq!(sim.integrator(), Integrator::ExplicitPlanar, "{name}");
            fast.push(sim.outputs());
        }
        assert_eq!(sim.stats().jacobians, 0, "{name}");
        let (radau, _) = run(&scene, Integrator::Radau, 1e-10, false);
        let (truth, _) = run(&scene, Integrator::Radau, 1e-12, false);
        let worst = |a: &[Outputs], f: &dyn Fn(&Outputs) -> f64| {
            a.iter()
                .zip(&truth)
                .map(|(x, y)| (f(x) - f(y)).abs())
                .fold(0.0, f64::max)
        };
        let quantities: [Quantity; 9] = [
            ("F_Fx", &|o| o.f_fx, f_c),
            ("F_Fy", &|o| o.f_fy, f_c),
            ("F_mean", &|o| o.f_mean, f_c),
            ("s_x", &|o| o.s_x, s_ss),
            ("s_y", &|o| o.s_y, s_ss),
            ("x", &|o| o.x, x_nom),
            ("y", &|o| o.y, x_nom),
            ("v_x", &|o| o.v_x, v_nom),
            ("v_y", &|o| o.v_y, v_nom),
        ];
        for (q, f, scale) in quantities {
            let (path_err, radau_err) = (worst(&fast, f), worst(&radau, f));
            // Positions on the vibration's scale and the distance the body travelled.
            let scale = match q {
                "x" | "y" => scale + truth.iter().map(|o| f(o).abs()).fold(0.0, f64::max),
                _ => scale,
            };
            assert!(
                path_err <= radau_err.max(1e-10 * scale),
                "{name}: {q} {:.2e} of its scale against Radau's {:.2e}",
                path_err / scale,
                radau_err / scale
            );
        }
    }
}

/// `scene` on its path (which must be `path`) at tolerance 1e-10 against Radau at 1e-12: both
/// friction components, their window and step means, the deformation and the body's position
/// and velocity in x and y within 1e-9 of their scales. The outputs of the path's run, each
/// with its label.
fn agrees_with_radau_at_1e_12(scene: &Scene, path: Integrator) -> Vec<(String, Outputs)> {
    let Nominal {
        f_c,
        s_ss,
        v_nom,
        x_nom,
    } = Nominal::of(scene);
    let (fast, taken) = run(scene, Integrator::ClosedForm, 1e-10, false);
    assert_eq!(taken, path);
    let (radau, _) = run(scene, Integrator::Radau, 1e-12, false);
    let (name, k_t) = (&scene.model_identifier, scene.start.k_t);
    let mut out = vec![];
    for (k, (a, b)) in fast.iter().zip(&radau).enumerate() {
        let what = format!("{name} k_t {k_t:e} at {} ms", k + 1);
        for (q, x, y, bound) in [
            ("F_Fx", a.f_fx, b.f_fx, 1e-9 * f_c),
            ("F_Fy", a.f_fy, b.f_fy, 1e-9 * f_c),
            ("F_mean", a.f_mean, b.f_mean, 1e-9 * f_c),
            ("F_Fx_step", a.f_fx_step, b.f_fx_step, 1e-9 * f_c),
            ("F_Fy_step", a.f_fy_step, b.f_fy_step, 1e-9 * f_c),
            ("s_x", a.s_x, b.s_x, 1e-9 * s_ss),
            ("s_y", a.s_y, b.s_y, 1e-9 * s_ss),
            ("x", a.x, b.x, 1e-9 * (x_nom + b.x.abs())),
            ("y", a.y, b.y, 1e-9 * (x_nom + b.y.abs())),
            ("v_x", a.v_x, b.v_x, 1e-9 * (v_nom + b.v_x.abs())),
            ("v_y", a.v_y, b.v_y, 1e-9 * (v_nom + b.v_y.abs())),
        ] {
            assert!((x - y).abs() <= bound, "{what}: {q} {x} vs {y}");
        }
        out.push((what, *a));
    }
    out
}

/// One step over many periods of 2 kHz vibration with the inputs held costs O(1) and equals
/// stepping the same time period by period: 1e6 periods on the closed form, 2e4 on the
/// exponential path (its stepping costs about 17 µs a period at tolerance 1e-8).
#[test]
fn a_step_over_a_million_periods_equals_stepping_them() {
    for (file, periods) in [
        ("paper-longitudinal.toml", 1_000_000u64),
        ("paper-transverse-guided.toml", 20_000),
    ] {
        let scene = scene(file);
        let tol = 1e-8;
        let t_end = periods as f64 / scene.start.f;
        let start = |sim: &mut Box<dyn Simulator>| {
            sim.set_input(InputId::VD, scene.inputs.v_d).unwrap();
        };
        let mut one = build(scene.config, scene.start, 0.0, tol).unwrap();
        start(&mut one);
        one.step_to(t_end).unwrap();
        // O(1): two windows integrated, not millions.
        assert!(one.stats().steps < 200, "{file}: {:?}", one.stats());

        let mut each = build(scene.config, scene.start, 0.0, tol).unwrap();
        start(&mut each);
        let period = 1.0 / scene.start.f;
        for k in 1..=periods {
            each.step_to(k as f64 * period).unwrap();
        }
        let (a, b) = (one.outputs(), each.outputs());
        let f_c = scene.start.f_c();
        let s_ss = f_c / scene.start.k_t;
        for (q, x, y, scale) in [
            ("F_mean", a.f_mean, b.f_mean, f_c),
            ("F_Fx", a.f_fx, b.f_fx, f_c),
            ("F_Fy", a.f_fy, b.f_fy, f_c),
            ("s_x", a.s_x, b.s_x, s_ss),
            ("s_y", a.s_y, b.s_y, s_ss),
        ] {
            assert!((x - y).abs() <= tol * scale, "{file}: {q} {x} vs {y}");
        }
        // x = v_d·t exactly in one step; stepping adds rounded increments.
        assert!(
            (a.x - b.x).abs() <= periods as f64 * f64::EPSILON * b.x.abs(),
            "{file}: x {} vs {}",
            a.x,
            b.x
        );
        assert_eq!(a.x, scene.inputs.v_d * t_end);
    }
}

/// A body held by a force drive within Dupont's breakaway, without vibration: it rings on the
/// contact without loss and its deformation stays elastic, which the explicit path steps in
/// closed form (one step per call). Against Radau at 1e-12 over 20 ms at `k_t` = 1e8, and at
/// 1e12 the same number of steps as at 1e8 over 1 s (Radau needs two million there).
#[test]
fn a_stuck_dupont_body_rings_in_closed_form() {
    let dupont = scene("contact-dupont.toml");
    for k_t in [1e8, 1e12] {
        let mut scene = dupont.clone();
        scene.start.k_t = k_t;
        scene.start.u0 = 0.0;
        // 2 N from rest: s rings between 0 and 4 N/k_t, below s_ba = 5 N/k_t.
        scene.inputs.f_d = 2.0;
        let build = |path: Integrator, tol: f64| {
            Setup::new(scene.config, scene.start)
                .inputs(scene.inputs)
                .tolerance(tol)
                .force_radau(path == Integrator::Radau)
                .build()
                .unwrap()
        };
        let mut fast = build(Integrator::ClosedForm, 1e-6);
        assert_eq!(fast.integrator(), Integrator::Explicit);
        if k_t == 1e8 {
            let mut radau = build(Integrator::Radau, 1e-12);
            let f_c = scene.start.f_c();
            for k in 1..=20 {
                let t = k as f64 * 1e-3;
                fast.step_to(t).unwrap();
                radau.step_to(t).unwrap();
                let (a, b) = (fast.outputs(), radau.outputs());
                for (q, x, y) in [
                    ("F_Fx", a.f_fx, b.f_fx),
                    ("F_mean", a.f_mean, b.f_mean),
                    ("F_Fx_step", a.f_fx_step, b.f_fx_step),
                ] {
                    assert!((x - y).abs() <= 1e-9 * f_c, "{t} s: {q} {x} vs {y}");
                }
                assert!((a.v_x - b.v_x).abs() <= 1e-9 * 2e-4, "{t} s: v_x");
                assert!(
                    a.s_x.abs() < 4.0 / k_t * (1.0 + 1e-9),
                    "{t} s: s_x {}",
                    a.s_x
                );
            }
        } else {
            for k in 1..=1000 {
                fast.step_to(k as f64 * 1e-3).unwrap();
            }
            // One closed-form step per averaging window (0.5 ms) at both stiffnesses.
            assert_eq!(fast.stats().steps, 2000);
            assert_eq!(fast.stats().rejected, 0);
        }
    }
}

/// The planar explicit path's work at tight tolerances on a stiff contact: plain steps, whose
/// error in the relaxing deformation grows as the fifth power of the relaxation per step, must
/// hand over to the exponential step before the error control holds them below it
/// (PaperTransverse at `k_t` = 1e11, 10 ms: about 14,000 steps at tolerance 1e-11 and 24,000
/// at 1e-12; with a fixed threshold, 600,000 and 940,000).
#[test]
fn tight_tolerances_keep_the_planar_path_s_steps_bounded() {
    let mut scene = scene("paper-transverse.toml");
    scene.start.k_t = 1e11;
    for tol in [1e-10, 1e-11, 1e-12] {
        let mut sim = Setup::new(scene.config, scene.start)
            .inputs(scene.inputs)
            .tolerance(tol)
            .build()
            .unwrap();
        assert_eq!(sim.integrator(), Integrator::ExplicitPlanar);
        for k in 1..=100 {
            sim.step_to(k as f64 * 1e-4).unwrap();
        }
        let steps = sim.stats().steps + sim.stats().rejected;
        assert!(
            steps < 50_000,
            "tol {tol:e}: {steps} attempted steps in 10 ms"
        );
    }
}

/// `scene` at the contact stiffness `k_t` on `path` at tolerance `tol` for `n` communication
/// steps of 1 ms: the outputs after each, and the simulator.
fn run_at_stiffness(
    scene: &Scene,
    k_t: f64,
    tol: f64,
    path: Integrator,
    n: usize,
) -> (Vec<Outputs>, Box<dyn Simulator>) {
    let p = vibrofric::table::Params { k_t, ..scene.start };
    let mut sim = Setup::new(scene.config, p)
        .inputs(scene.inputs)
        .tolerance(tol)
        .force_radau(path == Integrator::Radau)
        .build()
        .unwrap();
    let mut out = vec![];
    for k in 1..=n {
        sim.step_to(k as f64 * 1e-3).unwrap();
        out.push(sim.outputs());
    }
    (out, sim)
}

/// The planar explicit path on a stiff Dahl contact takes its step on the Coulomb limit's slow
/// manifold (the body alone, the deformation a function of its motion) wherever that is
/// certified: RigTransverse and PaperTransverse at `k_t` = 1e11 and 1e12, tolerances 1e-6 and
/// 1e-8, against Radau IIA at 1e-10 (an independent reference; it and the path at 1e-12 agree to
/// 6e-10 of `F_C`), over 20 ms in communication steps of 1 ms: `F_Fx` and `F_Fy` within a
/// fifth of the tolerance of `F_C` (plus the reference's own error) at every communication
/// point, the deformation on the manifold's side of `|s| ≤ s_ss`, and the manifold's steps
/// counted. A state saved on the manifold and restored continues bit for bit.
#[test]
fn coulomb_limit_agrees_with_radau_at_1e_10() {
    let n = 20;
    let run = |scene: &Scene, k_t: f64, tol: f64, path: Integrator| {
        run_at_stiffness(scene, k_t, tol, path, n)
    };
    for file in ["rig-transverse.toml", "paper-transverse.toml"] {
        let scene = scene(file);
        for k_t in [1e11, 1e12] {
            let f_c = scene.start.f_c();
            let s_ss = f_c / k_t;
            let (reference, _) = run(&scene, k_t, 1e-10, Integrator::Radau);
            for tol in [1e-6, 1e-8] {
                let (out, sim) = run(&scene, k_t, tol, Integrator::ClosedForm);
                let what = format!("{file} k_t {k_t:e} tol {tol:e}");
                assert_eq!(sim.integrator(), Integrator::ExplicitPlanar, "{what}");
                let bound = (0.2 * tol + 2e-9) * f_c;
                for (k, (a, b)) in out.iter().zip(&reference).enumerate() {
                    for (q, x, y) in [("F_Fx", a.f_fx, b.f_fx), ("F_Fy", a.f_fy, b.f_fy)] {
                        assert!(
                            (x - y).abs() <= bound,
                            "{what} at {} ms: {q} {x} vs {y}",
                            k + 1
                        );
                    }
                    // On the manifold of a body sliding at `|v_r| ≥ v_d` the deformation is
                    // the Coulomb limit's, `s_ss` less a relative `|z1|²/2` (`|z1| ≤ 1e-2`).
                    if file == "paper-transverse.toml" && k_t == 1e12 {
                        let rel = a.s_x.hypot(a.s_y) / s_ss;
                        assert!((1.0 - 1e-4..=1.0).contains(&rel), "{what}: |s|/s_ss {rel}");
                    }
                }
                let stats = sim.stats();
                // The manifold is certified at 1e12 (PaperTransverse: |v_r| ≥ v_d throughout,
                // nearly every step; RigTransverse: away from its start's slow sliding), and
                // at 1e11 at the looser tolerance only.
                let share = stats.limit_steps as f64 / stats.steps as f64;
                let least = match (file, k_t == 1e12, tol == 1e-6) {
                    ("paper-transverse.toml", true, _) => Some(0.35),
                    (_, true, _) => Some(0.05),
                    (_, false, true) => Some(0.01),
                    // At 1e11 and 1e-8 the certificate rarely holds: no share is promised.
                    _ => None,
                };
                if let Some(least) = least {
                    assert!(share >= least, "{what}: {stats:?}");
                }
            }
        }
    }
    // A state saved on the manifold (PaperTransverse at 1e12) continues bit for bit.
    // (LuGre's manifold: `lugre_coulomb_limit_agrees_with_radau_at_1e_10`.)
    let scene = scene("paper-transverse.toml");
    let (_, mut a) = run(&scene, 1e12, 1e-6, Integrator::ClosedForm);
    assert!(a.stats().limit_steps > 0);
    let snap = a.snapshot();
    // `b` restored from a later state of its own, `c` from a simulator just built.
    let (_, mut b) = run(&scene, 1e12, 1e-6, Integrator::ClosedForm);
    b.step_to(n as f64 * 1e-3 + 3.3e-3).unwrap();
    b.restore(&snap).unwrap();
    let mut c = build(scene.config, scene.start, 0.0, 1e-6).unwrap();
    c.restore(&snap).unwrap();
    for k in 1..=5 {
        let t = (n as f64 + 0.7 * k as f64) * 1e-3;
        a.step_to(t).unwrap();
        b.step_to(t).unwrap();
        c.step_to(t).unwrap();
        let (oa, ob, oc) = (a.outputs(), b.outputs(), c.outputs());
        assert_eq!(format!("{oa:?}"), format!("{ob:?}"));
        assert_eq!(format!("{oa:?}"), format!("{oc:?}"));
        assert_eq!(oa.f_fy.to_bits(), oc.f_fy.to_bits());
    }
}

/// A LuGre contact in longitudinal motion is the planar one whose motion stays on the x axis:
/// VibratingContactLuGre with `motion = "longitudinal"` takes the planar explicit path's steps
/// in one dimension, and its outputs are those of the planar scene to the last bit, at the
/// scene's stiffness and on the slow manifold at 1e12, tolerances 1e-6 and 1e-8, over 30 ms.
#[test]
fn longitudinal_lugre_takes_the_planar_paths_steps_on_the_axis() {
    let planar = scene("contact-lugre.toml");
    let mut line = planar.clone();
    line.config.motion = Motion::Longitudinal;
    for k_t in [1e8, 1e12] {
        for tol in [1e-6, 1e-8] {
            let sims = [&planar, &line].map(|s| {
                let p = Params { k_t, ..s.start };
                Setup::new(s.config, p)
                    .inputs(s.inputs)
                    .tolerance(tol)
                    .build()
                    .unwrap()
            });
            let [mut a, mut b] = sims;
            assert_eq!(b.integrator(), Integrator::ExplicitPlanar);
            for k in 1..=30 {
                let t = k as f64 * 1e-3;
                a.step_to(t).unwrap();
                b.step_to(t).unwrap();
                let (oa, ob) = (a.outputs(), b.outputs());
                for (x, y) in [
                    (oa.f_fx, ob.f_fx),
                    (oa.f_mean, ob.f_mean),
                    (oa.x, ob.x),
                    (oa.v_x, ob.v_x),
                    (oa.s_x, ob.s_x),
                ] {
                    assert_eq!(x.to_bits(), y.to_bits(), "k_t {k_t}, tol {tol}, {t} s");
                }
            }
            assert_eq!(a.stats().steps, b.stats().steps);
        }
    }
}

/// The path's step on a stiff LuGre contact's slow manifold on the x axis (VibratingContactLuGre
/// at `k_t` = 1e11 and 1e12, where the contact damping `2·sqrt(m·k_t)` makes a stuck body's
/// motion 130 and 420 times faster than the window), over 20 ms in communication steps of 1 ms
/// at tolerances 1e-6 and 1e-8, against Radau IIA at 1e-10: `F_Fx` at every communication
/// point at least as close to it as Radau at the same tolerance (within the reference's own
/// error, 2e-9 of `F_C`), the window mean within 20 tolerances of `F_C` (it follows the body's
/// momentum over the window, whose global error here is larger than Radau's: 12 tolerances
/// measured at 1e11 and 1e-8 against Radau's 2), the manifold's steps counted, and a state
/// saved on the manifold continuing bit for bit.
#[test]
fn lugre_coulomb_limit_agrees_with_radau_at_1e_10() {
    let n = 20;
    let scene = scene("contact-lugre.toml");
    let run = |k_t: f64, tol: f64, path: Integrator| run_at_stiffness(&scene, k_t, tol, path, n);
    let f_c = scene.start.f_c();
    let worst = |a: &[Outputs], b: &[Outputs], f: fn(&Outputs) -> f64| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (f(x) - f(y)).abs())
            .fold(0.0, f64::max)
    };
    for k_t in [1e11, 1e12] {
        let (reference, _) = run(k_t, 1e-10, Integrator::Radau);
        for tol in [1e-6, 1e-8] {
            let what = format!("k_t {k_t:e} tol {tol:e}");
            let (out, sim) = run(k_t, tol, Integrator::ClosedForm);
            assert_eq!(sim.integrator(), Integrator::ExplicitPlanar, "{what}");
            let (radau, _) = run(k_t, tol, Integrator::Radau);
            let (fx, fx_radau) = (
                worst(&out, &reference, |o| o.f_fx),
                worst(&radau, &reference, |o| o.f_fx),
            );
            assert!(
                fx <= fx_radau + 2e-9 * f_c,
                "{what}: F_Fx {fx:e} vs Radau's {fx_radau:e}"
            );
            let mean = worst(&out, &reference, |o| o.f_mean);
            assert!(mean <= 20.0 * tol * f_c, "{what}: F_mean {mean:e}");
            let stats = sim.stats();
            assert!(stats.limit_steps > 0, "{what}: {stats:?}");
        }
    }
    let (_, mut a) = run(1e12, 1e-6, Integrator::ClosedForm);
    let snap = a.snapshot();
    let p = vibrofric::table::Params {
        k_t: 1e12,
        ..scene.start
    };
    let mut c = build(scene.config, p, 0.0, 1e-6).unwrap();
    c.restore(&snap).unwrap();
    for k in 1..=5 {
        let t = (n as f64 + 0.7 * k as f64) * 1e-3;
        a.step_to(t).unwrap();
        c.step_to(t).unwrap();
        assert_eq!(format!("{:?}", a.outputs()), format!("{:?}", c.outputs()));
    }
}

/// A stiff contact whose body the vibration does not keep sliding may stick for long, where an
/// explicit method steps at the contact's stability bound: Radau IIA takes a stiff Dahl or
/// LuGre contact held by a force drive without vibration (Dupont keeps its closed form), and a
/// LuGre contact damped beyond what the axial path was measured at. Held at `F_d` = 2 N below
/// the Coulomb force from rest for 0.2 s at `k_t` = 1e12, each body sticks: its friction force
/// balances the drive (`F_Fx = F_d` within 1e-6 of `F_C` after 20 ms, `F_mean` likewise) at
/// every communication step, in a bounded number of steps.
#[test]
fn held_stiff_contacts_take_radau_and_stick() {
    for (file, path) in [
        ("contact.toml", Integrator::Radau),
        ("contact-lugre.toml", Integrator::Radau),
        ("contact-dupont.toml", Integrator::Explicit),
    ] {
        let mut scene = scene(file);
        scene.start.k_t = 1e12;
        scene.start.u0 = 0.0;
        scene.inputs.f_d = 2.0;
        let mut sim = Setup::new(scene.config, scene.start)
            .inputs(scene.inputs)
            .tolerance(1e-6)
            .build()
            .unwrap();
        assert_eq!(sim.integrator(), path, "{file}");
        let f_c = scene.start.f_c();
        for k in 1..=200 {
            sim.step_to(k as f64 * 1e-3).unwrap();
            let o = sim.outputs();
            if k > 20 {
                // Dupont rings without loss on the contact (its own test checks the ring).
                if path == Integrator::Radau {
                    assert!((o.f_fx - 2.0).abs() <= 1e-6 * f_c, "{file} {k} ms: {o:?}");
                    assert!((o.f_mean - 2.0).abs() <= 1e-6 * f_c, "{file} {k} ms: {o:?}");
                }
                assert!(o.s_x.abs() <= 1.3 * f_c / 1e12, "{file} {k} ms: {o:?}");
            }
        }
        let steps = sim.stats().steps;
        assert!(steps < 20_000, "{file}: {steps} steps in 0.2 s");
    }
    // Vibrated, the stiff LuGre contact keeps the path on the x axis at the default damping
    // ratio, and Radau takes it thirty times as damped.
    let mut scene = scene("contact-lugre.toml");
    scene.start.k_t = 1e12;
    let sim = build(scene.config, scene.start, 0.0, 1e-6).unwrap();
    assert_eq!(sim.integrator(), Integrator::ExplicitPlanar);
    scene.start.zeta_t = 30.0;
    let sim = build(scene.config, scene.start, 0.0, 1e-6).unwrap();
    assert_eq!(sim.integrator(), Integrator::Radau);
}
