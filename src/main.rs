fn main() -> std::process::ExitCode {
    beamflow::app::cli::main()
}
