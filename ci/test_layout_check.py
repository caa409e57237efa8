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


if __name__ == "__main__":
    unittest.main()
