//! Replays the fuzz inputs kept in the repository through the C ABI on stable Rust, without
//! libFuzzer, with the same decoding and contract checks as the fuzz targets
//! (`crates/uvflat-capi/fuzz/src/decode.rs`, included below): every file of `crates/uvflat-capi/fuzz/regressions/<target>/` (inputs
//! that once crashed, hung or broke the contract) and of the seed corpus
//! `crates/uvflat-capi/fuzz/corpus/<target>/` (capped in count and time so the test stays fast).
//!
//! A caught panic inside uvflat shows up here as `UVF_INTERNAL_ERROR`, which the checks reject.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[path = "../../fuzz/src/decode.rs"]
mod decode;

/// At most this many corpus files per target, and this much time over all corpus files.
const CORPUS_FILES_PER_TARGET: usize = 300;
const CORPUS_BUDGET: Duration = Duration::from_secs(10);

/// `crates/uvflat-capi/fuzz/` of the repository, or `$UVFLAT_FUZZ_DIR` (a folder with `regressions/` and
/// `corpus/`, e.g. a local fuzzing corpus).
fn fuzz_dir() -> PathBuf {
    match std::env::var_os("UVFLAT_FUZZ_DIR") {
        Some(dir) => PathBuf::from(dir),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz"),
    }
}

/// `UVFLAT_FUZZ_ALL=1` lifts the corpus caps (to replay a whole local corpus).
fn uncapped() -> bool {
    std::env::var_os("UVFLAT_FUZZ_ALL").is_some_and(|v| v == "1")
}

fn is_hidden(path: &Path) -> bool {
    path.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.'))
}

/// Files of `dir` except hidden ones (`.keep`), sorted by name (none when the folder does not
/// exist).
fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => {
            entries.filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.is_file() && !is_hidden(p)).collect()
        }
        Err(_) => Vec::new(),
    };
    files.sort();
    files
}

/// Runs one input; a violation or a panic of the harness is returned as text.
fn replay(target: decode::Target, path: &Path) -> Result<(), String> {
    let data = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    match std::panic::catch_unwind(|| decode::run(target, &data)) {
        Ok(Ok(())) => Ok(()),
        Ok(Err(violation)) => Err(format!("{}: {violation}", path.display())),
        Err(_) => Err(format!("{}: the harness panicked", path.display())),
    }
}

#[test]
fn every_regression_input_passes_the_contract() {
    let mut failures = Vec::new();
    let mut count = 0;
    for (name, target) in decode::TARGETS {
        for path in files_in(&fuzz_dir().join("regressions").join(name)) {
            count += 1;
            if let Err(e) = replay(target, &path) {
                failures.push(e);
            }
        }
    }
    eprintln!("replayed {count} regression inputs");
    assert!(failures.is_empty(), "{} of {count} regression inputs fail:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn seed_corpus_passes_the_contract() {
    let start = Instant::now();
    let mut failures = Vec::new();
    let mut count = 0;
    'targets: for (name, target) in decode::TARGETS {
        let cap = if uncapped() { usize::MAX } else { CORPUS_FILES_PER_TARGET };
        for path in files_in(&fuzz_dir().join("corpus").join(name)).into_iter().take(cap) {
            if start.elapsed() > CORPUS_BUDGET && !uncapped() {
                eprintln!("corpus time budget of {CORPUS_BUDGET:?} reached; stopping");
                break 'targets;
            }
            count += 1;
            if let Err(e) = replay(target, &path) {
                failures.push(e);
            }
        }
    }
    eprintln!("replayed {count} corpus inputs in {:?}; statuses:", start.elapsed());
    for (call, status, n) in decode::take_status_counts() {
        eprintln!("  {call:<45} {status:<26} {n}");
    }
    assert!(failures.is_empty(), "{} of {count} corpus inputs fail:\n{}", failures.len(), failures.join("\n"));
}

/// Inputs the decoder must survive: empty, short, all zeros, all ones.
#[test]
fn degenerate_inputs_decode() {
    for (_, target) in decode::TARGETS {
        for data in [&[][..], &[1][..], &[0; 64][..], &[0xff; 64][..], &[1, 3, 3, 0][..]] {
            decode::run(target, data).unwrap_or_else(|e| panic!("{target:?} on {data:?}: {e}"));
        }
    }
}
