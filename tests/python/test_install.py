"""`cmake --install --component python` gives a package that Debian's /usr/bin/python3 imports."""
import os
import pathlib
import subprocess
import sys

import pytest


def test_installed_package_imports_from_a_site_packages_layout(tmp_path):
    build = os.environ.get("MDBRIEF_BUILD_DIR")
    folder = os.environ.get("MDBRIEF_PYTHON_INSTALL_DIR")
    if not build or not folder:
        pytest.skip("MDBRIEF_BUILD_DIR / MDBRIEF_PYTHON_INSTALL_DIR are not set: run through ctest")
    subprocess.run(["cmake", "--install", build, "--component", "python", "--prefix", str(tmp_path)], check=True,
                   capture_output=True)
    site = tmp_path / folder
    assert (site / "mdbrief" / "__init__.py").exists()
    env = dict(os.environ, PYTHONPATH=str(site))
    found = subprocess.run([sys.executable, "-c", "import mdbrief; print(mdbrief.__file__, len(mdbrief.patterns()))"],
                           check=True, capture_output=True, text=True, env=env, cwd=tmp_path).stdout
    assert found.startswith(str(site / "mdbrief" / "__init__.py"))
    # Installed under /usr/local (CMake's default prefix), the folder is on the interpreter's path.
    if not pathlib.PurePath(folder).is_absolute() and folder.startswith("lib/python3."):
        path = subprocess.run([sys.executable, "-c", "import sys; print('\\n'.join(sys.path))"], check=True,
                              capture_output=True, text=True, env={}).stdout.split()
        assert str(pathlib.Path("/usr/local") / folder) in path
