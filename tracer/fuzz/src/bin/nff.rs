//! AFL++ target: the NFF reader (plain and gzip-compressed).
fn main() {
    afl::fuzz!(|data: &[u8]| tracer_fuzz::nff(data));
}
