//! Drives every FMU of a folder through one fixed sequence of calls and prints what comes back
//! as exact bits: outputs of FMI 2.0 and 3.0 Co-Simulation, the serialized FMU state (FMI 2.0
//! and 3.0) after a step, and, through FMI 2.0 Model Exchange, the states, derivatives and
//! event indicators at the start. Two builds of the library that must behave the same (a
//! restructuring, another platform) must print the same text:
//!
//! `cargo run --release -p vibrofric-import --example golden_calls -- dist > before.txt`

use std::path::Path;
use std::process::ExitCode;

use vibrofric_import::fmi3::Fmu3;
use vibrofric_import::{Fmu, Status};

fn hex(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{:016x}", x.to_bits()))
        .collect::<Vec<_>>()
        .join(" ")
}

fn bytes(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

fn ok(s: Status, what: &str) -> Result<(), String> {
    if s <= Status::Warning {
        Ok(())
    } else {
        Err(format!("{what} returned {s:?}"))
    }
}

fn run(dir: &Path) -> Result<usize, String> {
    let mut n = 0;
    for path in vibrofric_import::fmus_in(dir)? {
        let fmu = Fmu::load(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let id = fmu.description.model_identifier.clone();
        let vrs: Vec<u32> = fmu.description.variables.iter().map(|v| v.vr).collect();
        // Co-Simulation, FMI 2.0: every variable after each of 7 steps, then the state.
        let mut inst = fmu
            .instantiate("golden")
            .map_err(|e| format!("{id}: {e}"))?;
        ok(inst.setup_experiment(None, 0.0, None), "setup")?;
        ok(inst.enter_initialization_mode(), "enter")?;
        ok(inst.exit_initialization_mode(), "exit")?;
        let mut t = 0.0;
        for h in [1e-3, 3.7e-4, 2e-3, 1e-5, 5e-3, 1e-3, 0.02] {
            ok(inst.do_step(t, h), "doStep")?;
            t += h;
            let y = inst
                .get_real(&vrs)
                .map_err(|s| format!("{id} getReal {s:?}"))?;
            println!("{id} cs2 t={t} {}", hex(&y));
        }
        let st = inst
            .get_state()
            .map_err(|s| format!("{id} getState {s:?}"))?;
        let b = inst
            .serialize_state(&st)
            .map_err(|s| format!("{id} serialize {s:?}"))?;
        println!("{id} cs2 state {}", bytes(&b));
        ok(inst.free_state(st), "freeState")?;
        drop(inst);
        // Model Exchange, FMI 2.0: the start, and the derivatives with every state moved.
        let mut me = fmu
            .instantiate_model_exchange("golden")
            .map_err(|e| format!("{id}: {e}"))?;
        ok(me.setup_experiment(None, 0.0, None), "setup")?;
        ok(me.enter_initialization_mode(), "enter")?;
        ok(me.exit_initialization_mode(), "exit")?;
        let (s, _) = me.new_discrete_states();
        ok(s, "newDiscreteStates")?;
        ok(me.enter_continuous_time_mode(), "continuous")?;
        let nx = fmu
            .description
            .variables
            .iter()
            .filter(|v| v.name.starts_with("der("))
            .count();
        if nx > 0 {
            ok(me.set_time(1.234e-3), "setTime")?;
            let dx = me
                .get_derivatives(nx)
                .map_err(|s| format!("{id} der {s:?}"))?;
            println!("{id} me2 nx={nx} der {}", hex(&dx));
            let y = me
                .get_real(&vrs)
                .map_err(|s| format!("{id} getReal {s:?}"))?;
            println!("{id} me2 values {}", hex(&y));
            let nz = fmu
                .description
                .variables
                .iter()
                .filter(|v| v.name.starts_with("event."))
                .count();
            let z = me
                .get_event_indicators(nz)
                .map_err(|s| format!("{id} z {s:?}"))?;
            println!("{id} me2 nz={nz} {}", hex(&z));
        }
        drop(me);
        // Co-Simulation, FMI 3.0.
        let path3 = dir.join("fmi3").join(path.file_name().unwrap_or_default());
        if path3.is_file() {
            let fmu3 = Fmu3::load(&path3).map_err(|e| format!("{}: {e}", path3.display()))?;
            // FMI 3.0's own variables (arrays whole), but the independent time.
            let vars3 = fmu3.description.variables.iter().filter(|v| v.vr != 0);
            let vrs3: Vec<u32> = vars3.clone().map(|v| v.vr).collect();
            let n3: usize = vars3.map(|v| v.size).sum();
            let mut i3 = fmu3
                .instantiate("golden")
                .map_err(|e| format!("{id}: {e}"))?;
            ok(i3.enter_initialization_mode(None, 0.0, None), "enter3")?;
            ok(i3.exit_initialization_mode(), "exit3")?;
            let mut t = 0.0;
            for h in [1e-3, 3.7e-4, 2e-3, 0.02] {
                let (s, _) = i3.do_step(t, h);
                ok(s, "doStep3")?;
                t += h;
                let y = i3
                    .get_f64_values(&vrs3, n3)
                    .map_err(|s| format!("{id} get3 {s:?}"))?;
                println!("{id} cs3 t={t} {}", hex(&y));
            }
            let st = i3
                .get_state()
                .map_err(|s| format!("{id} getState3 {s:?}"))?;
            let b = i3
                .serialize_state(&st)
                .map_err(|s| format!("{id} ser3 {s:?}"))?;
            println!("{id} cs3 state {}", bytes(&b));
            ok(i3.free_state(st), "freeState3")?;
        }
        eprintln!("{id}: done");
        n += 1;
    }
    Ok(n)
}

fn main() -> ExitCode {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "dist".into());
    match run(Path::new(&dir)) {
        Ok(n) if n > 0 => ExitCode::SUCCESS,
        Ok(_) => {
            eprintln!("golden_calls: no *.fmu in {dir}");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("golden_calls: {e}");
            ExitCode::FAILURE
        }
    }
}
