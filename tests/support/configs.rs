//! The two configurations the stability matrix exercises (tests and report share them).
#![allow(dead_code)]

use vibrofric::model::{Config, Drive, Lateral, Law, Motion};

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
