//! "With N = 1 and free ends the string is the single scene bit for bit": a string scene of one
//! section whose end elements are 0 (`k_top = c_top = k_bottom = c_bottom = 0`) and the same
//! scene without `[string]` (same law, normal force, support, start values), both FMUs built
//! around this test run's library and driven alike through `vibrofric_import` (FMI 2.0
//! Co-Simulation): every step sets the driving force, the wall's velocity and, where it is an
//! input, the normal force (falling to 0 for a while: the section lifts off), and `x`, `v_x`,
//! `s_x`, `F_Fx`, `F_Fx_step` must be the same bit patterns after each of 200 steps of 1 ms.
//! A state saved from the string and restored into a fresh instance continues the same way;
//! an end element set in initialization mode takes the string's own integration (its ends then
//! hold the section).

mod support;

use support::fmu::{bits, ok, temp, unpack};
use vibrofric::description::xml_string::{self, Edition};
use vibrofric::description::Scene;
use vibrofric_import::{Fmu, Instance};

const H: f64 = 1e-3;
const STEPS: usize = 200;
const OUTPUTS: [&str; 5] = ["x", "v_x", "s_x", "F_Fx", "F_Fx_step"];

/// The value reference of `name` in a single scene, or of `name[1]` (or the scalar `name`) in a
/// string scene.
fn vr(scene: &Scene, name: &str) -> u32 {
    if scene.string.is_some() {
        let element = format!("{name}[1]");
        let rows = xml_string::rows(scene, Edition::Fmi2);
        let row = rows.iter().find(|r| r.name == element || r.name == name);
        return row
            .unwrap_or_else(|| panic!("no {element} in the string"))
            .vr;
    }
    let v = scene.variables().find(|v| v.name() == name);
    v.unwrap_or_else(|| panic!("no {name} in the scene")).vr
}

/// The scene's text, with `[string]` of one section and free ends when `string`.
fn text(head: &str, start: &str, string: bool) -> String {
    let (id, table, ends) = if string {
        (
            "One",
            "[string]\nsections = 1\n",
            "k_top = 0.0\nc_top = 0.0\nk_bottom = 0.0\nc_bottom = 0.0\n",
        )
    } else {
        ("Single", "", "")
    };
    format!("model_identifier = \"{id}\"\nmotion = \"longitudinal\"\ndrive = \"force\"\n{head}\n{table}[start]\n{start}\n{ends}")
}

/// An FMU of the scene text, unpacked in a temporary folder.
fn load(text: &str, tag: &str) -> (Fmu, Scene) {
    let dir = temp(tag);
    let scene = unpack(&dir, text);
    (Fmu::load(&dir).unwrap(), scene)
}

/// The inputs of step `k`: a driving force of the order of the Coulomb force `f_c`, pushing
/// forwards and back at 5 Hz, the wall's velocity (reversing at 15 Hz), and the normal force relative to its start value (0 from step 80 to 110).
fn inputs(k: usize, f_c: f64) -> (f64, f64, f64) {
    let t = k as f64 * H;
    let f_d = f_c * (0.9 * (0.7 * k as f64).sin() + 0.8 * (std::f64::consts::TAU * 5.0 * t).cos());
    let v_sx = 0.02 * (std::f64::consts::TAU * 15.0 * t).sin();
    let load = if (80..110).contains(&k) {
        0.0
    } else {
        1.0 + 0.3 * (0.3 * k as f64).cos()
    };
    (f_d, v_sx, load)
}

/// Sets the inputs of step `k` (`f_n0` the start load, where the normal force is an input).
fn set_inputs(i: &mut Instance, scene: &Scene, k: usize, f_c: f64, f_n0: Option<f64>) {
    let (f_d, v_sx, load) = inputs(k, f_c);
    let mut vrs = vec![vr(scene, "F_d"), vr(scene, "v_sx")];
    let mut values = vec![f_d, v_sx];
    if let Some(f_n) = f_n0 {
        vrs.push(vr(scene, "F_N"));
        values.push(f_n * load);
    }
    let s = i.set_real(&vrs, &values);
    ok(i, s);
}

/// Runs steps `k0..k1` from `k0·H` and returns the outputs' bit patterns after each.
fn run(
    i: &mut Instance,
    scene: &Scene,
    ks: std::ops::Range<usize>,
    f_c: f64,
    f_n0: Option<f64>,
) -> Vec<Vec<u64>> {
    let outs: Vec<u32> = OUTPUTS.iter().map(|n| vr(scene, n)).collect();
    let mut rows = vec![];
    for k in ks {
        set_inputs(i, scene, k, f_c, f_n0);
        let s = i.do_step(k as f64 * H, H);
        ok(i, s);
        rows.push(bits(&i.get_real(&outs).unwrap()));
    }
    rows
}

/// Instantiates and starts at tolerance 1e-6 with `init` set in initialization mode.
fn start<'a>(fmu: &'a Fmu, name: &str, init: &[(u32, f64)]) -> Instance<'a> {
    let mut i = fmu.instantiate(name).unwrap();
    let s = i.setup_experiment(Some(1e-6), 0.0, None);
    ok(&i, s);
    let s = i.enter_initialization_mode();
    ok(&i, s);
    for &(vr, x) in init {
        let s = i.set_real(&[vr], &[x]);
        ok(&i, s);
    }
    let s = i.exit_initialization_mode();
    ok(&i, s);
    i
}

