fn main() -> std::process::ExitCode {
    krlkit::cli::main()
}
