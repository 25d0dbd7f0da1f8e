//! The `nffrt` command line: argument parsing, timing and error reporting only.

mod cli;

fn main() {
    std::process::exit(cli::run());
}
