//! What the fuzz targets feed the scene readers; shared by the AFL binaries and the
//! corpus replay test (`tracer/tests/fuzz_replay.rs` keeps its own copy of the two
//! functions, since the tracer's tests cannot depend on this package).

use tracer::scene::{parse_nff_for, parse_obj, ObjOptions, Precision};

/// One NFF input, read for both precisions. Errors are expected; panics are bugs.
pub fn nff(data: &[u8]) {
    for precision in [Precision::F32, Precision::F64] {
        let _ = parse_nff_for(data, "fuzz.nff", precision);
    }
}

/// One OBJ input: the bytes up to the first NUL are the OBJ file (gzip-compressed or
/// not), the bytes after it the contents of every material library it names.
pub fn obj(data: &[u8]) {
    let (obj, mtl) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    for precision in [Precision::F32, Precision::F64] {
        let library = |_: &str| Ok(mtl.to_vec());
        let _ = parse_obj(obj, "fuzz.obj", &ObjOptions::default(), precision, library);
    }
}
