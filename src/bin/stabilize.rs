//! The `stabilize` command-line tool (feature `cli`).

fn main() {
    eprintln!("stabilize: no subcommand is implemented yet");
    std::process::exit(2);
}
