"""The build backend behind `pip install .` (PEP 517), from the standard library alone.

It needs nothing from the network: no setuptools, no scikit-build. `build_wheel` configures the
project's CMake build in build/python-wheel (kept, so a second install rebuilds only what
changed), builds the module target alone, and zips the package, the module and the data folder
(the scenes, and the models when the setup has fetched them) into a wheel for this interpreter.

Environment:
  CMAKE_ARGS           extra CMake arguments, e.g. "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
  CMAKE_BUILD_PARALLEL_LEVEL   build jobs (default: every core)
"""

from __future__ import annotations

import base64
import hashlib
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile
from pathlib import Path

NAME = "ffdaabb"
ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "python-wheel"
SUMMARY = (
    "Real-time simulation of many deformable objects: FFD lattices, shape matching and the "
    "Enhanced FFD-AABB collision pipeline"
)


def _version() -> str:
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(ffdaabb VERSION ([0-9.]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no `project(ffdaabb VERSION x.y.z` line")
    return match.group(1)


def _tag() -> str:
    if sys.implementation.name != "cpython":
        raise RuntimeError(f"ffdaabb's module is built for CPython, not {sys.implementation.name}")
    python = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{python}-{python}-{platform}"


def _dist_info() -> str:
    return f"{NAME}-{_version()}.dist-info"


def _metadata() -> str:
    readme = ROOT / "README.md"
    lines = [
        "Metadata-Version: 2.1",
        f"Name: {NAME}",
        f"Version: {_version()}",
        f"Summary: {SUMMARY}",
        "Requires-Python: >=3.8",
        "Requires-Dist: numpy",
        "Description-Content-Type: text/markdown",
        "",
        readme.read_text() if readme.exists() else "",
    ]
    return "\n".join(lines)


def _wheel_file() -> str:
    return "\n".join(
        ["Wheel-Version: 1.0", f"Generator: {NAME}_build", "Root-Is-Purelib: false",
         f"Tag: {_tag()}", ""]
    )


def _run(command: list[str]) -> None:
    print("ffdaabb_build: " + " ".join(shlex.quote(c) for c in command), file=sys.stderr)
    subprocess.run(command, check=True, cwd=ROOT)


def _build_module() -> Path:
    """Configures and builds the module target; returns the build tree's package folder."""
    if not shutil.which("cmake"):
        raise RuntimeError("cmake not found: run scripts/setup.sh first (it installs cmake, "
                           "ninja, pybind11-dev and python3-dev)")
    configure = [
        "cmake", "-S", str(ROOT), "-B", str(BUILD),
        "-DCMAKE_BUILD_TYPE=Release",
        "-DFFD_BUILD_PYTHON=ON", "-DFFD_BUILD_TESTS=OFF", "-DFFD_BUILD_BENCH=OFF",
        "-DFFD_BUILD_APPS=OFF", "-DFFD_BUILD_RENDER=OFF", "-DFFD_BUILD_PEERS=OFF",
        f"-DPython3_EXECUTABLE={sys.executable}",
    ]
    if shutil.which("ninja") and not (BUILD / "CMakeCache.txt").exists():
        configure += ["-G", "Ninja"]
    configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
    _run(configure)
    jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
    _run(["cmake", "--build", str(BUILD), "--target", "ffdaabb_python", "-j", jobs])
    return BUILD / "python" / NAME


def _package_files(package: Path) -> list[tuple[str, Path]]:
    """(name in the wheel, file) for the package, the module and the data folder."""
    files = []
    for path in sorted(package.iterdir()):
        if path.is_file() and not path.is_symlink() and (
            path.suffix in (".py", ".pyi", ".so") or path.name == "py.typed"
        ):
            files.append((f"{NAME}/{path.name}", path))
    for scene in sorted((ROOT / "scenes").glob("*.json")):
        files.append((f"{NAME}/data/scenes/{scene.name}", scene))
    for model in sorted((ROOT / ".cache" / "models").glob("*.ply.gz")):
        files.append((f"{NAME}/data/models/{model.name}", model))
    if not any(name.endswith(".so") for name, _ in files):
        raise RuntimeError(f"the build made no module in {package}")
    return files


def _record_line(name: str, data: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def get_requires_for_build_wheel(config_settings=None) -> list[str]:
    return []


def get_requires_for_build_sdist(config_settings=None) -> list[str]:
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None) -> str:
    info = Path(metadata_directory) / _dist_info()
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata())
    (info / "WHEEL").write_text(_wheel_file())
    (info / "top_level.txt").write_text(NAME + "\n")
    return info.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None) -> str:
    package = _build_module()
    name = f"{NAME}-{_version()}-{_tag()}.whl"
    target = Path(wheel_directory) / name
    partial = target.with_suffix(".whl.part")
    info = _dist_info()
    record = []
    with zipfile.ZipFile(partial, "w", compression=zipfile.ZIP_DEFLATED) as wheel:
        for arcname, path in _package_files(package):
            data = path.read_bytes()
            wheel.writestr(arcname, data)
            record.append(_record_line(arcname, data))
        for arcname, text in (
            (f"{info}/METADATA", _metadata()),
            (f"{info}/WHEEL", _wheel_file()),
            (f"{info}/top_level.txt", NAME + "\n"),
        ):
            data = text.encode()
            wheel.writestr(arcname, data)
            record.append(_record_line(arcname, data))
        record.append(f"{info}/RECORD,,")
        wheel.writestr(f"{info}/RECORD", "\n".join(record) + "\n")
    os.replace(partial, target)  # nothing half-written is left under the wheel's name
    return name


def build_sdist(sdist_directory, config_settings=None) -> str:
    """The files git tracks (or, outside a clone, the source tree without build outputs)."""
    base = f"{NAME}-{_version()}"
    try:
        listed = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True,
                                capture_output=True).stdout.decode().split("\0")
        files = [f for f in listed if f and (ROOT / f).is_file()]
    except (OSError, subprocess.CalledProcessError):
        skip = {"build", ".cache", "out", ".git"}
        files = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*")
                 if p.is_file() and not skip.intersection(p.relative_to(ROOT).parts)]
    name = f"{base}.tar.gz"
    target = Path(sdist_directory) / name
    partial = target.with_suffix(".gz.part")
    with tarfile.open(partial, "w:gz", format=tarfile.PAX_FORMAT) as sdist:
        for f in sorted(files):
            sdist.add(ROOT / f, arcname=f"{base}/{f}", recursive=False)
        info = tarfile.TarInfo(f"{base}/PKG-INFO")
        data = _metadata().encode()
        info.size = len(data)
        sdist.addfile(info, io.BytesIO(data))
    os.replace(partial, target)
    return name
