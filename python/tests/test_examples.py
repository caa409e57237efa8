"""The examples in python/examples/ keep working: they and the package pass
`mypy --strict`, the notebook runs with no error and shows images, and
the scripts and the example golden test run and write their files.

Everything runs in a temporary folder (a subprocess's cwd, the kernel's
cwd), so that python/package/ never shadows the installed package and no
output lands in the checkout.
"""

from __future__ import annotations

import base64
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Dict, List

import pytest

PYTHON = Path(__file__).resolve().parents[1]
EXAMPLES = PYTHON / "examples"
PACKAGE = PYTHON / "package"
NOTEBOOK = EXAMPLES / "shading-modes.ipynb"
SCRIPTS = sorted(EXAMPLES.glob("*.py"))

PNG = b"\x89PNG\r\n\x1a\n"


def run(args: List[str], cwd: Path, env: Dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=300
    )


def said(out: subprocess.CompletedProcess[str]) -> str:
    return f"exit status {out.returncode}\n--- stdout\n{out.stdout}\n--- stderr\n{out.stderr}"


@pytest.fixture(scope="module")
def mypy_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One cache for both runs: numpy's stubs are read once."""
    return tmp_path_factory.mktemp("mypy-cache")


def test_the_examples_pass_mypy_strict(tmp_path: Path, mypy_cache: Path) -> None:
    # Against the package's sources and stubs (MYPYPATH), the API the
    # checkout declares, not whatever build is installed; the package's
    # own errors are the next test's.
    assert {p.name for p in SCRIPTS} >= {"four_modes.py", "moving_light.py", "golden_test_example.py"}
    env = {**os.environ, "MYPYPATH": str(PACKAGE)}
    out = run(
        ["-m", "mypy", "--strict", "--follow-imports=silent", "--cache-dir", str(mypy_cache),
         *map(str, SCRIPTS)],
        cwd=tmp_path,
        env=env,
    )
    assert out.returncode == 0, said(out)


def test_the_package_passes_mypy_strict(tmp_path: Path, mypy_cache: Path) -> None:
    out = run(["-m", "mypy", "--strict", "--cache-dir", str(mypy_cache), str(PACKAGE / "shadelab")], cwd=tmp_path)
    assert out.returncode == 0, said(out)


def test_the_notebook_is_stored_without_outputs() -> None:
    nbformat = pytest.importorskip("nbformat")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(notebook)
    assert notebook.metadata["kernelspec"]["name"] == "python3"
    for cell in notebook.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, cell.source


def test_the_notebook_runs_and_shows_images(tmp_path: Path) -> None:
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        notebook, kernel_name="python3", timeout=120, resources={"metadata": {"path": str(tmp_path)}}
    )
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as e:
        pytest.fail(f"a cell of {NOTEBOOK.name} raised:\n{e}", pytrace=False)
    outputs = [o for c in notebook.cells if c.cell_type == "code" for o in c.outputs]
    errors = [o for o in outputs if o.output_type == "error"]
    assert not errors, [f"{o.ename}: {o.evalue}" for o in errors]
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert images, "no cell showed an image/png"
    for image in images:
        assert base64.b64decode(image.data["image/png"])[:8] == PNG


def test_four_modes_writes_four_pngs_and_says_their_times(tmp_path: Path) -> None:
    out = run([str(EXAMPLES / "four_modes.py"), "renders"], cwd=tmp_path)
    assert out.returncode == 0, said(out)
    for mode in ("flat", "gouraud", "phong", "raytrace"):
        png = tmp_path / "renders" / f"default-{mode}.png"
        assert png.is_file(), said(out)
        assert png.read_bytes()[:8] == PNG
        assert re.search(rf"^\s*{mode}:\s+[0-9.]+ ms", out.stdout, re.MULTILINE), said(out)
    # With no folder given: out/.
    out = run([str(EXAMPLES / "four_modes.py")], cwd=tmp_path)
    assert out.returncode == 0, said(out)
    assert (tmp_path / "out" / "default-phong.png").is_file()


def test_moving_light_renders_each_step(tmp_path: Path) -> None:
    out = run([str(EXAMPLES / "moving_light.py"), "3", "frames"], cwd=tmp_path)
    assert out.returncode == 0, said(out)
    means = [float(m) for m in re.findall(r"mean brightness ([0-9.]+)", out.stdout)]
    assert len(means) == 3, said(out)
    # The light moved: each frame its own.
    assert len(set(means)) == 3 and all(m > 0 for m in means), means
    frames = sorted(p.name for p in (tmp_path / "frames").iterdir())
    assert frames == ["frame-001.png", "frame-002.png", "frame-003.png"]


def test_the_golden_example_fails_without_references_then_makes_and_passes_them(tmp_path: Path) -> None:
    # Copied as a test module of its own (its own name is not collected),
    # run by pytest with the package's plugin, as a user would.
    shutil.copy(EXAMPLES / "golden_test_example.py", tmp_path / "test_golden.py")
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    env = {k: v for k, v in os.environ.items() if k != "SHADELAB_BLESS"}
    pytest_args = ["-m", "pytest", "-q", "-p", "no:cacheprovider", "test_golden.py"]
    out = run(pytest_args, cwd=tmp_path, env=env)
    assert out.returncode == 1 and "--shadelab-create" in out.stdout, said(out)
    out = run([*pytest_args, "--shadelab-create"], cwd=tmp_path, env=env)
    assert out.returncode == 0, said(out)
    made = sorted(p.name for p in (tmp_path / "references").glob("*.png"))
    assert "default-phong.png" in made and len(made) == 6, made
    out = run(pytest_args, cwd=tmp_path, env=env)
    assert out.returncode == 0 and "6 passed" in out.stdout, said(out)
