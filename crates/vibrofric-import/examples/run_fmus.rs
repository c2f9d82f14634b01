//! Co-simulates every FMU of a folder (FMI 2.0 `*.fmu` and FMI 3.0 `fmi3/*.fmu`) with the
//! platform's own library inside it, and prints every output at every communication point as
//! the bits of its `f64`: the same program built for Linux and for Windows (run under Wine) must
//! print the same text (`tests/cross/test.sh` compares them).
//!
//! `cargo run --release -p vibrofric-import --example run_fmus -- dist [FMI3_DIR]`
//!
//! The FMI 3.0 editions are looked for in `FMI3_DIR`, by default `dist/fmi3`: on ARM Linux the
//! FMI 2.0 FMUs are those of `dist/aarch64-linux` (their `linux64` holds the aarch64 library) and
//! the FMI 3.0 ones those of `dist/fmi3` (`tests/cross/test.sh` runs it so under qemu).
//!
//! Each FMU runs its default experiment from its scene's start values (0.1 s, communication step
//! 1 ms) with every output read at every point (of a string, its FMI 2.0 edition only), twice:
//! the second time with 0.37 ms steps and, where the FMU has them, the inputs `F_d` and `v_sx`
//! set to other values than their start values.

use std::path::Path;
use std::process::ExitCode;

use vibrofric_import::fmi3::Fmu3;
use vibrofric_import::{Fmu, Importer};

fn print_rows(label: &str, rows: &[Vec<f64>]) {
    for row in rows {
        let bits: Vec<String> = row
            .iter()
            .map(|v| format!("{:016x}", v.to_bits()))
            .collect();
        println!("{label} {}", bits.join(" "));
    }
}

fn run(dir: &Path, dir3: &Path) -> Result<usize, String> {
    let mut n = 0;
    for path in vibrofric_import::fmus_in(dir)? {
        let fmu = Fmu::load(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let d = &fmu.description;
        // Every output; FMI 3.0 repeats the names and value references of FMI 2.0.
        let outputs: Vec<u32> = d
            .variables
            .iter()
            .filter(|v| v.causality == "output")
            .map(|v| v.vr)
            .collect();
        // `F_d` is an input under a force drive, an output under a spring drive.
        let inputs: Vec<(u32, f64)> = [("F_d", 7.5), ("v_sx", 1e-3)]
            .iter()
            .filter_map(|(name, x)| d.variables.iter().find(|v| v.name == *name).map(|v| (v, x)))
            .filter(|(v, _)| v.causality == "input")
            .map(|(v, x)| (v.vr, *x))
            .collect();
        let id = d.model_identifier.clone();
        for (step, set) in [(1e-3, &[][..]), (3.7e-4, &inputs[..])] {
            let rows = fmu
                .simulate(0.1, step, set, &outputs)
                .map_err(|e| format!("{id} (FMI 2.0): {e}"))?;
            print_rows(&format!("{id} fmi2 h={step}"), &rows);
        }
        let path3 = dir3.join(path.file_name().unwrap_or_default());
        // A string's FMI 3.0 edition reads its arrays whole (a value reference per array), which
        // this importer's scalar getter does not: its FMI 2.0 edition runs here on every
        // platform, and tests/python/test_string.py checks both editions equal bit for bit.
        let string = d.variables.iter().any(|v| v.name.contains('['));
        if path3.is_file() && !string {
            let fmu3 = Fmu3::load(&path3).map_err(|e| format!("{}: {e}", path3.display()))?;
            let rows = fmu3
                .simulate(0.1, 1e-3, &[], &outputs)
                .map_err(|e| format!("{id} (FMI 3.0): {e}"))?;
            print_rows(&format!("{id} fmi3 h=0.001"), &rows);
        }
        eprintln!("{id}: {} outputs co-simulated", outputs.len());
        n += 1;
    }
    Ok(n)
}

fn main() -> ExitCode {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "dist".into());
    let dir3 = std::env::args()
        .nth(2)
        .map_or_else(|| Path::new(&dir).join("fmi3"), Into::into);
    match run(Path::new(&dir), &dir3) {
        Ok(0) => {
            eprintln!("run_fmus: no *.fmu in {dir}");
            ExitCode::FAILURE
        }
        Ok(n) => {
            eprintln!(
                "run_fmus: {n} FMUs co-simulated on {} {}",
                std::env::consts::ARCH,
                std::env::consts::OS
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("run_fmus: {e}");
            ExitCode::FAILURE
        }
    }
}
