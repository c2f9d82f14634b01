//! The two configurations the stability matrix exercises (tests and report share them), and the
//! drill string the string's tests and benchmark share.
#![allow(dead_code)]

use vibrofric::model::string::StringParams;
use vibrofric::model::{Config, Drive, Lateral, Law, Motion};
use vibrofric::table::Params;

/// Longitudinal contact under velocity drive with the harmonic source: the paper's setting.
pub fn long_velocity(law: Law) -> Config {
    Config {
        law,
        motion: Motion::Longitudinal,
        drive: Drive::Velocity,
        lateral: Lateral::Guided,
        harmonic: true,
        input_support: false,
        normal_input: false,
    }
}

/// Planar contact under force drive with harmonic and input support: the default scene.
pub fn planar_force(law: Law) -> Config {
    Config {
        law,
        motion: Motion::Planar,
        drive: Drive::Force,
        lateral: Lateral::Guided,
        harmonic: true,
        input_support: true,
        normal_input: false,
    }
}

/// `n` sections of 5-inch drill pipe (10 m, 267 kg, EA/L = 7.1e7 N/m, links damped by
/// 2e3 N·s/m), each on the wall with 2.28 kN at mu = 0.3, LuGre's `F_S = 1.3·F_C` at that load
/// and k_t = 1e8; the top held by a spring–dashpot (1e6 N/m, 1e4 N·s/m), the bit a
/// spring–dashpot on the rock (1e7 N/m, 1e4 N·s/m); no step budget.
pub fn drill_pipe(n: usize) -> StringParams {
    let mut shared = Params {
        m: 267.0,
        f_n: 2280.0,
        mu: 0.3,
        k_t: 1e8,
        f_s: 1.3 * 0.3 * 2280.0,
        ..Params::default()
    };
    shared.f_n_ref = shared.f_n;
    shared.mu_ref = shared.mu;
    shared.max_steps = 1e9;
    let mut p = StringParams::uniform(n, shared, 7.1e7, 2e3);
    p.links.k_top = 1e6;
    p.links.c_top = 1e4;
    p.links.k_bottom = 1e7;
    p.links.c_bottom = 1e4;
    p
}
