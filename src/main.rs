//! `lorentz`: the command-line face of lorentz-gas. Parsing and dispatch only; see [`cli`].

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
