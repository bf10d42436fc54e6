//! A second Rust static library, as an application might link next to libuvflat.a: it carries
//! its own copy of the Rust runtime (rust_eh_personality, __rust_alloc, …), which clashes with
//! uvflat's unless uvflat's archive exports only its uvf_* functions.

/// The sum of 0..n, computed through a heap allocation and a caught panic, so the allocator
/// and the unwinder of this library are linked in.
#[no_mangle]
pub extern "C" fn other_rust_sum(n: u32) -> u64 {
    let values: Vec<u64> = (0..u64::from(n)).collect();
    std::panic::catch_unwind(|| values.iter().sum()).unwrap_or(0)
}
