//! The integration tests of the C ABI, in one test binary: the header and C/C++ programs
//! (`c_abi`, `openmesh`), the installed SDK (`install`), bad input through every entry point,
//! threads sharing a handle, and the fuzzing corpus replayed on stable Rust.

mod bad_input;
mod c_abi;
mod concurrency;
mod fuzz_regressions;
mod install;
mod openmesh;
