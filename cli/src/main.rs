//! The `satflock` binary: the command line of the library half ([`satflock_cli::main_with`]) with the
//! built-in laws.

fn main() -> std::process::ExitCode {
    satflock_cli::main_with(satflock::guidance::LawRegistry::builtin())
}
