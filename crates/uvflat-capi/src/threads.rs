//! How many threads the library computes on inside a call. The library runs its parallel loops
//! and factorizations on one pool of worker threads, created on first use with one thread per
//! core (or `RAYON_NUM_THREADS`); `uvf_set_thread_count` chooses the size before that.

use super::guard;
use super::status::UvfStatus;
use uvflat_core::error::Error;

/// Sets the number of worker threads the library computes on (0: one per core, or the
/// `RAYON_NUM_THREADS` environment variable if set; 1: everything runs on the calling thread's
/// pool of one). Must be called before any call that runs in parallel — in practice, before any
/// other uvflat call; afterwards it returns `UVF_INVALID_ARGUMENT` (the pool exists and keeps
/// its size, see `uvf_thread_count`). Progress callbacks are always called on the thread that
/// made the call.
#[no_mangle]
pub extern "C" fn uvf_set_thread_count(count: u32) -> UvfStatus {
    guard(|| {
        let mut builder = rayon::ThreadPoolBuilder::new().thread_name(|i| format!("uvflat-{i}"));
        if count > 0 {
            builder = builder.num_threads(count as usize);
        }
        builder.build_global().map_err(|_| {
            Error::InvalidArgument(format!(
                "the worker threads already exist ({} of them): call uvf_set_thread_count before any other uvflat call",
                rayon::current_num_threads()
            ))
        })
    })
}

/// Number of worker threads the library computes on. Creates the pool with its default size if
/// no call has needed it yet (after which `uvf_set_thread_count` can no longer change it).
#[no_mangle]
pub extern "C" fn uvf_thread_count() -> u32 {
    u32::try_from(rayon::current_num_threads()).unwrap_or(u32::MAX)
}