/// The first step (1-based) and output at which two runs differ.
fn first_difference(a: &[Vec<u64>], b: &[Vec<u64>]) -> Option<(usize, &'static str, f64, f64)> {
    a.iter().zip(b).enumerate().find_map(|(k, (ra, rb))| {
        (0..OUTPUTS.len()).find(|&j| ra[j] != rb[j]).map(|j| {
            (
                k + 1,
                OUTPUTS[j],
                f64::from_bits(ra[j]),
                f64::from_bits(rb[j]),
            )
        })
    })
}

/// The string of one section with free ends against the single scene, then a saved state of
/// the string continued in a fresh instance against the same single run.
fn check(tag: &str, head: &str, start_values: &str, f_c: f64, f_n0: Option<f64>) {
    let (single, s1) = load(&text(head, start_values, false), &format!("{tag}-single"));
    let (string, s2) = load(&text(head, start_values, true), &format!("{tag}-string"));
    let mut a = start(&single, "single", &[]);
    let want = run(&mut a, &s1, 0..STEPS, f_c, f_n0);
    let mut b = start(&string, "string", &[]);
    let got = run(&mut b, &s2, 0..STEPS / 2, f_c, f_n0);
    if let Some((k, name, x, y)) = first_difference(&got, &want[..STEPS / 2]) {
        panic!("{tag}: step {k}: {name} of the string {x:e}, of the single scene {y:e}");
    }
    // Saved there, serialized, restored into a fresh instance: the rest of the single run.
    let state = b.get_state().unwrap();
    let bytes = b.serialize_state(&state).unwrap();
    let mut c = start(&string, "restored", &[]);
    let restored = c.deserialize_state(&bytes).unwrap();
    let s = c.set_state(&restored);
    ok(&c, s);
    let rest = run(&mut c, &s2, STEPS / 2..STEPS, f_c, f_n0);
    if let Some((k, name, x, y)) = first_difference(&rest, &want[STEPS / 2..]) {
        panic!(
            "{tag}: restored string, step {}: {name} {x:e} against {y:e}",
            k + STEPS / 2
        );
    }
    // The single run moved: stuck and sliding, forwards and back.
    let j = OUTPUTS.iter().position(|n| *n == "v_x").unwrap();
    let speeds: Vec<f64> = want.iter().map(|r| f64::from_bits(r[j])).collect();
    let (lo, hi) = speeds
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(lo < -1e-3 && hi > 1e-3, "{tag}: v_x from {lo} to {hi} m/s");
}

#[test]
fn one_section_with_free_ends_is_the_single_lugre_scene_with_its_load_as_input() {
    // A section of 5-inch drill pipe on the wall, its load an input (lifting off for 30 ms).
    check(
        "lugre",
        "law = \"lugre\"\nnormal = \"input\"\nsupport = [\"input\"]",
        "m = 267.0\nF_N = 2280.0\nmu = 0.3\nF_S = 889.2",
        0.3 * 2280.0,
        Some(2280.0),
    );
}

#[test]
fn one_section_with_free_ends_is_the_single_dahl_scene_on_a_vibrating_wall() {
    check(
        "dahl",
        "law = \"dahl\"\nsupport = [\"harmonic\", \"input\"]",
        "m = 5.6\nu0 = 2e-6",
        0.2 * 55.0,
        None,
    );
}

#[test]
fn one_section_with_free_ends_is_the_single_dupont_scene() {
    check(
        "dupont",
        "law = \"dupont\"\nsupport = [\"input\"]",
        "m = 5.6",
        0.2 * 55.0,
        None,
    );
}

/// An end element set in initialization mode holds the section: the string is then no longer
/// the free single contact (the top spring pulls it back towards its start).
#[test]
fn an_end_set_in_initialization_mode_holds_the_section() {
    let head = "law = \"lugre\"\nnormal = \"input\"\nsupport = [\"input\"]";
    let start_values = "m = 267.0\nF_N = 2280.0\nmu = 0.3\nF_S = 889.2";
    let f_c = 0.3 * 2280.0;
    let (single, s1) = load(&text(head, start_values, false), "ends-single");
    let (string, s2) = load(&text(head, start_values, true), "ends-string");
    let mut a = start(&single, "single", &[]);
    let free = run(&mut a, &s1, 0..STEPS, f_c, Some(2280.0));
    let mut b = start(&string, "held", &[(vr(&s2, "k_top"), 1e6)]);
    let held = run(&mut b, &s2, 0..STEPS, f_c, Some(2280.0));
    assert!(first_difference(&held, &free).is_some());
    let f_top = b.get_real(&[vr(&s2, "F_top")]).unwrap()[0];
    let x = f64::from_bits(held[STEPS - 1][0]);
    // F_top = k_top·(x_top − x[1]) with x_top = 0 (v_top held at 0).
    assert_eq!(f_top, 1e6 * (0.0 - x));
    assert!(f_top != 0.0);
}
