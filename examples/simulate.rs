//! The core's reference run of a scene as CSV (see `vibrofric::cli_simulate`):
//! `cargo run --release --example simulate -- SCENE.toml --step H --stop T [--set NAME=VALUE]...`

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match vibrofric::cli_simulate::run(&args) {
        Ok(csv) => print!("{csv}"),
        Err(e) => {
            eprintln!("simulate: {e}");
            std::process::exit(2);
        }
    }
}
