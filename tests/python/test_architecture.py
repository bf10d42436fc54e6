"""The workspace structure ARCHITECTURE.md promises ("Rules"): no import cycle between the files
of a crate, crate dependencies only along the layers, no C or command-line types in the core
crate. The check is scripts/check_architecture.py; these tests run it on the repository and show
that it catches each kind of violation on a small crafted workspace."""
from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "scripts" / "check_architecture.py"


def load_checker():
    spec = importlib.util.spec_from_file_location("check_architecture", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_repository_follows_the_rules():
    run = subprocess.run([sys.executable, str(SCRIPT)], capture_output=True, text=True, cwd=REPO)
    assert run.returncode == 0, f"architecture check failed:\n{run.stdout}{run.stderr}"


def write(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


def test_a_cycle_between_two_files_is_found(tmp_path):
    checker = load_checker()
    src = write(tmp_path / "src", {
        "lib.rs": "mod a;\nmod b;\nmod c;\n",
        "a.rs": "use crate::b::f;\npub fn g() {}\n",
        "b.rs": "pub fn f() { crate::a::g() }\n",
        "c.rs": "use super::a::{g};\n",
    })
    cycles = checker.crate_cycles(src)
    assert [sorted(Path(p).name for p in c) for c in cycles] == [["a.rs", "b.rs"]]


def test_a_parent_re_exporting_its_children_is_not_a_cycle(tmp_path):
    checker = load_checker()
    src = write(tmp_path / "src", {
        "lib.rs": "pub mod m;\n",
        "m/mod.rs": "mod x;\npub use self::x::X;\npub struct Y;\n",
        "m/x.rs": "use super::Y;\npub struct X(Y);\n",
    })
    assert checker.crate_cycles(src) == []


def test_paths_inside_comments_and_strings_are_not_imports(tmp_path):
    checker = load_checker()
    src = write(tmp_path / "src", {
        "lib.rs": "mod a;\nmod b;\n",
        "a.rs": "use crate::b::f;\n",
        "b.rs": "// crate::a::g\npub fn f() -> &'static str { \"crate::a::g\" }\n",
    })
    assert checker.crate_cycles(src) == []


def test_use_trees_expand_to_every_path():
    checker = load_checker()
    assert checker.expand_use_tree("crate::a::{b, c::{d, e as f}, self}") == [
        "crate::a::b", "crate::a::c::d", "crate::a::c::e", "crate::a"]


def test_a_forbidden_crate_dependency_and_c_types_in_the_core_are_found(tmp_path):
    checker = load_checker()
    write(tmp_path / "crates", {
        "uvflat-sparse/Cargo.toml": '[package]\nname = "uvflat-sparse"\n[dependencies]\nuvflat-core = "1"\n',
        "uvflat-sparse/src/lib.rs": "pub fn f() {}\n",
        "uvflat-core/Cargo.toml": '[package]\nname = "uvflat-core"\n[dependencies]\nclap = "4"\n',
        "uvflat-core/src/lib.rs": '#[repr(C)]\npub struct S;\n#[no_mangle]\npub extern "C" fn g() {}\n',
    })
    problems = checker.violations(tmp_path / "crates")
    assert any("uvflat-sparse: depends on ['uvflat-core']" in p for p in problems), problems
    assert any("uvflat-core: depends on clap" in p for p in problems), problems
    assert any("repr" in p for p in problems) and any("extern" in p for p in problems), problems
    assert len(problems) == 4, problems
