//! AFL++ target: the OBJ reader with an MTL library (plain and gzip-compressed OBJ).
fn main() {
    afl::fuzz!(|data: &[u8]| tracer_fuzz::obj(data));
}
