//! The `physframes` command. All the work is in the library; see `physframes --help`.

fn main() -> std::process::ExitCode {
    physframes::cli::main()
}
