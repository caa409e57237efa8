"""ci/layout-check.py catches what it is there to catch: each rule broken
once in a small tree of its own, and the same tree passing when mended."""

import subprocess
import sys
import tempfile
import textwrap
import unittest
from pathlib import Path

SCRIPT = Path(__file__).resolve().parent / "layout-check.py"


def check(files: dict) -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory() as root:
        for name, text in files.items():
            path = Path(root) / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(textwrap.dedent(text))
        return subprocess.run(
            [sys.executable, str(SCRIPT), "--root", root], capture_output=True, text=True
        )


LIB = "pub mod a;\npub mod b;\npub mod room;\n"
CLEAN = {
    "src/lib.rs": LIB,
    "src/a.rs": "use crate::b::Thing;\npub fn f(_: Thing) {}\n",
    "src/b.rs": "pub struct Thing;\n",
    "src/room/mod.rs": "mod inner;\npub use inner::Item;\n",
    "src/room/inner.rs": "pub struct Item;\n",
}


class LayoutCheck(unittest.TestCase):
    def test_a_clean_tree_passes(self):
        result = check(CLEAN)
        self.assertEqual(result.returncode, 0, result.stdout)

    def test_two_files_naming_each_other_are_a_loop(self):
        files = dict(CLEAN, **{"src/b.rs": "pub struct Thing;\npub fn g() { crate::a::f(Thing) }\n"})
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("import loop: src/a, src/b", result.stdout)

    def test_a_parent_and_the_child_it_calls_are_a_loop(self):
        files = dict(CLEAN, **{
            "src/room/mod.rs": "mod inner;\npub struct Shared;\npub fn go() { inner::run() }\n",
            "src/room/inner.rs": "use super::Shared;\npub fn run() { let _ = Shared; }\n",
        })
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("import loop: src/room, src/room/inner", result.stdout)

    def test_a_re_export_is_not_a_loop_but_its_source_is_read(self):
        # The child names the parent's re-export of a sibling's item: an
        # import of the sibling, so no loop with the parent.
        files = dict(CLEAN, **{
            "src/room/mod.rs": "mod inner;\nmod other;\npub use other::Shared;\npub fn go() { inner::run() }\n",
            "src/room/inner.rs": "use super::Shared;\npub fn run() { let _ = Shared; }\n",
            "src/room/other.rs": "pub struct Shared;\n",
        })
        self.assertEqual(check(files).returncode, 0)

    def test_a_file_over_800_lines_fails(self):
        files = dict(CLEAN, **{"src/b.rs": "pub struct Thing;\n" + "// line\n" * 800})
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/b.rs: 801 lines", result.stdout)

    def test_a_function_over_100_lines_fails_outside_tests_only(self):
        body = "    let _x = 1;\n" * 99
        long_fn = "pub fn long() {\n" + body + "}\n"
        result = check(dict(CLEAN, **{"src/b.rs": "pub struct Thing;\n" + long_fn}))
        self.assertEqual(result.returncode, 1)
        self.assertIn("fn long is 101 lines", result.stdout)
        in_tests = "pub struct Thing;\n#[cfg(test)]\nmod tests {\n    #[test]\n" + long_fn + "}\n"
        self.assertEqual(check(dict(CLEAN, **{"src/b.rs": in_tests})).returncode, 0)
        exactly = "pub struct Thing;\npub fn long() {\n" + "    let _x = 1;\n" * 98 + "}\n"
        self.assertEqual(check(dict(CLEAN, **{"src/b.rs": exactly})).returncode, 0)



# A binary with two commands and what they share, over a library.
CLI = {
    "src/lib.rs": "pub mod judge;\n",
    "src/judge.rs": "pub struct Limits;\n",
    "src/main.rs": "mod cli;\nfn main() { cli::run() }\n",
    "src/cli/mod.rs": "mod common;\nmod golden;\nmod diff;\npub fn run() { golden::run(); diff::run() }\n",
    "src/cli/common/mod.rs": "pub mod failure;\n",
    "src/cli/common/failure.rs": "pub struct Failure;\n",
    "src/cli/golden/mod.rs": "mod judge;\npub fn run() { judge::go() }\n",
    "src/cli/golden/judge.rs": "use crate::cli::common::failure::Failure;\npub fn go() { let _ = Failure; }\n",
    "src/cli/diff/mod.rs": "pub fn run() { let _ = crate::cli::common::failure::Failure; }\npub struct Judging;\n",
}


