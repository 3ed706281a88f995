"""`cmake --install` puts the package into the interpreter's site directory under the prefix."""
import os
import subprocess
import sys
import sysconfig

import pytest


def test_install_into_a_prefix(tmp_path):
    build = os.environ.get("ELLIPSEKIT_BUILD_DIR")
    if not build or not os.path.exists(os.path.join(build, "CMakeCache.txt")):
        pytest.skip("ELLIPSEKIT_BUILD_DIR (a configured build tree) not set")
    prefix = tmp_path / "prefix"
    r = subprocess.run(["cmake", "--install", build, "--component", "python", "--prefix", str(prefix)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    site = sysconfig.get_path("platlib", "posix_prefix", vars={"base": str(prefix), "platbase": str(prefix)})
    pkg = os.path.join(site, "ellipsekit")
    for name in ("__init__.py", "__init__.pyi", "py.typed", "batch.py", "_batch_worker.py", "robot.py",
                 "robot.pyi", "_detections.py", "_option_names.py"):
        assert os.path.isfile(os.path.join(pkg, name)), name
    assert any(n.startswith("_ellipsekit.") and n.endswith(".so") for n in os.listdir(pkg))
    # The installed copy imports and works without the build tree on the path.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = site
    code = ("import ellipsekit, numpy as np; print(ellipsekit.__file__); "
            "print(len(ellipsekit.Detector().detect(np.zeros((32, 32), np.uint8))))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == [os.path.join(pkg, "__init__.py"), "0"]
