//! libFuzzer target: arbitrary bytes decoded by `crates/uvflat-capi/fuzz/src/decode.rs` into a mesh and options
//! for the C entry point(s) of this family; any contract violation panics (a finding).
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../src/decode.rs"]
mod decode;

fuzz_target!(|data: &[u8]| {
    if let Err(violation) = decode::run(decode::Target::Metrics, data) {
        panic!("contract violation: {violation}");
    }
});