class CommandsApart(unittest.TestCase):
    def test_commands_sharing_only_common_and_the_library_pass(self):
        result = check(CLI)
        self.assertEqual(result.returncode, 0, result.stdout)

    def test_a_command_importing_another_commands_item_fails(self):
        files = dict(CLI, **{
            "src/cli/golden/judge.rs": "use crate::cli::diff::Judging;\npub fn go() { let _ = Judging; }\n",
        })
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn(
            "src/cli/golden/judge.rs:1: the command golden imports the command diff (src/cli/diff/mod.rs)",
            result.stdout,
        )

    def test_a_command_in_one_file_is_a_command_too(self):
        files = dict(CLI, **{
            "src/cli/mod.rs": "mod common;\nmod golden;\nmod diff;\nmod info;\npub fn run() { info::run() }\n",
            "src/cli/info.rs": "pub fn run() { super::golden::run() }\n",
        })
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("the command info imports the command golden", result.stdout)

    def test_what_commands_share_importing_a_command_fails(self):
        files = dict(CLI, **{
            "src/cli/common/failure.rs": "pub struct Failure(crate::cli::diff::Judging);\n",
        })
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/cli/common/ imports the command diff", result.stdout)

    def test_the_library_naming_the_cli_fails(self):
        files = dict(CLI, **{"src/judge.rs": "pub struct Limits(crate::cli::common::failure::Failure);\n"})
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/judge.rs:1: the library imports the command line", result.stdout)
        declared = dict(CLI, **{"src/lib.rs": "pub mod judge;\nmod cli;\n"})
        result = check(declared)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/lib.rs:2: the library declares the command line (mod cli)", result.stdout)

if __name__ == "__main__":
    unittest.main()


class TestsFolder(unittest.TestCase):
    """tests/ holds to the same limits, each test binary on its own."""

    COMMON = {
        "tests/common/mod.rs": "pub mod cli;\npub fn gpu() {}\n",
        "tests/common/cli.rs": "pub fn shadelab() {}\n",
        "tests/gpu/main.rs": '#[path = "../common/mod.rs"]\nmod common;\nmod raster;\nmod raytrace;\n',
        "tests/gpu/raster.rs": "use crate::common;\n#[test]\nfn draws() { common::gpu() }\n",
        "tests/gpu/raytrace.rs": "use crate::common::cli::shadelab;\n#[test]\nfn traces() { shadelab() }\n",
        "tests/alone.rs": "mod common;\n#[test]\nfn alone() { common::gpu() }\n",
    }

    def tree(self, changes: dict) -> dict:
        return {**CLEAN, **self.COMMON, **changes}

    def test_a_clean_tests_folder_passes(self):
        result = check(self.tree({}))
        self.assertEqual(result.returncode, 0, result.stdout)
        self.assertIn("no import loop in 2 test binaries", result.stdout)

    def test_a_test_file_over_800_lines_fails(self):
        long = self.COMMON["tests/gpu/raster.rs"] + "// line\n" * 800
        result = check(self.tree({"tests/gpu/raster.rs": long}))
        self.assertEqual(result.returncode, 1)
        self.assertIn("tests/gpu/raster.rs: 803 lines", result.stdout)

    def test_a_test_function_over_100_lines_fails(self):
        long = "#[test]\nfn long() {\n" + "    let _x = 1;\n" * 99 + "}\n"
        result = check(self.tree({"tests/gpu/raster.rs": long}))
        self.assertEqual(result.returncode, 1)
        self.assertIn("tests/gpu/raster.rs:2: fn long is 101 lines", result.stdout)
        exactly = "#[test]\nfn long() {\n" + "    let _x = 1;\n" * 98 + "}\n"
        result = check(self.tree({"tests/gpu/raster.rs": exactly}))
        self.assertEqual(result.returncode, 0, result.stdout)

    def test_two_modules_of_a_test_binary_naming_each_other_are_a_loop(self):
        files = self.tree({
            "tests/gpu/raster.rs": "pub fn f() { crate::raytrace::g() }\n",
            "tests/gpu/raytrace.rs": "pub fn g() {}\npub fn h() { crate::raster::f() }\n",
        })
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("import loop in test binary gpu: tests/gpu/raster.rs, tests/gpu/raytrace.rs", result.stdout)

    def test_the_shared_helpers_are_a_module_of_each_binary(self):
        # common naming a test module back is a loop, in the binary that has both.
        files = self.tree({
            "tests/common/cli.rs": "pub fn shadelab() { crate::raytrace::traces() }\n",
            "tests/gpu/raytrace.rs": "use crate::common::cli::shadelab;\npub fn traces() { shadelab() }\n",
        })
        result = check(files)
        self.assertEqual(result.returncode, 1)
        self.assertIn("import loop in test binary gpu: tests/common/cli.rs, tests/gpu/raytrace.rs", result.stdout)

    def test_fixtures_are_not_checked(self):
        files = self.tree({"tests/data/big.rs": "// line\n" * 900})
        self.assertEqual(check(files).returncode, 0)
