//! AFL++ target: the command line, every check before the first ray
//! ([`tracer_cli::fuzz`]), in a sandbox directory under the system's temporary one.
fn main() {
    let tracer = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = std::env::temp_dir().join(format!("tracer-cli-fuzz-{}", std::process::id()));
    let sandbox = tracer_cli::fuzz::Sandbox::new(&dir, &tracer).expect("cannot make the sandbox");
    afl::fuzz!(|data: &[u8]| {
        sandbox.run(data);
    });
}
